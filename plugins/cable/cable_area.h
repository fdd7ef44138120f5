/* cable_area.h - the pulled area of a surface cable (cable_area.c). */
#ifndef PLIANT_CABLE_AREA_H
#define PLIANT_CABLE_AREA_H

#include "cable.h"

enum { CABLE_AREA_POINT = 0, CABLE_AREA_SPHERE = 1, CABLE_AREA_GEODESIC = 2 };

/* The points of the surface (p: np x 3, tris: ntris x 3) within `radius`
 * of center (CABLE_AREA_SPHERE: straight distance; CABLE_AREA_GEODESIC:
 * along the triangles' edges).  idx and w (np entries each, caller's)
 * receive the *nsel points and their weights (radius - d), normalised to
 * sum 1.  PL_OK; PL_EINPUT when no point is within the radius or the
 * surface is unusable (bad index, no triangle for geodesic); PL_EINTERNAL
 * when out of memory. */
int cable_area(const double *p, int np, const int *tris, int ntris, const double center[3],
               double radius, int method, int *idx, double *w, int *nsel);

/* A triangle surface: points (npoints x 3) and triangles (ntris x 3). */
typedef struct cable_surface {
    const double *points;
    int npoints;
    const int *tris;
    int ntris;
} cable_surface;

/* The path of a surface cable: one point per center (centers: ncenters x
 * 3), the area of that center (radius radii[i], radii[0] for all when
 * nradii = 1, 1 when nradii = 0), each area point located in the
 * tetrahedra (x: rest positions, tets: ntets x 4).  PL_OK; PL_EINPUT with
 * *bad_center = i when center i's area is empty (-1: no tetrahedron);
 * *outside counts area points outside the tetrahedra (extrapolated). */
int cable_area_path(pl_cable_path *p, const cable_surface *s, const double *centers, int ncenters,
                    const double *radii, int nradii, int method, const double *x,
                    const int *tets, int ntets, int *bad_center, int *outside);

/* q = the point of triangle (a, b, c) nearest to p. */
void cable_closest_on_triangle(const double *p, const double *a, const double *b,
                               const double *c, double q[3]);

#endif
