/* local_global_device.c - the LocalGlobalSolver's iterations on a device
 * (device = "cuda", or "auto" with a CudaDevice in the scene).
 *
 * libpliant knows no CUDA: everything goes through the device service
 * found by role (pl_device_ops, plugins/cuda).  Per time step:
 *   host:   gather q_t, v_t from the states, sn = q_t + h v_t + h^2 g
 *           (with firstOrder and rayleighStiffness as on the CPU, dynamics.h:
 *           their terms are in sn and in the inertia masses copied below),
 *           q = sn with the prescribed vertices at t + h (as on the CPU);
 *   copy:   sn and q to the device (page-locked host buffers);
 *   device: K iterations of
 *             rhs = M' sn; every local term's project(q, rhs) on device
 *             buffers; b_f = rhs restricted to the unknowns - A_fp q_p;
 *             q_f = solve(b_f) by the global solver on device buffers;
 *             q[free] = q_f (and the largest change, for tolerances);
 *           the first iteration of each step eager (terms upload their
 *           per-step data, such as ADMM duals, when first called in a step),
 *           the others as one device loop with the stopping rule on the
 *           device, or one at a time through a replayed graph
 *           (local_global_device_loop.c);
 * The model's arrays (masses, the free-vertex map, A_fp) go to the device
 * once, at reinit; each pl_data has its own vectors and graph, in the
 * solver's workspace, so several data step over one model on the device.
 *   copy:   q back to the host once, then v = (q - q_t) / h and the
 *           scatter into the states on the host.
 * Or, for a step whose vectors the host needs for nothing else (no rows,
 * host residual, energy, tolerance or Rayleigh damping), the start and the
 * end on the device: local_global_device_state.c.
 * Without the device loop q comes back every iteration only when
 * tolerance > 0 (the change, one number) or computeEnergy is set (all of
 * q, for the energy).
 * Constraints (contact, cables): the rows and the contact solver's begin
 * run on the host at the start of the step (with q_t, as on the CPU path);
 * when there are rows, each iteration's global step is the contact
 * solver's iterate() on the device buffers (its device path queues the
 * constraint update and the correction on the same stream), and after the
 * copy of q the multipliers go to the constraints on the host.  The
 * contact solver's kernels read the step's rows from a device descriptor
 * and are sized by a capacity of rows, so the graph holding its iterate
 * replays later steps' rows too (graph_epoch: local_global_device_loop.c).  The contact solver must have a device path: a field "device"
 * whose value is not "cpu" (NonSmoothNewtonContactSolver in a CUDA build;
 * pl_contact_solver_ops has no accepts member yet). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "local_global.h"
#include "pliant/util.h"

/* Appends to a reason message (truncated silently: it is only a message). */
static void say(char *buf, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void say(char *buf, size_t size, const char *fmt, ...)
{
    size_t len = strlen(buf);
    if (len + 1 >= size) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf + len, size - len, fmt, ap);
    va_end(ap);
}

