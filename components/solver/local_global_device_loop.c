/* local_global_device_loop.c - how the device path's K iterations of a step
 * are launched (local_global_device.c queues one iteration).
 *
 * Iteration 0 of a step is always queued eagerly: terms upload their
 * per-step data (ADMM duals) and the contact solver runs stickStart when
 * first called in a step.  Iterations 1 .. K-1 then run in one of two ways.
 *
 * The device loop (device ops version 3, PL_DEVICE_LOOPS: a CUDA 12.4+ GPU
 * with CudaDevice graph="1"; used when tolerance or forceTolerance decides
 * when to stop, or with PLIANT_DEVICE_LOOP=device): the service's loop() queues
 *     while (pl_device_loop_rule(state, change, residual)) iteration;
 * as one graph (CUDA: a conditional WHILE node over one captured
 * iteration), so the stopping rule (pliant/device_loop.h: the CPU's
 * tolerance, forceTolerance, the cap and the NaN check, in the CPU's
 * order) is applied on the device and the host launches once per step and
 * reads {iterations done, last residual, NaN flag} once at its end, instead
 * of one launch and, with a tolerance, one read-back and wait per
 * iteration (stat "device loop steps": the steps that took this way).  The iterations, counts and positions are those of the other
 * way (and of the CPU: test_lg_device, gpu_loop).  Not with computeEnergy
 * (q comes back every iteration for the energy), profile (a sync per
 * phase), no unknowns, or PLIANT_DEVICE_LOOP=host (a diagnostic: the
 * other way, for comparisons).  A fixed count keeps the other way by
 * default: the host queues its replays without waiting, and on the H100
 * the loop's rule kernel cost stick_slip.xml (10 iterations) 2.54 against
 * 2.49 ms a frame.
 *
 * Otherwise one iteration at a time from the host: eager, or (graph="1")
 * iteration 1 captured as a graph and replayed for the next ones, the
 * change and residual read after each iteration when a tolerance asks.
 *
 * Either graph is kept across steps in graph[0] (steps without rows) or
 * graph[1] (with the contact solver's iterate), captured again only when
 * the contact solver's graph_epoch moves (its buffers, capacities or
 * parameters changed), when the device's flags change, or every step with
 * rows for a solver without graph_epoch (or PLIANT_DEVICE_GRAPH_REUSE=0). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "local_global.h"

/* The contact solver's graph_epoch for this data (0 without one). */
static unsigned long contact_epoch(const local_global_solver *s, pl_ctx *ctx)
{
    const pl_contact_solver_ops *cs =
        s->contact ? pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER) : NULL;
    return cs && cs->version >= 3 && cs->graph_epoch ? cs->graph_epoch(s->contact, ctx->data) : 0;
}

/* Whether a graph holding the contact solver's iterate may be replayed in
 * later steps: the solver says when it goes stale (graph_epoch).
 * PLIANT_DEVICE_GRAPH_REUSE=0 (a diagnostic) captures it every step. */
static int rows_graph_reusable(const local_global_solver *s)
{
    const pl_contact_solver_ops *cs =
        s->contact ? pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER) : NULL;
    const char *env = getenv("PLIANT_DEVICE_GRAPH_REUSE");
    return cs && cs->version >= 3 && cs->graph_epoch && !(env && !strcmp(env, "0"));
}

static int drop_graph(lg_device_ws *g, int k, pl_error *err)
{
    if (!g->graph[k]) return PL_OK;
    int rc = g->ops->sync(g->dev, err); /* nothing may still run it */
    if (rc) return rc;
    g->ops->graph_free(g->dev, g->graph[k]);
    g->graph[k] = NULL;
    return PL_OK;
}

int pl_lg_device_graphs_begin_step(const local_global_solver *s, lg_device_ws *g, int flags,
                                   pl_error *err)
{
    for (int k = 0; k < 2; ++k) {
        int drop = flags != g->flags || (k == 1 && g->nrows > 0 && !rows_graph_reusable(s));
        int rc = drop ? drop_graph(g, k, err) : PL_OK;
        if (rc) return rc;
    }
    g->flags = flags;
    return PL_OK;
}

