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
 *                       pl_ncp_step (CR), the step length, lambda +=
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
             "relative residual at which CR stops early [1] (0: always run crIterations)",
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
                  "a matrix-free product's launches count as 8e6 entries; else auto keeps it "
                  "explicit only up to 1024 rows)",
                  PL_FIELD_RUNTIME),
    PL_FIELD(ncp_contact_solver, max_explicit_mb, "maxExplicitMB", PL_F_DOUBLE, "256",
             "largest dense W that delassus=auto builds explicitly [MB, 2^20 bytes]", PL_FIELD_RUNTIME),
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
    s->slot = pl_model_add_var_slot(ctx->model, c, "warmStart", sizeof(pl_ncpc_key), INT_MAX);
    if (s->slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->model, s->slot, pl_ncpc_keys_check);
    return PL_OK;
}

/* A model field changed somewhere: the factor may have changed too. */
static int solver_reinit(pl_component *c, pl_ctx *ctx)
{
    (void)ctx;
    ((ncp_contact_solver *)c)->inv_diag_ok = 0;
    return PL_OK;
}

static void free_step(ncp_contact_solver *s)
{
    pl_ncp_work_destroy(s->work);
    s->work = NULL;
    pl_ncpc_delassus_free(&s->D);
    pl_ncpc_rows_free(&s->rows);
    double **arrays[] = {&s->r, &s->diag_mass, &s->lambda, &s->dlambda, &s->scale, &s->delta,
                         &s->delta_free, &s->force, &s->ls0, &s->ls1, &s->q_free, &s->corr, &s->lambda_all};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
        free(*arrays[k]);
        *arrays[k] = NULL;
    }
    free(s->keys);
    s->keys = NULL;
}

static void solver_destroy(pl_component *c)
{
    ncp_contact_solver *s = (ncp_contact_solver *)c;
#ifdef PLIANT_HAVE_CUDA
    pl_ncpc_device_destroy(s->gpu);
    s->gpu = NULL;
#endif
    free_step(s);
    free(s->inv_diag);
    s->inv_diag = NULL;
}

static int alloc_step(ncp_contact_solver *s, int m, pl_error *err)
{
    size_t m1 = (size_t)(m > 0 ? m : 1), f3 = 3 * (size_t)(s->nfree > 0 ? s->nfree : 1);
    s->r = malloc(sizeof(double) * m1);
    s->diag_mass = malloc(sizeof(double) * m1);
    s->lambda = calloc(m1, sizeof(double));
    s->dlambda = malloc(sizeof(double) * m1);
    s->scale = malloc(sizeof(double) * m1);
    s->delta = malloc(sizeof(double) * m1);
    s->delta_free = malloc(sizeof(double) * m1);
    s->force = malloc(sizeof(double) * m1);
    s->ls0 = malloc(sizeof(double) * m1);
    s->ls1 = malloc(sizeof(double) * m1);
    s->keys = calloc(m1, sizeof *s->keys);
    s->q_free = malloc(sizeof(double) * f3);
    s->corr = malloc(sizeof(double) * f3);
    s->lambda_all = calloc((size_t)(s->nall > 0 ? s->nall : 1), sizeof(double));
    if (!s->r || !s->diag_mass || !s->lambda || !s->dlambda || !s->scale || !s->delta ||
        !s->delta_free || !s->force || !s->ls0 || !s->ls1 || !s->keys || !s->q_free || !s->corr || !s->lambda_all)
        return pl_component_fail(&s->base, err, PL_EINTERNAL, "out of memory");
    return PL_OK;
}

