#!/usr/bin/env python3
"""tests/bench/explicit_work.py PLIANT [-r RUNS] [-n STEPS] [-w W1,W2,...] SCENE.xml...

The CPU's explicit-W budget (NonSmoothNewtonContactSolver maxExplicitWork,
delassus="auto") against the time of the contact phases: each scene runs
RUNS times per value (interleaved, so that a slow spell of a shared machine
hits every value alike) on one thread with --device cpu and --timings, and a
table prints, per scene and value, the medians over the runs of the sums
over the frames of Frame, Schur (W or its diagonal) and Constraint solve (the
CR iterations), the frames whose W was explicit, the largest frame over the
median frame, and whether the exporters' files at the end are those of the
first value (same = bitwise).  "mf" is delassus="matrix-free" in every frame.
Python 3, standard library only."""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile


def run(pliant, scene, steps, value, out):
    setting = ("contact.delassus=matrix-free" if value == "mf"
               else "contact.maxExplicitWork=" + value)
    tj = os.path.join(out, "t.json")
    vtk = os.path.join(out, "vtk")
    shutil.rmtree(vtk, ignore_errors=True)
    cmd = [pliant, "run", scene, "-n", str(steps), "--device", "cpu", "--set", setting,
           "--timings", tj, "-o", vtk, "--export-every", str(steps), "-q"]
    env = dict(os.environ, OMP_NUM_THREADS="1", PLIANT_DEVICE="cpu")
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    fr = json.load(open(tj))["frames"]
    state = b""  # the exporters' files of the last step
    for name in sorted(os.listdir(vtk)):
        if not name.endswith(".pvd"):
            with open(os.path.join(vtk, name), "rb") as f:
                state += f.read()
    frame = fr["Frame"]
    return {
        "frame": sum(frame), "schur": sum(fr.get("Schur", [0])),
        "solve": sum(fr.get("Constraint solve", [0])),
        "explicit": sum(1 for w in fr.get("W memory [MB]", []) if w > 0),
        "spike": max(frame) / statistics.median(frame), "state": state,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[1])
    ap.add_argument("pliant")
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("-r", "--runs", type=int, default=3)
    ap.add_argument("-n", "--steps", type=int, default=150)
    ap.add_argument("-w", "--values", default="2,0.3")
    a = ap.parse_args()
    values = a.values.split(",")
    print("| scene | maxExplicitWork | Frame [ms] | Schur [ms] | Constraint solve [ms] "
          "| explicit frames | max / median frame | end positions |")
    print("|---|--:|--:|--:|--:|--:|--:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in a.scenes:
            res = {v: [] for v in values}
            for _ in range(a.runs):
                for v in values:
                    res[v].append(run(a.pliant, scene, a.steps, v, tmp))
            ref = res[values[0]][0]["state"]
            for v in values:
                r = res[v]
                med = {k: statistics.median(x[k] for x in r) for k in
                       ("frame", "schur", "solve", "spike")}
                same = "same" if r[0]["state"] == ref else "differ"
                print("| %s | %s | %.0f | %.0f | %.0f | %d | %.2f | %s |" % (
                    os.path.basename(scene), v, med["frame"], med["schur"], med["solve"],
                    r[0]["explicit"], med["spike"], same))
                sys.stdout.flush()


if __name__ == "__main__":
    main()
