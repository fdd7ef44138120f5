#!/usr/bin/env python3
"""Writes the raptor meshes of the paper's three Table 3 sizes with gmsh.

    python3 tests/gripper/make_raptor_meshes.py            # the three meshes
    python3 tests/gripper/make_raptor_meshes.py --search   # find the sizes again

Needs gmsh on the PATH (Debian: apt-get install gmsh; these files were made
with gmsh 4.8.4 of Debian 12).  Only this script needs it: the meshes are
committed, the build never runs gmsh.

How: the boundary surface of SOFA's raptorTetra_19409.vtu (10416 triangles,
5207 vertices, oriented outward) is written as a Gmsh surface mesh and kept
as it is; gmsh fills the volume (Delaunay, one thread, default optimisation)
with the element size MeshSizeMax = L everywhere inside (MeshSizeExtendFrom
Boundary off, so the interior does not inherit the surface's spacing).  L
sets the vertex count; the values below hit the paper's raptor-only counts
(its memory table: 10.0k, 15.0k, 20.1k vertices; Table 3 adds the two fingers'
2 x 158 vertices: 10.3k, 15.3k, 20.4k).  The same surface at every size keeps
the contact between fingers and raptor alike (as in the paper, whose contact
counts stay at 0.13-0.14k at every size).  gmsh writes legacy VTK (binary,
tetrahedra only, the source mesh's units); this script stores the same
numbers as a zlib-compressed VTU (Float64 points, Int32 cells: half the bytes).
"""
import base64
import os
import re
import struct
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zlib

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MESHES = os.path.join(ROOT, "scenes", "meshes")
SOURCE = "raptorTetra_19409.vtu"
# name -> (target raptor vertices, MeshSizeMax in mesh units, found by --search)
SIZES = {
    "raptor_10k.vtu": (10000, 0.1382),
    "raptor_15k.vtu": (15000, 0.1114),
    "raptor_20k.vtu": (20100, 0.0983),
}


def read_vtu(path):
    """Points and tetrahedra of an ASCII VTU file."""
    piece = ET.parse(path).getroot().find(".//Piece")
    xyz = [float(x) for x in piece.find("Points/DataArray").text.split()]
    cells = {a.get("Name"): [int(x) for x in a.text.split()]
             for a in piece.find("Cells").findall("DataArray")}
    if set(cells["types"]) != {10}:
        raise SystemExit("%s: cells other than tetrahedra" % path)
    conn = cells["connectivity"]
    pts = [tuple(xyz[i:i + 3]) for i in range(0, len(xyz), 3)]
    return pts, [tuple(conn[o - 4:o]) for o in cells["offsets"]]


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def boundary(pts, tets):
    """Faces that belong to one tetrahedron, each turned to face outward."""
    owner = {}
    for t in tets:
        for k in range(4):
            f = t[:k] + t[k + 1:]
            key = tuple(sorted(f))
            if key in owner:
                owner[key] = None
            else:
                owner[key] = (f, t[k])
    out = []
    for val in owner.values():
        if val is None:
            continue
        (a, b, c), opp = val
        n = cross(sub(pts[b], pts[a]), sub(pts[c], pts[a]))
        out.append((a, b, c) if dot(n, sub(pts[opp], pts[a])) < 0 else (a, c, b))
    return out


def write_surface(path, pts, tris):
    """A Gmsh 2.2 ASCII surface mesh (one discrete surface, tag 1)."""
    used = sorted({v for t in tris for v in t})
    idx = {v: k + 1 for k, v in enumerate(used)}
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(used))
        for v in used:
            f.write("%d %r %r %r\n" % ((idx[v],) + pts[v]))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tris))
        for k, (a, b, c) in enumerate(tris):
            f.write("%d 2 2 1 1 %d %d %d\n" % (k + 1, idx[a], idx[b], idx[c]))
        f.write("$EndElements\n")


GEO = """Merge "{surface}";
Surface Loop(1) = {{1}};
Volume(1) = {{1}};
Physical Volume(1) = {{1}};
Mesh.MeshSizeMax = {size};
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
General.NumThreads = 1;
Mesh.Binary = 1;
Mesh 3;
Save "{out}";
"""


