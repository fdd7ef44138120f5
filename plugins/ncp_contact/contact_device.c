/* contact_device.c - NonSmoothNewtonContactSolver on device buffers (see
 * contact_device.h): the step's data up once, then each iteration queued
 * on the device's stream (its kernels: contact_device_update.c). */
#include "contact_device_impl.h"
#include "pliant/util.h"

#include <cuda_runtime_api.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "contact_device_pack.h"
#include "ncp_cuda.h"
#include "ncp_cuda_correct.h"

enum { SERIES_CAP = 1024 };

/* The dense correction (ncp_cuda_correct.h) up to this many rows: U costs
 * a device solve a row once a step (about 6.6 us on the H100) and saves
 * the scatter, solve and sum of each iteration (about 10 us) less one
 * kernel (2 us): a gain while the step iterates more than about m / 1.3
 * times.  PLIANT_NCP_DENSE_CORR=0: off (the comparison, tests), =N: N rows. */
enum { DENSE_CORR_MAX_ROWS = 8, DENSE_CORR_CAP = 64 };
/* The least capacity of rows whose phases run over many blocks. */
enum { GRID_MIN_ROWS = 4096 };

int ncpc_device_fail(const pl_ncpc_device *g, pl_error *err, int code, const char *what)
{
    return pl_component_fail(g->owner, err, code ? code : PL_EINTERNAL, "device: %s", what);
}

int ncpc_device_cuda_fail(const pl_ncpc_device *g, pl_error *err, int e, const char *what)
{
    return pl_component_fail(g->owner, err, PL_EINTERNAL, "device: %s: %s", what,
                             cudaGetErrorString((cudaError_t)e));
}

/* A switch kept for comparisons: on unless the variable is "0". */
static int switch_on(const char *name)
{
    const char *v = getenv(name);
    return !(v && !strcmp(v, "0"));
}

