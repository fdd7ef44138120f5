/* contact_solver.c - NonSmoothNewtonContactSolver: the constrained global
 * step of Algorithm 4 (paper Section 5) for the LocalGlobalSolver.
 *
 * Once per step (begin, timer "Schur"): the rows of every constraint
 * component become the active scalarised rows, W = H A^-1 H^T is built
 * (explicit Y^T Y or matrix-free) with its diagonal, the complementarity
 * scaling r (Delassus or mass diagonal), and lambda is warm-started.
 * Per local-global iteration (iterate, all inside "Constraint global"):
 *   "Global"            q_free = A^-1 b^k
 *   "Assembly"          delta_free = H q_free - o (and delta^k = H q^k - o
 *                       for correction=jacobian)
 *   "Constraint solve"  the linearisation point (correction=multiplier:
 *                       delta = delta_free + h^2 W lambda^k), dlambda by
 *                       ncp_step (CR), the step length, lambda +=
 *                       damping alpha dlambda, the projection
 *   "Correction"        q^{k+1} = q_free + h^2 A^-1 H^T (S .* lambda)
 * correction=multiplier (default) applies the force lambda itself (S = 1)
 * and takes the Newton step of that system; correction=jacobian is the
 * paper's J^T lambda (S = Omega) linearised at q^k.  DERIVATION.md
 * section 7 gives the reasons and the measurements.
 *
 * When the animation loop hands iterate() device buffers (LocalGlobalSolver
 * device="cuda", CUDA builds), the iterations run on the GPU:
 * contact_device.c; begin stays on the CPU. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact_solver.h"
#include "pliant/plugin.h"
#include "pliant/work_limits.h"

static const char *const NCP_CHOICES[] = {"fischer-burmeister", "minimum-map", NULL};
static const char *const PRECOND_CHOICES[] = {"delassus", "mass", NULL};
static const char *const CORRECTION_CHOICES[] = {"jacobian", "multiplier", NULL};
static const char *const DELASSUS_CHOICES[] = {"auto", "explicit", "matrix-free", NULL};
static const char *const CR_SCALING_CHOICES[] = {"jacobi", "none", NULL};
static const char *const DEVICE_CHOICES[] = {"cpu", "auto", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD_ENUM(ncp_contact_solver, ncp, "ncp", NCP_CHOICES, "fischer-burmeister",
                  "NCP function of normal and friction rows: fischer-burmeister or minimum-map "
                  "(paper Appendix B)",
                  PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, cr_iterations, "crIterations", PL_F_INT, "10",
             "conjugate residual iterations per constraint solve [count] (the paper's Table 3 uses 10)",
             PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, cr_tolerance, "crTolerance", PL_F_DOUBLE, "0",
             "relative residual at which CR stops early [1] (0: run crIterations unless the "
             "residual is at round-off, 4 machine epsilons)",
             PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(ncp_contact_solver, cr_scaling, "crScaling", CR_SCALING_CHOICES, "jacobi",
                  "scaling of the linear system CR solves: jacobi (symmetric diagonal scaling "
                  "D^-1/2 A D^-1/2, D = diag A: the friction compliances of contacts that barely "
                  "touch span many decades, which unscaled CR cannot reduce in 10 iterations) or "
                  "none (the paper's plain CR)",
                  PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(ncp_contact_solver, preconditioner, "preconditioner", PRECOND_CHOICES, "delassus",
                  "complementarity scaling r: delassus (diagonal of W = H A^-1 H^T, the paper's "
                  "choice) or mass (diagonal of H M^-1 H^T, as Macklin et al. 2019)",
                  PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(ncp_contact_solver, delassus, "delassus", DELASSUS_CHOICES, "auto",
                  "how W is applied: explicit (dense W = Y^T Y, Y = S P H^T, built once per step; on "
                  "the GPU by cuBLAS from the columns of S the rows touch), "
                  "matrix-free (W x = H A^-1 H^T x, one global solve per product) or auto "
                  "(explicit while the dense W fits in maxExplicitMB, a dense product, m^2, costs "
                  "no more than a matrix-free one, 6 nnz(S) as the global solver reports it, and, on "
                  "the CPU, building W costs no more than a step's matrix-free products; with "
                  "the global step on a GPU, W is built there when the global solver can, and "
                  "a matrix-free product counts as 3 nnz(S) + 2.1e6 entries (its launches), "
                  "fitted on an H100; else auto keeps it explicit only up to 1024 rows)",
                  PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, max_explicit_mb, "maxExplicitMB", PL_F_DOUBLE, "256",
             "largest dense W that delassus=auto builds explicitly [MB, 2^20 bytes]", PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, max_explicit_work, "maxExplicitWork", PL_F_DOUBLE, "0.3",
             "delassus=auto with W built on the CPU: W is built only while the exact work of "
             "Y^T Y (sum over the rows of Y of nnz^2, statistic 'Schur W work max') is at most "
             "this many times a step's matrix-free products (65 x 6 nnz(S)); else matrix-free. "
             "The default is cost parity on one core, measured on the same states "
             "(tests/bench/bench_w_parity.c, docs/benchmarks.md)",
             PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, warm_start, "warmStart", PL_F_BOOL, "1",
             "start each step from the multipliers of the rows that persist (same emitter, kind, "
             "first vertex and direction within 30 degrees; friction by its contact's force vector)",
             PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, damping, "damping", PL_F_DOUBLE, "1",
             "relaxation of the multiplier update, lambda += damping dlambda [1], in (0, 1] "
             "(1: the plain Newton step)",
             PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, fb_eps, "fbEpsilon", PL_F_DOUBLE, "1e-12",
             "Fischer-Burmeister regularisation [m]: sqrt(delta^2 + (r lambda)^2 + eps^2) keeps the "
             "derivatives finite at delta = lambda = 0 (a new resting contact)",
             PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(ncp_contact_solver, correction, "correction", CORRECTION_CHOICES, "multiplier",
                  "force of the constraint correction: multiplier (q = A^-1 (b + h^2 H^T lambda): "
                  "the force is lambda on every row, the Newton step of the unsymmetric system, "
                  "solved as h^2 W + E / Omega) or jacobian (the paper's q = A^-1 (b + h^2 J^T "
                  "lambda), J = Omega H, solved as h^2 Omega W Omega + E); the same solution, "
                  "see DERIVATION.md section 7",
                  PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, project, "project", PL_F_BOOL, "0",
             "after each update, project lambda onto the admissible set (lambda_n >= 0, "
             "|lambda_f| <= mu lambda_n, bounded rows in [lo, hi]): the solution is unchanged and "
             "the force of an unfinished iteration stays admissible.  Off by default (the paper "
             "does not project): with nearly dependent rows (a vertex-face and an edge-edge "
             "contact at one place) the Newton step has large opposite multipliers whose "
             "difference is the force; clamping the negative one leaves the other unbalanced "
             "(docs/contact.md)",
             PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, line_search, "lineSearch", PL_F_BOOL, "1",
             "halve the multiplier update (at most 3 times) until the constraint residual decreases "
             "(one more W product per iteration; breaks the cycles of coupled rows between NCP "
             "branches, e.g. bounded rows jumping between their bounds)",
             PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, record, "recordConvergence", PL_F_BOOL, "0",
             "push, after every iteration, the series \"ncp residual\" (max |phi| at the "
             "linearisation point [m]), \"cr iterations\", \"cr residual\" (CR's relative residual) "
             "and \"step length\" into the timings",
             PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, stick_start, "stickStart", PL_F_BOOL, "0",
             "at the first iteration of a step, contacts without force (new ones, all of them "
             "in the first step from rest) that the free motion closes start from the forces "
             "that hold them still (normal and friction rows as equalities, one conjugate "
             "residual solve), projected on the friction cone; 0: they start from 0 and the "
             "friction grows over the iterations.  Makes the first step of a body resting on a "
             "slope exact (scenes/stick_slip.xml sets it); off by default: on the gripper of "
             "grabbing_raptor_small.xml it pushed the raptor out of the closing fingers "
             "(docs/contact.md)",
             PL_FIELD_RUNTIME),
    /* in every build: without CUDA, auto is the CPU */
    PL_FIELD_ENUM(ncp_contact_solver, device, "device", DEVICE_CHOICES, "auto",
                  "where the iterations' constraint work runs: auto (where the animation loop "
                  "runs it: on the GPU with LocalGlobalSolver device=\"cuda\") or cpu (a loop on "
                  "the device is then refused)",
                  0),
};

