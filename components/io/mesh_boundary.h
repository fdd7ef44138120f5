/* mesh_boundary.h - the boundary surface of a tetrahedral mesh. */
#ifndef PLIANT_IO_MESH_BOUNDARY_H
#define PLIANT_IO_MESH_BOUNDARY_H

#include "pliant/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Extracts the faces used by exactly one tetrahedron, oriented outward
 * (counter-clockwise seen from outside) when the tetrahedra are positively
 * oriented.  *tris (ntris x 3, malloc'ed, caller frees; NULL when empty).
 * PL_OK; PL_EINPUT if an index is out of range or a face is shared by more
 * than two tetrahedra (not a manifold); PL_EINTERNAL if out of memory. */
int pl_mesh_boundary_triangles(const pl_mesh *m, int **tris, int *ntris);

#ifdef __cplusplus
}
#endif
#endif