pl_ncpc_device *ncpc_device_create(const pl_component *c, pl_error *err)
{
    pl_component *dev = pl_util_device(c);
    const pl_device_ops *ops = dev ? pl_component_role(dev, PL_ROLE_DEVICE) : NULL;
    if (!ops || ops->version < 1 || !ops->stream) {
        pl_component_fail(c, err, PL_EINPUT,
                          "device buffers, but no device service (CudaDevice) in this node or "
                          "above");
        return NULL;
    }
    pl_ncpc_device *g = calloc(1, sizeof *g);
    if (!g) {
        pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        return NULL;
    }
    g->owner = c, g->dev = dev, g->ops = ops;
    g->stale = 1; /* made by the step's first device iterate: its data must go up */
    g->stream = ops->stream(dev);
    /* on by default: on the H100 the fused update equals the phased one bitwise (gpu_graph,
     * four scenes, 100 steps) and is faster (raptor small 4.85 against 5.35 ms a step);
     * PLIANT_NCP_FUSED_CR=0 keeps the phase kernels */
    g->fused_env = switch_on("PLIANT_NCP_FUSED_CR");
    /* 2 by default: at most 32 rows by one warp on shared copies (the cable
     * finger's one row: docs/benchmarks.md); 1: in place, 0: the block */
    const char *fw = getenv("PLIANT_NCP_FUSED_WARP");
    g->fused_warp = fw && (!strcmp(fw, "0") || !strcmp(fw, "1")) ? atoi(fw) : 2;
    /* 1 by default: a capacity of at most 128 or 256 rows updated by a block
     * of 128 or 256 threads (bitwise the 512's); 0: always 512 */
    g->fused_narrow = switch_on("PLIANT_NCP_FUSED_NARROW");
    /* on by default: the phase kernels' consecutive phases (CR's F and the
     * next E, ...) two a launch, the same results; PLIANT_NCP_PHASE_PAIRS=0
     * keeps one a launch */
    g->phase_pairs = switch_on("PLIANT_NCP_PHASE_PAIRS");
    /* on by default: H^T x (the correction's and a matrix-free product's)
     * a warp an unknown, the same sums; PLIANT_NCP_SCATTER_WARP=0: a thread */
    g->scatter_warp = switch_on("PLIANT_NCP_SCATTER_WARP");
    /* on by default: a step's first (eager) iteration replays the phase
     * kernels' update from a graph, the same launches; PLIANT_NCP_UPDATE_GRAPH=0
     * launches them one by one (contact_device_update.c) */
    g->update_graph_env = switch_on("PLIANT_NCP_UPDATE_GRAPH");
    const char *dc = getenv("PLIANT_NCP_DENSE_CORR");
    g->dense_max = dc && *dc ? atoi(dc) : DENSE_CORR_MAX_ROWS;
    if (g->dense_max < 0) g->dense_max = 0;
    if (g->dense_max > DENSE_CORR_CAP) g->dense_max = DENSE_CORR_CAP;
    /* on by default: few rows' row values, fused update (by the warp) and
     * dense correction in one launch, the same values bitwise as the three
     * (ncp_cuda_iterate_few); PLIANT_NCP_ONE_KERNEL=0 keeps the three.
     * Only while the dense correction's rows fit the warp, so that a graph
     * replaying it with another step's m stays on the warp's path. */
    g->one_env = switch_on("PLIANT_NCP_ONE_KERNEL") && g->dense_max <= NCP_CUDA_WARP_MAX_ROWS;
    /* the phases over many blocks from GRID_MIN_ROWS rows of capacity (a
     * single block's phase kernel is the cheaper below: docs/benchmarks.md);
     * PLIANT_NCP_GRID_MIN=N sets the least capacity, 0 turns it off */
    const char *gm = getenv("PLIANT_NCP_GRID_MIN");
    g->grid_min = gm && *gm ? atoi(gm) : GRID_MIN_ROWS;
    if (g->grid_min <= 0) g->grid_min = INT_MAX;
    g->sc = ops->alloc(dev, sizeof *g->sc, err);
    g->series = g->sc ? ops->alloc(dev, SERIES_CAP * 4 * sizeof(double), err) : NULL;
    g->part = g->series ? ops->alloc(dev, NCP_CUDA_GRID_PART * sizeof(double), err) : NULL;
    g->h_sc = calloc(1, sizeof *g->h_sc);
    if (!g->sc || !g->series || !g->part || !g->h_sc ||
        (ops->pin && ops->pin(dev, g->h_sc, sizeof *g->h_sc, err) != PL_OK)) {
        if (!g->h_sc) pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        free(g->h_sc);
        g->h_sc = NULL;
        ncpc_device_destroy(g);
        return NULL;
    }
    return g;
}

static void free_host(pl_ncpc_device *g, void **p)
{
    if (*p && g->ops->unpin) g->ops->unpin(g->dev, *p);
    free(*p);
    *p = NULL;
}

void ncpc_device_destroy(pl_ncpc_device *g)
{
    if (!g) return;
    pl_error err;
    g->ops->sync(g->dev, &err); /* nothing may still use the buffers */
    if (g->update_graph) g->ops->graph_free(g->dev, g->update_graph);
    void *d[] = {g->in_dev, g->work, g->W, g->X, g->q_free, g->corr, g->U, g->sc, g->series, g->part};
    for (size_t k = 0; k < sizeof d / sizeof d[0]; ++k) g->ops->free(g->dev, d[k]);
    free_host(g, &g->in_host);
    free_host(g, (void **)&g->h_lambda);
    free_host(g, (void **)&g->h_lambda_all);
    free_host(g, (void **)&g->h_sc);
    free_host(g, (void **)&g->h_series);
    free(g);
}

void ncpc_device_begin(pl_ncpc_device *g)
{
    if (g) g->stale = 1, g->ran = 0, g->fetched = 0;
}

int ncpc_device_ran(const pl_ncpc_device *g)
{
    return g && g->ran;
}