def mesh(surface, size, out, tmp):
    """Runs gmsh; returns the points and tetrahedra (flat lists)."""
    geo = os.path.join(tmp, "raptor.geo")
    with open(geo, "w") as f:
        f.write(GEO.format(surface=surface, size=size, out=out))
    log = subprocess.run(["gmsh", "-nopopup", "-0", geo], capture_output=True, text=True)
    if log.returncode != 0 or not os.path.exists(out):
        raise SystemExit("gmsh failed:\n" + log.stdout[-2000:] + log.stderr[-2000:])
    return read_gmsh_vtk(out)


def read_gmsh_vtk(path):
    """Points (big-endian doubles) and tetrahedra of gmsh's binary legacy VTK
    (which also holds the surface triangles: dropped)."""
    with open(path, "rb") as f:
        data = f.read()
    m = re.search(rb"POINTS (\d+) double\n", data)
    n = int(m.group(1))
    xyz = struct.unpack(">%dd" % (3 * n), data[m.end():m.end() + 24 * n])
    m = re.search(rb"CELLS (\d+) (\d+)\n", data)
    size = int(m.group(2))
    ints = struct.unpack(">%di" % size, data[m.end():m.end() + 4 * size])
    tets, k = [], 0
    while k < size:
        if ints[k] == 4:
            tets.extend(ints[k + 1:k + 5])
        elif ints[k] != 3:
            raise SystemExit("%s: a cell of %d vertices" % (path, ints[k]))
        k += ints[k] + 1
    return xyz, tets


def data_array(kind, name, ncomp, fmt, values):
    """One zlib-compressed DataArray (one block, UInt32 header), base64."""
    raw = struct.pack("<%d%s" % (len(values), fmt), *values)
    packed = zlib.compress(raw, 9)
    head = struct.pack("<4I", 1, len(raw), len(raw), len(packed))
    text = base64.b64encode(head + packed).decode("ascii")
    return ('        <DataArray type="%s" Name="%s" NumberOfComponents="%d" format="binary">\n'
            "          %s\n        </DataArray>\n" % (kind, name, ncomp, text))


def write_vtu(path, xyz, tets):
    n, c = len(xyz) // 3, len(tets) // 4
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" '
                'byte_order="LittleEndian" header_type="UInt32" compressor="vtkZLibDataCompressor">\n'
                '  <UnstructuredGrid>\n    <Piece NumberOfPoints="%d" NumberOfCells="%d">\n'
                "      <Points>\n" % (n, c))
        f.write(data_array("Float64", "Points", 3, "d", xyz))
        f.write("      </Points>\n      <Cells>\n")
        f.write(data_array("Int32", "connectivity", 1, "i", tets))
        f.write(data_array("Int32", "offsets", 1, "i", range(4, 4 * c + 1, 4)))
        f.write(data_array("UInt8", "types", 1, "B", [10] * c))
        f.write("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n")


def search(surface, target, tmp, nsurf):
    """The interior vertex count goes about as 1 / size^3: a few secant steps."""
    size, out = 0.2, os.path.join(tmp, "try.vtk")
    for _ in range(8):
        xyz, tet = mesh(surface, size, out, tmp)
        n, c = len(xyz) // 3, len(tet) // 4
        print("  size %.4f: %d vertices, %d tetrahedra" % (size, n, c))
        if abs(n - target) <= 0.003 * target:
            break
        size = round(size * ((n - nsurf) / (target - nsurf)) ** (1.0 / 3.0), 4)
    return size


def main():
    pts, tets = read_vtu(os.path.join(MESHES, SOURCE))
    tris = boundary(pts, tets)
    print("%s: %d vertices, %d tetrahedra, %d boundary triangles" % (SOURCE, len(pts), len(tets), len(tris)))
    with tempfile.TemporaryDirectory() as tmp:
        surface = os.path.join(tmp, "raptor_surface.msh")
        write_surface(surface, pts, tris)
        for name, (target, size) in SIZES.items():
            if "--search" in sys.argv[1:]:
                size = search(surface, target, tmp, len({v for t in tris for v in t}))
            out = os.path.join(tmp, "raptor.vtk")
            xyz, tet = mesh(surface, size, out, tmp)
            n, c = len(xyz) // 3, len(tet) // 4
            write_vtu(os.path.join(MESHES, name), xyz, tet)
            print("%s: MeshSizeMax %.4f, %d vertices, %d tetrahedra (target %d vertices)" % (
                name, size, n, c, target))


if __name__ == "__main__":
    main()
