/* sweep.c - a point's straight path over a time step against an analytic
 * shape (look-ahead detection): where the path first comes within the kept
 * gap of the surface.  Every shape here is convex, so its signed distance
 * is a convex function of the path parameter: a golden-section search finds
 * the nearest point of the path and a bisection on the descending part
 * before it the first point at the kept gap. */
#include <math.h>

#include "collision.h"

/* golden-section and bisection steps: 0.618^48 and 2^-40 of a path of at
 * most a few metres are far below any contactDistance */
#define SWEEP_GOLDEN 48
#define SWEEP_BISECT 40

static void along(const double y0[3], const double y1[3], double t, double y[3])
{
    for (int k = 0; k < 3; ++k) y[k] = y0[k] + t * (y1[k] - y0[k]);
}

static double phi_at(const pl_shape *s, const double y0[3], const double y1[3], double t)
{
    double y[3];
    along(y0, y1, t, y);
    return shape_query(s, y, NULL, NULL);
}

int shape_sweep(const pl_shape *s, const double y0[3], const double y1[3], double alarm,
                   double gap, double *t, double closest[3], double normal[3])
{
    double d[3] = {y1[0] - y0[0], y1[1] - y0[1], y1[2] - y0[2]};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double phi0 = shape_query(s, y0, closest, normal);
    *t = 0.0;
    if (phi0 <= gap) return 1;
    /* phi is 1-Lipschitz: a path shorter than phi0 - alarm cannot come near */
    if (!(phi0 - len < alarm)) return 0;
    /* the nearest point of the path (phi convex along it) */
    const double g = 0.6180339887498949;
    double a = 0.0, b = 1.0, c = b - g * (b - a), e = a + g * (b - a);
    double fc = phi_at(s, y0, y1, c), fe = phi_at(s, y0, y1, e);
    for (int k = 0; k < SWEEP_GOLDEN; ++k) {
        if (fc <= fe) {
            b = e, e = c, fe = fc;
            c = b - g * (b - a);
            fc = phi_at(s, y0, y1, c);
        } else {
            a = c, c = e, fc = fe;
            e = a + g * (b - a);
            fe = phi_at(s, y0, y1, e);
        }
    }
    double tmin = 0.5 * (a + b), fmin = phi_at(s, y0, y1, tmin);
    double f1 = phi_at(s, y0, y1, 1.0);
    if (f1 < fmin) tmin = 1.0, fmin = f1; /* the search keeps the ends out */
    if (!(fmin < alarm)) return 0;
    if (fmin <= gap) {
        /* the first point at the kept gap: phi decreases on [0, tmin] */
        double lo = 0.0, hi = tmin;
        for (int k = 0; k < SWEEP_BISECT; ++k) {
            double mid = 0.5 * (lo + hi);
            if (phi_at(s, y0, y1, mid) > gap) lo = mid;
            else hi = mid;
        }
        tmin = hi;
    }
    double y[3];
    along(y0, y1, tmin, y);
    shape_query(s, y, closest, normal);
    *t = tmin;
    return 1;
}