/* The multipliers and scalars of the step's last iteration to the host,
 * once per step: after the iterations (a device loop runs them all without
 * the host), not after each of them. */
static int fetch(pl_ncpc_device *g, pl_error *err)
{
    if (g->fetched) return PL_OK;
    cudaStream_t s = (cudaStream_t)g->stream;
    cudaError_t ce = cudaMemcpyAsync(g->h_lambda, g->V.lambda, sizeof(double) * (size_t)g->R.m,
                                     cudaMemcpyDeviceToHost, s);
    if (ce == cudaSuccess)
        ce = cudaMemcpyAsync(g->h_lambda_all, g->V.lambda_all,
                             sizeof(double) * (size_t)g->R.nall, cudaMemcpyDeviceToHost, s);
    if (ce == cudaSuccess)
        ce = cudaMemcpyAsync(g->h_sc, g->sc, sizeof *g->h_sc, cudaMemcpyDeviceToHost, s);
    if (ce == cudaSuccess) ce = cudaStreamSynchronize(s);
    if (ce != cudaSuccess) return ncpc_device_cuda_fail(g, err, (int)ce, "multipliers to the host");
    g->fetched = 1;
    return PL_OK;
}

const double *ncpc_device_lambda(pl_ncpc_device *g, pl_error *err)
{
    return fetch(g, err) ? NULL : g->h_lambda;
}

const double *ncpc_device_lambda_all(pl_ncpc_device *g, pl_error *err)
{
    return fetch(g, err) ? NULL : g->h_lambda_all;
}

unsigned long ncpc_device_epoch(const pl_ncpc_device *g)
{
    return g ? g->epoch : 0;
}

/* A capacity of at least n (doubled, at least 64): the grids and copies of
 * a captured graph are sized by it, so it changes rarely (from 0 to 1000
 * rows: 5 times). */
static int grow(int cap, int n)
{
    if (n <= cap) return cap;
    int c = 2 * cap;
    return c > n ? c : (n > 64 ? n : 64);
}

/* W's bytes for m rows: the capacity's square (W's address then changes
 * with the capacity only) while that is at most 64 MB; above, m^2 (and
 * reserve's half more): a large W does not take 4 m^2. */
static size_t w_bytes(const pl_ncpc_device *g, int m)
{
    size_t full = sizeof(double) * (size_t)g->mcap * (size_t)g->mcap;
    return full <= ((size_t)64 << 20) ? full : sizeof(double) * (size_t)m * (size_t)m;
}

/* Device memory of at least `bytes` in *p (capacity *cap, grown by half). */
static int reserve(pl_ncpc_device *g, void **p, size_t *cap, size_t bytes, pl_error *err)
{
    if (bytes <= *cap && *p) return PL_OK;
    int rc = g->ops->sync(g->dev, err); /* the old buffer may still be in use */
    if (rc) return rc;
    g->ops->free(g->dev, *p);
    *cap = bytes + bytes / 2 + 256;
    *p = g->ops->alloc(g->dev, *cap, err);
    if (!*p) {
        *cap = 0;
        return err->code ? err->code : PL_EINTERNAL;
    }
    return PL_OK;
}

/* Page-locked host memory of at least `bytes`. */
static int reserve_host(pl_ncpc_device *g, void **p, size_t *cap, size_t bytes, pl_error *err)
{
    if (bytes <= *cap && *p) return PL_OK;
    int rc = g->ops->sync(g->dev, err);
    if (rc) return rc;
    free_host(g, p);
    *cap = bytes + bytes / 2 + 256;
    *p = malloc(*cap);
    if (!*p) {
        *cap = 0;
        return ncpc_device_fail(g, err, PL_EINTERNAL, "out of memory");
    }
    if (g->ops->pin && (rc = g->ops->pin(g->dev, *p, *cap, err)) != PL_OK) {
        free(*p);
        *p = NULL, *cap = 0;
        return rc;
    }
    return PL_OK;
}

