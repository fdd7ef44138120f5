/* cable.h - internals of the cable plugin (CableConstraint).
 *
 * A cable runs from a fixed pull point through points carried by the body:
 *     pullPoint -> P_0 -> P_1 -> ... -> P_{m-1}
 * (without a pull point it starts at P_0).  Each point P_i follows up to
 * four vertices of the body's state with fixed weights: one vertex with
 * weight 1 (`indices`, `centers`) or the corners of the tetrahedron that
 * contains it (`position`, SOFA's BarycentricMapping).  Its length is
 *     L(x) = |P_0 - pullPoint| + sum_i |P_{i+1} - P_i|
 * and its constraint row is -dL/dx (the direction a tension pulls the
 * vertices in), so that a multiplier lambda > 0 is a tension [N], as
 * SoftRobots' CableConstraint reports it.  The plugin-private functions
 * (pl_cable_*) are shared by the plugin's files and its tests. */
#ifndef PLIANT_CABLE_H
#define PLIANT_CABLE_H

#include "pliant/pliant.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The cable's points as weighted vertices of one state. */
typedef struct pl_cable_path {
    int npoints;
    int nslot;            /* vertex slots per point: 4, more for an area point */
    int *vert;            /* npoints x nslot local vertex indices, -1 = unused slot */
    double *weight;       /* npoints x nslot weights (sum 1) */
    int has_pull;         /* 1: the cable starts at the fixed point `pull` */
    double pull[3];       /* [m] */
} pl_cable_path;

void cable_path_init(pl_cable_path *c);
void cable_path_free(pl_cable_path *c);
/* Allocates npoints points, every slot unused. PL_OK or PL_EINTERNAL. */
int cable_path_alloc(pl_cable_path *c, int npoints);
/* The same with nslot slots per point (an area point: many vertices). */
int cable_path_alloc_slots(pl_cable_path *c, int npoints, int nslot);

/* Point i of the cable for positions x (state-local, n x 3). */
void cable_point(const pl_cable_path *c, const double *x, int i, double p[3]);
/* Length of the cable [m] for positions x. */
double cable_path_length(const pl_cable_path *c, const double *x);
/* Length, and g (npoints x 3) = dL/dP_i.  A segment of zero length adds no
 * gradient (its direction is undefined; SoftRobots normalises it to 0). */
double cable_gradient(const pl_cable_path *c, const double *x, double *g);
/* The row -dL/dx over vertices: entries (vert[k], coef[3k..3k+2]) merged
 * per vertex and sorted by vertex, from the point gradients g.  vert and
 * coef hold at least 4 npoints entries.  Returns the number of entries,
 * or -1 on allocation failure. */
int cable_row(const pl_cable_path *c, const double *g, int *vert, double *coef);

/* Barycentric location of p in the tetrahedra (x: vertices, tets: ntets x
 * 4).  Picks the tetrahedron whose smallest barycentric coordinate is the
 * largest (the containing one when p is inside the mesh, else the nearest
 * one in that sense; SOFA's BarycentricMapping also extrapolates then).
 * Writes its corners and weights; *outside gets that smallest coordinate's
 * deficit (0 when inside, > 0 outside).  Returns the tetrahedron or -1 when
 * there is none with a positive volume. */
int cable_locate(const double *x, const int *tets, int ntets, const double p[3], int v[4],
                    double w[4], double *outside);
/* The vertex of x (n x 3) nearest to p (SoftRobots' `centers`); -1 if n = 0. */
int cable_nearest(const double *x, int n, const double p[3]);

#ifdef __cplusplus
}
#endif
#endif
