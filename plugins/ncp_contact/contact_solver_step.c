/* contact_solver_step.c - NonSmoothNewtonContactSolver's per-step choices:
 * W explicit or matrix-free (delassus="auto", also with the global step on
 * a GPU), its build, the step's statistics, and iterate() on device
 * buffers handed to contact_device.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact_solver.h"
#include "pliant/util.h"

/* Products of W in a step, about: local-global iterations times (CR
 * iterations + the linearisation and the line search); the paper's 5 x 13. */
#define PRODUCTS_PER_STEP 65.0

/* On the GPU the two products cost, per step's product (H100, fitted on
 * the frames of six contact scenes run both ways: docs/benchmarks.md,
 * "W explicit or matrix-free on the GPU"): a dense W reads m^2 entries at
 * about 2.1 TB/s (3.8 ps an entry); a matrix-free product pays its launches
 * (scatter, S, S^T, gather: about 8 us, as much as 2.1e6 dense entries)
 * and about 11.5 ps per entry of S, i.e. 3 dense entries per nnz(S). */
#define DEVICE_LAUNCH_ENTRIES 2.1e6
#define DEVICE_ENTRIES_PER_NNZ_S 3.0

/* delassus=auto: explicit when the dense W fits in maxExplicitMB and one
 * dense product (m^2 multiply-adds, memory-bound) costs no more than one
 * matrix-free product (S and S^T on 3 columns: about 6 nnz(S) on the CPU;
 * on a device its launches and 3 nnz(S), above) and, where W is built on
 * the CPU (dev_w = 0), building
 * it costs no more than the step's matrix-free products.  nnz(S) is the
 * statistic the global solver records when it factors; without it the
 * memory rule decides alone.  Deterministic: no timing decides. */
static int auto_explicit(const ncp_contact_solver *s, pl_timers *timers, int m, int n, int dev_w)
{
    double mb = (double)m * (double)m * sizeof(double) / (1024.0 * 1024.0), nnz_s;
    if (mb > s->max_explicit_mb) return 0;
    if (pl_stat_get(timers, "nnz(S)", &nnz_s) != 0) return 1;
    double free_product = dev_w ? DEVICE_ENTRIES_PER_NNZ_S * nnz_s + DEVICE_LAUNCH_ENTRIES
                                : 6.0 * nnz_s;
    if (!((double)m * (double)m <= free_product)) return 0;
    if (dev_w || n <= 0) return 1;
    /* the build, W = Y^T Y from the rows of Y, costs the sum over rows of
     * nnz^2: with a column of S holding nnz(S) / n entries on average, the
     * 3m columns of Y hold 3 m nnz(S) / n spread over n rows.  A dense S
     * makes it dominate (squeezing_ball.xml, 3.4k rows, S 72 MB: 10.5 s a
     * frame on one core, docs/scenes.md).  This estimate only screens: the
     * exact count from Y decides (max_build_work). */
    double ynnz = 3.0 * (double)m * nnz_s / (double)n;
    return ynnz * ynnz / (double)n <= PRODUCTS_PER_STEP * 6.0 * nnz_s;
}

/* The most multiply-adds that building W on the CPU may cost: maxExplicitWork
 * times the step's matrix-free products (infinite without nnz(S): the
 * memory rule alone).  The default, 0.3, is parity on one core: the same
 * states stepped both ways (tests/bench/bench_w_parity.c) cost 0.8-0.96x
 * explicit against matrix-free at 0.2-0.3, 1.1-1.4x at 0.3-0.45, on the
 * four small scenes that build W.  It was 2 while a look-ahead decided by
 * round-off made cloth_on_knives_small.xml's check fail on some W paths
 * (lookahead.c).  docs/benchmarks.md, spikes and knives. */
static double max_build_work(const ncp_contact_solver *s, pl_timers *timers)
{
    double nnz_s;
    if (pl_stat_get(timers, "nnz(S)", &nnz_s) != 0) return INFINITY;
    return s->max_explicit_work * PRODUCTS_PER_STEP * 6.0 * nnz_s;
}

/* W explicit or matrix-free (see the delassus field). */
/* With the global step on a device (a device service above and a global
 * solver that takes device buffers: the iterations run there), W is built
 * on that device when the global solver can (delassus_device: cuBLAS);
 * otherwise it would be built here on the CPU (Y = S P H^T and Y^T Y) every
 * step, and delassus=auto keeps it explicit only up to this many rows
 * (measured on the GPU: squeezing_ball, 3.6k rows, 390 ms to build W on the
 * CPU). */
enum { DEVICE_EXPLICIT_MAX_ROWS = 1024 };