/* Why the loop cannot run on the device, or "" when it can. */
static void device_refusals(local_global_solver *s, char *why, size_t size)
{
    pl_dynamics *d = &s->dyn;
    char path[256];
    why[0] = '\0';
    pl_lg_device_residual_refusals(s, why, size); /* forceTolerance */
    if (s->contact) {
        const pl_field *f = pl_component_field(s->contact, "device");
        char v[64] = "";
        if (!f || pl_field_format(f, s->contact, v, sizeof v) != PL_OK || !strcmp(v, "cpu"))
            say(why, size,
                "%sthe contact solver %s (%s) has no device path here (NonSmoothNewtonContactSolver "
                "in a CUDA build with device=\"auto\" has one)",
                why[0] ? "; " : "", pl_component_path(s->contact, path, sizeof path),
                s->contact->type->name);
    }
    const pl_global_solver_ops *gs = pl_component_role(s->solver, PL_ROLE_GLOBAL_SOLVER);
    if (!(gs->version >= 2 && gs->accepts && gs->accepts(s->solver, PL_DEVICE, PL_F64)))
        say(why, size,
            "%sthe global solver %s (%s) does not take device buffers (SparseInverseSolver: set "
            "device=\"cuda\" or \"auto\" on it)",
            why[0] ? "; " : "", pl_component_path(s->solver, path, sizeof path),
            s->solver->type->name);
    int first = 1;
    for (int k = 0; k < d->nterms; ++k) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[k], PL_ROLE_LOCAL_TERM);
        if (ops->version >= 2 && ops->accepts && ops->accepts(d->terms[k], PL_DEVICE, PL_F64))
            continue;
        if (first)
            say(why, size,
                "%slocal terms without a device local step (ARAP, Corotational, NeoHookean, "
                "the bending terms, PositionTarget and ConstantForceField have one):",
                why[0] ? "; " : "");
        say(why, size, "%s %s (%s)", first ? "" : ",",
            pl_component_path(d->terms[k], path, sizeof path), d->terms[k]->type->name);
        first = 0;
    }
}

/* The device service for this solver, or NULL (why says why). */
static pl_component *find_device(local_global_solver *s, char *why, size_t size)
{
    pl_component *c = &s->base, *dev = pl_util_device(c);
    why[0] = '\0';
    if (!dev) {
        pl_component *absent = pl_node_find_role_up(c->node, PL_ROLE_DEVICE);
        if (absent)
            snprintf(why, size, "the device service %s has no device here (no GPU answers, or "
                     "this build has no CUDA)", absent->name);
        else
            snprintf(why, size,
                     "no device service in this node or above (add <RequiredPlugin "
                     "name=\"cuda\"/> and <CudaDevice/> to the root node, in a CUDA build)");
        return NULL;
    }
    const pl_device_ops *ops = pl_component_role(dev, PL_ROLE_DEVICE);
    if (ops->version < 1) {
        snprintf(why, size, "the device service %s is of an unknown version", dev->name);
        return NULL;
    }
    /* components of a node are destroyed in reverse order: the device must
     * outlive this solver, which frees its memory through it */
    if (dev->node == c->node)
        for (int k = 0; k < c->node->ncomponents; ++k) {
            if (c->node->components[k] == dev) break;
            if (c->node->components[k] == c) {
                snprintf(why, size,
                         "%s must come before the solver in the scene (it has to "
                         "outlive it)",
                         dev->name);
                return NULL;
            }
        }
    return dev;
}

void *pl_lg_dalloc(pl_component *dev, const pl_device_ops *ops, size_t bytes, int *rc,
                   pl_error *err)
{
    if (*rc) return NULL;
    void *p = ops->alloc(dev, bytes, err);
    if (!p) *rc = err->code ? err->code : PL_EINTERNAL;
    return p;
}

static void put(lg_device *g, void *dst, const void *src, size_t bytes, int *rc, pl_error *err)
{
    if (!*rc && bytes) *rc = g->ops->copy(g->dev, dst, PL_DEVICE, src, PL_HOST, bytes, err);
}

/* The rows of nm CSC matrices side by side (each nrows tall) as one host
 * CSR with ncols columns: the entries of M[k]'s column j go to column
 * cols[k][j] (j itself where cols[k] is NULL).  Within a row the entries
 * keep the order of the matrices, then of their columns: the order in which
 * the CPU loop subtracts them.  R's arrays are the caller's to free, also
 * on failure. */
