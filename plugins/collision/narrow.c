/* narrow.c - closest points of point-triangle and segment-segment pairs:
 * the host entry points of the routines shared with the device
 * (geom_hd.h). */
#include "detect.h"
#include "geom_hd.h"

double closest_point_triangle(const double p[3], const double a[3], const double b[3],
                                 const double c[3], double w[3])
{
    return coll_hd_closest_point_triangle(p, a, b, c, w);
}

double closest_segments(const double p0[3], const double p1[3], const double q0[3],
                           const double q1[3], double *s, double *t)
{
    return coll_hd_closest_segments(p0, p1, q0, q1, s, t);
}
