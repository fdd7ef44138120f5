#!/usr/bin/env python3
"""Writes scenes/grabbing_raptor.xml, scenes/grabbing_raptor_small.xml and the
paper's three sizes scenes/grabbing_raptor_10k.xml, _15k.xml, _20k.xml (the
gmsh meshes of make_raptor_meshes.py; physics and timeline of the full scene).

Run from anywhere (pure Python standard library):
    python3 tests/gripper/make_grabbing_raptor.py

Why a generator: the fingers' bases follow the gripper's rigid motion (lift,
turn, move, lower, retreat).  PrescribedMotion has one constant rotation and
velocity (positions are computed from t, several on the same vertices
overwrite each other), so the bases are driven by PositionTarget keyframes
that list every base vertex at every key time (the turn sampled every 7.5
degrees).  This script computes those positions and the cable points from the
SoftRobots finger mesh, so the scenes can be regenerated after a change of the
parameters below.  SI units throughout.
"""
import math
import os
import struct

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MESHES = os.path.join(ROOT, "scenes", "meshes")

# ---- geometry ----------------------------------------------------------------
RAPTOR_SCALE = 0.006        # mesh units -> m: the raptor is 25 x 43 x 96 mm
# The raptor lies on its side: MeshLoader rotation 0 0 90 maps mesh (x, y, z)
# to (-y, x, z).  Its torso between the legs and the tail (mesh y in [2.1, 5.5],
# z in [1, 3.5]; no leg below it there) is centred on the gripper's axis x = z = 0.
RAPTOR_TORSO_Y = 3.8        # world x = (3.8 - mesh y) * scale
RAPTOR_TORSO_Z = 2.25       # world z = (mesh z - 2.25) * scale
RAPTOR_HALF_X = 2.114       # half width of the mesh along x (its height once lying) [mesh units]
RAPTOR_LIFTOFF = 0.0003     # starts this far above the floor [m]
GAP = 0.036                 # distance between the open fingers' contact faces [m]
TIP_Y = 0.003               # height of the finger tips above the floor [m]
FINGER_LEN = 0.1033664      # finger length along its axis [m]
# ---- actuation and motion ----------------------------------------------------
CABLE_PULL = 0.013          # cable shortening when closed [m]: a firm squeeze of the 20 mm
                            # thick torso (7 mm closed the fingers without lifting it)
LIFT = 0.05                 # [m]
TURN_DEG = 90.0             # about the vertical axis [deg]
MOVE = (0.06, 0.0, 0.0)     # horizontal move [m]
RETREAT = 0.04              # the open fingers rise after the release [m]
BASE_STIFFNESS = 1e4        # PositionTarget spring per base vertex [N/m]
TURN_KEYS = 12              # keyframes of the turn (7.5 degrees each)

# cable points of SoftRobots' CableGripper finger (cable.json) [mm, finger frame]
CABLE_MM = [(-17.5, 12.5, 2.5), (-32.5, 12.5, 2.5), (-47.5, 12.5, 2.5), (-62.5, 12.5, 2.5),
            (-77.5, 12.5, 2.5), (-83.5, 12.5, 4.5), (-85.5, 12.5, 6.5), (-85.5, 12.5, 8.5),
            (-83.5, 12.5, 10.5), (-77.5, 12.5, 12.5), (-62.5, 12.5, 12.5), (-47.5, 12.5, 12.5),
            (-32.5, 12.5, 12.5), (-17.5, 12.5, 12.5)]

# phase end times [s]
FULL_T = {"settle": 0.2, "close": 0.7, "lift": 1.2, "turn": 1.7, "move": 2.2, "lower": 2.7,
          "open": 3.0, "retreat": 3.3, "end": 4.3}
SMALL_T = {"settle": 0.1, "close": 0.45, "lift": 0.85, "turn": 1.25, "move": 1.65, "lower": 2.05,
           "open": 2.25, "retreat": 2.45, "end": 3.45}