int pl_lg_csc_rows(const pl_csc *const *M, const int *const *cols, int nm, int nrows, int ncols,
                   pl_csr *R)
{
    int nnz = 0;
    for (int k = 0; k < nm; ++k) nnz += pl_csc_nnz(M[k]);
    R->nrows = nrows, R->ncols = ncols;
    R->p = calloc((size_t)nrows + 1, sizeof *R->p);
    R->j = malloc((size_t)(nnz ? nnz : 1) * sizeof *R->j);
    R->x = malloc((size_t)(nnz ? nnz : 1) * sizeof *R->x);
    int *next = malloc((size_t)(nrows ? nrows : 1) * sizeof *next);
    if (!R->p || !R->j || !R->x || !next) {
        free(next);
        return PL_EINTERNAL;
    }
    for (int k = 0; k < nm; ++k)
        for (int p = 0; p < pl_csc_nnz(M[k]); ++p) R->p[M[k]->i[p] + 1]++;
    for (int r = 0; r < nrows; ++r) R->p[r + 1] += R->p[r];
    memcpy(next, R->p, (size_t)nrows * sizeof *next);
    for (int k = 0; k < nm; ++k)
        for (int j = 0; j < M[k]->ncols; ++j)
            for (int p = M[k]->p[j]; p < M[k]->p[j + 1]; ++p) {
                int q = next[M[k]->i[p]]++;
                R->j[q] = cols[k] ? cols[k][j] : j;
                R->x[q] = M[k]->x[p];
            }
    free(next);
    return PL_OK;
}

/* The local terms of different states write different rows of rhs, so
 * their projects may run side by side (device ops version 5): a branch a
 * state, the terms of one state in one branch in their order, so that
 * every value is the one-stream run's, bitwise (a soft gripper's fingers
 * and body: each local step is a kernel of a few us that leaves the GPU
 * mostly idle).  Nothing to do with fewer than two states, without branch
 * or with PLIANT_DEVICE_BRANCHES=0 (a diagnostic). */
static int plan_branches(const pl_dynamics *d, lg_device *g, pl_error *err)
{
    const char *env = getenv("PLIANT_DEVICE_BRANCHES");
    if (g->ops->version < 5 || !g->ops->branch || (env && !strcmp(env, "0")) || d->nterms < 2)
        return PL_OK;
    int *br = malloc(sizeof(int) * (size_t)d->nterms), states = 0;
    if (!br) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ot = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        br[t] = 0;
        for (int u = 0; u < t && !br[t]; ++u) {
            const pl_local_term_ops *ou = pl_component_role(d->terms[u], PL_ROLE_LOCAL_TERM);
            if (ou->state(d->terms[u]) == ot->state(d->terms[t])) br[t] = br[u];
        }
        if (!br[t]) br[t] = states++ % PL_DEVICE_BRANCHES + 1;
    }
    if (states < 2) {
        free(br);
        return PL_OK;
    }
    g->term_branch = br;
    g->nbranch = states < PL_DEVICE_BRANCHES ? states : PL_DEVICE_BRANCHES;
    return PL_OK;
}

/* Queues every local term's project (on their branches, closed again before
 * returning, errors included). */
static int project_terms(const local_global_solver *s, const lg_device_ws *g, pl_ctx *ctx,
                         const pl_buffer *qb, pl_buffer *rb, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    const int *br = s->gpu.term_branch;
    int rc = PL_OK;
    for (int t = 0; !rc && t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        if (br) rc = g->ops->branch(g->dev, br[t], err);
        if (!rc)
            rc = ops->project(d->terms[t], ctx->data, d->term_offset[t], d->h * d->h, qb, rb, err);
    }
    if (br) {
        pl_error e2;
        int rc2 = g->ops->branch(g->dev, 0, rc ? &e2 : err);
        if (!rc) rc = rc2;
    }
    return rc;
}

