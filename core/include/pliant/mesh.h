/* mesh.h - a plain mesh: vertices, tetrahedra and triangles.
 * Loaders fill it from files (format detected from content), generators
 * build it (bars, cloths, spheres), components read it through the
 * topology role. */
#ifndef PLIANT_MESH_H
#define PLIANT_MESH_H

#include <stddef.h>

#include "api.h"
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

/* A format named in advance (PL_MESH_AUTO: recognised from the content). */
typedef enum pl_mesh_format {
    PL_MESH_AUTO = 0,
    PL_MESH_VTK_LEGACY,
    PL_MESH_VTU,
    PL_MESH_GMSH,
    PL_MESH_OBJ,
    PL_MESH_STL_ASCII,
    PL_MESH_STL_BINARY
} pl_mesh_format;

typedef struct pl_mesh_load_options {
    int drop_unused;   /* remove vertices no element uses (renumbering elements) */
    int keep_inverted; /* leave negatively oriented tetrahedra as they are */
    pl_mesh_format format; /* PL_MESH_AUTO (0): detect */
} pl_mesh_load_options;

PL_API void pl_mesh_init(pl_mesh *m);
PL_API void pl_mesh_free(pl_mesh *m);
/* Deep copy; PL_OK or PL_EINTERNAL. */
PL_API int pl_mesh_copy(pl_mesh *dst, const pl_mesh *src);

/* Loads any supported format, detected from the content (not the extension):
 * legacy VTK (ASCII/BINARY, UNSTRUCTURED_GRID/POLYDATA), VTU (ascii/base64),
 * Gmsh .msh v1/v2/v4 ASCII, OBJ, STL ASCII/binary.  Warnings (skipped cell
 * kinds, fixed inverted tetrahedra) go to diag; an error names the file and
 * line.  opt may be NULL (defaults: fix inverted tets, keep unused vertices). */
PL_API int pl_mesh_load(const char *path, const pl_mesh_load_options *opt, pl_mesh *out,
                        pl_diag *diag);
/* The same from size bytes in memory (a copy is made); `name` stands for
 * the file name in messages. */
PL_API int pl_mesh_load_buffer(const char *name, const void *buf, size_t size,
                               const pl_mesh_load_options *opt, pl_mesh *out,
                               pl_diag *diag);

/* Checks indices are in range and coordinates finite; PL_EINPUT otherwise. */
PL_API int pl_mesh_validate(const pl_mesh *m, const char *file, pl_diag *diag);
/* Flips negatively oriented tetrahedra; returns how many were flipped. */
PL_API int pl_mesh_fix_inverted(pl_mesh *m);
/* Removes vertices no element uses; returns how many were removed (<0 on error). */
PL_API int pl_mesh_drop_unused(pl_mesh *m);
/* Applies scale, then rotation (degrees about x, y, z, in that order), then translation. */
PL_API void pl_mesh_transform(pl_mesh *m, const double scale[3], const double rotation_deg[3],
                              const double translation[3]);

#if PL_ABI_TARGET_MINOR >= 1
/* The boundary surface of a tetrahedral mesh: the faces used by exactly one
 * tetrahedron, oriented outward (counter-clockwise seen from outside) when
 * the tetrahedra are positively oriented.  *tris (ntris x 3, malloc'ed,
 * caller frees; NULL when empty).  PL_OK; PL_EINPUT if an index is out of
 * range or a face is shared by more than two tetrahedra (not a manifold);
 * PL_EINTERNAL if out of memory.  Since ABI 5.1 (4.1 before 5.0). */
PL_API int pl_mesh_boundary_triangles(const pl_mesh *m, int **tris, int *ntris);
#endif

#ifdef __cplusplus
}
#endif
#endif
