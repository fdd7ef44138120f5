#!/usr/bin/env python3
"""tests/bench/spikes_median.py OUT.json RUN1.json RUN2.json ... - one timings
file whose per-frame table ("frames") holds, for every phase and frame, the
median over repeated runs of one scene (same steps, same settings).  On a
shared or noisy machine a single run's frame times carry other processes'
pauses; table3_spikes.py on the medians sees the scene's own spikes.  The
statistics (contacts, rows) must agree across the runs: they are copied from
the first.  Python 3, standard library only."""
import json
import statistics
import sys


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    runs = [json.load(open(p)) for p in sys.argv[2:]]
    out = runs[0]
    fr = out["frames"]
    for k, v in fr.items():
        if not isinstance(v, list):
            continue
        cols = [r["frames"][k] for r in runs]
        if any(len(c) != len(v) for c in cols):
            sys.exit("%s: the runs have different frame counts" % k)
        if "max" in k or "memory" in k:
            if any(c != v for c in cols):
                sys.exit("%s differs between the runs: not the same scene and settings" % k)
            continue
        fr[k] = [statistics.median(c[i] for c in cols) for i in range(len(v))]
    json.dump(out, open(sys.argv[1], "w"))


if __name__ == "__main__":
    main()
