/* cavity.h - the geometry of SurfacePressureConstraint (the cable plugin's
 * pneumatic actuator): a closed triangle surface whose points follow the
 * body's vertices with fixed weights (one vertex with weight 1, or the
 * corners of the tetrahedron containing the point: SOFA's
 * BarycentricMapping), its enclosed volume and the volume's gradient.
 *
 *     V(x) = sum_t p0 . (p1 x p2) / 6          (divergence theorem)
 *     dV/dP_i = sum_{t containing i} N_t / 3,  N_t = (p1 - p0) x (p2 - p0) / 2
 *
 * The second form is the exact gradient of V on a closed, consistently
 * oriented surface (the terms that differ cancel around each vertex's
 * ring) and does not depend on the origin; it is SoftRobots' row (each
 * triangle's area normal shared by its corners).  Surfaces face out of the
 * cavity (counter-clockwise seen from the material): V > 0. */
#ifndef PLIANT_CAVITY_H
#define PLIANT_CAVITY_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct cavity_surface {
    int npoints;
    int *vert;      /* npoints x 4 local vertex indices, -1 = unused slot */
    double *weight; /* npoints x 4 weights (sum 1) */
    int ntris;
    int *tris;      /* ntris x 3 into the points */
} cavity_surface;

void cavity_init(cavity_surface *s);
void cavity_free(cavity_surface *s);
/* Allocates npoints points (slots unused) and ntris triangles; 0 or -1. */
int cavity_alloc(cavity_surface *s, int npoints, int ntris);

/* Point i for positions x (state-local, n x 3). */
void cavity_point(const cavity_surface *s, const double *x, int i, double p[3]);
/* Enclosed volume for positions x. */
double cavity_volume(const cavity_surface *s, const double *x);
/* Volume, and g (npoints x 3) = dV/dP_i. */
double cavity_gradient(const cavity_surface *s, const double *x, double *g);

/* Checks that tris (ntris x 3 over npoints points) form a closed,
 * edge-manifold, consistently oriented surface: every edge is used exactly
 * twice, once in each direction.  Returns 0, or 1 (an open edge), 2 (an
 * edge of more than two triangles), 3 (an edge twice in one direction:
 * neighbours oriented oppositely), 4 (a degenerate triangle: a repeated
 * point), -1 (out of memory); *a, *b: the edge (points) at fault. */
int cavity_check_closed(const int *tris, int ntris, int npoints, int *a, int *b);

/* The boundary faces of tetrahedra (ntets x 4, positively oriented) whose
 * three vertices all lie in one of the boxes (nbox x 6: min, max), turned
 * to face out of the hole they bound (into the material).  *out (malloc'ed,
 * ntris x 3 vertex indices); returns ntris or -1 when out of memory. */
int cavity_faces_in_boxes(const double *x, const int *tets, int ntets, const double *boxes,
                          int nbox, int **out);

#ifdef __cplusplus
}
#endif
#endif