double *ncpc_device_w(pl_ncpc_device *g, int m, pl_error *err)
{
    g->mcap = grow(g->mcap, m); /* W follows the capacity of rows */
    return reserve(g, (void **)&g->W, &g->W_cap, w_bytes(g, m), err) == PL_OK ? g->W : NULL;
}

/* The work vectors in one device arena of capacity mcap (nallcap for
 * lambda_all): 22 x mcap doubles, nallcap doubles, mcap ints. */
static int work_vectors(pl_ncpc_device *g, int nall, pl_error *err)
{
    g->nallcap = grow(g->nallcap, nall > g->mcap ? nall : g->mcap);
    size_t mc = (size_t)g->mcap, na = (size_t)g->nallcap;
    size_t bytes = (22 * mc + na) * sizeof(double) + mc * sizeof(int);
    void *old = g->work;
    int rc = reserve(g, &g->work, &g->work_cap, bytes, err);
    if (!rc && g->work != old) rc = g->ops->zero(g->dev, g->work, g->work_cap, err);
    if (rc) return rc;
    double *w = g->work;
    double **vecs[] = {&g->V.dlambda,  &g->V.delta, &g->V.delta_free, &g->V.omega, &g->V.e,
                       &g->V.phi,      &g->V.rhs,   &g->V.tmp,        &g->V.tmp2,  &g->V.scale,
                       &g->V.clamped,  &g->V.op_omega, &g->V.op_e,    &g->V.force, &g->V.ls0,
                       &g->V.ls1,      &g->V.cr_r,  &g->V.cr_p,       &g->V.cr_Ar, &g->V.cr_Ap,
                       &g->V.cr_s,     &g->V.lambda};
    for (size_t v = 0; v < sizeof vecs / sizeof vecs[0]; ++v) *vecs[v] = w + v * mc;
    g->V.lambda_all = w + 22 * mc;
    g->V.is_clamped = (int *)(w + 22 * mc + na);
    g->V.series = g->series, g->V.series_cap = SERIES_CAP, g->V.sc = g->sc;
    g->V.part = g->part;
    return PL_OK;
}

/* Whether a graph captured around iterate() before this step still fits
 * (graph_key); bumps epoch when not. */
static void check_key(pl_ncpc_device *g, int nfree)
{
    graph_key k;
    memset(&k, 0, sizeof k); /* padding too: the keys are compared bytewise */
    k.in_dev = g->in_dev, k.work = g->work, k.W = g->W, k.X = g->X, k.q_free = g->q_free;
    k.corr = g->corr, k.U = g->dense ? g->U : NULL;
    k.mcap = g->mcap, k.nallcap = g->nallcap, k.nfree = nfree, k.active = g->R.m > 0;
    k.jacobian = g->jacobian, k.explicit_w = g->explicit_w, k.fused = g->fused, k.dense = g->dense;
    k.one = g->one, k.grid = g->grid;
    memcpy(&k.P, &g->P, sizeof k.P);
    /* unique over the process: a device path made again (a rebuilt
     * workspace) never repeats an epoch a loop's graph was captured at */
    static _Atomic unsigned long epochs;
    if (memcmp(&k, &g->key, sizeof k)) {
        g->key = k;
        g->epoch = ++epochs;
    }
}

/* U_j = A^-1 H_j^T for the step's m rows (queued after the upload: the
 * kernel reads the rows' device copy): the rows' blocks, then the global
 * solver's device solve on each, in place. */
static int dense_columns(pl_ncpc_device *g, const pl_system *sys, int m, pl_error *err)
{
    size_t f3 = 3 * sizeof(double) * (size_t)sys->nfree;
    int rc = reserve(g, (void **)&g->U, &g->U_cap, (size_t)g->dense_max * f3, err);
    if (rc) return rc;
    int e = ncp_cuda_rows_blocks(g->stream, g->in_dev, sys->nfree, g->U);
    if (e) return ncpc_device_cuda_fail(g, err, e, "the rows' columns");
    const pl_global_solver_ops *gs = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    for (int j = 0; !rc && j < m; ++j) {
        pl_buffer Ub = {g->U + 3 * (size_t)sys->nfree * (size_t)j, (size_t)sys->nfree, 3, PL_DEVICE,
                        PL_F64};
        rc = gs->solve(sys->global_solver, &Ub, &Ub, err);
    }
    return rc;
}