def finger_points():
    """Vertices of finger.vtk (legacy VTK, binary big-endian) [mm]."""
    with open(os.path.join(MESHES, "finger.vtk"), "rb") as f:
        b = f.read()
    i = b.index(b"POINTS")
    head = b[i:b.index(b"\n", i)].split()
    n, kind = int(head[1]), head[2]
    start = b.index(b"\n", i) + 1
    fmt_ = ">%d%s" % (3 * n, "d" if kind == b"double" else "f")
    v = struct.unpack(fmt_, b[start:start + struct.calcsize(fmt_)])
    return [v[k:k + 3] for k in range(0, 3 * n, 3)]


def rot_deg(deg):
    """R = Rz Ry Rx (MeshLoader's rotation convention)."""
    def axis(k, a):
        c, s = math.cos(a), math.sin(a)
        if k == 0:
            return [[1, 0, 0], [0, c, -s], [0, s, c]]
        if k == 1:
            return [[c, 0, s], [0, 1, 0], [-s, 0, c]]
        return [[c, -s, 0], [s, c, 0], [0, 0, 1]]

    def mul(a, b):
        return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    rx, ry, rz = (axis(k, math.radians(deg[k])) for k in range(3))
    return mul(rz, mul(ry, rx))


def apply(R, t, p, scale):
    return tuple(sum(R[i][k] * p[k] * scale for k in range(3)) + t[i] for i in range(3))


def fmt(x):
    s = "%.6g" % (0.0 if abs(x) < 1e-12 else x)
    return "0" if s == "-0" else s


def vec(v):
    return " ".join(fmt(x) for x in v)


class Finger:
    """A finger hanging tip down, its contact side (+y of the mesh, the cable
    side) facing the gripper's axis from side `side` (+1: at +x, -1: at -x)."""

    def __init__(self, name, side):
        self.name = name
        self.rotation = (0.0, 0.0, 90.0) if side > 0 else (180.0, 0.0, 90.0)
        self.translation = (side * (GAP / 2 + 0.015), TIP_Y + FINGER_LEN,
                            -0.0075 if side > 0 else 0.0075)
        R = rot_deg(self.rotation)
        pts = finger_points()
        # SoftRobots fixes x in [-15, 0] mm of the finger (its base block)
        self.base = [i for i, p in enumerate(pts) if p[0] >= -15.0]
        self.base_rest = [apply(R, self.translation, pts[i], 0.001) for i in self.base]
        self.cable = [apply(R, self.translation, p, 0.001) for p in CABLE_MM]


def gripper_pose(t, T):
    """Angle [rad] about the vertical axis x = z = 0 and translation [m] at t."""
    def ramp(a, b):
        return min(max((t - a) / (b - a), 0.0), 1.0)
    up = LIFT * (ramp(T["close"], T["lift"]) - ramp(T["move"], T["lower"]))
    up += RETREAT * ramp(T["open"], T["retreat"])
    m = ramp(T["turn"], T["move"])
    return math.radians(TURN_DEG) * ramp(T["lift"], T["turn"]), (MOVE[0] * m, up, MOVE[2] * m)


def base_key_times(T):
    times = [0.0, T["close"], T["lift"]]
    times += [T["lift"] + (T["turn"] - T["lift"]) * k / TURN_KEYS for k in range(1, TURN_KEYS + 1)]
    return times + [T["move"], T["lower"], T["open"], T["retreat"]]


def base_values(f, times, T):
    rows = []
    for t in times:
        a, tr = gripper_pose(t, T)
        c, s = math.cos(a), math.sin(a)
        # rotation about +y: x' = c x + s z, z' = -s x + c z
        rows.append("  ".join("%s %s %s" % (fmt(c * x + s * z + tr[0]), fmt(y + tr[1]),
                                            fmt(-s * x + c * z + tr[2]))
                              for x, y, z in f.base_rest))
    return rows


