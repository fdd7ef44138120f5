"""Sofa.Core: Node, Object (BaseObject), Data and Controller, as SoftRobots'
scripts use them.  The tree is plain Python until Sofa.Simulation.init; then
it is written as a SOFA scene that libpliant loads through its SOFA
vocabulary, and Data read and write the running simulation by path."""
import difflib
import os
import re
import sys
from xml.sax.saxutils import quoteattr

import numpy as np

from .. import simulation
from .vocabulary import vocabulary


class UnsupportedError(AttributeError):
    """A SofaPython3 call that pliant.sofa does not provide."""


# SofaPython2 and older SofaPython3 names -> today's
_RENAMED = {"createObject": "addObject", "createChild": "addChild", "getChildren": "children",
            "getObjects": "objects", "findData": "getData", "getContext": "getRoot"}


def _unsupported(owner, name, supported):
    close = [_RENAMED[name]] if _RENAMED.get(name) in supported else \
        difflib.get_close_matches(name, supported, n=1, cutoff=0.5)
    hint = f"; closest supported: {owner}.{close[0]}" if close else \
        f"; supported: {', '.join(sorted(supported))}"
    return UnsupportedError(f"{owner}.{name} is not supported by pliant.sofa (docs/python.md)"
                            f"{hint}")


def _caller():
    """file:line of the script code that called into this module."""
    f = sys._getframe(2)
    while f and f.f_code.co_filename.startswith(os.path.dirname(__file__)):
        f = f.f_back
    return (f.f_code.co_filename, f.f_lineno) if f else ("<unknown>", 0)


class _Link(str):
    """What getLinkPath() returns: SOFA's "@/node/obj.field" text, which knows
    its target so that the scene can write it relative to its user."""

    def __new__(cls, target, field):
        node = target if isinstance(target, Node) else target._node
        path = node.getPathName() + ("" if isinstance(target, Node) else
                                     ("/" if node._parent else "") + target._name)
        text = "@" + path + (f".{field}" if field else "")
        s = str.__new__(cls, text)
        s.target, s.field = target, field
        return s


def _text(value, user):
    """A Python value as SOFA attribute text (as a .scn would write it)."""
    if isinstance(value, _Link):
        return "@" + _relative(user, value.target) + (f".{value.field}" if value.field else "")
    if isinstance(value, Data):
        return _text(value.getLinkPath(), user)
    if isinstance(value, (Object, Node)):
        return "@" + _relative(user, value)
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return "1" if value else "0"
    if isinstance(value, (int, float, np.integer, np.floating)):
        return repr(value.item() if hasattr(value, "item") else value)
    if isinstance(value, (list, tuple, np.ndarray, range)):
        return " ".join(_text(v, user) for v in np.asarray(value, dtype=object).ravel())
    raise TypeError(f"cannot write a {type(value).__name__} as a SOFA attribute")


def _relative(user_node, target):
    """SOFA link path from user_node to target (a Node or an Object)."""
    node = target if isinstance(target, Node) else target._node
    up, path = [], []
    a = user_node
    ancestors = []
    n = node
    while n:
        ancestors.append(n)
        n = n._parent
    while a not in ancestors:
        up.append("..")
        a = a._parent
    n = node
    while n is not a:
        path.append(n._name)
        n = n._parent
    parts = up + path[::-1] + ([] if isinstance(target, Node) else [target._name])
    return "/".join(parts) if parts else "."


def _value(sim, path, text):
    """A field's text as SofaPython3 gives Data values: lists as numpy arrays."""
    info = sim.field_info(path)
    kind = info[0] if info else ""
    parts = text.split()
    try:
        if kind in ("double list", "vec3"):
            return np.array([float(p) for p in parts])
        if kind == "int list":
            return np.array([int(p) for p in parts], dtype=int)
        if kind == "double":
            return float(text)
        if kind == "int":
            return int(text)
        if kind == "bool":
            return text.strip() in ("1", "true")
    except ValueError:
        pass
    return simulation._parse(text) if kind not in ("string", "enum", "link") else text


class Data:
    """One attribute of an Object or a Node (SofaPython3's Data): .value
    reads and writes it (in the running simulation once built)."""
    __slots__ = ("_owner", "_field")

    def __init__(self, owner, field):
        object.__setattr__(self, "_owner", owner)
        object.__setattr__(self, "_field", field)

    @property
    def value(self):
        return self._owner._get(self._field)

    @value.setter
    def value(self, v):
        self._owner._set(self._field, v)

    def getLinkPath(self):
        return _Link(self._owner, self._field)

    def getValueString(self):
        v = self.value
        return _text(v, self._owner if isinstance(self._owner, Node) else self._owner._node)

    def getName(self):
        return self._field

    def __getattr__(self, name):
        raise _unsupported("Data", name, ["value", "getLinkPath", "getValueString", "getName"])

    def __setattr__(self, name, v):
        if name == "value":
            object.__setattr__(self, name, v)
        else:
            raise _unsupported("Data", name, ["value"])

    def __repr__(self):
        return f"Data({self._field}={self.value!r})"


