/* local_global_device_state.c - a time step's start and end on the device.
 *
 * The device loop (local_global_device.c) began each step on the host:
 * gather q_t and v_t from the states, sn and the first iterate q
 * (pl_dynamics_begin), copy sn and q up; and ended it there: copy q down,
 * check it, v = (q - q_t) / h and the scatter into the states.  For a
 * 20k-vertex cloth those passes over n x 3 arrays were about a third of a
 * frame that the GPU computes in 0.5 ms (docs/benchmarks.md, session 17).
 * When the host needs those vectors for nothing else, the device does it
 * (device ops version 6):
 *   up:     each state's positions and velocities (their slots page-locked);
 *   device: step_begin: q_t, sn, q; the prescribed vertices' positions at
 *           t + h (computed by the host into w->q, as before) scattered
 *           into q;
 *   ... the iterations ...
 *   device: step_end: the states' new positions and velocities, and a flag
 *           for a position that is not finite;
 *   down:   each state's positions and velocities, then the flag (the wait).
 * The values are the host's, bitwise (the kernels round each operation as
 * the host's code does).  The host vectors w->q_t, w->v_t, w->sn and w->q
 * are then not kept: steps that read them stay on the host's path, namely
 * with constraint rows (the rows and the contact solver read q_t), a host
 * force residual, computeEnergy, a tolerance (its scale reads q_t) or
 * Rayleigh damping (sn's L q_t term): pl_lg_device_state_setup decides for
 * the model, pl_lg_device_state_now at each step (some are run-time fields). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "local_global.h"

/* The vertices prescribed at each step, each once, in pl_dynamics_prescribe's
 * order of writing (a vertex two components prescribe keeps the last one's
 * position, as on the host): npres and pres_host; -1 when out of memory. */
static int prescribed_vertices(const pl_dynamics *d, lg_device *g)
{
    int *last = malloc(sizeof(int) * (size_t)(d->n ? d->n : 1)), m = 0;
    if (!last) return -1;
    for (int i = 0; i < d->n; ++i) last[i] = 0;
    for (int k = 0; k < d->nprescribed; ++k) {
        const pl_prescribed_ops *ops = pl_component_role(d->prescribed[k], PL_ROLE_PRESCRIBED);
        int off = pl_dynamics_state_offset(d, ops->state(d->prescribed[k]));
        const int *idx;
        int cnt = ops->indices(d->prescribed[k], &idx);
        for (int j = 0; off >= 0 && j < cnt; ++j)
            if (!last[off + idx[j]]++) ++m;
    }
    g->pres_host = malloc(sizeof(int) * (size_t)(m ? m : 1));
    if (!g->pres_host) {
        free(last);
        return -1;
    }
    g->npres = 0;
    for (int i = 0; i < d->n; ++i)
        if (last[i]) g->pres_host[g->npres++] = i;
    free(last);
    return 0;
}

