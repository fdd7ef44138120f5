/* mesh_subdivide.h - uniform refinement of tetrahedral meshes. */
#ifndef PLIANT_IO_MESH_SUBDIVIDE_H
#define PLIANT_IO_MESH_SUBDIVIDE_H

#include "pliant/error.h"
#include "pliant/mesh.h"

/* One round of 1-to-8 subdivision: a vertex at the midpoint of every edge
 * (one per edge, shared by all the elements around it), each tetrahedron
 * split into its 4 corner tetrahedra and the inner octahedron cut along its
 * shortest diagonal into 4 more; each triangle into 4.  Every child of a
 * positively oriented tetrahedron is positively oriented and has 1/8 of its
 * volume.  Vertices keep their indices; midpoints follow (nverts + edge
 * index, edges sorted by their vertex pair).  out must not alias in; it is
 * overwritten (pl_mesh_free'd first).  PL_OK, PL_EINPUT (the mesh would
 * overflow int indices) or PL_EINTERNAL (allocation). */
int pl_mesh_subdivide_tets(const pl_mesh *in, pl_mesh *out, pl_error *err);

/* `rounds` rounds in place (0 = none). */
int pl_mesh_subdivide(pl_mesh *m, int rounds, pl_error *err);

#endif
