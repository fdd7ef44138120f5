/* ncp_residual.c - how far (delta, lambda) is from the bilateral, box and
 * Signorini-Coulomb conditions (Appendix A.2), each part in its own units. */
#include "ncp.h"

#include <math.h>
#include <stdlib.h>

static double fmax3(double a, double b, double c) { return fmax(a, fmax(b, c)); }

/* Friction part of one contact: cone excess [N] and the natural-map
 * residual |rho lf - P_disk(rho mu ln+)(rho lf - y)| [m], which is zero iff
 * y = 0 with |lf| <= mu ln (stick) or lf = -mu ln y / |y| (slide). */
static void friction_residual(int nt, const double *y, const double *lf, double ln, double mu,
                              double rho, double *cone, double *fric)
{
    double lnp = ln > 0.0 ? ln : 0.0, L2 = 0.0, z[2], z2 = 0.0;
    for (int i = 0; i < nt; ++i) {
        L2 += lf[i] * lf[i];
        z[i] = rho * lf[i] - y[i];
        z2 += z[i] * z[i];
    }
    double radius = rho * mu * lnp, zn = sqrt(z2);
    double scale = zn > radius ? radius / zn : 1.0;
    double f2 = 0.0;
    for (int i = 0; i < nt; ++i) {
        double d = rho * lf[i] - scale * z[i];
        f2 += d * d;
    }
    double ex = sqrt(L2) - mu * lnp;
    *cone = ex > 0.0 ? ex : 0.0;
    *fric = sqrt(f2);
}

int pl_ncp_residual_eval(const pl_ncp_work *w, const double *r, double h, const double *delta,
                         const double *lambda, pl_ncp_residual *res, pl_error *err)
{
    const pl_ncp_rows *R = &w->rows;
    pl_ncp_residual z = {0, 0, 0, 0, 0, 0, 0};
    double cone_scaled = 0.0, ss = 0.0;
    for (int j = 0; j < w->m; ++j) {
        double v;
        switch (R->kind[j]) {
        case PL_ROW_BILATERAL:
            v = fabs(delta[j] + (R->compliance ? R->compliance[j] : 0.0) * lambda[j]);
            z.bilateral = fmax(z.bilateral, v);
            ss += v * v;
            break;
        case PL_ROW_NORMAL:
            v = fabs(fmin(delta[j], r[j] * lambda[j]));
            z.normal = fmax(z.normal, v);
            ss += v * v;
            break;
        case PL_ROW_BOUNDED: {
            double lo = R->lo ? R->lo[j] : -INFINITY, hi = R->hi ? R->hi[j] : INFINITY;
            double t = fmin(fmax(lambda[j] - delta[j] / r[j], lo), hi);
            v = fabs(r[j] * (lambda[j] - t));
            z.bounded = fmax(z.bounded, v);
            ss += v * v;
            break;
        }
        case PL_ROW_FRICTION:
            break;
        }
    }
    for (int c = 0; c < w->nc; ++c) {
        const int *ct = w->contact + 3 * c;
        int nt = 0;
        double y[2], lf[2], cone, fric;
        for (int i = 1; i <= 2; ++i)
            if (ct[i] >= 0) {
                y[nt] = delta[ct[i]];
                lf[nt] = lambda[ct[i]];
                ++nt;
            }
        if (nt == 0)
            continue;
        double rho = h * r[ct[1] >= 0 ? ct[1] : ct[2]];
        friction_residual(nt, y, lf, lambda[ct[0]], R->mu ? R->mu[ct[0]] : 0.0, rho, &cone, &fric);
        z.cone = fmax(z.cone, cone);
        z.friction = fmax(z.friction, fric);
        cone_scaled = fmax(cone_scaled, rho * cone);
        ss += fric * fric + rho * cone * rho * cone;
    }
    z.total = fmax3(fmax(z.bilateral, z.normal), fmax(z.friction, z.bounded), cone_scaled);
    z.norm2 = sqrt(ss);
    if (!isfinite(z.total) || !isfinite(z.norm2))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_residual", "non-finite values in delta or lambda");
    *res = z;
    return PL_OK;
}
