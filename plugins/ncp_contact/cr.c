/* cr.c - conjugate residual for a symmetric operator given as products.
 *
 * CR minimises ||b - A x|| over the Krylov space like MINRES, with one
 * product per iteration and short recurrences; it needs A symmetric, not
 * definite (PAPER_NOTES 7).  Unpreconditioned, as in the paper. */
#include "ncp.h"

#include <math.h>
#include <string.h>

static double dot(int n, const double *x, const double *y)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i)
        s += x[i] * y[i];
    return s;
}

int ncp_cr(int n, pl_ncp_apply_fn op, void *user, const double *b, double *x,
              int max_iter, double rtol, double *work, int *iters, double *relres,
              pl_error *err)
{
    double *r = work, *p = work + n, *Ar = work + 2 * (size_t)n, *Ap = work + 3 * (size_t)n;
    int it = 0, st;
    if (iters) *iters = 0;
    if (relres) *relres = 0.0;
    if (n <= 0)
        return PL_OK;
    double bnorm = sqrt(dot(n, b, b));
    if (!isfinite(bnorm))
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_cr", "right-hand side is not finite");
    /* r = b - A x (no product for the usual zero guess) */
    int zero = 1;
    for (int i = 0; i < n && zero; ++i)
        zero = x[i] == 0.0;
    if (zero) {
        memcpy(r, b, sizeof(double) * (size_t)n);
    } else {
        if ((st = op(user, x, Ar)) != PL_OK)
            return pl_error_set(err, st, NULL, 0, "ncp_cr", "operator failed");
        for (int i = 0; i < n; ++i)
            r[i] = b[i] - Ar[i];
    }
    double rnorm = sqrt(dot(n, r, r));
    if (bnorm == 0.0 || rnorm <= rtol * bnorm) {
        if (bnorm == 0.0)
            memset(x, 0, sizeof(double) * (size_t)n); /* exact: A x = 0 has x = 0 for SPD A */
        if (relres) *relres = bnorm > 0.0 ? rnorm / bnorm : 0.0;
        return PL_OK;
    }
    if ((st = op(user, r, Ar)) != PL_OK)
        return pl_error_set(err, st, NULL, 0, "ncp_cr", "operator failed");
    ++it;
    memcpy(p, r, sizeof(double) * (size_t)n);
    memcpy(Ap, Ar, sizeof(double) * (size_t)n);
    double rAr = dot(n, r, Ar);
    while (it < max_iter) {
        double ApAp = dot(n, Ap, Ap);
        if (!(ApAp > 0.0) || rAr == 0.0)
            break; /* breakdown: A singular on the Krylov space (not for SPD A) */
        double alpha = rAr / ApAp;
        for (int i = 0; i < n; ++i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * Ap[i];
        }
        rnorm = sqrt(dot(n, r, r));
        if (!isfinite(rnorm))
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_cr", "residual is not finite");
        if (rnorm <= rtol * bnorm)
            break;
        if ((st = op(user, r, Ar)) != PL_OK)
            return pl_error_set(err, st, NULL, 0, "ncp_cr", "operator failed");
        ++it;
        double rAr_new = dot(n, r, Ar);
        double beta = rAr_new / rAr;
        rAr = rAr_new;
        for (int i = 0; i < n; ++i) {
            p[i] = r[i] + beta * p[i];
            Ap[i] = Ar[i] + beta * Ap[i];
        }
    }
    if (iters) *iters = it;
    if (relres) *relres = rnorm / bnorm;
    return PL_OK;
}