/* The model's arrays on the device. */
static int allocate(local_global_solver *s, pl_error *err)
{
    pl_dynamics *d = &s->dyn;
    lg_device *g = &s->gpu;
    int rc = PL_OK;
    g->mass = pl_lg_dalloc(g->dev, g->ops, (size_t)d->n * sizeof(double), &rc, err);
    g->free_vertex =
        pl_lg_dalloc(g->dev, g->ops, (size_t)(d->nfree ? d->nfree : 1) * sizeof(int), &rc, err);
    put(g, g->mass, d->inertia, (size_t)d->n * sizeof(double), &rc, err);
    put(g, g->free_vertex, d->free_vertex, (size_t)d->nfree * sizeof(int), &rc, err);
    if (rc) return rc;
    pl_csr R = {0};
    const pl_csc *fp[1] = {&d->A_fp};
    const int *fp_cols[1] = {NULL}; /* A_fp's columns are global already */
    if (pl_lg_csc_rows(fp, fp_cols, 1, d->A_fp.nrows, d->A_fp.ncols, &R) != PL_OK) {
        pl_csr_free(&R);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    }
    int nnz = pl_csr_nnz(&R);
    g->fp_nnz = nnz;
    g->A_fp.nrows = R.nrows, g->A_fp.ncols = R.ncols;
    g->A_fp.p = pl_lg_dalloc(g->dev, g->ops, ((size_t)R.nrows + 1) * sizeof(int), &rc, err);
    g->A_fp.j = pl_lg_dalloc(g->dev, g->ops, (size_t)(nnz ? nnz : 1) * sizeof(int), &rc, err);
    g->A_fp.x = pl_lg_dalloc(g->dev, g->ops, (size_t)(nnz ? nnz : 1) * sizeof(double), &rc, err);
    put(g, g->A_fp.p, R.p, ((size_t)R.nrows + 1) * sizeof(int), &rc, err);
    put(g, g->A_fp.j, R.j, (size_t)nnz * sizeof(int), &rc, err);
    put(g, g->A_fp.x, R.x, (size_t)nnz * sizeof(double), &rc, err);
    pl_csr_free(&R);
    if (!rc) rc = g->ops->sync(g->dev, err); /* the host arrays above may go */
    if (!rc) rc = pl_lg_device_residual_setup(s, err);
    if (!rc) rc = plan_branches(d, g, err);
    if (!rc) rc = pl_lg_device_state_setup(s, err);
    return rc;
}

int pl_lg_device_ws_alloc(const local_global_solver *s, lg_ws *ws, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    lg_device_ws *g = &ws->gpu;
    size_t n3 = (size_t)d->n * 3 * sizeof(double);
    size_t f3 = (size_t)(d->nfree ? d->nfree : 1) * 3 * sizeof(double);
    int rc = PL_OK;
    pl_lg_device_ws_free(ws);
    g->dev = s->gpu.dev;
    g->ops = s->gpu.ops;
    g->flags = g->ops->flags ? g->ops->flags(g->dev) : 0;
    g->q = pl_lg_dalloc(g->dev, g->ops, n3, &rc, err);
    g->sn = pl_lg_dalloc(g->dev, g->ops, n3, &rc, err);
    g->rhs = pl_lg_dalloc(g->dev, g->ops, n3, &rc, err);
    g->b_free = pl_lg_dalloc(g->dev, g->ops, f3, &rc, err);
    g->q_free = pl_lg_dalloc(g->dev, g->ops, f3, &rc, err);
    /* change, then with forceTolerance the residual and the gradient (n x 3):
     * one block, so that one memset clears them at the start of an iteration */
    int ftol = s->force_tolerance > 0;
    g->scalars = ftol ? 2 + (size_t)d->n * 3 : 1;
    g->change = pl_lg_dalloc(g->dev, g->ops, g->scalars * sizeof(double), &rc, err);
    if (g->ops->version >= 3 && g->ops->loop)
        g->loop = pl_lg_dalloc(g->dev, g->ops, sizeof(pl_device_loop), &rc, err);
    if (!rc) rc = pl_lg_device_residual_ws_alloc(s, g, err);
    if (!rc) rc = pl_lg_device_state_ws_alloc(s, g, err);
    if (rc) {
        pl_lg_device_ws_free(ws);
        return rc;
    }
    /* page-locked q and sn: their copies are the per-step traffic */
    pl_error pe;
    if (g->ops->pin && g->ops->pin(g->dev, ws->w.q, n3, &pe) == PL_OK) {
        if (g->ops->pin(g->dev, ws->w.sn, n3, &pe) == PL_OK) {
            g->pinned_q = ws->w.q;
            g->pinned_sn = ws->w.sn;
        } else {
            g->ops->unpin(g->dev, ws->w.q);
        }
    }
    return PL_OK;
}

