/* generators.h - procedural meshes: boxes, cloths, spheres and cylinders.
 *
 * Each generator fills an (uninitialised or freed) pl_mesh and returns
 * PL_OK, PL_EINPUT for bad parameters (err says which) or PL_EINTERNAL
 * when out of memory.  Tetrahedra are positively oriented, closed
 * surfaces face outward (counter-clockwise seen from outside).  On error
 * *out is left empty.  err may be NULL. */
#ifndef PLIANT_GENERATORS_H
#define PLIANT_GENERATORS_H

#include "pliant/error.h"
#include "pliant/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Box [lo, hi] with n[a] >= 2 vertices along axis a: every grid cell is
 * split into the 6 Kuhn (Freudenthal) tetrahedra around its lo->hi
 * diagonal, so neighbouring cells share face diagonals.  Vertex (i,j,k) has
 * index i + n[0]*(j + n[1]*k).  n[0]*n[1]*n[2] vertices, 6*(n-1)^3 tets. */
int pl_generate_box_tets(const int n[3], const double lo[3], const double hi[3], pl_mesh *out,
                         pl_error *err);

/* Triangle grid of nu x nv >= 2 x 2 vertices over the parallelogram
 * origin + s*edge_u + t*edge_v (s, t in [0, 1]); vertex (i, j) has index
 * i + nu*j.  Cells are split along alternating diagonals (a symmetric
 * "union jack" pattern, so a hanging cloth has no preferred shear
 * direction); triangle normals point along edge_u x edge_v. */
int pl_generate_triangle_grid(int nu, int nv, const double origin[3], const double edge_u[3],
                              const double edge_v[3], pl_mesh *out, pl_error *err);

/* Cloth in the plane y = y0: nx x nz vertices spanning [x0, x1] x [z0, z1],
 * vertex (i, k) at index i + nx*k, normals +y. */
int pl_generate_cloth_xz(int nx, int nz, double x0, double x1, double z0, double z1, double y0,
                         pl_mesh *out, pl_error *err);

/* Icosphere surface: the icosahedron subdivided `level` (0..8) times and
 * projected onto the sphere: 10*4^level + 2 vertices, 20*4^level triangles. */
int pl_generate_sphere_surface(const double center[3], double radius, int level, pl_mesh *out,
                               pl_error *err);

/* Solid ball of tetrahedra with about target_verts vertices: a Kuhn grid of
 * (2k+1)^3 vertices whose cubic shells are mapped onto spheres (equal-angle
 * cubed-sphere spacing).  Each cell's diagonal points away from the centre,
 * so no tetrahedron has all four vertices on the surface (no flat slivers).
 * k = round((cbrt(target_verts) - 1) / 2), at least 1. */
int pl_generate_sphere_tets(const double center[3], double radius, int target_verts,
                            pl_mesh *out, pl_error *err);

/* Thick-walled hollow sphere (spherical shell) between radii inner < outer:
 * the icosphere of `level` (as above) on layers + 1 concentric spheres,
 * every triangle-by-layer prism cut into 3 tetrahedra (conforming).  Vertex
 * i of layer l (0 = inner) has index l * (10*4^level + 2) + i; its
 * triangles are the two boundary spheres, facing out of the material (the
 * inner one towards the centre). 60*4^level*layers tets. */
int pl_generate_sphere_shell(const double center[3], double inner, double outer, int level,
                             int layers, pl_mesh *out, pl_error *err);

/* Closed cylinder surface around the y axis through `center`, y in
 * [center.y - height/2, center.y + height/2]: nsides >= 3 around, nlayers
 * >= 1 along the axis, caps fanned from a centre vertex.
 * nsides*(nlayers+1) + 2 vertices, 2*nsides*(nlayers+1) triangles. */
int pl_generate_cylinder_surface(const double center[3], double radius, double height,
                                 int nsides, int nlayers, pl_mesh *out, pl_error *err);

/* Solid cylinder (axis y, as above): a disk of `rings` >= 1 concentric
 * rings (ring r has 6r vertices) extruded through nlayers >= 1 layers
 * (nlayers <= 0 picks layers about as thick as a ring), each prism split
 * into 3 tetrahedra with consistent diagonals.
 * (1 + 3 rings (rings+1)) (nlayers+1) vertices, 18 rings^2 nlayers tets. */
int pl_generate_cylinder_tets(const double center[3], double radius, double height, int rings,
                              int nlayers, pl_mesh *out, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
