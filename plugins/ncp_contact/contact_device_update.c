/* contact_device_update.c - a constrained iteration of the contact
 * solver's device path (contact_device_impl.h): the row values, the
 * constraint update (phase kernels and W products, or one fused kernel)
 * and the correction, queued on the device's stream; for few rows, all
 * three in one launch (ncp_cuda_iterate_few). */
#include "contact_device_impl.h"

#include <stdlib.h>

#include "ncp_cuda_correct.h"

/* y = W x: the dense product, or H A^-1 H^T x through the device solve. */
static int product(pl_ncpc_device *g, const pl_system *sys, const double *x, double *y,
                   pl_error *err)
{
    int e;
    if (g->explicit_w) {
        e = ncp_cuda_dense(g->stream, g->in_dev, g->mcap, g->W, x, y);
        return e ? ncpc_device_cuda_fail(g, err, e, "W product") : PL_OK;
    }
    const pl_global_solver_ops *gs = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    pl_buffer Xb = {g->X, (size_t)sys->nfree, 3, PL_DEVICE, PL_F64};
    if ((e = ncp_cuda_scatter(g->stream, g->in_dev, sys->nfree, x, 1.0, g->X, g->scatter_warp)))
        return ncpc_device_cuda_fail(g, err, e, "H^T x");
    int rc = gs->solve(sys->global_solver, &Xb, &Xb, err);
    if (rc) return rc;
    e = ncp_cuda_gather(g->stream, g->in_dev, g->mcap, g->X, y);
    return e ? ncpc_device_cuda_fail(g, err, e, "H X") : PL_OK;
}

static int phase(pl_ncpc_device *g, pl_ncp_cuda_phase p, int last, pl_error *err)
{
    int e = ncp_cuda_phase_run(g->stream, p, g->in_dev, &g->V, &g->P, last);
    return e ? ncpc_device_cuda_fail(g, err, e, "constraint update") : PL_OK;
}

/* Phase p, then q with no product between them: one launch (the same
 * results; PLIANT_NCP_PHASE_PAIRS=0 keeps two). */
static int phases(pl_ncpc_device *g, pl_ncp_cuda_phase p, int last, pl_ncp_cuda_phase q,
                  int last_q, pl_error *err)
{
    if (!g->phase_pairs) {
        int rc = phase(g, p, last, err);
        return rc ? rc : phase(g, q, last_q, err);
    }
    int e = ncp_cuda_phase_run2(g->stream, p, last, q, last_q, g->in_dev, &g->V, &g->P);
    return e ? ncpc_device_cuda_fail(g, err, e, "constraint update") : PL_OK;
}

/* The grid's launches (ncp_cuda_grid.cu) return a CUDA error. */
static int grid_rc(pl_ncpc_device *g, int e, pl_error *err)
{
    return e ? ncpc_device_cuda_fail(g, err, e, "constraint update") : PL_OK;
}

/* [LIN (lin),] A: a block's phase kernel, or the grid's for many rows. */
static int step_a(pl_ncpc_device *g, int lin, pl_error *err)
{
    if (g->grid) return grid_rc(g, ncp_cuda_grid_a(g->stream, lin, g->in_dev, g->mcap, &g->V, &g->P), err);
    return lin ? phases(g, PL_NCP_PHASE_LIN, 0, PL_NCP_PHASE_A, 0, err) : phase(g, PL_NCP_PHASE_A, 0, err);
}

/* Phase p, then q unless q < 0 (B or the one-assignment phases). */
static int step_rows(pl_ncpc_device *g, pl_ncp_cuda_phase p, int q, pl_error *err)
{
    if (g->grid)
        return grid_rc(g, ncp_cuda_grid_rows(g->stream, p, q, g->in_dev, g->mcap, &g->V, &g->P), err);
    return q < 0 ? phase(g, p, 0, err) : phases(g, p, 0, (pl_ncp_cuda_phase)q, 0, err);
}