/* The graph slot of this step (1 with rows), emptied when the contact
 * solver's buffers moved since its capture or when it holds the other kind
 * (loop: a device loop, else one iteration); *epoch: the epoch now. */
static int graph_slot(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx, int loop,
                      int *slot, unsigned long *epoch, pl_error *err)
{
    *slot = g->nrows > 0;
    *epoch = *slot ? contact_epoch(s, ctx) : 0;
    if ((*slot && *epoch != g->graph_epoch) || g->graph_loop[*slot] != loop)
        return drop_graph(g, *slot, err);
    return PL_OK;
}

/* A graph was recorded into slot: counted (stat "device graph captures"). */
static void captured(lg_device_ws *g, pl_ctx *ctx, int slot, int loop, unsigned long epoch)
{
    if (slot) g->graph_epoch = epoch;
    g->graph_loop[slot] = (unsigned char)loop;
    g->captures++;
    double total = 0.0; /* over every data of the timers */
    pl_stat_get(ctx->timers, "device graph captures", &total);
    pl_stat_set(ctx->timers, "device graph captures", total + 1.0);
}

/* Iteration `it` of a step from the host: eager, or through the graph
 * captured at the second iteration when there is none. */
static int run_iteration(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx, int it,
                         pl_error *err)
{
    int profile = (g->flags & PL_DEVICE_PROFILE) != 0;
    if (profile || !(g->flags & PL_DEVICE_GRAPHS) || it == 0)
        return pl_lg_device_iteration(s, g, ctx, profile, err);
    int r;
    unsigned long epoch;
    int rc = graph_slot(s, g, ctx, 0, &r, &epoch, err);
    if (rc) return rc;
    if (!g->graph[r]) {
        rc = g->ops->capture_begin(g->dev, err);
        if (rc) return rc;
        captured(g, ctx, r, 0, epoch);
        rc = pl_lg_device_iteration(s, g, ctx, 0, err);
        pl_error e2;
        int rc2 = g->ops->capture_end(g->dev, &g->graph[r], rc ? &e2 : err);
        if (rc || rc2) {
            g->ops->graph_free(g->dev, g->graph[r]);
            g->graph[r] = NULL;
            return rc ? rc : rc2;
        }
    }
    return g->ops->replay(g->dev, g->graph[r], err);
}

/* The iterations one at a time, the CPU's rule applied on the host after
 * each (a read-back and wait when a tolerance asks for it). */
static int host_loop(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx, double scale,
                     pl_dyn_work *w, int *done, double *residual, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    const pl_device_ops *o = g->ops;
    size_t n3 = (size_t)d->n * 3 * sizeof(double);
    int rc = PL_OK, ftol = s->force_tolerance > 0 && d->nfree > 0;
    for (int it = 0; !rc && it < s->iterations; ++it) {
        rc = run_iteration(s, g, ctx, it, err);
        *done = it + 1;
        if (rc || !(s->tolerance > 0 || ftol || s->compute_energy) || d->nfree == 0) continue;
        double change = 0.0;
        if (s->tolerance > 0)
            rc = o->copy(g->dev, &change, PL_HOST, g->change, PL_DEVICE, sizeof change, err);
        if (!rc && ftol)
            rc = o->copy(g->dev, residual, PL_HOST, g->residual, PL_DEVICE, sizeof *residual, err);
        if (!rc && s->compute_energy) {
            rc = o->copy(g->dev, w->q, PL_HOST, g->q, PL_DEVICE, n3, err);
            if (!rc)
                pl_series_push(ctx->timers, "energy", pl_dynamics_energy(d, w, ctx->data, w->q));
        }
        if (rc) break;
        if (!isfinite(change))
            return pl_component_fail(&s->base, err, PL_EINTERNAL,
                                     "the solution became NaN/inf at iteration %d of step %ld",
                                     it + 1, ctx->data->step + 1);
        if ((s->tolerance > 0 || ftol) && (s->tolerance <= 0 || change < s->tolerance * scale) &&
            (!ftol || *residual < s->force_tolerance))
            break;
    }
    return rc;
}

