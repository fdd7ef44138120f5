"""SOFA's vocabulary as libpliant reads it: the one table of the XML loader
(pl_sofa_write_vocabulary, TSV), not a copy."""
import difflib
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

    def refusal(self, sofa_type):
        """The table's reason when SOFA component sofa_type is refused, else None."""
        entry = self.components.get(sofa_type)
        if entry and entry[0] == "refused":
            return entry[3]
        return None

    def closest(self, name):
        """The SOFA names of the table closest to name (for did-you-mean)."""
        known = [n for n, e in self.components.items() if e[0] != "refused"]
        return difflib.get_close_matches(name, known, n=1, cutoff=0.6)


@functools.lru_cache(maxsize=1)
def vocabulary():
    return _Vocabulary(_core.sofa_vocabulary())