/* Phase C. */
static int step_c(pl_ncpc_device *g, pl_error *err)
{
    if (g->grid) return grid_rc(g, ncp_cuda_grid_c(g->stream, g->in_dev, g->mcap, &g->V, &g->P), err);
    return phase(g, PL_NCP_PHASE_C, 0, err);
}

/* CR's D and E_1 (first) or F_t and E_t+1 between two products. */
static int step_cr(pl_ncpc_device *g, int first, int last, pl_error *err)
{
    if (g->grid)
        return grid_rc(g, ncp_cuda_cr_grid(g->stream, first, last, g->in_dev, g->mcap, &g->V, &g->P),
                       err);
    return phases(g, first ? PL_NCP_PHASE_D : PL_NCP_PHASE_F, 0, PL_NCP_PHASE_E, last, err);
}

/* UPDATE (after the line search's product, or G). */
static int step_update(pl_ncpc_device *g, pl_error *err)
{
    if (g->grid) return grid_rc(g, ncp_cuda_grid_update(g->stream, g->in_dev, g->mcap, &g->V, &g->P), err);
    return phase(g, PL_NCP_PHASE_UPDATE, 0, err);
}

/* G, then UPDATE (no line search: no product between them). */
static int step_g_update(pl_ncpc_device *g, pl_error *err)
{
    if (!g->grid) return phases(g, PL_NCP_PHASE_G, 0, PL_NCP_PHASE_UPDATE, 0, err);
    int rc = step_rows(g, PL_NCP_PHASE_G, -1, err);
    return rc ? rc : step_update(g, err);
}

/* The constraint update: dlambda (CR), step length, lambda, projection. */
static int constraint_update(pl_ncpc_device *g, const pl_system *sys, pl_error *err)
{
    int rc = PL_OK, maxit = g->P.cr_max_iter;
    pl_ncp_cuda_vecs *V = &g->V;
    if (g->fused) { /* all of the below in one kernel */
        int e = ncp_cuda_update_fused(g->stream, g->in_dev, V, &g->P, g->W, g->jacobian,
                                      g->fused_warp, g->fused_narrow ? g->mcap : 0);
        return e ? ncpc_device_cuda_fail(g, err, e, "constraint update") : PL_OK;
    }
    /* the sequence (phases with no product between them go in pairs; over
     * a grid of blocks for many rows, `grid`):
     *   [W lambda, LIN,] A, W, B, W, C, W, D, E_1, then for t < maxit - 1:
     *   W, F_t, E_t+1 (E_t's last = t == maxit - 1); G,
     *   line search: [LAMBDA, W, LS0,] DLAMBDA, W; UPDATE */
    if (!g->jacobian) { /* linearise at delta_free + h^2 W lambda */
        rc = product(g, sys, V->lambda, V->tmp2, err);
        if (!rc) rc = step_a(g, 1, err);
    } else {
        rc = step_a(g, 0, err);
    }
    if (!rc) rc = product(g, sys, V->tmp, V->tmp2, err);
    if (!rc) rc = step_rows(g, PL_NCP_PHASE_B, -1, err);
    if (!rc) rc = product(g, sys, V->tmp, V->tmp2, err);
    if (!rc) rc = step_c(g, err);
    if (!rc) rc = product(g, sys, V->tmp, V->tmp2, err);
    if (!rc) {
        if (maxit > 1)
            rc = step_cr(g, 1, maxit == 2, err);
        else
            rc = phase(g, PL_NCP_PHASE_D, 0, err);
    }
    for (int t = 1; !rc && t < maxit - 1; ++t) { /* E_t ran; not the last */
        rc = product(g, sys, V->tmp, V->tmp2, err);
        if (!rc) rc = step_cr(g, 0, t + 1 == maxit - 1, err);
    }
    if (rc) return rc;
    if (!g->P.line_search) return step_g_update(g, err);
    if (g->jacobian) {
        rc = step_rows(g, PL_NCP_PHASE_G, PL_NCP_PHASE_LAMBDA, err);
        if (!rc) rc = product(g, sys, V->force, V->tmp2, err);
        if (!rc) rc = step_rows(g, PL_NCP_PHASE_LS0, PL_NCP_PHASE_DLAMBDA, err);
    } else {
        rc = step_rows(g, PL_NCP_PHASE_G, PL_NCP_PHASE_DLAMBDA, err);
    }
    if (!rc) rc = product(g, sys, V->force, V->tmp2, err);
    if (!rc) rc = step_update(g, err);
    return rc;
}