static int solver_begin(pl_component *c, pl_ctx *ctx, const pl_system *sys, const pl_rows *rows,
                        const pl_buffer *q_t, pl_error *err)
{
    ncp_contact_solver *s = (ncp_contact_solver *)c;
    char msg[256];
    s->active = 0;
#ifdef PLIANT_HAVE_CUDA
    pl_ncpc_device_begin(s->gpu);
#endif
    free_step(s);
    if (check_fields(s, msg, sizeof msg) != PL_OK) return pl_component_fail(c, err, PL_EINPUT, "%s", msg);
    const double *qt = pl_buffer_f64(q_t);
    if (!sys || !rows || !qt || q_t->rows != (size_t)sys->nverts || q_t->cols != 3)
        return pl_component_fail(c, err, PL_EINPUT, "begin: expected q_t as a host %d x 3 block",
                                 sys ? sys->nverts : 0);
    if (!(sys->h > 0.0)) return pl_component_fail(c, err, PL_EINPUT, "time step h = %g", sys->h);
    pl_timers *t = ctx->timers;
    s->t_global = pl_timer_id(t, "Global");
    s->t_schur = pl_timer_id(t, "Schur");
    s->t_assembly = pl_timer_id(t, "Assembly");
    s->t_solve = pl_timer_id(t, "Constraint solve");
    s->t_corr = pl_timer_id(t, "Correction");
    s->t_cglobal = pl_timer_id(t, "Constraint global");
    s->nall = rows->n;
    s->nfree = sys->nfree;
    s->h = sys->h;
    pl_timer_start(t, s->t_schur);
    int st = pl_ncpc_rows_build(&s->rows, sys, rows, qt, err);
    if (st == PL_OK) st = alloc_step(s, s->rows.m, err);
    if (st == PL_OK && s->rows.m > 0) {
        pl_ncp_rows view = pl_ncpc_rows_view(&s->rows);
        st = pl_ncp_work_create(&view, &s->work, err);
        if (st == PL_OK) st = pl_ncpc_build_delassus(s, ctx, sys, err);
        if (st == PL_OK && s->preconditioner == 1) st = pl_ncpc_mass_diagonal(&s->rows, sys, s->diag_mass, err);
        if (st == PL_OK)
            st = pl_ncp_scaling(s->work, s->preconditioner == 1 ? s->diag_mass : s->D.diag, sys->h, s->r, err);
    }
    pl_timer_stop(t, s->t_schur);
    if (st == PL_OK && s->rows.m > 0) st = pl_ncpc_keys_build(&s->rows, rows, s->keys, err);
    if (st == PL_OK && s->rows.m > 0 && s->warm_start && s->slot >= 0) {
        const pl_ncpc_key *old = pl_data_slot(ctx->data, s->slot);
        int nold = (int)(pl_data_slot_bytes(ctx->data, s->slot) / sizeof *old);
        int got = pl_ncpc_warm_start(s->keys, s->rows.m, old, nold, s->lambda, err);
        if (got < 0) st = -got;
    }
    if (st != PL_OK) {
        char where[256];
        if (!err->where[0]) snprintf(err->where, sizeof err->where, "%s", pl_component_path(c, where, sizeof where));
        return st;
    }
    for (int j = 0; j < s->rows.m; ++j) s->lambda_all[s->rows.full[j]] = s->lambda[j];
    pl_ncpc_statistics(s, t);
    s->active = 1;
    return PL_OK;
}

static int correction(ncp_contact_solver *s, const pl_system *sys, double *qn, pl_error *err)
{
    int any = 0, m = s->rows.m;
    for (int j = 0; j < m; ++j) {
        s->force[j] = s->scale[j] * s->lambda[j];
        any |= s->force[j] != 0.0;
    }
    size_t f3 = 3 * (size_t)s->nfree;
    if (!any) {
        memcpy(qn, s->q_free, sizeof(double) * f3);
        return PL_OK;
    }
    /* q^{k+1} = q_free + h^2 A^-1 H^T (S .* lambda) */
    pl_ncpc_rows_scatter(&s->rows, s->nfree, s->force, s->h * s->h, s->corr);
    const pl_global_solver_ops *ops = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    pl_buffer cb = pl_buffer_host_f64(s->corr, (size_t)s->nfree, 3);
    int st = ops->solve(sys->global_solver, &cb, &cb, err);
    if (st != PL_OK) return st;
    for (size_t i = 0; i < f3; ++i) qn[i] = s->q_free[i] + s->corr[i];
    return PL_OK;
}

/* The step length along dlambda: delta(alpha) = delta_free + h^2 W S
 * (lambda + alpha dlambda) is affine, so W products give every trial: ls0
 * = delta(0) is already there with correction=multiplier (the
 * linearisation point), one more product otherwise. */
static int line_search(ncp_contact_solver *s, const pl_ncp_operator *op, pl_ncp_line_info *li, pl_error *err)
{
    int m = s->rows.m, st = PL_OK;
    double h2 = s->h * s->h;
    if (s->correction == 0) {
        for (int j = 0; j < m; ++j) s->force[j] = s->scale[j] * s->lambda[j];
        st = pl_ncp_operator_apply(op, s->force, s->ls0);
        for (int j = 0; j < m && st == PL_OK; ++j) s->ls0[j] = s->delta_free[j] + h2 * s->ls0[j];
    }
    if (st == PL_OK) {
        for (int j = 0; j < m; ++j) s->force[j] = s->scale[j] * s->dlambda[j];
        st = pl_ncp_operator_apply(op, s->force, s->ls1);
    }
    if (st != PL_OK || s->D.status != PL_OK) {
        *err = s->D.err;
        return s->D.status != PL_OK ? s->D.status : st;
    }
    for (int j = 0; j < m; ++j) s->ls1[j] *= h2;
    return pl_ncp_line_search(s->work, s->r, s->h, s->ls0, s->ls1, s->lambda, s->dlambda, 3, li, err);
}

