/* mesh.h - a plain mesh: vertices, tetrahedra and triangles.
 * Loaders fill it from files (format detected from content), generators
 * build it (bars, cloths, spheres), components read it through the
 * topology role. */
#ifndef PLIANT_MESH_H
#define PLIANT_MESH_H

#include "error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pl_mesh {
    int nverts;
    double *verts;   /* nverts x 3, row-major */
    int ntets;
    int *tets;       /* ntets x 4, 0-based, positively oriented after loading */
    int ntris;
    int *tris;       /* ntris x 3, 0-based */
} pl_mesh;

typedef struct pl_mesh_load_options {
    int drop_unused;   /* remove vertices no element uses (renumbering elements) */
    int keep_inverted; /* leave negatively oriented tetrahedra as they are */
} pl_mesh_load_options;

void pl_mesh_init(pl_mesh *m);
void pl_mesh_free(pl_mesh *m);
/* Deep copy; PL_OK or PL_EINTERNAL. */
int pl_mesh_copy(pl_mesh *dst, const pl_mesh *src);

/* Loads any supported format, detected from the content (not the extension):
 * legacy VTK (ASCII/BINARY, UNSTRUCTURED_GRID/POLYDATA), VTU (ascii/base64),
 * Gmsh .msh v1/v2/v4 ASCII, OBJ, STL ASCII/binary.  Warnings (skipped cell
 * kinds, fixed inverted tetrahedra) go to diag; an error names the file and
 * line.  opt may be NULL (defaults: fix inverted tets, keep unused vertices). */
int pl_mesh_load(const char *path, const pl_mesh_load_options *opt, pl_mesh *out, pl_diag *diag);

/* Checks indices are in range and coordinates finite; PL_EINPUT otherwise. */
int pl_mesh_validate(const pl_mesh *m, const char *file, pl_diag *diag);
/* Flips negatively oriented tetrahedra; returns how many were flipped. */
int pl_mesh_fix_inverted(pl_mesh *m);
/* Removes vertices no element uses; returns how many were removed (<0 on error). */
int pl_mesh_drop_unused(pl_mesh *m);
/* Applies scale, then rotation (degrees about x, y, z, in that order), then translation. */
void pl_mesh_transform(pl_mesh *m, const double scale[3], const double rotation_deg[3],
                       const double translation[3]);

/* The faces used by exactly one tetrahedron, oriented outward (counter-
 * clockwise seen from outside) when the tetrahedra are positively oriented:
 * *tris (ntris x 3, malloc'ed, the caller frees; NULL when empty).  PL_OK;
 * PL_EINPUT if an index is out of range or a face is shared by more than two
 * tetrahedra; PL_EINTERNAL if out of memory. */
int pl_mesh_boundary_triangles(const pl_mesh *m, int **tris, int *ntris);

#ifdef __cplusplus
}
#endif
#endif
