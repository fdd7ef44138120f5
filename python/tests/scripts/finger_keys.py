# A keyboard controller in SofaPython3's style (a module imported by cable_finger.py).
import Sofa.Core
from Sofa.constants import *  # noqa: F401,F403  (Key)


class FingerKeys(Sofa.Core.Controller):
    """+ pulls the cable by 1 mm, - releases it (never below 0)."""

    def __init__(self, *a, **kw):
        Sofa.Core.Controller.__init__(self, *a, **kw)
        self.node = kw["node"]

    def onKeypressedEvent(self, e):
        value = self.node.aCableActuator.value
        displacement = value.value[0]
        if e["key"] == Key.plus:  # noqa: F405
            displacement += 1.0
        elif e["key"] == Key.minus:  # noqa: F405
            displacement = max(0.0, displacement - 1.0)
        value.value = [displacement]
