"""Cost of a Python controller call from Pliant's C loop (issue 18 item 3).

Steps two scenes N steps at a time: an empty one (a MechanicalObject and no
solver: a step costs under a microsecond, so the cost of the calls shows) and
a tiny one (one tetrahedron, one solver iteration); without controllers, with
a controller whose two events do nothing, and with one that sets an input
field (begin) and reads the state (end).  Prints the median time of a step
over R runs and the cost of one call ((with - without) / 2: two events a step).

    python python/examples/bench_controller.py [--steps 2000] [--runs 9]
"""
import argparse
import os
import statistics
import time

import pliant

pliant.set_log_level("warning")
MESH = os.path.join(os.path.dirname(pliant.scene("cable_finger_small.xml")), "meshes",
                    "single_tetra.msh")
SCENE = f"""<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <RequiredPlugin name="hyperelastic"/><RequiredPlugin name="sparse_inverse"/>
  <LocalGlobalSolver name="solver" iterations="1" damping="0"/><SparseInverseSolver/>
  <Node name="body"><MeshLoader filename="{MESH}"/><MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1000"/><NeoHookean youngModulus="1e5" poissonRatio="0.3"/>
  </Node>
</Node>"""


EMPTY = """<Node name="root" dt="0.01"><RequiredPlugin name="hyperelastic"/>
  <Node name="body"><MechanicalObject name="dofs" position="0 0 0"/></Node></Node>"""


class Empty(pliant.Controller):
    pass


class Working(pliant.Controller):
    def __init__(self, sim):
        self.sim = sim

    def onAnimateBeginEvent(self, event):
        self.sim["solver.damping"] = 0.0

    def onAnimateEndEvent(self, event):
        self.y = self.sim.positions("body/dofs")[0, 1]


class Reading(pliant.Controller):
    def __init__(self, sim):
        self.sim = sim
        self.x = sim.positions("body/dofs")

    def onAnimateBeginEvent(self, event):
        self.dt = self.sim["root.dt"]

    def onAnimateEndEvent(self, event):
        self.y = self.x[0, 1]


def per_step(cases, steps, runs, scene):
    """Median seconds a step for each (label, make_controller) of cases; the
    cases take turns within each run, so that a busy machine slows all alike."""
    sims = []
    for _, make in cases:
        sim = pliant.Simulation(xml=scene, name="bench.xml")
        if make:
            sim.add_controller(make(sim))
        sim.step(100)                              # warm up
        sims.append(sim)
    times = [[] for _ in cases]
    for _ in range(runs):
        for k, sim in enumerate(sims):
            t0 = time.perf_counter()
            sim.step(steps)
            times[k].append((time.perf_counter() - t0) / steps)
    return [statistics.median(t) for t in times]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--runs", type=int, default=9)
    a = ap.parse_args()
    rows = []
    for scene, name, nsteps, work, work_label in (
            (EMPTY, "empty", 20 * a.steps, Reading, "get a field / read a view"),
            (SCENE, "one tetrahedron", a.steps, Working, "set an input / read the state")):
        cases = [("none", None), ("two empty events", lambda sim: Empty()), (work_label, work)]
        medians = per_step(cases, nsteps, a.runs, scene)
        for (label, make), t in zip(cases, medians):
            call = "" if make is None else f"{(t - medians[0]) / 2 * 1e6:.2f}"
            rows.append(f"| {name} | {label} | {t * 1e6:.2f} | {call} |")
    print("| scene | controller | step [us] | per call [us] |")
    print("|---|---|---|---|")
    print("\n".join(rows))
    print(f"(medians of {a.runs} runs of {a.steps} steps, {20 * a.steps} for the empty scene)")


if __name__ == "__main__":
    main()
