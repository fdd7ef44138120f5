#!/usr/bin/env python3
"""tests/bench/frame_fit.py RUN.json ... - a line per timings file
(`pliant run SCENE -n N --timings RUN.json`): the median Frame, Schur and
Detection [ms], the local-global iterations over the run, and, when the
run records them a frame ("iterations"), the least-squares line
Frame = a + b iterations over the frames after the first five: b is what
an iteration costs, a what a frame costs besides its iterations (uploads,
launches, read-backs, host phases).  The median alone mixes the two; a
change that shortens the iteration moves b, one that removes host work or
waits moves a.  Python 3, standard library only."""
import json
import statistics
import sys

SKIP = 5  # the first frames: graph captures, first allocations


def fit(its, frames):
    """(a, b) of frame = a + b its, or None when the counts do not vary."""
    mx, my = statistics.mean(its), statistics.mean(frames)
    sxx = sum((x - mx) ** 2 for x in its)
    if sxx == 0:
        return None
    b = sum((x - mx) * (y - my) for x, y in zip(its, frames)) / sxx
    return my - b * mx, b


def line(path):
    d = json.load(open(path))
    fr, se = d["frames"], d.get("series", {})

    def med(k):
        v = fr.get(k)
        return statistics.median(v) if isinstance(v, list) and v else 0.0

    its = se.get("iterations", [])
    out = "%s: frame %.3f ms, Schur %.3f, Detection %.3f, iterations %d" % (
        path, med("Frame"), med("Schur"), med("Detection"), sum(its))
    frames = fr.get("Frame", [])
    if len(its) == len(frames) > SKIP + 2:
        ab = fit(its[SKIP:], frames[SKIP:])
        if ab:
            out += ", fit %.4f ms + %.4f ms an iteration (median %g iterations)" % (
                ab[0], ab[1], statistics.median(its))
    return out


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for p in sys.argv[1:]:
        print(line(p))


if __name__ == "__main__":
    main()
