/* narrow.c - closest points of point-triangle and segment-segment pairs
 * (Ericson, "Real-Time Collision Detection", 5.1.5 and 5.1.9): Voronoi
 * regions of the triangle, clamped parameters of the segments. */
#include <math.h>

#include "detect.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void sub3(const double a[3], const double b[3], double r[3])
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

static double dist2_bary(const double p[3], const double a[3], const double b[3],
                         const double c[3], const double w[3])
{
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double q = w[0] * a[k] + w[1] * b[k] + w[2] * c[k] - p[k];
        d2 += q * q;
    }
    return d2;
}

static void set_w(double w[3], double u, double v, double x)
{
    w[0] = u;
    w[1] = v;
    w[2] = x;
}

/* Closest point of segment a b to p as a parameter in [0, 1]. */
static double segment_param(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3];
    sub3(b, a, ab);
    sub3(p, a, ap);
    double l2 = dot3(ab, ab);
    if (!(l2 > 0.0)) return 0.0;
    double t = dot3(ap, ab) / l2;
    return t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
}

/* A degenerate triangle (zero area): the best of its three edges. */
static double degenerate_triangle(const double p[3], const double a[3], const double b[3],
                                  const double c[3], double w[3])
{
    double t, best, d2, cand[3];
    t = segment_param(p, a, b);
    set_w(w, 1.0 - t, t, 0.0);
    best = dist2_bary(p, a, b, c, w);
    t = segment_param(p, b, c);
    set_w(cand, 0.0, 1.0 - t, t);
    if ((d2 = dist2_bary(p, a, b, c, cand)) < best) {
        best = d2;
        set_w(w, cand[0], cand[1], cand[2]);
    }
    t = segment_param(p, a, c);
    set_w(cand, 1.0 - t, 0.0, t);
    if ((d2 = dist2_bary(p, a, b, c, cand)) < best) {
        best = d2;
        set_w(w, cand[0], cand[1], cand[2]);
    }
    return best;
}

double closest_point_triangle(const double p[3], const double a[3], const double b[3],
                                 const double c[3], double w[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], n[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    n[0] = ab[1] * ac[2] - ab[2] * ac[1];
    n[1] = ab[2] * ac[0] - ab[0] * ac[2];
    n[2] = ab[0] * ac[1] - ab[1] * ac[0];
    double scale = dot3(ab, ab) + dot3(ac, ac);
    if (!(dot3(n, n) > 1e-24 * scale * scale)) return degenerate_triangle(p, a, b, c, w);
    sub3(p, a, ap);
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) { /* vertex a */
        set_w(w, 1, 0, 0);
        return dist2_bary(p, a, b, c, w);
    }
    sub3(p, b, bp);
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) { /* vertex b */
        set_w(w, 0, 1, 0);
        return dist2_bary(p, a, b, c, w);
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) { /* edge ab */
        double v = d1 / (d1 - d3);
        set_w(w, 1.0 - v, v, 0);
        return dist2_bary(p, a, b, c, w);
    }
    sub3(p, c, cp);
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) { /* vertex c */
        set_w(w, 0, 0, 1);
        return dist2_bary(p, a, b, c, w);
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) { /* edge ac */
        double v = d2 / (d2 - d6);
        set_w(w, 1.0 - v, 0, v);
        return dist2_bary(p, a, b, c, w);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) { /* edge bc */
        double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        set_w(w, 0, 1.0 - v, v);
        return dist2_bary(p, a, b, c, w);
    }
    double denom = 1.0 / (va + vb + vc); /* inside the face */
    double v = vb * denom, x = vc * denom;
    set_w(w, 1.0 - v - x, v, x);
    return dist2_bary(p, a, b, c, w);
}

static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

double closest_segments(const double p0[3], const double p1[3], const double q0[3],
                           const double q1[3], double *s, double *t)
{
    double d1[3], d2[3], r[3];
    sub3(p1, p0, d1);
    sub3(q1, q0, d2);
    sub3(p0, q0, r);
    double a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r);
    double eps = 1e-30;
    double ss, tt;
    if (a <= eps && e <= eps) {
        ss = tt = 0.0;
    } else if (a <= eps) {
        ss = 0.0;
        tt = clamp01(f / e);
    } else {
        double c = dot3(d1, r);
        if (e <= eps) {
            tt = 0.0;
            ss = clamp01(-c / a);
        } else {
            double b = dot3(d1, d2), denom = a * e - b * b;
            /* nearly parallel: any s works, take the clamped projection of q0 */
            ss = denom > 1e-14 * a * e ? clamp01((b * f - c * e) / denom) : 0.0;
            tt = (b * ss + f) / e;
            if (tt < 0.0) {
                tt = 0.0;
                ss = clamp01(-c / a);
            } else if (tt > 1.0) {
                tt = 1.0;
                ss = clamp01((b - c) / a);
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