void pl_lg_device_ws_free(lg_ws *ws)
{
    lg_device_ws *g = &ws->gpu;
    if (!g->dev) return;
    const pl_device_ops *o = g->ops;
    pl_error err;
    o->sync(g->dev, &err); /* nothing may still use the buffers */
    for (int k = 0; k < 2; ++k)
        if (g->graph[k]) o->graph_free(g->dev, g->graph[k]);
    void *bufs[] = {g->q, g->sn, g->rhs, g->b_free, g->q_free, g->change, g->loop};
    for (size_t k = 0; k < sizeof bufs / sizeof bufs[0]; ++k) o->free(g->dev, bufs[k]);
    pl_lg_device_residual_ws_free(g);
    pl_lg_device_state_ws_free(g);
    if (g->pinned_q) o->unpin(g->dev, g->pinned_q);
    if (g->pinned_sn) o->unpin(g->dev, g->pinned_sn);
    memset(g, 0, sizeof *g);
}

int pl_lg_device_setup(local_global_solver *s, pl_ctx *ctx)
{
    pl_component *c = &s->base;
    char why[1024], path[256];
    if (s->device == 0) return PL_OK;
    pl_component *dev = find_device(s, why, sizeof why);
    if (dev) device_refusals(s, why, sizeof why);
    if (why[0]) {
        if (s->device == 1)
            return pl_component_error(c, ctx, PL_EINPUT, "device=\"cuda\": %s", why);
        /* auto is the default: a scene without a device service runs on the
         * CPU silently; one with a device says why it is not used */
        if (dev)
            pl_log_info("%s: device=\"auto\" runs on the CPU: %s",
                        pl_component_path(c, path, sizeof path), why);
        return PL_OK;
    }
    lg_device *g = &s->gpu;
    g->dev = dev;
    g->ops = pl_component_role(dev, PL_ROLE_DEVICE);
    pl_error err;
    pl_error_clear(&err);
    int rc = allocate(s, &err);
    if (rc) {
        pl_lg_device_free(s);
        return pl_component_error(c, ctx, rc, "device buffers: %s", err.msg);
    }
    return PL_OK;
}

void pl_lg_device_free(local_global_solver *s)
{
    lg_device *g = &s->gpu;
    if (!g->dev) return;
    const pl_device_ops *o = g->ops;
    pl_error err;
    o->sync(g->dev, &err); /* nothing may still use the buffers */
    void *bufs[] = {g->mass, g->free_vertex, g->A_fp.p, g->A_fp.j, g->A_fp.x};
    for (size_t k = 0; k < sizeof bufs / sizeof bufs[0]; ++k) o->free(g->dev, bufs[k]);
    pl_lg_device_residual_free(g);
    pl_lg_device_state_free(g);
    free(g->term_branch);
    memset(g, 0, sizeof *g);
}

int pl_lg_device_gather_sub(const lg_device_ws *g, int m, const int *map, const double *x,
                            const pl_csr *A, const double *q, double *y, pl_error *err)
{
    const pl_device_ops *o = g->ops;
    if (o->version >= 3 && o->gather_sub_csr)
        return o->gather_sub_csr(g->dev, m, map, x, A, q, y, err);
    int rc = o->gather_rows(g->dev, m, map, x, y, err);
    return rc || !A ? rc : o->sub_csr(g->dev, A, q, y, err);
}

/* Waits for the device when profiling, so that the phase timer is right. */
static int phase_end(const lg_device_ws *g, pl_ctx *ctx, int timer, pl_error *err)
{
    int rc = g->ops->sync(g->dev, err);
    pl_timer_stop(ctx->timers, timer);
    return rc;
}

/* One iteration queued on the device: rhs, local step, reduction to the
 * unknowns, global step, positions.  profile: time each phase (syncs). */