static int check_fields(const ncp_contact_solver *s, char *msg, size_t size)
{
    if (s->cr_iterations < 1)
        return snprintf(msg, size, "crIterations must be >= 1, got %d", s->cr_iterations), PL_EINPUT;
    if (!(s->cr_tolerance >= 0.0 && s->cr_tolerance < 1.0))
        return snprintf(msg, size, "crTolerance must be in [0, 1), got %g", s->cr_tolerance), PL_EINPUT;
    if (!(s->max_explicit_mb >= 0.0))
        return snprintf(msg, size, "maxExplicitMB must be >= 0, got %g", s->max_explicit_mb), PL_EINPUT;
    if (!(s->max_explicit_work >= 0.0))
        return snprintf(msg, size, "maxExplicitWork must be >= 0, got %g", s->max_explicit_work), PL_EINPUT;
    if (!(s->damping > 0.0 && s->damping <= 1.0))
        return snprintf(msg, size, "damping must be in (0, 1], got %g", s->damping), PL_EINPUT;
    if (!(s->fb_eps >= 0.0 && isfinite(s->fb_eps)))
        return snprintf(msg, size, "fbEpsilon must be >= 0, got %g", s->fb_eps), PL_EINPUT;
    return PL_OK;
}

static int solver_init(pl_component *c, pl_ctx *ctx)
{
    ncp_contact_solver *s = (ncp_contact_solver *)c;
    char msg[256];
    if (check_fields(s, msg, sizeof msg) != PL_OK) return pl_component_error(c, ctx, PL_EINPUT, "%s", msg);
    pl_work_limits lim;
    pl_work_limits_of(ctx->model, c->node, &lim);
    if (pl_work_limit_check(c, ctx, s->cr_iterations, lim.max_iterations,
                            "crIterations (per constraint solve)", "maxIterations"))
        return PL_EINPUT;
    s->slot = pl_model_add_var_slot(ctx->build, c, "warmStart", sizeof(pl_ncpc_key), INT_MAX);
    if (s->slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->build, s->slot, ncpc_keys_check);
    return PL_OK;
}

