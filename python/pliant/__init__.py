"""Pliant from Python: load a scene, step it, read its state as NumPy arrays
(views of the simulation's own memory), change fields by path, drive it from
Python controllers (docs/python.md).

    import pliant
    sim = pliant.Simulation(pliant.scene("cable_finger_small.xml"))
    sim["finger/cable.value"] = 0.005
    sim.step(50)
    print(sim.time, sim.positions("finger/dofs")[-1])
"""
import os as _os

# libgomp reads OMP_WAIT_POLICY once, when libpliant loads it (with _core):
# waiting threads sleep rather than spin, as the pliant CLI does
# (docs/embedding.md: spinning threads cost 10x on shared cores).
_os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

from ._core import Error, InputError  # noqa: E402
from .simulation import Simulation, Controller, scene

__all__ = ["Simulation", "Controller", "Error", "InputError", "scene", "load", "set_log_level"]


def load(path, **kw):
    """A Simulation of a scene file: Pliant XML, SOFA .scn, or a SofaPython3
    createScene script (.py, built through pliant.sofa; its controllers run)."""
    if str(path).endswith(".py"):
        from .sofa import Simulation as _S, load_script
        if kw:
            raise TypeError("load(script.py) takes no options")
        root = load_script(path)
        _S.init(root)
        return root.simulation
    return Simulation(path, **kw)
__version__ = "0.1.0"

_LEVELS = {"error": 0, "warning": 1, "info": 2, "debug": 3}
_level = 2  # the last set_log_level (libpliant's default: info)


def _print_warnings(text):
    """Prints a load's warnings (Simulation.warnings) to stderr, as `pliant run`
    does, unless set_log_level("error")."""
    if text and _level >= 1:
        import sys
        print(text, file=sys.stderr)


def set_log_level(level):
    """How much libpliant writes to stderr: "error", "warning", "info" (the
    default) or "debug"; process-wide."""
    from ._core import set_log_level as _set
    if level not in _LEVELS:
        raise ValueError(f"log level '{level}': expected one of {', '.join(_LEVELS)}")
    _set(_LEVELS[level])
    global _level
    _level = _LEVELS[level]