int pl_lg_device_iteration(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx,
                           int profile, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    const lg_device *m = &s->gpu;
    const pl_device_ops *o = g->ops;
    pl_component *dev = g->dev;
    pl_buffer qb = {g->q, (size_t)d->n, 3, PL_DEVICE, PL_F64};
    pl_buffer rb = {g->rhs, (size_t)d->n, 3, PL_DEVICE, PL_F64};
    pl_buffer bb = {g->b_free, (size_t)d->nfree, 3, PL_DEVICE, PL_F64};
    pl_buffer xb = {g->q_free, (size_t)d->nfree, 3, PL_DEVICE, PL_F64};
    if (profile) pl_timer_start(ctx->timers, s->t_local);
    /* rhs = M sn; change, residual and grad cleared (one launch: version 4) */
    int rc;
    if (o->version >= 4 && o->scale_rows_zero) {
        rc = o->scale_rows_zero(dev, d->n, m->mass, g->sn, g->rhs, g->change,
                                g->scalars * sizeof(double), err);
    } else {
        rc = o->zero(dev, g->change, g->scalars * sizeof(double), err);
        if (!rc) rc = o->scale_rows(dev, d->n, m->mass, g->sn, g->rhs, err);
    }
    if (!rc) rc = project_terms(s, g, ctx, &qb, &rb, err);
    if (profile && !rc) rc = phase_end(g, ctx, s->t_local, err);
    if (rc || d->nfree == 0) return rc;
    if (profile) pl_timer_start(ctx->timers, s->t_assembly);
    rc = pl_lg_device_gather_sub(g, d->nfree, m->free_vertex, g->rhs,
                                 m->fp_nnz ? &m->A_fp : NULL, g->q, g->b_free, err);
    if (profile && !rc) rc = phase_end(g, ctx, s->t_assembly, err);
    if (rc) return rc;
    if (g->nrows > 0) {
        /* Algorithm 4: the contact solver's constrained global step (it
         * times its own phases) */
        const pl_contact_solver_ops *cs = pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER);
        rc = cs->iterate(s->contact, ctx, &d->sys, &qb, &bb, &xb, err);
    } else {
        if (profile) pl_timer_start(ctx->timers, s->t_global);
        const pl_global_solver_ops *gs = pl_component_role(s->solver, PL_ROLE_GLOBAL_SOLVER);
        rc = gs->solve(s->solver, &bb, &xb, err);
        if (profile && !rc) rc = phase_end(g, ctx, s->t_global, err);
    }
    if (!rc) rc = o->scatter_rows(dev, d->nfree, m->free_vertex, g->q_free, g->q, g->change, err);
    if (rc || !(s->force_tolerance > 0)) return rc;
    if (profile) pl_timer_start(ctx->timers, s->t_residual);
    rc = pl_lg_device_residual_queue(s, g, ctx, err);
    if (profile && !rc) rc = phase_end(g, ctx, s->t_residual, err);
    return rc;
}

/* With constraints, at the data's first step: the global solver's one-time
 * setup of W on the device (delassus_device with m = 0, roles.h), which the
 * frame of the first contact paid before (33 ms on the H100: cuBLAS's handle
 * and lazily loaded kernels, docs/benchmarks.md).  The first step already
 * carries the setup of everything else. */
static int prepare_rows(const local_global_solver *s, lg_device_ws *g, pl_error *err)
{
    if (g->prepared || !s->nconstraints || !s->contact) return PL_OK;
    g->prepared = 1;
    const pl_global_solver_ops *gs = pl_component_role(s->solver, PL_ROLE_GLOBAL_SOLVER);
    if (!gs || gs->version < 3 || !gs->delassus_device || !gs->accepts ||
        !gs->accepts(s->solver, PL_DEVICE, PL_F64)) /* the contact solver's test: W on that device */
        return PL_OK;
    return gs->delassus_device(s->solver, NULL, 0, NULL, NULL, err);
}

