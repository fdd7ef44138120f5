"""SOFA's vocabulary as libpliant reads it: the one table of the XML loader
(pl_sofa_write_vocabulary, TSV), not a copy.  pliant.sofa reads its
attribute renames, to find the Pliant field of a SOFA attribute after init;
which components exist, are refused or are moved is the loader's business."""
import functools

from .. import _core


class _Vocabulary:
    def __init__(self, tsv):
        self.components = {}   # SOFA name -> (kind, pliant name, plugin, note)
        self.attributes = {}   # (component or "*", attribute) -> (kind, pliant field, note)
        for line in tsv.splitlines():
            cells = line.split("\t")
            if cells[0] == "component" and len(cells) >= 6:
                self.components[cells[1]] = tuple(cells[2:6])
            elif cells[0] == "attribute" and len(cells) >= 6:
                self.attributes[(cells[1], cells[2])] = tuple(cells[3:6])


@functools.lru_cache(maxsize=1)
def vocabulary():
    return _Vocabulary(_core.sofa_vocabulary())
