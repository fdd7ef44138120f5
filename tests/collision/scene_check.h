/* scene_check.h - independent geometric measures for the contact scenes'
 * tests: tunnelling of moving points through triangles, edges piercing
 * triangles, the depth of an edge beyond a cloth, inside tests for closed
 * surfaces.  Plain geometry written for the tests (Moller-Trumbore, prism
 * clipping, ray parity), not the plugin's detection code. */
#ifndef PLIANT_SCENE_CHECK_H
#define PLIANT_SCENE_CHECK_H

/* Whether the segment p q crosses the triangle a b c (end points on the
 * triangle count). */
int sc_segment_hits_triangle(const double p[3], const double q[3], const double a[3],
                             const double b[3], const double c[3]);

/* When the segment p q crosses the triangle: how deep inside the triangle
 * the crossing is (distance from the crossing point to the triangle's
 * border: a graze at a border is shallow); -1 when it does not cross. */
double sc_crossing_depth(const double p[3], const double q[3], const double a[3],
                         const double b[3], const double c[3]);
/* Distance from x to the plane of triangle a b c. */
double sc_plane_distance(const double x[3], const double a[3], const double b[3],
                         const double c[3]);

/* How far the segment p q reaches beyond the triangle a b c on its side
 * `sign` (the unit normal (b - a) x (c - a) times sign points to where the
 * segment must not go): the segment is clipped to the triangle's prism and
 * to heights below `band` (farther parts are another part of the scene);
 * when what is left crosses the triangle's plane, returns its largest
 * height, else 0 (nothing pierces the triangle). */
double sc_edge_depth_beyond(const double p[3], const double q[3], const double a[3],
                            const double b[3], const double c[3], double sign, double band);

/* Boundary triangles of a tetrahedral mesh (faces used once), malloc'ed;
 * returns their count. */
int sc_boundary(const int *tets, int ntets, int **tris);

/* Whether x is inside the closed surface (ray parity along a fixed skew
 * direction). */
int sc_inside(const double *v, const int *tris, int ntris, const double x[3]);

/* Distance from x to the nearest triangle of the surface. */
double sc_surface_distance(const double *v, const int *tris, int ntris, const double x[3]);

/* Signed volume of a tetrahedral mesh. */
double sc_volume(const double *v, const int *tets, int ntets);

#endif
