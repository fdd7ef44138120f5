/* force_residual.c - the force residual of an implicit-Euler step (see
 * force_residual.h). */
#include "force_residual.h"

#include <math.h>
#include <stdlib.h>

int pl_force_residual_possible(const pl_dynamics *d)
{
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        if (!ops->add_gradient) return 0;
    }
    return 1;
}

int pl_force_residual_check(const pl_dynamics *d, pl_component *owner, pl_ctx *ctx)
{
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        if (!ops->add_gradient)
            return pl_component_error(owner, ctx, PL_EINPUT,
                                      "%s '%s' provides no gradient: the force residual (and "
                                      "forceTolerance) cannot be computed; set "
                                      "computeResidual=\"off\" and forceTolerance=\"0\"",
                                      d->terms[t]->type->name, d->terms[t]->name);
    }
    return PL_OK;
}

void pl_force_residual_free(pl_force_residual *r)
{
    free(r->f);
    r->f = NULL;
    r->n = 0;
}

int pl_force_residual_eval(pl_force_residual *r, const pl_dynamics *d, const pl_dyn_work *w,
                           const pl_data *data, const double *q, const pl_rows *rows,
                           const double *lambda, double *out, pl_error *err)
{
    if (r->n != d->n || !r->f) {
        pl_force_residual_free(r);
        r->f = malloc(sizeof(double) * 3 * (size_t)(d->n > 0 ? d->n : 1));
        if (!r->f)
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "force residual: out of memory");
        r->n = d->n;
    }
    double h2 = d->h * d->h, *f = r->f;
    /* f = M' (q - sn) / h^2 + grad psi(q) + (rS/h) L q - H^T lambda: M' the
     * inertia masses (h m first order: M (q - q_t) / h - M g); sn holds the
     * damping's - h rS M'^-1 L q_t, so the last terms make rS L (q - q_t) / h */
    for (int i = 0; i < d->n; ++i)
        for (int k = 0; k < 3; ++k)
            f[3 * i + k] = d->inertia[i] * (q[3 * i + k] - w->sn[3 * i + k]) / h2;
    if (d->scheme.rayleigh_stiffness > 0)
        pl_dynamics_add_Lq(d, q, d->scheme.rayleigh_stiffness / d->h, f);
    pl_buffer qb = pl_buffer_host_f64((double *)q, (size_t)d->n, 3);
    pl_buffer fb = pl_buffer_host_f64(f, (size_t)d->n, 3);
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        int rc = ops->add_gradient(d->terms[t], data, d->term_offset[t], &qb, &fb, err);
        if (rc) return rc;
    }
    if (rows && lambda && rows->n) pl_rows_add_transpose(rows, lambda, -1.0, f);
    double worst = 0.0;
    for (int v = 0; v < d->nfree; ++v) {
        const double *x = &f[3 * d->free_vertex[v]];
        double norm = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (!isfinite(norm)) {
            worst = INFINITY;
            break;
        }
        if (norm > worst) worst = norm;
    }
    *out = worst;
    return PL_OK;
}