static int upload(pl_ncpc_device *g, const pl_ncpc_device_step *st, const pl_system *sys,
                  pl_error *err)
{
    const pl_ncpc_rows *r = st->rows;
    int m = r->m, nf = sys->nfree, rc;
    for (int j = 0; j < m; ++j) /* ncp_step's check, once for the step */
        if (r->kind[j] != PL_ROW_BILATERAL && !(st->r[j] > 0.0 && st->r[j] < 1e308))
            return pl_component_fail(g->owner, err, PL_EINPUT, "row %d: scaling r = %g must be > 0",
                                     j, st->r[j]);
    g->jacobian = !st->full_force;
    g->explicit_w = st->D->explicit_w;
    g->mcap = grow(g->mcap, m);
    int *kind = malloc(sizeof(int) * (size_t)(m > 0 ? m : 1)), *tr = ncpc_pack_transpose(r, nf);
    if (!kind || !tr) {
        free(kind), free(tr);
        return ncpc_device_fail(g, err, PL_EINTERNAL, "out of memory");
    }
    for (int j = 0; j < m; ++j) kind[j] = (int)r->kind[j];
    ncpc_pack k = {0, NULL, NULL, NULL, NULL};
    ncpc_pack_layout(&g->R, g->jacobian, st, sys, kind, tr, &k);
    size_t bytes = k.at;
    rc = reserve(g, &g->in_dev, &g->in_cap, bytes, err);
    if (!rc) rc = reserve_host(g, &g->in_host, &g->in_host_cap, bytes, err);
    if (!rc) rc = work_vectors(g, st->nall, err);
    ncpc_pack fill = {0, g->in_host, g->in_dev, NULL, NULL};
    if (!rc) {
        ncpc_pack_layout(&g->R, g->jacobian, st, sys, kind, tr, &fill);
        memcpy(g->in_host, &g->R, sizeof g->R); /* the descriptor the kernels read */
        rc = g->ops->copy(g->dev, g->in_dev, PL_DEVICE, g->in_host, PL_HOST, bytes, err);
    }
    free(kind), free(tr);
    /* the warm start into the work vectors (queued after the upload) */
    if (!rc && m)
        rc = g->ops->copy(g->dev, g->V.lambda, PL_DEVICE, fill.lambda, PL_DEVICE,
                          sizeof(double) * (size_t)m, err);
    if (!rc && st->nall)
        rc = g->ops->copy(g->dev, g->V.lambda_all, PL_DEVICE, fill.lambda_all, PL_DEVICE,
                          sizeof(double) * (size_t)st->nall, err);
    size_t mm = (size_t)g->mcap, f3 = 3 * sizeof(double) * (size_t)(nf > 0 ? nf : 1);
    if (!rc && g->f_cap < f3) {
        g->ops->free(g->dev, g->X), g->ops->free(g->dev, g->q_free), g->ops->free(g->dev, g->corr);
        g->X = g->q_free = g->corr = NULL;
        g->f_cap = 0;
        if (!(g->X = g->ops->alloc(g->dev, f3, err)) || !(g->q_free = g->ops->alloc(g->dev, f3, err)) ||
            !(g->corr = g->ops->alloc(g->dev, f3, err)))
            rc = err->code ? err->code : PL_EINTERNAL;
        else
            g->f_cap = f3;
    }
    if (!rc && g->explicit_w && st->D->W_dev && st->D->W_dev != g->W)
        rc = ncpc_device_fail(g, err, PL_EINTERNAL, "W was built into another device array");
    if (!rc && g->explicit_w && !st->D->W_dev) {
        rc = reserve(g, (void **)&g->W, &g->W_cap, w_bytes(g, m), err);
        if (!rc && m)
            rc = g->ops->copy(g->dev, g->W, PL_DEVICE, st->D->W, PL_HOST,
                              sizeof(double) * (size_t)m * (size_t)m, err);
    }
    /* the multipliers come back whole capacities (a captured copy's size) */
    if (!rc) rc = reserve_host(g, (void **)&g->h_lambda, &g->h_cap, sizeof(double) * mm, err);
    if (!rc)
        rc = reserve_host(g, (void **)&g->h_lambda_all, &g->h_all_cap,
                          sizeof(double) * (size_t)g->nallcap, err);
    if (rc) return rc;
    pl_ncp_cuda_params *P = &g->P;
    memset(P, 0, sizeof *P); /* compared bytewise (check_key) */
    P->fn = st->fn, P->h = st->h, P->fb_eps = st->fb_eps, P->cr_rtol = st->cr_tolerance;
    P->damping = st->damping, P->cr_max_iter = st->cr_iterations, P->full_force = st->full_force;
    P->project = st->project, P->line_search = st->line_search, P->cr_jacobi = st->cr_jacobi;
    g->fused = g->fused_env && g->explicit_w && g->mcap <= NCP_CUDA_FUSED_MAX_ROWS;
    g->dense = m > 0 && m <= g->dense_max && nf > 0;
    g->one = g->one_env && g->fused && g->fused_warp == 2 && g->dense;
    g->grid = !g->fused && g->mcap >= g->grid_min;
    if (g->dense && (rc = dense_columns(g, sys, m, err))) return rc;
    int e = ncp_cuda_reset(g->stream, g->sc);
    if (e) return ncpc_device_cuda_fail(g, err, e, "reset");
    check_key(g, nf);
    g->stale = 0;
    return PL_OK;
}

