/* local_global_device_residual.c - forceTolerance on the device: the force
 * residual of force_residual.h computed by kernels after every device
 * iteration, so that the loop stops by the CPU's rule without the CPU
 * evaluating it.
 *
 * The residual of free vertex i at the iterate q is
 *     r_i = m_i (q_i - sn_i) / h^2 + grad_i psi(q) - (H^T lambda)_i
 * (force_residual.c).  The constraint force is not formed from the
 * multipliers here: the iteration's global step solved
 *     A_ff q_f = rhs_f - A_fp q_p + h^2 H^T S lambda
 * (rhs = M sn + the local terms' projections; the contact solver's
 * correction), so h^2 (H^T lambda)_f = (A_f* q - rhs)_f with A_f* = [A_ff
 * A_fp] the free rows of A in global columns, uploaded once.  Hence
 *     r_f = m (q - sn) / h^2 + grad + (rhs_f - A_f* q) / h^2,
 * which holds for any constraint (contacts, cables) and equals the CPU's
 * value to the round-off of the global solve (SparseInverseSolver: a
 * direct solve).  Per iteration: every local term's add_gradient
 * on device buffers (accepts(PL_DEVICE, PL_F64 | PL_ACCEPTS_GRADIENT))
 * into grad (zeroed with change at the iteration's start),
 * t = rhs_f - A_f* q (gather_sub_csr; only with rows), and the
 * device service's residual_max (version 2) into one device double (t and
 * the residual in one launch where the service has residual_max_csr,
 * version 4); all
 * queued on the stream, so the iteration's graph holds them.  Without rows
 * the t term is left out, as the CPU leaves out H^T lambda.  The loop reads
 * that double after each iteration (a copy and a wait): the device runs no
 * iteration past the one the CPU stops at. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "local_global.h"
#include "pliant/util.h"

void pl_lg_device_residual_refusals(const local_global_solver *s, char *why, size_t size)
{
    const pl_dynamics *d = &s->dyn;
    char path[256];
    size_t len = strlen(why);
    if (!(s->force_tolerance > 0) || len + 1 >= size) return;
    char *out = why + len;
    size_t left = size - len;
    const char *sep = len ? "; " : "";
    pl_component *dev = pl_util_device(&s->base);
    const pl_device_ops *ops = dev ? pl_component_role(dev, PL_ROLE_DEVICE) : NULL;
    if (ops && !(ops->version >= 2 && ops->residual_max)) {
        snprintf(out, left, "%sforceTolerance > 0: the device service %s has no residual_max "
                 "(device ops version 2)", sep, dev->name);
        return;
    }
    if (s->rayleigh_stiffness > 0) {
        snprintf(out, left, "%sforceTolerance > 0 with rayleighStiffness > 0: the damping force's "
                 "L q is evaluated on the CPU only", sep);
        return;
    }
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *o = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        if (o->add_gradient && o->version >= 2 && o->accepts &&
            o->accepts(d->terms[t], PL_DEVICE, (pl_precision)(PL_F64 | PL_ACCEPTS_GRADIENT)))
            continue;
        snprintf(out, left, "%sforceTolerance > 0: %s (%s) has no gradient on device buffers "
                 "(the FEM terms ARAP, Corotational and NeoHookean have one)", sep,
                 pl_component_path(d->terms[t], path, sizeof path), d->terms[t]->type->name);
        return;
    }
}

int pl_lg_device_residual_setup(local_global_solver *s, pl_error *err)
{
    lg_device *g = &s->gpu;
    if (!(s->force_tolerance > 0) || s->dyn.nfree == 0) return PL_OK;
    /* A_f* = [A_ff A_fp] (nfree x n): A_ff's columns are free indices */
    const pl_dynamics *d = &s->dyn;
    const pl_csc *M[2] = {&d->A_ff, &d->A_fp};
    const int *cols[2] = {d->free_vertex, NULL};
    pl_csr R = {0};
    if (pl_lg_csc_rows(M, cols, 2, d->nfree, d->n, &R) != PL_OK) {
        pl_csr_free(&R);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    }
    size_t nnz = (size_t)R.p[R.nrows], rows = (size_t)R.nrows + 1;
    int rc = PL_OK;
    g->A_f.nrows = R.nrows, g->A_f.ncols = R.ncols;
    void **dst[3] = {(void **)&g->A_f.p, (void **)&g->A_f.j, (void **)&g->A_f.x};
    const void *src[3] = {R.p, R.j, R.x};
    size_t bytes[3] = {rows * sizeof(int), nnz * sizeof(int), nnz * sizeof(double)};
    for (int k = 0; k < 3 && !rc; ++k) {
        *dst[k] = g->ops->alloc(g->dev, bytes[k] ? bytes[k] : 1, err);
        if (!*dst[k]) rc = err->code ? err->code : PL_EINTERNAL;
        if (!rc && bytes[k])
            rc = g->ops->copy(g->dev, *dst[k], PL_DEVICE, src[k], PL_HOST, bytes[k], err);
    }
    if (!rc) rc = g->ops->sync(g->dev, err); /* R may go */
    pl_csr_free(&R);
    return rc;
}