static int on_device(const ncp_contact_solver *s, const pl_global_solver_ops *ops, const pl_system *sys)
{
#ifdef PLIANT_HAVE_CUDA
    return s->device != 0 && pl_util_device(&s->base) && ops && ops->version >= 2 &&
           ops->accepts && ops->accepts(sys->global_solver, PL_DEVICE, PL_F64);
#else
    (void)s, (void)ops, (void)sys;
    return 0;
#endif
}

/* W explicit on the device: the global solver builds it there. */
static int device_w(const ncp_contact_solver *s, ncpc_ws *w, const pl_system *sys, pl_error *err)
{
#ifdef PLIANT_HAVE_CUDA
    if (!w->gpu && !(w->gpu = ncpc_device_create(&s->base, err))) return err->code ? err->code : PL_EINPUT;
    double *W = ncpc_device_w(w->gpu, w->rows.m, err);
    if (!W) return err->code ? err->code : PL_EINTERNAL;
    return ncpc_delassus_explicit_device(&w->D, sys, &w->rows, W, err);
#else
    (void)s, (void)w, (void)sys;
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact", "no CUDA in this build");
#endif
}

/* PLIANT_DEVICE_WDIAG=0 keeps a matrix-free W's diagonal on the host with
 * the loop on the device (the comparison of docs/benchmarks.md). */
static int device_wdiag(void)
{
    const char *e = getenv("PLIANT_DEVICE_WDIAG");
    return !(e && !strcmp(e, "0"));
}

/* A few rows' W is cheaper to build here and upload than on the device:
 * the device build (gather, SYRK, sum, the diagonal back) is a chain of
 * launches and a wait whatever m (cable_finger, 1 row: 0.27 ms a step on
 * the H100 against 0.05 ms for the CPU's whole Schur phase). The upload
 * of the iterations' first call takes the host's W. PLIANT_DEVICE_W=host
 * or device forces one (the comparison of docs/benchmarks.md). */
enum { HOST_W_MAX_ROWS = 16 };

static int w_on_host(int m)
{
    const char *e = getenv("PLIANT_DEVICE_W");
    if (e && !strcmp(e, "host")) return 1;
    if (e && !strcmp(e, "device")) return 0;
    return m <= HOST_W_MAX_ROWS;
}

int ncpc_build_delassus(const ncp_contact_solver *s, ncpc_ws *w, pl_ctx *ctx,
                           const pl_system *sys, pl_error *err)
{
    const pl_global_solver_ops *ops = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    int dev = on_device(s, ops, sys), dev_w = dev && ops->version >= 3 && ops->delassus_device;
    if (dev_w && w->rows.m > 0 && w_on_host(w->rows.m) && ops->apply_inverse_to_rows &&
        (s->delassus == W_EXPLICIT || s->delassus == W_AUTO))
        return ncpc_delassus_explicit(&w->D, sys, &w->rows, err);
    int explicit_w = s->delassus == W_EXPLICIT || (s->delassus == W_AUTO && ops && ops->apply_inverse_to_rows &&
                                                   auto_explicit(s, ctx->timers, w->rows.m, sys->nfree, dev_w) &&
                                                   (w->rows.m <= DEVICE_EXPLICIT_MAX_ROWS || !dev || dev_w));
    if (explicit_w && dev_w) return device_w(s, w, sys, err);
    if (explicit_w && s->delassus == W_EXPLICIT) return ncpc_delassus_explicit(&w->D, sys, &w->rows, err);
    if (!w->inv_diag_ok && ops && ops->inverse_diagonal) {
        free(w->inv_diag);
        w->inv_diag = malloc(sizeof(double) * (size_t)(sys->nfree > 0 ? sys->nfree : 1));
        if (!w->inv_diag) return pl_component_fail(&s->base, err, PL_EINTERNAL, "out of memory");
        int st = ops->inverse_diagonal(sys->global_solver, w->inv_diag, err);
        if (st != PL_OK) return st;
        w->inv_diag_n = sys->nfree;
        w->inv_diag_ok = 1;
    }
    const double *inv = w->inv_diag_ok && w->inv_diag_n == sys->nfree ? w->inv_diag : NULL;
    /* auto on the CPU: Y first, then W only if its exact work is within
     * budget (the estimate from the average column of S misses where the
     * contacts gather: their etree paths share the top of the tree) */
    if (explicit_w)
        return ncpc_delassus_auto(&w->D, sys, &w->rows, max_build_work(s, ctx->timers), inv, err);
    if (dev_w && device_wdiag()) /* the iterations run on the device: S is there */
        return ncpc_delassus_matrix_free_device(&w->D, sys, &w->rows, inv, err);
    return ncpc_delassus_matrix_free(&w->D, sys, &w->rows, inv, err);
}