/* The constraint update of one iteration: dlambda by pl_ncp_step, the step
 * length, lambda += damping alpha dlambda, the projection. */
static int constraint_solve(ncp_contact_solver *s, pl_ncp_step_info *info, pl_ncp_line_info *li,
                            pl_error *err)
{
    int m = s->rows.m, st = PL_OK;
    pl_ncp_params par;
    pl_ncp_params_default(&par);
    par.fn = s->ncp == 1 ? PL_NCP_MINMAP : PL_NCP_FB;
    par.h = s->h;
    par.fb_eps = s->fb_eps;
    par.cr_max_iter = s->cr_iterations;
    par.cr_rtol = s->cr_tolerance;
    par.full_force = s->correction == 1;
    par.cr_jacobi = s->cr_scaling == 0;
    pl_ncp_operator op = pl_ncpc_delassus_operator(&s->D);
    s->D.status = PL_OK;
    if (s->correction == 1) {
        /* linearise at the corrected point qbar = A^-1 (b^k + h^2 H^T lambda^k):
         * delta = delta_free + h^2 W lambda^k (DERIVATION.md section 7) */
        st = pl_ncp_operator_apply(&op, s->lambda, s->ls0);
        if (st == PL_OK && s->D.status == PL_OK)
            for (int j = 0; j < m; ++j) s->delta[j] = s->ls0[j] = s->delta_free[j] + s->h * s->h * s->ls0[j];
    }
    if (st == PL_OK && s->D.status == PL_OK)
        st = pl_ncp_step(s->work, &par, &op, s->r, s->delta, s->delta_free, s->lambda, s->dlambda, s->scale,
                         info, err);
    if (s->D.status != PL_OK) {
        *err = s->D.err; /* the global solver's own message */
        return s->D.status;
    }
    if (st == PL_OK && s->line_search) st = line_search(s, &op, li, err);
    if (st != PL_OK) return st;
    for (int j = 0; j < m; ++j) s->lambda[j] += s->damping * li->alpha * s->dlambda[j];
    if (s->project) pl_ncp_project(s->work, s->lambda);
    return PL_OK;
}

static int solver_iterate(pl_component *c, pl_ctx *ctx, const pl_system *sys, const pl_buffer *q_k,
                          const pl_buffer *b, pl_buffer *q_next, pl_error *err)
{
    ncp_contact_solver *s = (ncp_contact_solver *)c;
    const double *qk = pl_buffer_f64(q_k), *bb = pl_buffer_f64(b);
    double *qn = pl_buffer_f64(q_next);
    if (!s->active) return pl_component_fail(c, err, PL_EINTERNAL, "iterate called before begin");
    if (q_k->location == PL_DEVICE || b->location == PL_DEVICE || q_next->location == PL_DEVICE)
        return pl_ncpc_iterate_device(s, ctx, sys, q_k, b, q_next, err);
    if (!qk || !bb || !qn || q_k->rows != (size_t)sys->nverts || b->rows != (size_t)sys->nfree ||
        q_next->rows != (size_t)sys->nfree || q_k->cols != 3 || b->cols != 3 || q_next->cols != 3 ||
        sys->nfree != s->nfree)
        return pl_component_fail(c, err, PL_EINPUT, "iterate: expected host blocks %d x 3 and %d x 3",
                                 sys->nverts, sys->nfree);
    const pl_global_solver_ops *ops = pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER);
    pl_timers *t = ctx->timers;
    int m = s->rows.m, st;
    /* W was built on the device for a device loop that did not come (the
     * loop chose the CPU after all): build it here once for the step */
    if (m > 0 && s->D.explicit_w && !s->D.W &&
        (st = pl_ncpc_delassus_explicit(&s->D, sys, &s->rows, err)) != PL_OK)
        return st;
    pl_timer_start(t, s->t_cglobal);
    /* q_free = A^-1 b^k */
    pl_timer_start(t, s->t_global);
    pl_buffer fb = pl_buffer_host_f64(s->q_free, (size_t)s->nfree, 3);
    st = ops->solve(sys->global_solver, b, &fb, err);
    pl_timer_stop(t, s->t_global);
    if (st != PL_OK || m == 0) {
        if (st == PL_OK) memcpy(qn, s->q_free, sizeof(double) * 3 * (size_t)s->nfree);
        pl_timer_stop(t, s->t_cglobal);
        return st;
    }
    /* row values at q_free (and, for the paper's linearisation, at q^k) */
    pl_timer_start(t, s->t_assembly);
    if (s->correction == 0) pl_ncpc_rows_delta_all(&s->rows, sys->free_vertex, qk, s->delta);
    pl_ncpc_rows_delta(&s->rows, s->q_free, qk, s->delta_free);
    pl_timer_stop(t, s->t_assembly);
    pl_ncp_step_info info = {0, 0.0, 0.0};
    pl_ncp_line_info li = {1.0, 0.0, 0.0, 0, 0};
    pl_timer_start(t, s->t_solve);
    st = constraint_solve(s, &info, &li, err);
    pl_timer_stop(t, s->t_solve);
    if (st == PL_OK) {
        pl_timer_start(t, s->t_corr);
        st = correction(s, sys, qn, err);
        pl_timer_stop(t, s->t_corr);
    }
    pl_timer_stop(t, s->t_cglobal);
    if (st != PL_OK) return st;
    for (int j = 0; j < m; ++j) s->lambda_all[s->rows.full[j]] = s->lambda[j];
    if (s->record) {
        pl_series_push(t, "ncp residual", info.phi_norm);
        pl_series_push(t, "cr iterations", info.cr_iters);
        pl_series_push(t, "cr residual", info.cr_relres);
        pl_series_push(t, "step length", li.alpha);
    }
    return PL_OK;
}

