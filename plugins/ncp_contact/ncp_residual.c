/* ncp_residual.c - how far (delta, lambda) is from the bilateral, box and
 * Signorini-Coulomb conditions (Appendix A.2), each part in its own units;
 * the parts of one row or contact are ncp_residual.h, shared with the GPU. */
#include "ncp_residual.h"

#include "ncp.h"

#include <math.h>
#include <stdlib.h>

static double fmax3(double a, double b, double c) { return fmax(a, fmax(b, c)); }

int ncp_residual_eval(const pl_ncp_work *w, const double *r, double h, const double *delta,
                         const double *lambda, pl_ncp_residual *res, pl_error *err)
{
    const pl_ncp_rows *R = &w->rows;
    pl_ncp_residual z = {0, 0, 0, 0, 0, 0, 0};
    double cone_scaled = 0.0, ss = 0.0;
    for (int j = 0; j < w->m; ++j) {
        const int k = R->kind[j];
        if (k == PL_ROW_FRICTION)
            continue; /* below, per contact */
        double v = ncp_row_residual(k, delta[j], lambda[j], R->compliance ? R->compliance[j] : 0.0,
                                    r[j], R->lo ? R->lo[j] : -INFINITY, R->hi ? R->hi[j] : INFINITY);
        double *part = k == PL_ROW_BILATERAL ? &z.bilateral : k == PL_ROW_NORMAL ? &z.normal : &z.bounded;
        *part = fmax(*part, v);
        ss += v * v;
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
        ncp_friction_residual(nt, y, lf, lambda[ct[0]], R->mu ? R->mu[ct[0]] : 0.0, rho, &cone, &fric);
        z.cone = fmax(z.cone, cone);
        z.friction = fmax(z.friction, fric);
        cone_scaled = fmax(cone_scaled, rho * cone);
        ss += ncp_friction_residual2(rho, cone, fric);
    }
    z.total = fmax3(fmax(z.bilateral, z.normal), fmax(z.friction, z.bounded), cone_scaled);
    z.norm2 = sqrt(ss);
    if (!isfinite(z.total) || !isfinite(z.norm2))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_residual", "non-finite values in delta or lambda");
    *res = z;
    return PL_OK;
}
