/* mesh_boundary.h - the boundary surface of a tetrahedral mesh: declared
 * in the SDK (pliant/mesh.h, pl_mesh_boundary_triangles), kept for the
 * includes of components/. */
#ifndef PLIANT_IO_MESH_BOUNDARY_H
#define PLIANT_IO_MESH_BOUNDARY_H

#include "pliant/mesh.h"

#endif