class Object:
    """A component added by addObject(type, **attributes)."""
    _API = ["name", "getLinkPath", "getPathName", "getName", "getClassName", "getData"]

    def __init__(self, node, type_, name, attrs, where):
        d = self.__dict__
        d["_node"], d["_type"], d["_name"], d["_attrs"], d["_where"] = node, type_, name, attrs, where
        d["_path"] = None

    def getName(self):
        return self._name

    def getClassName(self):
        return self._type

    def getPathName(self):
        return self._node.getPathName().rstrip("/") + "/" + self._name

    def getLinkPath(self):
        return _Link(self, None)

    def getData(self, name):
        return Data(self, name)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        if name == "name":
            return Data(self, "name")
        return Data(self, name)

    def __setattr__(self, name, value):
        self._set(name, value)

    # the simulation's path of this component (the lowering may move it: a
    # mapped node's cable acts in the parent node)
    def _pliant_path(self, sim):
        if self._path is None:
            node = self._node
            while True:
                cand = node.getPathName().strip("/")
                cand = f"{cand}/{self._name}" if cand else self._name
                try:
                    sim.component(cand)
                    self.__dict__["_path"] = cand
                    break
                except Exception:
                    if node._parent is None:
                        self.__dict__["_path"] = self._name   # unique names stand alone
                        break
                    node = node._parent
        return self._path

    def _field(self, name):
        """The Pliant field of SOFA attribute `name` (the vocabulary's renames)."""
        voc = vocabulary().attributes
        for key in ((self._type, name), ("*", name)):
            rule = voc.get(key)
            if rule and rule[0] == "renamed" and rule[1]:
                return rule[1]
        return name

    def _get(self, name):
        if name == "name":
            return self._name
        sim = self._node.getRoot()._sim
        if sim is None:
            return self._attrs.get(name)
        path = f"{self._pliant_path(sim)}.{self._field(name)}"
        slot = f"{sim.component(self._pliant_path(sim))[0]}.{self._field(name)}"
        if name in ("position", "velocity", "constraintForce") and \
                any(n == slot and fixed for n, _, fixed in sim.slots()):
            return sim.array(slot).reshape(-1, 3)   # the state itself (read-only view)
        return _value(sim, path, sim.get(path))

    def _set(self, name, value):
        root = self._node.getRoot()
        if root._sim is None:
            self._attrs[name] = value
            return
        path = f"{self._pliant_path(root._sim)}.{self._field(name)}"
        v = np.asarray(value).ravel() if not isinstance(value, str) else value
        root._sim.set(path, _text(v, self._node))

    def __repr__(self):
        return f"<{self._type} {self.getPathName()}>"


class Controller:
    """Base of Python controllers (SofaPython3's Sofa.Core.Controller):
    onAnimateBeginEvent(event) and onAnimateEndEvent(event) are called at the
    start and end of every step from the C loop; onKeypressedEvent(event) by
    Sofa.Simulation.keypress or a viewer.  event is a dict ("type", "dt",
    "time"; "key" for a key)."""

    def __init__(self, *args, **kw):
        self.__dict__["_kw"] = kw
        self.__dict__["_cname"] = kw.get("name", type(self).__name__)

    def getName(self):
        return self.__dict__.get("_cname", type(self).__name__)

    @property
    def name(self):
        return _Const(self.getName())


class _Const:
    def __init__(self, value):
        self.value = value


