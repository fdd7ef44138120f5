"""pliant.Simulation: one loaded scene (a pl_sim) with NumPy views of its state."""
import os

import numpy as np

from . import _core

_HERE = os.path.dirname(os.path.abspath(__file__))


def scene(name):
    """Path of a scene shipped with the package (pliant/scenes), e.g.
    scene("cable_finger_small.xml")."""
    path = os.path.join(_HERE, "scenes", name)
    if not os.path.exists(path):
        raise FileNotFoundError(f"no scene '{name}' in {os.path.join(_HERE, 'scenes')}")
    return path


def _format(value):
    """A Python value as the text of a field (as written in a scene)."""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    arr = np.asarray(value)
    if arr.dtype.kind in "iub":
        return " ".join(str(int(x)) for x in arr.ravel())
    return " ".join(repr(float(x)) for x in arr.ravel())


def _parse(text):
    """A field's text as a float, an int, a float array or the text itself."""
    parts = text.split()
    try:
        if len(parts) == 1:
            return int(parts[0]) if parts[0].lstrip("+-").isdigit() else float(parts[0])
        if parts:
            return np.array([float(p) for p in parts])
    except ValueError:
        pass
    return text


class Controller:
    """Base of Python controllers (SofaPython3's Sofa.Core.Controller names):
    onAnimateBeginEvent(event) runs at the start of every step, inside the C
    loop (the data being stepped is what sim[...] reads and writes), and
    onAnimateEndEvent(event) at its end.  event is a dict {"time": t, "dt": dt}."""

    def onAnimateBeginEvent(self, event):
        pass

    def onAnimateEndEvent(self, event):
        pass


class Simulation(_core.Sim):
    """A scene loaded from a file (Pliant XML or SOFA .scn) or from XML text:

        sim = Simulation("scenes/cable_finger_small.xml")
        sim = Simulation(xml=text, name="made.scn")
        sim = Simulation(path, overrides=["finger/material.youngModulus=2e5"])

    Each Simulation is independent (its own registry, model and state).  The
    load's warnings (what was dropped or changed, as `pliant run` prints them)
    go to stderr, unless warn=False; they stay in `warnings`."""

    def __init__(self, path=None, warn=True, **kw):
        if path is not None:
            super().__init__(os.fspath(path), **kw)
        else:
            super().__init__(**kw)
        if warn:
            from . import _print_warnings
            _print_warnings(self.warnings)
        self._controllers = []
        self._views = {}

    def fork(self):
        """A Simulation over the same model (one factorisation, one copy of the
        meshes) with its own state, starting as a copy of this one's, and its
        own inputs (a cable's value) and controllers.  Fields that are not
        inputs (materials, tolerances) belong to the shared model: setting one
        changes it for every fork.  Exporters write the original's state only."""
        other = super().fork()
        other._controllers = []
        other._views = {}
        return other

    # ---- fields by path ------------------------------------------------------
    def __getitem__(self, path):
        """sim["finger/cable.force"]: a float, an int, a float array or text."""
        return _parse(self.get(path))

    def __setitem__(self, path, value):
        """sim["finger/cable.value"] = 0.005 (numbers, sequences, text)."""
        self.set(path, _format(value))

    # ---- state as NumPy views ------------------------------------------------
    def _mechanical_object(self, path):
        if path is not None:
            full, kind = self.component(path)
            return full
        owners = sorted({n.rsplit(".", 1)[0] for n, _, _ in self.slots() if n.endswith(".position")})
        if len(owners) != 1:
            raise ValueError(f"the scene has {len(owners)} state components "
                             f"({', '.join(owners)}): name one, e.g. positions('{owners[0] if owners else 'node/dofs'}')")
        return owners[0]

    def array(self, slot, writable=False):
        """The state slot `slot` ("root/finger/dofs.position") as a 1-D float64
        array viewing the simulation's memory (no copy, read-only by default)."""
        key = (slot, bool(writable))
        view = self._views.get(key)
        if view is None:
            view = self._views[key] = self.view(slot, writable)
        return np.frombuffer(view, dtype=np.float64)

    def _vec3(self, path, name):
        full = self._mechanical_object(path)
        return self.array(f"{full}.{name}").reshape(-1, 3)

    def positions(self, path=None):
        """(n, 3) positions [m] of the MechanicalObject at `path` (the only one
        when None): a read-only view that follows the simulation."""
        return self._vec3(path, "position")

    def velocities(self, path=None):
        """(n, 3) velocities [m/s], a read-only view."""
        return self._vec3(path, "velocity")

    def constraint_forces(self, path=None):
        """(n, 3) constraint forces [N] of the last step, a read-only view."""
        return self._vec3(path, "constraintForce")

    # ---- controllers -----------------------------------------------------------
    def add_controller(self, controller):
        """Calls controller.onAnimateBeginEvent / onAnimateEndEvent at the start
        and end of every step (either may be missing)."""
        self._controllers.append(controller)
        self._install_hooks()
        return controller

    def remove_controller(self, controller):
        self._controllers.remove(controller)
        self._install_hooks()

    def _install_hooks(self):
        dt = self.dt
        begins = [c.onAnimateBeginEvent for c in self._controllers
                  if hasattr(c, "onAnimateBeginEvent")]
        ends = [c.onAnimateEndEvent for c in self._controllers
                if hasattr(c, "onAnimateEndEvent")]

        def hook(calls):
            if not calls:
                return None
            if len(calls) == 1:
                call = calls[0]
                return lambda t: call({"time": t, "dt": dt})

            def many(t):
                event = {"time": t, "dt": dt}
                for c in calls:
                    c(event)
            return many

        self.set_hooks(hook(begins), hook(ends))