def finger_xml(f, T, every, prefix):
    times = base_key_times(T)
    values = "\n                ".join(base_values(f, times, T))
    cable = "  ".join(vec(p) for p in f.cable)
    ct = [0.0, T["settle"], T["close"], T["lower"], T["open"]]
    cv = [0.0, 0.0, CABLE_PULL, CABLE_PULL, 0.0]
    return f"""  <Node name="{f.name}">
    <MeshLoader name="mesh" filename="meshes/finger.vtk" scale3d="0.001 0.001 0.001"
                rotation="{vec(f.rotation)}" translation="{vec(f.translation)}"/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1070"/>
    <NeoHookean name="material" youngModulus="5e5" poissonRatio="0.45"/>
    <CableConstraint name="cable" hasPullPoint="0" valueType="displacement" minForce="0"
      position="{cable}"/>
    <Keyframes name="pull" target="@cable.value" times="{vec(ct)}" values="{vec(cv)}"/>
    <PositionTarget name="base" stiffness="{fmt(BASE_STIFFNESS)}" motion="keyframes"
      indices="{' '.join(str(i) for i in f.base)}"
      times="{vec(times)}"
      values="{values}"/>
    <MappedSurfaceCollisionModel name="collision" filename="meshes/finger.stl" scale3d="0.001 0.001 0.001"
                rotation="{vec(f.rotation)}" translation="{vec(f.translation)}" group="1"/>
    <VTKExporter name="vtk" filename="{prefix}_{f.name}" every="{every}"/>
  </Node>
"""


# the paper's Table 3 sizes: raptor + 2 x 158 finger vertices = 10.3k, 15.3k, 20.4k
SIZED = {"10k": ("raptor_10k.vtu", 10012, 44511, "10.3k / 34.7k"),
         "15k": ("raptor_15k.vtu", 15005, 75792, "15.3k / 55.2k"),
         "20k": ("raptor_20k.vtu", 20149, 107875, "20.4k / 77.8k")}


def header(small, T, dt, iters, nsteps, prefix, size=None):
    s = RAPTOR_SCALE
    if size:
        mesh, nv, nt, paper = SIZED[size]
        what = ("The raptor: %s (tests/gripper/make_raptor_meshes.py: gmsh fills the surface of\n"
                "     raptorTetra_19409.vtu): %d vertices, %d tetrahedra; with the fingers %d vertices\n"
                "     (the paper's Table 3: %s with the fingers).  %d local-global iterations."
                % (mesh, nv, nt, nv + 316, paper, iters))
    elif small:
        what = ("Small variant (the test's): the coarse raptor (raptorTetra_8418.vtu, 2993 vertices, "
                "8418 tetrahedra),\n     a shorter timeline and %d local-global iterations." % iters)
    else:
        what = ("The raptor: raptorTetra_8418.vtu refined by one 1-to-8 subdivision (subdivide=\"1\"): "
                "17277 vertices,\n     67344 tetrahedra (the paper: 15.3k / 55.2k).  %d local-global "
                "iterations." % iters)
    return f"""<?xml version="1.0"?>
<!-- Grabbing Raptor (the paper's Figure "Grabbing Raptor" and Table 3 row), SI units.
     GENERATED by tests/gripper/make_grabbing_raptor.py: edit the script's parameters and rerun it.
     {what}
     Raptor: Neo-Hookean, rho 10 kg/m^3, E 2e4 Pa, nu 0.1 (Table 3), the SOFA mesh scaled by {fmt(s)}
     (25 x 43 x 96 mm, 59 mg), lying on its side on the floor (a PlaneObstacle, y = 0).  Nothing holds it
     but contact and friction (mu 1 with the fingers and the floor).
     Gripper: two SoftRobots CableGripper fingers (finger.vtk, millimetres: scale3d 0.001; silicone
     E 0.5 MPa, nu 0.45, rho 1070) hanging tip down on both sides of the raptor's torso, 36 mm apart,
     their cable side (finger.stl, mapped into their tetrahedra, the contact surface) facing it.  Each
     cable (cable.json, no pull point: the loop's two ends, both in the base) shortens by
     {fmt(1000 * CABLE_PULL)} mm to close the finger.  The base block of each finger (x in [-15, 0] mm, 22 vertices)
     follows the gripper's rigid motion through PositionTarget keyframes ({fmt(BASE_STIFFNESS)} N/m per vertex:
     PrescribedMotion has no sequence of motions).
     Timeline: 0-{fmt(T['settle'])} s the raptor settles; {fmt(T['settle'])}-{fmt(T['close'])} s the cables pull (fingers close);
     {fmt(T['close'])}-{fmt(T['lift'])} s lift {fmt(1000 * LIFT)} mm; {fmt(T['lift'])}-{fmt(T['turn'])} s turn {fmt(TURN_DEG)} deg about the vertical axis;
     {fmt(T['turn'])}-{fmt(T['move'])} s move {fmt(1000 * MOVE[0])} mm along x; {fmt(T['move'])}-{fmt(T['lower'])} s lower {fmt(1000 * LIFT)} mm; {fmt(T['lower'])}-{fmt(T['open'])} s the
     cables release; {fmt(T['open'])}-{fmt(T['retreat'])} s the fingers rise {fmt(1000 * RETREAT)} mm; then rest until {fmt(T['end'])} s.
     Time step {fmt(dt)} s (at 0.005 and 0.01 s the raptor is lifted but slips out during the turn or
     the move: tests/gripper/README.md).  Contact: Fischer-Burmeister NCP, 10 CR iterations,
     CollisionPipeline alarm 1 mm / contact 0.3 mm (finger-raptor), floor alarm 0.5 mm / contact 0.2 mm.
     Run: pliant run scenes/{prefix}.xml -n {nsteps} -->
"""