/* With the device's profile flag: wait, so that timer `id` sees device time. */
int ncpc_device_lap(pl_ncpc_device *g, pl_ctx *ctx, int profile, int id, int start, pl_error *err)
{
    if (!profile) return PL_OK;
    if (start) {
        pl_timer_start(ctx->timers, id);
        return PL_OK;
    }
    int rc = g->ops->sync(g->dev, err);
    pl_timer_stop(ctx->timers, id);
    return rc;
}

int ncpc_device_iterate(pl_ncpc_device *g, const pl_ncpc_device_step *st, pl_ctx *ctx,
                           const pl_system *sys, const pl_buffer *q_k, const pl_buffer *b,
                           pl_buffer *q_next, pl_error *err)
{
    const pl_buffer *bufs[3] = {q_k, b, q_next};
    const size_t rows[3] = {(size_t)sys->nverts, (size_t)sys->nfree, (size_t)sys->nfree};
    for (int k = 0; k < 3; ++k)
        if (bufs[k]->location != PL_DEVICE || bufs[k]->precision != PL_F64 || bufs[k]->cols != 3 ||
            bufs[k]->rows != rows[k])
            return pl_component_fail(g->owner, err, PL_EINPUT,
                                     "iterate: expected device float64 blocks %d x 3 and %d x 3",
                                     sys->nverts, sys->nfree);
    const pl_global_solver_ops *gs = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    if (!(gs->version >= 2 && gs->accepts && gs->accepts(sys->global_solver, PL_DEVICE, PL_F64)))
        return ncpc_device_fail(g, err, PL_EINPUT, "the global solver does not take device buffers");
    int rc = g->stale ? upload(g, st, sys, err) : PL_OK;
    if (rc) return rc;
    g->ran = g->R.m > 0; /* no active row: the solver's own (zero) multipliers stand */
    int profile = g->ops->flags && (g->ops->flags(g->dev) & PL_DEVICE_PROFILE);
    size_t f3 = 3 * sizeof(double) * (size_t)sys->nfree;
    pl_buffer fb = {g->q_free, (size_t)sys->nfree, 3, PL_DEVICE, PL_F64};
    ncpc_device_lap(g, ctx, profile, st->t_cglobal, 1, err);
    ncpc_device_lap(g, ctx, profile, st->t_global, 1, err);
    rc = gs->solve(sys->global_solver, b, &fb, err);
    if (!rc) rc = ncpc_device_lap(g, ctx, profile, st->t_global, 0, err);
    if (rc || g->R.m == 0) {
        if (!rc) rc = g->ops->copy(g->dev, q_next->data, PL_DEVICE, g->q_free, PL_DEVICE, f3, err);
        ncpc_device_lap(g, ctx, profile, st->t_cglobal, 0, err);
        return rc;
    }
    /* the row values, the constraint update and the correction */
    if ((rc = ncpc_device_constrained(g, st, ctx, sys, q_k, q_next, profile, err))) return rc;
    /* the multipliers come to the host once, after the step's last
     * iteration (fetch) */
    g->fetched = 0;
    return ncpc_device_lap(g, ctx, profile, st->t_cglobal, 0, err);
}