/* The step's structures (rows, W, the NCP work) are rebuilt every step. */
static void free_step(ncpc_ws *w)
{
    ncp_work_destroy(w->work);
    w->work = NULL;
    ncpc_delassus_free(&w->D);
    ncpc_rows_free(&w->rows);
}

/* The step's arrays keep their capacity from step to step: a workspace
 * allocates when the row count (or nfree, nall) grows past what it has held,
 * not at every step of a contact scene. */
static void free_arrays(ncpc_ws *w)
{
    double **arrays[] = {&w->r, &w->diag_mass, &w->lambda, &w->dlambda, &w->scale, &w->delta,
                         &w->delta_free, &w->force, &w->ls0, &w->ls1, &w->q_free, &w->corr, &w->lambda_all};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
        free(*arrays[k]);
        *arrays[k] = NULL;
    }
    free(w->keys);
    w->keys = NULL;
    w->cap_m = w->cap_f3 = w->cap_all = 0;
}

/* A model field changed somewhere (the factor may have too): the core
 * remakes every workspace, inv_diag included. */
static void solver_workspace_free(const pl_component *c, void *ws)
{
    ncpc_ws *w = ws;
    (void)c;
#ifdef PLIANT_HAVE_CUDA
    ncpc_device_destroy(w->gpu);
    w->gpu = NULL;
#endif
    free_step(w);
    free_arrays(w);
    free(w->inv_diag);
    w->inv_diag = NULL;
}

/* *p resized to n doubles (its contents kept); 0 or -1 (out of memory). */
static int grow_f64(double **p, size_t n)
{
    double *q = realloc(*p, n * sizeof(double));
    if (!q) return -1;
    *p = q;
    return 0;
}

