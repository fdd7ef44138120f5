"""Sofa.Simulation: init (build the scene), animate (step it), reset."""
from .Core import Node, UnsupportedError


def _root(node, call):
    if not isinstance(node, Node):
        raise TypeError(f"Sofa.Simulation.{call}(root): expected the root Node, got "
                        f"{type(node).__name__}")
    return node.getRoot()


def init(node):
    """Builds the simulation of the tree (libpliant's SOFA loader)."""
    _root(node, "init")._build()


def animate(node, dt=0.0):
    """One time step of the root's dt (dt other than 0 or the root's dt is refused)."""
    root = _root(node, "animate")
    sim = root._sim or root._build()
    if dt and abs(dt - sim.dt) > 1e-15 * max(1.0, sim.dt):
        raise UnsupportedError(f"Sofa.Simulation.animate(root, dt={dt}): Pliant steps the root's "
                               f"dt ({sim.dt}); set rootNode.dt before init instead")
    sim.step(1)


def reset(node):
    """Back to the state after init."""
    root = _root(node, "reset")
    if root._sim:
        root._sim.reset()


def unload(node):
    root = _root(node, "unload")
    root.__dict__["_sim"] = None


def keypress(node, key):
    """Hands a key to every controller's onKeypressedEvent (a Pliant addition:
    what a viewer does when a key is pressed)."""
    root = _root(node, "keypress")
    used = False
    for c in root._all_controllers():
        if hasattr(c, "onKeypressedEvent"):
            c.onKeypressedEvent({"type": "KeypressedEvent", "key": key, "isHandled": False})
            used = True
    return used


def __getattr__(name):
    from .Core import _unsupported
    raise _unsupported("Sofa.Simulation", name, ["init", "animate", "reset", "unload", "keypress"])