/* The constraint update of an iteration queued eagerly (a step's first:
 * the loop records the others) from a graph: on the phase kernels' path
 * with W explicit that is about 40 launches whose host cost (6-10 us each on
 * the H100's host) exceeds their run time (3-4 us each), so the GPU waited
 * for the host.  The graph holds the same launches with the same arguments
 * (device addresses, capacities and parameters: what graph_key keeps, the
 * rows' sizes read on the device), so it is recorded once an epoch and
 * replayed while the epoch stays.  Only with W explicit: a matrix-free
 * product runs the global solver's launches, whose buffers are not this
 * path's to key.  Not while the stream records (the loop capturing an
 * iteration: its graph takes the launches), with graphs off or the
 * profile's flag, or with PLIANT_NCP_UPDATE_GRAPH=0. */
static int graph_wanted(const pl_ncpc_device *g)
{
    int flags = g->ops->flags ? g->ops->flags(g->dev) : 0;
    return g->update_graph_env && g->explicit_w && !g->fused && g->ops->capture_begin &&
           (flags & PL_DEVICE_GRAPHS) && !(flags & PL_DEVICE_PROFILE) &&
           !ncp_cuda_capturing(g->stream);
}

static int update_from_graph(pl_ncpc_device *g, pl_ctx *ctx, const pl_system *sys, pl_error *err)
{
    int rc;
    if (g->update_graph && g->update_epoch != g->epoch) { /* stale: its buffers moved */
        if ((rc = g->ops->sync(g->dev, err))) return rc;
        g->ops->graph_free(g->dev, g->update_graph);
        g->update_graph = NULL;
    }
    if (!g->update_graph) {
        if ((rc = g->ops->capture_begin(g->dev, err))) return rc;
        rc = constraint_update(g, sys, err);
        void *graph = NULL;
        pl_error e2;
        int rc2 = g->ops->capture_end(g->dev, &graph, rc ? &e2 : err);
        if (rc || rc2) {
            g->ops->graph_free(g->dev, graph);
            return rc ? rc : rc2;
        }
        g->update_graph = graph;
        g->update_epoch = g->epoch;
    }
    double total = 0.0; /* over every data of the timers: a test sees the path taken */
    pl_stat_get(ctx->timers, "contact update graph replays", &total);
    pl_stat_set(ctx->timers, "contact update graph replays", total + 1.0);
    return g->ops->replay(g->dev, g->update_graph, err);
}

/* q_next = q_free + h2 A^-1 H^T (S lambda), force = S lambda: with few
 * rows one dense product with the step's U, else H^T (force and it, one
 * launch), the device solve and the sum. */