static int alloc_step(const ncp_contact_solver *s, ncpc_ws *w, int m, pl_error *err)
{
    size_t m1 = (size_t)(m > 0 ? m : 1), f3 = 3 * (size_t)(w->nfree > 0 ? w->nfree : 1),
           all = (size_t)(w->nall > 0 ? w->nall : 1);
    if (m1 > w->cap_m) {
        double **rows_arrays[] = {&w->r, &w->diag_mass, &w->lambda, &w->dlambda, &w->scale,
                                  &w->delta, &w->delta_free, &w->force, &w->ls0, &w->ls1};
        for (size_t k = 0; k < sizeof rows_arrays / sizeof rows_arrays[0]; ++k)
            if (grow_f64(rows_arrays[k], m1)) goto oom;
        pl_ncpc_key *keys = realloc(w->keys, m1 * sizeof *keys);
        if (!keys) goto oom;
        w->keys = keys;
        w->cap_m = m1;
    }
    if (f3 > w->cap_f3) {
        if (grow_f64(&w->q_free, f3) || grow_f64(&w->corr, f3)) goto oom;
        w->cap_f3 = f3;
    }
    if (all > w->cap_all) {
        if (grow_f64(&w->lambda_all, all)) goto oom;
        w->cap_all = all;
    }
    memset(w->lambda, 0, sizeof(double) * m1); /* the keys: ncpc_keys_build writes each whole */
    memset(w->lambda_all, 0, sizeof(double) * all);
    return PL_OK;
oom:
    return pl_component_fail(&s->base, err, PL_EINTERNAL, "out of memory");
}

static int solver_begin(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                        const pl_rows *rows, const pl_buffer *q_t, pl_error *err)
{
    const ncp_contact_solver *s = (const ncp_contact_solver *)c;
    char msg[256];
    ncpc_ws *w = pl_data_workspace(ctx->data, c);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    w->active = 0;
#ifdef PLIANT_HAVE_CUDA
    ncpc_device_begin(w->gpu);
#endif
    free_step(w);
    if (check_fields(s, msg, sizeof msg) != PL_OK) return pl_component_fail(c, err, PL_EINPUT, "%s", msg);
    const double *qt = pl_buffer_f64(q_t);
    if (!sys || !rows || !qt || q_t->rows != (size_t)sys->nverts || q_t->cols != 3)
        return pl_component_fail(c, err, PL_EINPUT, "begin: expected q_t as a host %d x 3 block",
                                 sys ? sys->nverts : 0);
    if (!(sys->h > 0.0)) return pl_component_fail(c, err, PL_EINPUT, "time step h = %g", sys->h);
    pl_timers *t = ctx->timers;
    w->t_global = pl_timer_id(t, "Global");
    w->t_schur = pl_timer_id(t, "Schur");
    w->t_assembly = pl_timer_id(t, "Assembly");
    w->t_solve = pl_timer_id(t, "Constraint solve");
    w->t_corr = pl_timer_id(t, "Correction");
    w->t_cglobal = pl_timer_id(t, "Constraint global");
    w->nall = rows->n;
    w->nfree = sys->nfree;
    w->h = sys->h;
    pl_timer_start(t, w->t_schur);
    int st = ncpc_rows_build(&w->rows, sys, rows, qt, err);
    if (st == PL_OK) st = alloc_step(s, w, w->rows.m, err);
    if (st == PL_OK && w->rows.m > 0) {
        pl_ncp_rows view = ncpc_rows_view(&w->rows);
        st = ncp_work_create(&view, &w->work, err);
        if (st == PL_OK) st = ncpc_build_delassus(s, w, ctx, sys, err);
        if (st == PL_OK && s->preconditioner == 1) st = ncpc_mass_diagonal(&w->rows, sys, w->diag_mass, err);
        if (st == PL_OK)
            st = ncp_scaling(w->work, s->preconditioner == 1 ? w->diag_mass : w->D.diag, sys->h, w->r, err);
    }
    pl_timer_stop(t, w->t_schur);
    if (st == PL_OK && w->rows.m > 0) st = ncpc_keys_build(&w->rows, rows, w->keys, err);
    if (st == PL_OK && w->rows.m > 0 && s->warm_start && s->slot >= 0) {
        const pl_ncpc_key *old = pl_data_slot(ctx->data, s->slot);
        int nold = (int)(pl_data_slot_bytes(ctx->data, s->slot) / sizeof *old);
        int got = ncpc_warm_start(w->keys, w->rows.m, old, nold, w->lambda, err);
        if (got < 0) st = -got;
    }
    if (st != PL_OK) {
        char where[256];
        if (!err->where[0]) snprintf(err->where, sizeof err->where, "%s", pl_component_path(c, where, sizeof where));
        return st;
    }
    for (int j = 0; j < w->rows.m; ++j) w->lambda_all[w->rows.full[j]] = w->lambda[j];
    ncpc_statistics(w, t);
    w->active = 1;
    w->first_iteration = 1;
    return PL_OK;
}

