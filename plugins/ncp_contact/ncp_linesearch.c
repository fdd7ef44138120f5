/* ncp_linesearch.c - backtracking along a Newton direction of the
 * constraint update.  In Algorithm 4 the constraint values after an update
 * are affine in its length: with the right-hand side b^k fixed,
 *   delta(alpha) = delta_free + h^2 W S (lambda^k + alpha dlambda)
 *                = delta0 + alpha ddelta,
 * so the residual of every trial costs O(m), not a global solve.  A
 * semi-smooth Newton step can cycle between branches of the NCP functions
 * when rows are strongly coupled through W (bounded rows jumping between
 * their two bounds, sliding friction between stick and slip); halving the
 * step until the residual decreases breaks such cycles, as the standalone
 * fc3d solver does (ncp_solve.c). */
#include "ncp.h"

#include <math.h>

int ncp_line_search(pl_ncp_work *w, const double *r, double h, const double *delta0,
                       const double *ddelta, const double *lambda, const double *dlambda,
                       int max_halvings, pl_ncp_line_info *info, pl_error *err)
{
    int m = w->m, st;
    double *dt = w->tmp, *lt = w->tmp2;
    pl_ncp_residual res;
    if ((st = ncp_residual_eval(w, r, h, delta0, lambda, &res, err)) != PL_OK)
        return st;
    info->merit0 = res.norm2;
    info->alpha = 1.0;
    info->trials = 0;
    info->decreased = 0;
    double alpha = 1.0;
    for (int t = 0; t <= max_halvings; ++t, alpha *= 0.5) {
        for (int j = 0; j < m; ++j) {
            dt[j] = delta0[j] + alpha * ddelta[j];
            lt[j] = lambda[j] + alpha * dlambda[j];
        }
        if ((st = ncp_residual_eval(w, r, h, dt, lt, &res, err)) != PL_OK)
            return st;
        info->trials = t + 1;
        if (t == 0)
            info->merit = res.norm2; /* the full step's, kept if nothing decreases */
        if (res.norm2 <= (1.0 - 1e-4 * alpha) * info->merit0) {
            info->alpha = alpha;
            info->merit = res.norm2;
            info->decreased = 1;
            return PL_OK;
        }
    }
    /* no decrease along dlambda (a non-smooth kink, or already at the
     * round-off floor): the full Newton step */
    info->alpha = 1.0;
    return PL_OK;
}