/* g->h_series made (page-locked, reserve_host); non-zero with err set when
 * it cannot be. */
static int host_series(pl_ncpc_device *g, pl_error *err)
{
    return reserve_host(g, (void **)&g->h_series, &g->h_series_cap,
                        SERIES_CAP * 4 * sizeof(double), err);
}

/* The series' first `guess` iterations queued to g->h_series (the copy
 * waits with fetch's); -1 with err set on failure. */
static int queue_series(pl_ncpc_device *g, pl_error *err)
{
    if (host_series(g, err)) return -1;
    int guess = g->series_guess < 64 ? 64 : g->series_guess > SERIES_CAP ? SERIES_CAP
                                                                         : g->series_guess;
    cudaError_t ce = cudaMemcpyAsync(g->h_series, g->series, sizeof(double) * 4 * (size_t)guess,
                                     cudaMemcpyDeviceToHost, (cudaStream_t)g->stream);
    if (ce != cudaSuccess) return ncpc_device_cuda_fail(g, err, (int)ce, "series"), -1;
    return guess;
}

int ncpc_device_end_step(pl_ncpc_device *g, pl_timers *timers, int record, pl_error *err)
{
    if (!g || !g->ran) return PL_OK;
    int queued = 0; /* series iterations on their way with fetch's copies */
    if (record && timers && !g->fetched && (queued = queue_series(g, err)) < 0) return err->code;
    int rc = fetch(g, err);
    if (rc) return rc;
    static const char *const what[] = {"", "the CR right-hand side is not finite",
                                       "the CR residual is not finite",
                                       "non-finite values in delta or lambda (line search)"};
    int code = g->h_sc->error;
    if (code > 0 && code < 4)
        return pl_component_fail(g->owner, err, code == 3 ? PL_EINPUT : PL_EINTERNAL,
                                 "device: %s", what[code]);
    if (record && timers) {
        int n = g->h_sc->iter < SERIES_CAP ? g->h_sc->iter : SERIES_CAP;
        if (n > g->series_guess) g->series_guess = n;
        if ((rc = host_series(g, err))) return rc;
        if (n > queued) /* the rest (all if fetched earlier): one more wait */
            rc = g->ops->copy(g->dev, g->h_series + 4 * (size_t)queued, PL_HOST,
                              g->series + 4 * (size_t)queued, PL_DEVICE,
                              sizeof(double) * 4 * (size_t)(n - queued), err);
        const double *s = g->h_series;
        for (int k = 0; !rc && k < n; ++k) {
            pl_series_push(timers, "ncp residual", s[4 * k]);
            pl_series_push(timers, "cr iterations", s[4 * k + 1]);
            pl_series_push(timers, "cr residual", s[4 * k + 2]);
            pl_series_push(timers, "step length", s[4 * k + 3]);
        }
    }
    return rc;
}
