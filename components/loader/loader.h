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

/* Resolves a file name the way scenes expect: absolute as is; otherwise
 * relative to the scene file's folder, then the working directory, then
 * each folder of PLIANT_DATA_PATH.  Returns 0 and fills out, or -1 with the
 * folders tried in `tried`. */
int pl_resolve_data_file(const char *scene_file, const char *name, char *out, size_t size,
                         char *tried, size_t tried_size);

#endif