static int correction(ncpc_ws *w, const pl_system *sys, double *qn, pl_error *err)
{
    int any = 0, m = w->rows.m;
    for (int j = 0; j < m; ++j) {
        w->force[j] = w->scale[j] * w->lambda[j];
        any |= w->force[j] != 0.0;
    }
    size_t f3 = 3 * (size_t)w->nfree;
    if (!any) {
        memcpy(qn, w->q_free, sizeof(double) * f3);
        return PL_OK;
    }
    /* q^{k+1} = q_free + h^2 A^-1 H^T (S .* lambda) */
    ncpc_rows_scatter(&w->rows, w->nfree, w->force, w->h * w->h, w->corr);
    const pl_global_solver_ops *ops = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    pl_buffer cb = pl_buffer_host_f64(w->corr, (size_t)w->nfree, 3);
    int st = ops->solve(sys->global_solver, &cb, &cb, err);
    if (st != PL_OK) return st;
    for (size_t i = 0; i < f3; ++i) qn[i] = w->q_free[i] + w->corr[i];
    return PL_OK;
}

/* The step length along dlambda: delta(alpha) = delta_free + h^2 W S
 * (lambda + alpha dlambda) is affine, so W products give every trial: ls0
 * = delta(0) is already there with correction=multiplier (the
 * linearisation point), one more product otherwise. */
static int line_search(const ncp_contact_solver *s, ncpc_ws *w, const pl_ncp_operator *op,
                       pl_ncp_line_info *li, pl_error *err)
{
    int m = w->rows.m, st = PL_OK;
    double h2 = w->h * w->h;
    if (s->correction == 0) {
        for (int j = 0; j < m; ++j) w->force[j] = w->scale[j] * w->lambda[j];
        st = ncp_operator_apply(op, w->force, w->ls0);
        for (int j = 0; j < m && st == PL_OK; ++j) w->ls0[j] = w->delta_free[j] + h2 * w->ls0[j];
    }
    if (st == PL_OK) {
        for (int j = 0; j < m; ++j) w->force[j] = w->scale[j] * w->dlambda[j];
        st = ncp_operator_apply(op, w->force, w->ls1);
    }
    if (st != PL_OK || w->D.status != PL_OK) {
        *err = w->D.err;
        return w->D.status != PL_OK ? w->D.status : st;
    }
    for (int j = 0; j < m; ++j) w->ls1[j] *= h2;
    return ncp_line_search(w->work, w->r, w->h, w->ls0, w->ls1, w->lambda, w->dlambda, 3, li, err);
}

/* The constraint update of one iteration: dlambda by ncp_step, the step
 * length, lambda += damping alpha dlambda, the projection. */
static int constraint_solve(const ncp_contact_solver *s, ncpc_ws *w, pl_ncp_step_info *info,
                            pl_ncp_line_info *li, pl_error *err)
{
    int m = w->rows.m, st = PL_OK;
    pl_ncp_params par;
    ncp_params_default(&par);
    par.fn = s->ncp == 1 ? PL_NCP_MINMAP : PL_NCP_FB;
    par.h = w->h;
    par.fb_eps = s->fb_eps;
    par.cr_max_iter = s->cr_iterations;
    par.cr_rtol = ncpc_cr_rtol(s);
    par.full_force = s->correction == 1;
    par.cr_jacobi = s->cr_scaling == 0;
    pl_ncp_operator op = ncpc_delassus_operator(&w->D);
    w->D.status = PL_OK;
    if (s->correction == 1) {
        /* linearise at the corrected point qbar = A^-1 (b^k + h^2 H^T lambda^k):
         * delta = delta_free + h^2 W lambda^k (DERIVATION.md section 7) */
        st = ncp_operator_apply(&op, w->lambda, w->ls0);
        if (st == PL_OK && w->D.status == PL_OK)
            for (int j = 0; j < m; ++j) w->delta[j] = w->ls0[j] = w->delta_free[j] + w->h * w->h * w->ls0[j];
    }
    if (st == PL_OK && w->D.status == PL_OK)
        st = ncp_step(w->work, &par, &op, w->r, w->delta, w->delta_free, w->lambda, w->dlambda, w->scale,
                         info, err);
    if (w->D.status != PL_OK) {
        *err = w->D.err; /* the global solver's own message */
        return w->D.status;
    }
    if (st == PL_OK && s->line_search) st = line_search(s, w, &op, li, err);
    if (st != PL_OK) return st;
    for (int j = 0; j < m; ++j) w->lambda[j] += s->damping * li->alpha * w->dlambda[j];
    if (s->project) ncp_project(w->work, w->lambda);
    return PL_OK;
}

