"""pliant.sofa: the part of SofaPython3's API that SoftRobots' scripts use
(docs/python.md has the table of what is supported).

A script's createScene(rootNode) builds a tree of Node and Object; at
Simulation.init the tree becomes a SOFA scene (.scn XML) that libpliant loads
through its SOFA vocabulary table (core/src/sofa_vocab.c: the same table and
lowering as `pliant run scene.scn`); from then on Data values read and write
the running simulation.  Write `import pliant.sofa as Sofa` in your own code;
`pliant run script.py` makes it importable as `Sofa` for unmodified scripts.
"""
from . import Core, Simulation, constants  # noqa: F401
from .Core import Controller, Node, UnsupportedError  # noqa: F401
from .vocabulary import vocabulary  # noqa: F401


def install_as_sofa():
    """Makes this module importable as Sofa (Sofa.Core, Sofa.Simulation,
    Sofa.constants), as inside `pliant run script.py`."""
    import sys
    sys.modules.setdefault("Sofa", sys.modules[__name__])
    sys.modules.setdefault("Sofa.Core", Core)
    sys.modules.setdefault("Sofa.Simulation", Simulation)
    sys.modules.setdefault("Sofa.constants", constants)


def load_script(path):
    """Runs a createScene script as runSofa would (its folder on sys.path,
    __file__ set, Sofa importable) and returns its root Node, built: the
    simulation is root.simulation.  Exceptions of the script propagate."""
    import os
    import runpy
    import sys
    script = os.path.abspath(os.fspath(path))
    install_as_sofa()
    folder = os.path.dirname(script)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    module = runpy.run_path(script, run_name=os.path.splitext(os.path.basename(script))[0])
    create = module.get("createScene")
    if create is None:
        raise ValueError(f"{path} defines no createScene(rootNode)")
    root = Core.Node("root")
    create(root)
    return root
