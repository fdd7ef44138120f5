/* geom_hd.h - the closest-point routines of the narrow phase, one
 * implementation for the host (narrow.c wraps them) and the device (the
 * candidate kernels, detect_device.cu): point-triangle and segment-segment
 * closest points (Ericson, "Real-Time Collision Detection", 5.1.5 and
 * 5.1.9).  PL_HD (pliant/hostdevice.h) is static inline in C and adds
 * __host__ __device__ under nvcc; the .cu files that include this are
 * compiled with -fmad=false so that the device rounds exactly as the host
 * (no fused multiply-add): the same inputs give the same bits on both
 * sides. */
#ifndef PLIANT_COLLISION_GEOM_HD_H
#define PLIANT_COLLISION_GEOM_HD_H

#include "pliant/hostdevice.h"
#include <math.h>

PL_HD double coll_hd_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

PL_HD void coll_hd_sub3(const double a[3], const double b[3], double r[3])
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

PL_HD double coll_hd_dist2_bary(const double p[3], const double a[3], const double b[3],
                                const double c[3], const double w[3])
{
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double q = w[0] * a[k] + w[1] * b[k] + w[2] * c[k] - p[k];
        d2 += q * q;
    }
    return d2;
}

PL_HD void coll_hd_set_w(double w[3], double u, double v, double x)
{
    w[0] = u;
    w[1] = v;
    w[2] = x;
}

/* Closest point of segment a b to p as a parameter in [0, 1]. */
PL_HD double coll_hd_segment_param(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3];
    coll_hd_sub3(b, a, ab);
    coll_hd_sub3(p, a, ap);
    double l2 = coll_hd_dot3(ab, ab);
    if (!(l2 > 0.0)) return 0.0;
    double t = coll_hd_dot3(ap, ab) / l2;
    return t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
}

/* A degenerate triangle (zero area): the best of its three edges. */
PL_HD double coll_hd_degenerate_triangle(const double p[3], const double a[3],
                                         const double b[3], const double c[3], double w[3])
{
    double t, best, d2, cand[3];
    t = coll_hd_segment_param(p, a, b);
    coll_hd_set_w(w, 1.0 - t, t, 0.0);
    best = coll_hd_dist2_bary(p, a, b, c, w);
    t = coll_hd_segment_param(p, b, c);
    coll_hd_set_w(cand, 0.0, 1.0 - t, t);
    if ((d2 = coll_hd_dist2_bary(p, a, b, c, cand)) < best) {
        best = d2;
        coll_hd_set_w(w, cand[0], cand[1], cand[2]);
    }
    t = coll_hd_segment_param(p, a, c);
    coll_hd_set_w(cand, 1.0 - t, 0.0, t);
    if ((d2 = coll_hd_dist2_bary(p, a, b, c, cand)) < best) {
        best = d2;
        coll_hd_set_w(w, cand[0], cand[1], cand[2]);
    }
    return best;
}

PL_HD double coll_hd_closest_point_triangle(const double p[3], const double a[3],
                                            const double b[3], const double c[3],
                                            double w[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], n[3];
    coll_hd_sub3(b, a, ab);
    coll_hd_sub3(c, a, ac);
    n[0] = ab[1] * ac[2] - ab[2] * ac[1];
    n[1] = ab[2] * ac[0] - ab[0] * ac[2];
    n[2] = ab[0] * ac[1] - ab[1] * ac[0];
    double scale = coll_hd_dot3(ab, ab) + coll_hd_dot3(ac, ac);
    if (!(coll_hd_dot3(n, n) > 1e-24 * scale * scale))
        return coll_hd_degenerate_triangle(p, a, b, c, w);
    coll_hd_sub3(p, a, ap);
    double d1 = coll_hd_dot3(ab, ap), d2 = coll_hd_dot3(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) { /* vertex a */
        coll_hd_set_w(w, 1, 0, 0);
        return coll_hd_dist2_bary(p, a, b, c, w);
    }
    coll_hd_sub3(p, b, bp);
    double d3 = coll_hd_dot3(ab, bp), d4 = coll_hd_dot3(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) { /* vertex b */
        coll_hd_set_w(w, 0, 1, 0);
        return coll_hd_dist2_bary(p, a, b, c, w);
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) { /* edge ab */
        double v = d1 / (d1 - d3);
        coll_hd_set_w(w, 1.0 - v, v, 0);
        return coll_hd_dist2_bary(p, a, b, c, w);
    }
    coll_hd_sub3(p, c, cp);
    double d5 = coll_hd_dot3(ab, cp), d6 = coll_hd_dot3(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) { /* vertex c */
        coll_hd_set_w(w, 0, 0, 1);
        return coll_hd_dist2_bary(p, a, b, c, w);
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) { /* edge ac */
        double v = d2 / (d2 - d6);
        coll_hd_set_w(w, 1.0 - v, 0, v);
        return coll_hd_dist2_bary(p, a, b, c, w);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) { /* edge bc */
        double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        coll_hd_set_w(w, 0, 1.0 - v, v);
        return coll_hd_dist2_bary(p, a, b, c, w);
    }
    double denom = 1.0 / (va + vb + vc); /* inside the face */
    double v = vb * denom, x = vc * denom;
    coll_hd_set_w(w, 1.0 - v - x, v, x);
    return coll_hd_dist2_bary(p, a, b, c, w);
}

PL_HD double coll_hd_clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

PL_HD double coll_hd_closest_segments(const double p0[3], const double p1[3],
                                      const double q0[3], const double q1[3],
                                      double *s, double *t)
{
    double d1[3], d2[3], r[3];
    coll_hd_sub3(p1, p0, d1);
    coll_hd_sub3(q1, q0, d2);
    coll_hd_sub3(p0, q0, r);
    double a = coll_hd_dot3(d1, d1), e = coll_hd_dot3(d2, d2), f = coll_hd_dot3(d2, r);
    double eps = 1e-30;
    double ss, tt;
    if (a <= eps && e <= eps) {
        ss = tt = 0.0;
    } else if (a <= eps) {
        ss = 0.0;
        tt = coll_hd_clamp01(f / e);
    } else {
        double c = coll_hd_dot3(d1, r);
        if (e <= eps) {
            tt = 0.0;
            ss = coll_hd_clamp01(-c / a);
        } else {
            double b = coll_hd_dot3(d1, d2), denom = a * e - b * b;
            /* nearly parallel: any s works, take the clamped projection of q0 */
            ss = denom > 1e-14 * a * e ? coll_hd_clamp01((b * f - c * e) / denom) : 0.0;
            tt = (b * ss + f) / e;
            if (tt < 0.0) {
                tt = 0.0;
                ss = coll_hd_clamp01(-c / a);
            } else if (tt > 1.0) {
                tt = 1.0;
                ss = coll_hd_clamp01((b - c) / a);
            }
        }
    }
    *s = ss;
    *t = tt;
    double d2sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        double q = (p0[k] + ss * d1[k]) - (q0[k] + tt * d2[k]);
        d2sum += q * q;
    }
    return d2sum;
}

#endif
