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