void pl_lg_device_residual_free(lg_device *g)
{
    void *bufs[] = {g->A_f.p, g->A_f.j, g->A_f.x};
    for (int k = 0; k < 3; ++k)
        if (bufs[k]) g->ops->free(g->dev, bufs[k]);
    memset(&g->A_f, 0, sizeof g->A_f);
}

/* Whether the device service forms t and the residual in one launch
 * (version 4): then no t buffer. */
static int fused_residual(const lg_device_ws *g)
{
    return g->ops->version >= 4 && g->ops->residual_max_csr != NULL;
}

int pl_lg_device_residual_ws_alloc(const local_global_solver *s, lg_device_ws *g, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    if (!(s->force_tolerance > 0)) return PL_OK;
    /* the residual and the gradient follow change in its block (cleared
     * together at the start of an iteration) */
    g->residual = g->change + 1;
    g->grad = g->change + 2;
    if (fused_residual(g)) return PL_OK;
    size_t bytes = (size_t)(d->nfree ? d->nfree : 1) * 3 * sizeof(double);
    if (!(g->t = g->ops->alloc(g->dev, bytes, err))) return err->code ? err->code : PL_EINTERNAL;
    return PL_OK;
}

void pl_lg_device_residual_ws_free(lg_device_ws *g)
{
    if (g->t) g->ops->free(g->dev, g->t);
    g->grad = g->t = g->residual = NULL;
}

int pl_lg_device_residual_queue(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx,
                                pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    const lg_device *m = &s->gpu;
    const pl_device_ops *o = g->ops;
    pl_buffer qb = {g->q, (size_t)d->n, 3, PL_DEVICE, PL_F64};
    pl_buffer gb = {g->grad, (size_t)d->n, 3, PL_DEVICE, PL_F64};
    int rc = PL_OK; /* residual and grad were cleared with change (pl_lg_device_iteration) */
    for (int t = 0; !rc && t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        rc = ops->add_gradient(d->terms[t], ctx->data, d->term_offset[t], &qb, &gb, err);
    }
    if (rc || d->nfree == 0) return rc;
    int rows = g->nrows > 0;
    if (rows && fused_residual(g)) /* t and the residual in one launch */
        return o->residual_max_csr(g->dev, d->nfree, m->free_vertex, m->mass, d->h * d->h, g->q,
                                   g->sn, g->grad, g->rhs, &m->A_f, g->residual, err);
    if (rows) rc = pl_lg_device_gather_sub(g, d->nfree, m->free_vertex, g->rhs, &m->A_f, g->q, g->t, err);
    if (!rc)
        rc = o->residual_max(g->dev, d->nfree, m->free_vertex, m->mass, d->h * d->h, g->q,
                             g->sn, g->grad, rows ? g->t : NULL, g->residual, err);
    return rc;
}
