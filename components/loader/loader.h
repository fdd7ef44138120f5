/* loader.h - components that provide a mesh (PL_ROLE_TOPOLOGY). */
#ifndef PLIANT_LOADER_H
#define PLIANT_LOADER_H

#include "pliant/pliant.h"

extern const pl_type pl_mesh_loader_type;
extern const pl_type pl_grid_tetrahedra_type;
extern const pl_type pl_grid_triangles_type;
extern const pl_type pl_sphere_mesh_type;
extern const pl_type pl_cylinder_mesh_type;

/* The topology ops every mesh provider shares: the mesh is the struct
 * member right after the pl_component. */
extern const pl_topology_ops pl_mesh_provider_ops;

#endif