static const double *solver_multipliers(const pl_component *c, int *count)
{
    const ncp_contact_solver *s = (const ncp_contact_solver *)c;
    *count = s->active ? s->nall : 0;
#ifdef PLIANT_HAVE_CUDA
    if (s->active && pl_ncpc_device_ran(s->gpu)) return pl_ncpc_device_lambda_all(s->gpu);
#endif
    return s->active ? s->lambda_all : NULL;
}

/* The step's records (rows with their final lambda) replace the slot's:
 * an empty slot after a step without rows. */
static int solver_end_step(pl_component *c, pl_ctx *ctx, pl_error *err)
{
    ncp_contact_solver *s = (ncp_contact_solver *)c;
    int m = s->active ? s->rows.m : 0;
#ifdef PLIANT_HAVE_CUDA
    if (m > 0 && pl_ncpc_device_ran(s->gpu)) {
        /* the device's multipliers (the loop has waited for its stream) */
        int rc = pl_ncpc_device_end_step(s->gpu, ctx->timers, s->record, err);
        memcpy(s->lambda, pl_ncpc_device_lambda(s->gpu), sizeof(double) * (size_t)m);
        pl_ncpc_device_begin(s->gpu);
        if (rc) {
            s->active = 0;
            return rc;
        }
    }
#endif
    s->active = 0;
    if (s->slot < 0) return PL_OK;
    if (pl_data_resize_slot(ctx->data, s->slot, sizeof(pl_ncpc_key) * (size_t)m) != 0)
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    pl_ncpc_key *rec = pl_data_slot(ctx->data, s->slot);
    for (int j = 0; j < m; ++j) {
        rec[j] = s->keys[j];
        rec[j].lambda = s->lambda[j];
    }
    return PL_OK;
}

static const pl_contact_solver_ops CONTACT_OPS = {
    .version = PL_CONTACT_SOLVER_OPS_VERSION,
    .begin = solver_begin,
    .iterate = solver_iterate,
    .multipliers = solver_multipliers,
};

const pl_type pl_ncp_contact_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "NonSmoothNewtonContactSolver",
    .help = "Frictional contact and constraints inside the local-global iterations (paper Algorithm 4): "
            "non-smooth Newton on Fischer-Burmeister or minimum-map NCP functions with the non-smooth "
            "indicators split out of W = H A^-1 H^T, solved by conjugate residual.",
    .size = sizeof(ncp_contact_solver),
    .fields = FIELDS,
    .nfields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .ops = {.init = solver_init, .reinit = solver_reinit, .end_step = solver_end_step,
            .destroy = solver_destroy},
    .roles = {[PL_ROLE_CONTACT_SOLVER] = &CONTACT_OPS},
};