static int solver_iterate(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                          const pl_buffer *q_k, const pl_buffer *b, pl_buffer *q_next,
                          pl_error *err)
{
    const ncp_contact_solver *s = (const ncp_contact_solver *)c;
    const double *qk = pl_buffer_f64(q_k), *bb = pl_buffer_f64(b);
    double *qn = pl_buffer_f64(q_next);
    ncpc_ws *w = pl_data_workspace(ctx->data, c);
    if (!w || !w->active)
        return pl_component_fail(c, err, PL_EINTERNAL, "iterate called before begin");
    if (q_k->location == PL_DEVICE || b->location == PL_DEVICE || q_next->location == PL_DEVICE)
        return ncpc_iterate_device(s, w, ctx, sys, q_k, b, q_next, err);
    if (!qk || !bb || !qn || q_k->rows != (size_t)sys->nverts || b->rows != (size_t)sys->nfree ||
        q_next->rows != (size_t)sys->nfree || q_k->cols != 3 || b->cols != 3 || q_next->cols != 3 ||
        sys->nfree != w->nfree)
        return pl_component_fail(c, err, PL_EINPUT, "iterate: expected host blocks %d x 3 and %d x 3",
                                 sys->nverts, sys->nfree);
    const pl_global_solver_ops *ops = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    pl_timers *t = ctx->timers;
    int m = w->rows.m, st;
    /* W was built on the device for a device loop that did not come (the
     * loop chose the CPU after all): build it here once for the step */
    if (m > 0 && w->D.explicit_w && !w->D.W &&
        (st = ncpc_delassus_explicit(&w->D, sys, &w->rows, err)) != PL_OK)
        return st;
    pl_timer_start(t, w->t_cglobal);
    /* q_free = A^-1 b^k */
    pl_timer_start(t, w->t_global);
    pl_buffer fb = pl_buffer_host_f64(w->q_free, (size_t)w->nfree, 3);
    st = ops->solve(sys->global_solver, b, &fb, err);
    pl_timer_stop(t, w->t_global);
    if (st != PL_OK || m == 0) {
        if (st == PL_OK) memcpy(qn, w->q_free, sizeof(double) * 3 * (size_t)w->nfree);
        pl_timer_stop(t, w->t_cglobal);
        return st;
    }
    /* row values at q_free (and, for the paper's linearisation, at q^k) */
    pl_timer_start(t, w->t_assembly);
    if (s->correction == 0) ncpc_rows_delta_all(&w->rows, sys->free_vertex, qk, w->delta);
    ncpc_rows_delta(&w->rows, w->q_free, qk, w->delta_free);
    pl_timer_stop(t, w->t_assembly);
    pl_ncp_step_info info = {0, 0.0, 0.0};
    pl_ncp_line_info li = {1.0, 0.0, 0.0, 0, 0};
    pl_timer_start(t, w->t_solve);
    if (w->first_iteration && s->stick_start) {
        /* contacts without force start from the forces holding them still */
        pl_ncp_operator op = ncpc_delassus_operator(&w->D);
        w->D.status = PL_OK;
        int got = ncpc_stick_start(&w->rows, &op, w->h, w->delta_free, w->lambda,
                                      s->cr_iterations, err);
        st = got < 0 ? -got : w->D.status;
        if (st != PL_OK && w->D.status != PL_OK) *err = w->D.err;
    }
    w->first_iteration = 0;
    if (st == PL_OK) st = constraint_solve(s, w, &info, &li, err);
    pl_timer_stop(t, w->t_solve);
    if (st == PL_OK) {
        pl_timer_start(t, w->t_corr);
        st = correction(w, sys, qn, err);
        pl_timer_stop(t, w->t_corr);
    }
    pl_timer_stop(t, w->t_cglobal);
    if (st != PL_OK) return st;
    for (int j = 0; j < m; ++j) w->lambda_all[w->rows.full[j]] = w->lambda[j];
    if (s->record) {
        pl_series_push(t, "ncp residual", info.phi_norm);
        pl_series_push(t, "cr iterations", info.cr_iters);
        pl_series_push(t, "cr residual", info.cr_relres);
        pl_series_push(t, "step length", li.alpha);
    }
    return PL_OK;
}