def scene(small, T=None, dt=0.0025, iters=None, size=None):
    T = T or (SMALL_T if small else FULL_T)
    iters = iters or 10
    prefix = "grabbing_raptor_small" if small else "grabbing_raptor"
    prefix += "_" + size if size else ""
    every = int(round(0.1 / dt)) if small else int(round(0.05 / dt))
    nsteps = int(round(T["end"] / dt))
    s = RAPTOR_SCALE
    rt = (RAPTOR_TORSO_Y * s, RAPTOR_HALF_X * s + RAPTOR_LIFTOFF, -RAPTOR_TORSO_Z * s)
    sub = "" if small or size else ' subdivide="1"'
    mesh = SIZED[size][0] if size else "raptorTetra_8418.vtu"
    body = f"""<Node name="root" dt="{fmt(dt)}" gravity="0 -9.81 0">
  <RequiredPlugin name="hyperelastic"/>
  <RequiredPlugin name="sparse_inverse"/>
  <RequiredPlugin name="ncp_contact"/>
  <RequiredPlugin name="cable"/>
  <RequiredPlugin name="collision"/>
  <LocalGlobalSolver name="solver" iterations="{iters}"/>
  <SparseInverseSolver name="global"/>
  <NonSmoothNewtonContactSolver name="contact" ncp="fischer-burmeister" crIterations="10"/>
  <CollisionPipeline name="pipeline" alarmDistance="0.001" contactDistance="0.0003" mu="1"/>
  <PlaneObstacle name="floor" point="0 0 0" normal="0 1 0" mu="1" alarmDistance="0.0005"
                 contactDistance="0.0002"/>
  <Node name="raptor">
    <MeshLoader name="mesh" filename="meshes/{mesh}"{sub} onlyAttachedPoints="1"
                scale3d="{vec((s, s, s))}" rotation="0 0 90" translation="{vec(rt)}"/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass name="mass" massDensity="10"/>
    <NeoHookean name="material" youngModulus="2e4" poissonRatio="0.1"/>
    <SurfaceCollisionModel name="surface"/>
    <VTKExporter name="vtk" filename="{prefix}_raptor" every="{every}"/>
  </Node>
"""
    for f in (Finger("finger1", +1), Finger("finger2", -1)):
        body += finger_xml(f, T, every, prefix)
    return header(small, T, dt, iters, nsteps, prefix, size) + body + "</Node>\n"


def main():
    for small in (True, False):
        name = "grabbing_raptor_small.xml" if small else "grabbing_raptor.xml"
        with open(os.path.join(ROOT, "scenes", name), "w") as f:
            f.write(scene(small))
    for size in SIZED:
        with open(os.path.join(ROOT, "scenes", "grabbing_raptor_%s.xml" % size), "w") as f:
            f.write(scene(False, size=size))


if __name__ == "__main__":
    main()
