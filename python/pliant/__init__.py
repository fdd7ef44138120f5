"""Pliant from Python: load a scene, step it, read its state as NumPy arrays
(views of the simulation's own memory), change fields by path, drive it from
Python controllers (docs/python.md).

    import pliant
    sim = pliant.Simulation(pliant.scene("cable_finger_small.xml"))
    sim["finger/cable.value"] = 0.005
    sim.step(50)
    print(sim.time, sim.positions("finger/dofs")[-1])
"""
from ._core import Error, InputError
from .simulation import Simulation, Controller, scene

__all__ = ["Simulation", "Controller", "Error", "InputError", "scene"]
__version__ = "0.1.0"