/* Whether this step's iterations 1 .. K-1 run as one device loop: where
 * a tolerance decides when to stop (a fixed count makes the host wait for
 * nothing between iterations; its replays are queued ahead, and the rule
 * kernel would only add a launch an iteration), or always with
 * PLIANT_DEVICE_LOOP=device, never with PLIANT_DEVICE_LOOP=host. */
static int device_loop_wanted(const local_global_solver *s, const lg_device_ws *g)
{
    const char *env = getenv("PLIANT_DEVICE_LOOP");
    const pl_device_ops *o = g->ops;
    int decides = s->tolerance > 0 || s->force_tolerance > 0;
    if (env && !strcmp(env, "host")) return 0;
    if (env && !strcmp(env, "device")) decides = 1;
    return decides && g->loop && o->version >= 3 && o->loop && (g->flags & PL_DEVICE_LOOPS) &&
           !(g->flags & PL_DEVICE_PROFILE) && !s->compute_energy && s->dyn.nfree > 0;
}

typedef struct body_arg {
    const local_global_solver *s;
    lg_device_ws *g;
    pl_ctx *ctx;
} body_arg;

/* The loop's body: one iteration queued (recorded when the service
 * records the loop as a graph). */
static int body(void *p, pl_error *err)
{
    body_arg *a = p;
    return pl_lg_device_iteration(a->s, a->g, a->ctx, 0, err);
}

/* Iteration 0 eagerly, then the rest as one device loop; one read-back. */
static int device_loop(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx, double scale,
                       int *done, double *residual, pl_error *err)
{
    const pl_device_ops *o = g->ops;
    int ftol = s->force_tolerance > 0;
    pl_device_loop st = {.iterations = s->iterations,
                         .tolerance = s->tolerance > 0 ? s->tolerance : 0.0,
                         .scale = scale,
                         .force_tolerance = ftol ? s->force_tolerance : 0.0,
                         .residual = NAN};
    int rc = o->copy(g->dev, g->loop, PL_DEVICE, &st, PL_HOST, sizeof st, err);
    if (!rc) rc = pl_lg_device_iteration(s, g, ctx, 0, err);
    int slot;
    unsigned long epoch;
    if (!rc) rc = graph_slot(s, g, ctx, 1, &slot, &epoch, err);
    if (rc) return rc;
    void *before = g->graph[slot];
    body_arg a = {s, g, ctx};
    rc = o->loop(g->dev, body, &a, g->loop, g->change, ftol ? g->residual : NULL,
                 &g->graph[slot], err);
    if (!before && g->graph[slot]) captured(g, ctx, slot, 1, epoch);
    if (!rc) rc = o->copy(g->dev, &st, PL_HOST, g->loop, PL_DEVICE, sizeof st, err);
    if (rc) return rc;
    *done = st.done;
    if (ftol) *residual = st.residual;
    double total = 0.0; /* steps of every data of the timers that took this way */
    pl_stat_get(ctx->timers, "device loop steps", &total);
    pl_stat_set(ctx->timers, "device loop steps", total + 1.0);
    if (st.nonfinite)
        return pl_component_fail(&s->base, err, PL_EINTERNAL,
                                 "the solution became NaN/inf at iteration %d of step %ld",
                                 st.nonfinite, ctx->data->step + 1);
    return PL_OK;
}

int pl_lg_device_iterate(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx, double scale,
                         int *done, double *residual, pl_error *err)
{
    lg_device_ws *g = &ws->gpu;
    *done = 0;
    if (device_loop_wanted(s, g)) return device_loop(s, g, ctx, scale, done, residual, err);
    return host_loop(s, g, ctx, scale, &ws->w, done, residual, err);
}