int pl_lg_device_state_setup(local_global_solver *s, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    lg_device *g = &s->gpu;
    const pl_device_ops *o = g->ops;
    g->on_device = 0;
    const char *env = getenv("PLIANT_DEVICE_STATE"); /* 0: the host's path (a diagnostic) */
    if (o->version < 6 || !o->step_begin || !o->step_end || (env && !strcmp(env, "0")) ||
        s->nconstraints || d->scheme.rayleigh_stiffness > 0)
        return PL_OK;
    size_t n3 = (size_t)d->n * 3 * sizeof(double);
    if (prescribed_vertices(d, g) != 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    int rc = PL_OK;
    g->gravity = pl_lg_dalloc(g->dev, o, n3, &rc, err);
    g->pres_map = pl_lg_dalloc(g->dev, o, sizeof(int) * (size_t)(g->npres ? g->npres : 1), &rc, err);
    if (!rc) rc = o->copy(g->dev, g->gravity, PL_DEVICE, d->gravity, PL_HOST, n3, err);
    if (!rc && g->npres)
        rc = o->copy(g->dev, g->pres_map, PL_DEVICE, g->pres_host, PL_HOST,
                     sizeof(int) * (size_t)g->npres, err);
    if (!rc) rc = o->sync(g->dev, err);
    if (rc) {
        pl_lg_device_state_free(g);
        return rc;
    }
    g->on_device = 1;
    return PL_OK;
}

int pl_lg_device_state_now(const local_global_solver *s)
{
    /* run-time fields: asked at each step */
    return s->gpu.on_device && !s->report_residual && !s->compute_energy && !(s->tolerance > 0);
}

void pl_lg_device_state_free(lg_device *g)
{
    if (g->gravity) g->ops->free(g->dev, g->gravity);
    if (g->pres_map) g->ops->free(g->dev, g->pres_map);
    free(g->pres_host);
    g->gravity = NULL, g->pres_map = NULL, g->pres_host = NULL;
    g->npres = 0, g->on_device = 0;
}

int pl_lg_device_state_ws_alloc(const local_global_solver *s, lg_device_ws *g, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    if (!s->gpu.on_device) return PL_OK;
    size_t n3 = (size_t)d->n * 3 * sizeof(double);
    size_t p3 = (size_t)(s->gpu.npres ? s->gpu.npres : 1) * 3 * sizeof(double);
    int rc = PL_OK;
    g->x = pl_lg_dalloc(g->dev, g->ops, n3, &rc, err);
    g->v = pl_lg_dalloc(g->dev, g->ops, n3, &rc, err);
    g->q_t = pl_lg_dalloc(g->dev, g->ops, n3, &rc, err);
    g->pres = pl_lg_dalloc(g->dev, g->ops, p3, &rc, err);
    g->bad = pl_lg_dalloc(g->dev, g->ops, sizeof(int), &rc, err);
    if (rc) return rc;
    g->slot_tried = calloc((size_t)(2 * d->nstates + 1), sizeof(void *));
    g->slot_pinned = calloc((size_t)(2 * d->nstates + 1), 1);
    if (!g->slot_tried || !g->slot_pinned)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    return PL_OK;
}

void pl_lg_device_state_ws_free(lg_device_ws *g)
{
    void *bufs[] = {g->x, g->v, g->q_t, g->pres, g->bad};
    for (size_t k = 0; k < sizeof bufs / sizeof bufs[0]; ++k)
        if (bufs[k]) g->ops->free(g->dev, bufs[k]);
    for (int k = 0; g->slot_tried && g->slot_tried[k]; ++k)
        if (g->slot_pinned && g->slot_pinned[k]) g->ops->unpin(g->dev, g->slot_tried[k]);
    free(g->slot_tried);
    free(g->slot_pinned);
    g->x = g->v = g->q_t = g->pres = NULL, g->bad = NULL;
    g->slot_tried = NULL, g->slot_pinned = NULL;
}

/* A state slot page-locked once per data (a fixed slot keeps its memory):
 * its copies each way are then DMA.  slot_tried lists the slots tried (up
 * to the first NULL), slot_pinned marks those page-locked; one that cannot be
 * (pages shared with memory page-locked already) is not tried again and is
 * copied through the driver's staging. */
static void pin_once(const lg_device_ws *g, void *host, size_t bytes)
{
    int k = 0;
    for (; g->slot_tried[k]; ++k)
        if (g->slot_tried[k] == host) return;
    g->slot_tried[k] = host;
    pl_error e;
    if (bytes && g->ops->pin && g->ops->pin(g->dev, host, bytes, &e) == PL_OK)
        g->slot_pinned[k] = 1;
}

/* Each state's positions and velocities between its slots and g->x, g->v
 * (to: PL_DEVICE up, PL_HOST down; only the last copy down waits). */
static int copy_states(const local_global_solver *s, lg_device_ws *g, pl_data *data,
                       pl_location to, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    int rc = PL_OK;
    for (int k = 0; !rc && k < d->nstates; ++k) {
        const pl_state_ops *ops = pl_component_role(d->states[k], PL_ROLE_STATE);
        pl_buffer xb = ops->positions(d->states[k], data), vb = ops->velocities(d->states[k], data);
        size_t at = 3 * (size_t)ops->offset(d->states[k]), bytes = 3 * xb.rows * sizeof(double);
        double *px = pl_buffer_f64(&xb), *pv = pl_buffer_f64(&vb);
        pin_once(g, px, bytes);
        pin_once(g, pv, bytes);
        if (to == PL_DEVICE) {
            rc = g->ops->copy(g->dev, g->x + at, PL_DEVICE, px, PL_HOST, bytes, err);
            if (!rc) rc = g->ops->copy(g->dev, g->v + at, PL_DEVICE, pv, PL_HOST, bytes, err);
        } else {
            rc = g->ops->copy(g->dev, px, PL_HOST, g->x + at, PL_DEVICE, bytes, err);
            if (!rc) rc = g->ops->copy(g->dev, pv, PL_HOST, g->v + at, PL_DEVICE, bytes, err);
        }
    }
    return rc;
}

int pl_lg_device_state_begin(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx,
                             pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    const lg_device *m = &s->gpu;
    lg_device_ws *g = &ws->gpu;
    const pl_device_ops *o = g->ops;
    double hv = d->scheme.first_order ? 0.0 : d->h;
    int rc = copy_states(s, g, ctx->data, PL_DEVICE, err);
    if (!rc)
        rc = o->step_begin(g->dev, 3 * d->n, d->h, d->scheme.first_order, s->initial_guess, hv,
                           g->x, g->v, m->gravity, g->q_t, g->sn, g->q, err);
    if (rc || !m->npres) return rc;
    /* the prescribed positions at t + h, which pl_dynamics_prescribe wrote
     * into w->q, gathered into w->qp (scratch of n x 3) and scattered on
     * the device; the scatter's change goes to g->change, which every
     * iteration clears before use */
    double *qp = ws->w.qp;
    for (int f = 0; f < m->npres; ++f) memcpy(&qp[3 * f], &ws->w.q[3 * m->pres_host[f]], 3 * sizeof(double));
    rc = o->copy(g->dev, g->pres, PL_DEVICE, qp, PL_HOST, 3 * sizeof(double) * (size_t)m->npres,
                 err);
    if (!rc) rc = o->scatter_rows(g->dev, m->npres, m->pres_map, g->pres, g->q, g->change, err);
    return rc;
}

int pl_lg_device_state_end(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx, double damping,
                           pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    lg_device_ws *g = &ws->gpu;
    const pl_device_ops *o = g->ops;
    int bad = 0;
    int rc = o->zero(g->dev, g->bad, sizeof(int), err);
    if (!rc)
        rc = o->step_end(g->dev, 3 * d->n, d->h, 1.0 / (1.0 + d->h * damping), g->q, g->q_t, g->x,
                         g->v, g->bad, err);
    /* the flag first: a step that failed leaves the states as they were */
    if (!rc) rc = o->copy(g->dev, &bad, PL_HOST, g->bad, PL_DEVICE, sizeof bad, err);
    if (rc) return rc;
    if (bad) { /* which vertex: q down, the host's test and message */
        rc = o->copy(g->dev, ws->w.q, PL_HOST, g->q, PL_DEVICE, (size_t)d->n * 3 * sizeof(double),
                     err);
        for (int f = 0; !rc && f < d->nfree; ++f) {
            const double *x = &ws->w.q[3 * d->free_vertex[f]];
            if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
                return pl_component_fail(&s->base, err, PL_EINTERNAL,
                                         "the solution became NaN/inf during step %ld (vertex %d)",
                                         ctx->data->step + 1, d->free_vertex[f]);
        }
        if (rc) return rc;
        return pl_component_fail(&s->base, err, PL_EINTERNAL,
                                 "the solution became NaN/inf during step %ld (a prescribed "
                                 "vertex)",
                                 ctx->data->step + 1);
    }
    return copy_states(s, g, ctx->data, PL_HOST, err);
}