static const double *solver_multipliers(const pl_component *c, pl_data *d, int *count)
{
    const ncpc_ws *w = pl_data_workspace(d, c);
    *count = w && w->active ? w->nall : 0;
    if (!*count) return NULL;
#ifdef PLIANT_HAVE_CUDA
    if (w->active && ncpc_device_ran(w->gpu)) {
        pl_error err; /* a device failure is reported by end_step */
        const double *l = ncpc_device_lambda_all(w->gpu, &err);
        if (!l) *count = 0;
        return l;
    }
#endif
    return w->active ? w->lambda_all : NULL;
}

static unsigned long solver_graph_epoch(const pl_component *c, pl_data *d)
{
#ifdef PLIANT_HAVE_CUDA
    const ncpc_ws *w = pl_data_workspace(d, c);
    return w ? ncpc_device_epoch(w->gpu) : 0;
#else
    (void)c, (void)d;
    return 0;
#endif
}

/* The step's records (rows with their final lambda) replace the slot's:
 * an empty slot after a step without rows. */
static int solver_end_step(const pl_component *c, pl_ctx *ctx, pl_error *err)
{
    const ncp_contact_solver *s = (const ncp_contact_solver *)c;
    ncpc_ws *w = pl_data_workspace(ctx->data, c);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    int m = w->active ? w->rows.m : 0;
#ifdef PLIANT_HAVE_CUDA
    if (m > 0 && ncpc_device_ran(w->gpu)) {
        /* the device's multipliers (the loop has waited for its stream) */
        int rc = ncpc_device_end_step(w->gpu, ctx->timers, s->record, err);
        const double *l = rc ? NULL : ncpc_device_lambda(w->gpu, err);
        if (l) memcpy(w->lambda, l, sizeof(double) * (size_t)m);
        else if (!rc) rc = err->code ? err->code : PL_EINTERNAL;
        ncpc_device_begin(w->gpu);
        if (rc) {
            w->active = 0;
            return rc;
        }
    }
#endif
    w->active = 0;
    if (s->slot < 0) return PL_OK;
    if (pl_data_resize_slot(ctx->data, s->slot, sizeof(pl_ncpc_key) * (size_t)m) != 0)
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    pl_ncpc_key *rec = pl_data_slot(ctx->data, s->slot);
    for (int j = 0; j < m; ++j) {
        rec[j] = w->keys[j];
        rec[j].lambda = w->lambda[j];
    }
    return PL_OK;
}

static const pl_contact_solver_ops CONTACT_OPS = {
    .version = PL_CONTACT_SOLVER_OPS_VERSION,
    .begin = solver_begin,
    .iterate = solver_iterate,
    .multipliers = solver_multipliers,
    .graph_epoch = solver_graph_epoch,
};

const pl_type pl_ncp_contact_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "NonSmoothNewtonContactSolver",
    .help = "Frictional contact and constraints inside the local-global iterations (paper Algorithm 4): "
            "non-smooth Newton on Fischer-Burmeister or minimum-map NCP functions with the non-smooth "
            "indicators split out of W = H A^-1 H^T, solved by conjugate residual.",
    .size = sizeof(ncp_contact_solver),
    .workspace_size = sizeof(ncpc_ws),
    .fields = FIELDS,
    .nfields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .ops = {.init = solver_init, .end_step = solver_end_step,
            .workspace_free = solver_workspace_free},
    .roles = {[PL_ROLE_CONTACT_SOLVER] = &CONTACT_OPS},
};