void ncpc_statistics(const ncpc_ws *w, pl_timers *t)
{
    int contacts = 0;
    for (int j = 0; j < w->rows.m; ++j) contacts += w->rows.kind[j] == PL_ROW_NORMAL;
    pl_stat_max(t, "contacts max", contacts);
    pl_stat_max(t, "constraint rows max", w->rows.m);
    if (w->D.explicit_w)
        pl_stat_max(t, "W memory [MB]", (double)w->rows.m * w->rows.m * sizeof(double) / (1024.0 * 1024.0));
    pl_stat_max(t, "Schur W work max", w->D.work);
}

#ifdef PLIANT_HAVE_CUDA
typedef struct stick_user {
    const ncp_contact_solver *s;
    ncpc_ws *w;
} stick_user;

/* stickStart for the device path: the CPU's ncpc_stick_start on the host
 * copies (rows, warm start) with the row values computed on the device; W
 * built on the device comes down once for it (kept as the host W of the
 * step, freed with the Delassus at the next begin). */
static int stick_on_host(void *user, const double *delta_free, pl_error *err)
{
    stick_user *u = user;
    ncpc_ws *w = u->w;
    pl_ncpc_delassus *D = &w->D;
    int m = w->rows.m;
    if (D->explicit_w && !D->W && D->W_dev) {
        pl_component *dev = pl_util_device(&u->s->base);
        const pl_device_ops *ops = dev ? pl_component_role(dev, PL_ROLE_DEVICE) : NULL;
        size_t bytes = sizeof(double) * (size_t)m * (size_t)m;
        if (!ops) return -pl_component_fail(&u->s->base, err, PL_EINTERNAL, "no device service");
        if (!(D->W = malloc(bytes ? bytes : 1)))
            return -pl_component_fail(&u->s->base, err, PL_EINTERNAL, "out of memory");
        int rc = ops->copy(dev, D->W, PL_HOST, D->W_dev, PL_DEVICE, bytes, err);
        if (rc) return -rc;
    }
    pl_ncp_operator op = ncpc_delassus_operator(D);
    D->status = PL_OK;
    int got = ncpc_stick_start(&w->rows, &op, w->h, delta_free, w->lambda, u->s->cr_iterations, err);
    if (got >= 0 && D->status != PL_OK) {
        *err = D->err;
        return -D->status;
    }
    return got;
}
#endif

/* iterate() on device buffers: contact_device.c (CUDA builds). */
int ncpc_iterate_device(const ncp_contact_solver *s, ncpc_ws *w, pl_ctx *ctx,
                           const pl_system *sys, const pl_buffer *q_k, const pl_buffer *b,
                           pl_buffer *q_next, pl_error *err)
{
#ifdef PLIANT_HAVE_CUDA
    const pl_component *c = &s->base;
    if (s->device == 0)
        return pl_component_fail(c, err, PL_EINPUT, "iterate: device buffers, but device=\"cpu\"");
    if (sys->nfree != w->nfree)
        return pl_component_fail(c, err, PL_EINPUT, "iterate: %d unknowns, begin saw %d", sys->nfree,
                                 w->nfree);
    if (!w->gpu && !(w->gpu = ncpc_device_create(c, err))) return err->code ? err->code : PL_EINPUT;
    pl_ncpc_device_step st = {
        .rows = &w->rows, .D = &w->D, .work = w->work, .r = w->r, .lambda = w->lambda,
        .lambda_all = w->lambda_all, .nall = w->nall, .h = w->h, .fn = s->ncp == 1 ? PL_NCP_MINMAP : PL_NCP_FB,
        .cr_iterations = s->cr_iterations, .full_force = s->correction == 1, .project = s->project,
        .cr_jacobi = s->cr_scaling == 0,
        .line_search = s->line_search, .record = s->record, .cr_tolerance = ncpc_cr_rtol(s),
        .damping = s->damping, .fb_eps = s->fb_eps, .t_global = w->t_global, .t_assembly = w->t_assembly,
        .t_solve = w->t_solve, .t_corr = w->t_corr, .t_cglobal = w->t_cglobal};
    pl_ncp_work empty = {0};
    if (!st.work) st.work = &empty; /* no active row */
    stick_user su = {s, w};
    if (w->first_iteration && s->stick_start) st.stick = stick_on_host, st.stick_user = &su;
    w->first_iteration = 0;
    return ncpc_device_iterate(w->gpu, &st, ctx, sys, q_k, b, q_next, err);
#else
    (void)w, (void)ctx, (void)sys, (void)q_k, (void)b, (void)q_next;
    return pl_component_fail(&s->base, err, PL_EINPUT, "iterate: device buffers, but this build has no CUDA");
#endif
}