static int correction(pl_ncpc_device *g, const pl_system *sys, double h2, pl_buffer *q_next,
                      pl_error *err)
{
    int e, nf = sys->nfree;
    if (g->dense) {
        e = ncp_cuda_correct_dense(g->stream, g->in_dev, g->mcap, nf, g->V.scale, g->V.lambda, h2,
                                   g->U, g->q_free, g->V.force, q_next->data);
        return e ? ncpc_device_cuda_fail(g, err, e, "correction") : PL_OK;
    }
    if ((e = ncp_cuda_scatter_scaled(g->stream, g->in_dev, g->mcap, nf, g->V.scale, g->V.lambda,
                                     h2, g->V.force, g->corr, g->scatter_warp)))
        return ncpc_device_cuda_fail(g, err, e, "H^T lambda");
    pl_buffer cb = {g->corr, (size_t)nf, 3, PL_DEVICE, PL_F64};
    const pl_global_solver_ops *gs = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    int rc = gs->solve(sys->global_solver, &cb, &cb, err);
    if (!rc && (e = ncp_cuda_add(g->stream, 3L * nf, g->q_free, g->corr, q_next->data)))
        rc = ncpc_device_cuda_fail(g, err, e, "correction");
    return rc;
}

/* stickStart: delta_free down, the host's stick start (st->stick), lambda
 * up.  A step's first iterate only, which the loop runs eagerly (never in
 * a graph): the copy down waits for the device. */
static int stick_start(pl_ncpc_device *g, const pl_ncpc_device_step *st, pl_error *err)
{
    size_t bytes = sizeof(double) * (size_t)g->R.m;
    double *df = malloc(bytes ? bytes : 1);
    if (!df) return ncpc_device_fail(g, err, PL_EINTERNAL, "out of memory");
    int rc = g->ops->copy(g->dev, df, PL_HOST, g->V.delta_free, PL_DEVICE, bytes, err);
    int n = rc ? 0 : st->stick(st->stick_user, df, err);
    free(df);
    if (!rc && n < 0) rc = -n;
    if (!rc && n > 0) rc = g->ops->copy(g->dev, g->V.lambda, PL_DEVICE, st->lambda, PL_HOST, bytes, err);
    return rc;
}

int ncpc_device_constrained(pl_ncpc_device *g, const pl_ncpc_device_step *st, pl_ctx *ctx,
                            const pl_system *sys, const pl_buffer *q_k, pl_buffer *q_next,
                            int profile, pl_error *err)
{
    int rc;
    /* few rows: one launch, without the stick start's host round trip
     * (after the row values) and the profile's timers (between the parts) */
    if (g->one && !st->stick && !profile) {
        int e = ncp_cuda_iterate_few(g->stream, g->in_dev, &g->V, &g->P, g->W, g->jacobian,
                                     g->q_free, q_k->data, sys->nfree, st->h * st->h, g->U,
                                     q_next->data);
        return e ? ncpc_device_cuda_fail(g, err, e, "iteration") : PL_OK;
    }
    int e = 0;
    ncpc_device_lap(g, ctx, profile, st->t_assembly, 1, err);
    if (g->jacobian) /* delta at q_k and delta_free at q_free, one launch */
        e = ncp_cuda_delta2(g->stream, g->in_dev, g->mcap, g->q_free, q_k->data, g->V.delta,
                            g->V.delta_free);
    else
        e = ncp_cuda_delta(g->stream, g->in_dev, g->mcap, g->q_free, q_k->data, 0, g->V.delta_free);
    if (e) return ncpc_device_cuda_fail(g, err, e, "row values");
    if ((rc = ncpc_device_lap(g, ctx, profile, st->t_assembly, 0, err))) return rc;
    ncpc_device_lap(g, ctx, profile, st->t_solve, 1, err);
    if (st->stick && (rc = stick_start(g, st, err))) return rc;
    rc = graph_wanted(g) ? update_from_graph(g, ctx, sys, err) : constraint_update(g, sys, err);
    if (!rc) rc = ncpc_device_lap(g, ctx, profile, st->t_solve, 0, err);
    if (rc) return rc;
    /* q^{k+1} = q_free + h^2 A^-1 H^T (S lambda) */
    ncpc_device_lap(g, ctx, profile, st->t_corr, 1, err);
    rc = correction(g, sys, st->h * st->h, q_next, err);
    if (!rc) rc = ncpc_device_lap(g, ctx, profile, st->t_corr, 0, err);
    return rc;
}