class Node:
    """A node of the scene tree (SofaPython3's Sofa.Core.Node)."""
    _API = ["addChild", "addObject", "getChild", "getObject", "getRoot", "getPathName",
            "getLinkPath", "getName", "children", "objects", "name", "dt", "gravity",
            "removeChild", "getData"]
    _DATA = ("dt", "gravity", "time", "animate", "bbox")

    def __init__(self, name="root", parent=None):
        d = self.__dict__
        d["_name"], d["_parent"] = name, parent
        d["_children"], d["_objects"], d["_controllers"] = {}, [], []
        d["_data"], d["_sim"], d["_where"] = {}, None, _caller()

    # -- building
    def addChild(self, name):
        if isinstance(name, Node):
            child = name
            child.__dict__["_parent"] = self
        else:
            child = Node(str(name), self)
        if child._name in self._children or self._find_object(child._name):
            raise ValueError(f"{self.getPathName()}: a child or object is already named "
                             f"'{child._name}'")
        self._children[child._name] = child
        return child

    def addObject(self, type_, **attrs):
        where = _caller()
        if isinstance(type_, Controller):
            self._controllers.append(type_)
            return type_
        if not isinstance(type_, str):
            raise TypeError(f"addObject: a component type (str) or a Controller, got "
                            f"{type(type_).__name__}")
        # what the type means (and whether it is refused) is the loader's
        # decision at init, from the vocabulary table and the scene's structure
        # (a refused mapping in a node that only draws is dropped, not refused)
        name = str(attrs.pop("name", "") or "")
        if not name:   # SOFA names unnamed components by type, numbered when repeated
            k, name = 1, type_
            while self._find_object(name) or name in self._children:
                k += 1
                name = f"{type_}{k}"
        elif self._find_object(name) or name in self._children:
            raise ValueError(f"{where[0]}:{where[1]}: {self.getPathName()}: an object is "
                             f"already named '{name}'")
        obj = Object(self, type_, name, attrs, where)
        self._objects.append(obj)
        return obj

    def removeChild(self, child):
        name = child._name if isinstance(child, Node) else child
        self._children.pop(name)

    # -- reading
    def _find_object(self, name):
        for o in self._objects:
            if o._name == name:
                return o
        for c in self._controllers:
            if c.getName() == name:
                return c
        return None

    def getChild(self, name):
        return self._children.get(name)

    def getObject(self, name):
        return self._find_object(name)

    @property
    def children(self):
        return list(self._children.values())

    @property
    def objects(self):
        return list(self._objects)

    def getRoot(self):
        n = self
        while n._parent is not None:
            n = n._parent
        return n

    def getPathName(self):
        if self._parent is None:
            return "/"
        parts, n = [], self
        while n._parent is not None:
            parts.append(n._name)
            n = n._parent
        return "/" + "/".join(reversed(parts))

    def getLinkPath(self):
        return _Link(self, None)

    def getName(self):
        return self._name

    def getData(self, name):
        return Data(self, name)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        child = self._children.get(name)
        if child is not None:
            return child
        obj = self._find_object(name)
        if obj is not None:
            return obj
        if name == "name":
            return _Const(self._name)
        if name in self._DATA:
            return Data(self, name)
        names = list(self._children) + [o._name for o in self._objects] + self._API
        raise _unsupported(f"Node {self.getPathName()}", name, names)

    def __setattr__(self, name, value):
        if name in self._DATA:
            self._set(name, value)
        else:
            raise _unsupported(f"Node {self.getPathName()}", name, list(self._DATA))

    def _get(self, name):
        root = self.getRoot()
        if root._sim is None or name not in ("dt", "gravity"):
            if name == "time" and root._sim is not None:
                return root._sim.time
            return self._data.get(name)
        return _value(root._sim, f"{self._name}.{name}", root._sim.get(f"{self._name}.{name}"))

    def _set(self, name, value):
        root = self.getRoot()
        if root._sim is not None:
            root._sim.set(f"{self._name}.{name}", _text(np.asarray(value).ravel(), self))
        else:
            self._data[name] = value

    # -- the scene
    def _xml(self, lines, where, depth=0):
        pad = "  " * depth
        attrs = "".join(f" {k}={quoteattr(_text(v, self))}" for k, v in self._data.items()
                        if k in ("dt", "gravity"))
        lines.append(f"{pad}<Node name={quoteattr(self._name)}{attrs}>")
        where.append(self._where)
        for o in self._objects:
            a = "".join(f" {k}={quoteattr(_text(v, self))}" for k, v in o._attrs.items())
            lines.append(f"{pad}  <{o._type} name={quoteattr(o._name)}{a}/>")
            where.append(o._where)
        for c in self._children.values():
            c._xml(lines, where, depth + 1)
        lines.append(f"{pad}</Node>")
        where.append(self._where)

    def _all_controllers(self):
        out = list(self._controllers)
        for c in self._children.values():
            out += c._all_controllers()
        return out

    def _build(self):
        """Writes the tree as a SOFA scene and loads it (libpliant's SOFA loader)."""
        if self._parent is not None:
            return self.getRoot()._build()
        lines, where = ['<?xml version="1.0"?>'], [("<scene>", 0)]
        self._xml(lines, where)
        script = next((w[0] for w in where if w[0].endswith(".py")), "createScene.py")
        name = script  # relative mesh paths resolve beside the script
        from .. import InputError, _print_warnings

        # the scene's lines are the script's calls: name those instead
        def where_of(m):
            w = where[int(m.group(1)) - 1] if 0 < int(m.group(1)) <= len(where) else None
            return f"{w[0]}:{w[1]}:" if w else m.group(0)
        try:
            sim = simulation.Simulation(xml="\n".join(lines) + "\n", name=name, warn=False)
        except InputError as e:
            raise InputError(re.sub(re.escape(name) + r":(\d+):", where_of, str(e))) from None
        _print_warnings(re.sub(re.escape(name) + r":(\d+):", where_of, sim.warnings))
        self.__dict__["_sim"] = sim
        ctrls = self._all_controllers()
        for c in ctrls:
            sim.add_controller(_Adapter(c))
        return sim

    @property
    def simulation(self):
        """The pliant.Simulation once built (a Pliant addition)."""
        return self._sim


class _Adapter:
    """Gives a SofaPython3 controller the event dicts it expects."""

    def __init__(self, c):
        self.c = c
        if hasattr(c, "onAnimateBeginEvent"):
            self.onAnimateBeginEvent = lambda e: c.onAnimateBeginEvent(
                {"type": "AnimateBeginEvent", "isHandled": False, **e})
        if hasattr(c, "onAnimateEndEvent"):
            self.onAnimateEndEvent = lambda e: c.onAnimateEndEvent(
                {"type": "AnimateEndEvent", "isHandled": False, **e})


def __getattr__(name):
    raise _unsupported("Sofa.Core", name, ["Node", "Controller", "Object", "Data"])
