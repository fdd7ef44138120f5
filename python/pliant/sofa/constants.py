"""Sofa.constants: the key codes of SofaPython3's Key (the characters a
KeypressedEvent carries)."""


class Key:
    plus = "+"
    minus = "-"
    space = " "
    uparrow = chr(19)
    downarrow = chr(21)
    leftarrow = chr(18)
    rightarrow = chr(20)
    escape = chr(27)
    backspace = chr(8)
    enter = "\n"


for _c in "abcdefghijklmnopqrstuvwxyz":
    setattr(Key, _c, _c)
    setattr(Key, _c.upper(), _c.upper())
for _d in range(10):
    setattr(Key, f"_{_d}", str(_d))