int pl_lg_device_step(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    lg_device_ws *g = &ws->gpu;
    pl_dyn_work *w = &ws->w;
    const pl_device_ops *o = g->ops;
    const pl_component *c = &s->base;
    size_t n3 = (size_t)d->n * 3 * sizeof(double);
    int flags = o->flags ? o->flags(g->dev) : 0; /* graph / profile may change at run time */
    int on_device = pl_lg_device_state_now(s); /* the start and end on the device */
    if (!on_device) pl_dynamics_begin(d, w, ctx->data, s->initial_guess); /* gather, predict, q */
    int rc = pl_dynamics_prescribe(d, w, ctx->data, ctx->data->time + d->h, w->q, err);
    if (!rc) rc = prepare_rows(s, g, err);
    if (rc) return rc;
    g->nrows = 0;
    if (s->nconstraints) {
        g->nrows = pl_lg_begin_constraints(s, ws, ctx, err);
        if (g->nrows < 0) return -g->nrows;
    }
    rc = pl_lg_device_graphs_begin_step(s, g, flags, err);
    if (rc) return rc;
    if (s->gpu.term_branch) /* a statistic of the step, not of each queued iteration */
        pl_stat_max(ctx->timers, "device local-step branches", s->gpu.nbranch);
    double scale = s->tolerance > 0 ? pl_dynamics_bbox_diagonal(w->q_t, d->n) : 1.0;
    if (s->compute_energy)
        pl_series_push(ctx->timers, "energy0", pl_dynamics_energy(d, w, ctx->data, w->q));
    if (on_device) {
        rc = pl_lg_device_state_begin(s, ws, ctx, err);
    } else {
        rc = o->copy(g->dev, g->sn, PL_DEVICE, w->sn, PL_HOST, n3, err);
        if (!rc) rc = o->copy(g->dev, g->q, PL_DEVICE, w->q, PL_HOST, n3, err);
    }
    int done = 0;
    double residual = NAN;
    pl_timer_start(ctx->timers, s->t_queue);
    if (!rc) rc = pl_lg_device_iterate(s, ws, ctx, scale, &done, &residual, err);
    pl_timer_stop(ctx->timers, s->t_queue);
    /* the copy waits for the queued iterations: the time the host idles */
    pl_timer_start(ctx->timers, s->t_wait);
    if (!rc && on_device) /* the states' new values straight into the data */
        rc = pl_lg_device_state_end(s, ws, ctx, pl_input_double(ctx->data, c, &s->damping), err);
    else if (!rc)
        rc = o->copy(g->dev, w->q, PL_HOST, g->q, PL_DEVICE, n3, err);
    pl_timer_stop(ctx->timers, s->t_wait);
    if (rc) return rc;
    if (on_device) { /* checked and scattered by state_end; no host residual here */
        pl_lg_record_residual(s, ctx, residual, done);
        return PL_OK;
    }
    for (int f = 0; f < d->nfree; ++f) {
        const double *x = &w->q[3 * d->free_vertex[f]];
        if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
            return pl_component_fail(c, err, PL_EINTERNAL,
                                     "the solution became NaN/inf during step %ld (vertex %d)",
                                     ctx->data->step + 1, d->free_vertex[f]);
    }
    if (s->report_residual && isnan(residual)) { /* on the host, at the step's q and multipliers */
        const pl_contact_solver_ops *cs =
            g->nrows > 0 ? pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER) : NULL;
        if ((rc = pl_lg_residual(s, ws, ctx, cs, &residual, err))) return rc;
    }
    pl_lg_record_residual(s, ctx, residual, done); /* as the CPU loop: NaN is not recorded */
    if (g->nrows > 0)
        pl_lg_end_constraints(s, ws, ctx);
    else if (s->nconstraints)
        pl_dynamics_store_forces(d, w, ctx->data, NULL, NULL); /* no contact this step */
    pl_dynamics_scatter(d, w, ctx->data, w->q, pl_input_double(ctx->data, c, &s->damping));
    return PL_OK;
}
