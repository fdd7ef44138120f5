/* newton_solver.c - NewtonSolver: the reference, not the fast path.  It
 * minimises the same incremental potential as LocalGlobalSolver,
 *     E(q) = 1/(2h^2) ||M^1/2 (q - sn)||^2 + sum psi(q)
 * (or, with quasiStatic, the static potential sum psi(q) - sum m g . q),
 * by Newton's method on the 3n unknowns with each element's Hessian
 * projected to PSD, CHOLMOD for the linear systems and a backtracking line
 * search, to a tight tolerance.  Tests use it as ground truth. */
#include <cholmod.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "solver.h"

typedef struct newton_solver {
    pl_component base;
    int max_iterations;
    double tolerance;
    int quasi_static;
    int project;
    double damping; /* an input, as LocalGlobalSolver's: the same step, the same state slots */
    pl_dynamics dyn;
    int ready;
} newton_solver;

/* Per data (pl_data_workspace): the step's vectors and CHOLMOD's common. */
typedef struct newton_ws {
    int ready;
    pl_dyn_work w;
    double *grad, *dx, *trial;
    cholmod_common cm;
} newton_ws;

static const pl_field FIELDS[] = {
    PL_FIELD(newton_solver, max_iterations, "maxIterations", PL_F_INT, "100",
             "Newton iterations at most per step", 0),
    PL_FIELD(newton_solver, tolerance, "tolerance", PL_F_DOUBLE, "1e-10",
             "stop when the Newton step's largest component is below tolerance times the "
             "bounding-box diagonal",
             PL_FIELD_RUNTIME),
    PL_FIELD(newton_solver, quasi_static, "quasiStatic", PL_F_BOOL, "0",
             "solve for static equilibrium (no inertia; gravity as an external load)", 0),
    PL_FIELD(newton_solver, project, "projectHessian", PL_F_BOOL, "1",
             "project each element Hessian onto the PSD cone (robust far from equilibrium; 0 keeps "
             "the exact Hessian: quadratic convergence near a minimum)",
             PL_FIELD_RUNTIME),
    PL_FIELD(newton_solver, damping, "damping", PL_F_DOUBLE, "0",
             "Rayleigh-style mass damping [1/s] after the step: v <- v / (1 + h damping) "
             "(LocalGlobalSolver's, so that Newton solves the same step as a reference)",
             PL_FIELD_INPUT),
};

static int ns_reinit(pl_component *c, pl_ctx *ctx)
{
    newton_solver *s = (newton_solver *)c;
    s->ready = 0;
    pl_work_limits lim;
    pl_work_limits_of(ctx->model, c->node, &lim);
    if (pl_work_limit_check(c, ctx, s->max_iterations, lim.max_iterations,
                            "maxIterations (per time step)", "maxIterations"))
        return PL_EINPUT;
    pl_dynamics_free(&s->dyn);
    int rc = pl_dynamics_setup(&s->dyn, c, ctx, pl_node_dt(c->node), 0, NULL);
    if (rc) return rc;
    for (int t = 0; t < s->dyn.nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(s->dyn.terms[t], PL_ROLE_LOCAL_TERM);
        if (!ops->add_gradient || !ops->add_hessian)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "%s '%s' provides no gradient/Hessian: the Newton solver "
                                      "cannot use it",
                                      s->dyn.terms[t]->type->name, s->dyn.terms[t]->name);
    }
    s->ready = 1;
    return PL_OK;
}

static void ns_destroy(pl_component *c)
{
    pl_dynamics_free(&((newton_solver *)c)->dyn);
}

static void ns_workspace_free(const pl_component *c, void *ws)
{
    newton_ws *w = ws;
    (void)c;
    pl_dyn_work_free(&w->w);
    free(w->grad);
    free(w->dx);
    free(w->trial);
    w->grad = w->dx = w->trial = NULL;
    if (w->ready) cholmod_finish(&w->cm);
    w->ready = 0;
}

/* This data's workspace, made on first use; NULL when memory runs out. */
static newton_ws *workspace(const newton_solver *s, pl_data *d)
{
    newton_ws *w = pl_data_workspace(d, &s->base);
    if (!w || w->ready) return w;
    size_t n3 = (size_t)(s->dyn.n ? s->dyn.n : 1) * 3;
    ns_workspace_free(&s->base, w); /* what a failed attempt left */
    w->grad = calloc(n3, sizeof(double));
    w->dx = calloc(n3, sizeof(double));
    w->trial = calloc(n3, sizeof(double));
    if (!w->grad || !w->dx || !w->trial || pl_dyn_work_alloc(&w->w, &s->dyn) != PL_OK) return NULL;
    cholmod_start(&w->cm);
    w->cm.print = 0;
    w->ready = 1;
    return w;
}

static double potential(const newton_solver *s, const newton_ws *w, const pl_data *data,
                        const double *q)
{
    const pl_dynamics *d = &s->dyn;
    if (!s->quasi_static) return pl_dynamics_energy(d, &w->w, data, q);
    double e = 0.0;
    pl_buffer qb = pl_buffer_host_f64((double *)q, (size_t)d->n, 3);
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        e += ops->energy(d->terms[t], data, d->term_offset[t], &qb);
    }
    for (int i = 0; i < d->n; ++i)
        if (d->free_index[i] >= 0)
            for (int k = 0; k < 3; ++k) e -= d->mass[i] * d->gravity[3 * i + k] * q[3 * i + k];
    return e;
}

static int gradient(const newton_solver *s, newton_ws *w, const pl_data *data, const double *q,
                    pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    double h2 = d->h * d->h;
    for (int i = 0; i < d->n; ++i)
        for (int k = 0; k < 3; ++k)
            w->grad[3 * i + k] = s->quasi_static
                                     ? -d->mass[i] * d->gravity[3 * i + k]
                                     : d->mass[i] * (q[3 * i + k] - w->w.sn[3 * i + k]) / h2;
    pl_buffer qb = pl_buffer_host_f64((double *)q, (size_t)d->n, 3);
    pl_buffer gb = pl_buffer_host_f64(w->grad, (size_t)d->n, 3);
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        int rc = ops->add_gradient(d->terms[t], data, d->term_offset[t], &qb, &gb, err);
        if (rc) return rc;
    }
    return PL_OK;
}

/* dx (over all vertices; zero on prescribed ones) = -H^-1 g, H the
 * PSD-projected Hessian restricted to the unknowns. */
static int newton_direction(const newton_solver *s, newton_ws *w, const pl_data *data,
                            const double *q, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    cholmod_common *cm = &w->cm;
    int nf3 = 3 * d->nfree;
    pl_triplets H;
    if (pl_triplets_init(&H, 3 * d->n, 3 * d->n, 64 * d->n) != PL_OK)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    double h2 = d->h * d->h;
    for (int i = 0; i < d->n && !s->quasi_static; ++i)
        for (int k = 0; k < 3; ++k) pl_triplets_add(&H, 3 * i + k, 3 * i + k, d->mass[i] / h2);
    pl_buffer qb = pl_buffer_host_f64((double *)q, (size_t)d->n, 3);
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        int rc = ops->add_hessian(d->terms[t], data, d->term_offset[t], &qb, s->project, &H, err);
        if (rc) {
            pl_triplets_free(&H);
            return rc;
        }
    }
    /* keep the lower triangle of the free block, in free numbering */
    cholmod_triplet *T = cholmod_allocate_triplet((size_t)nf3, (size_t)nf3, (size_t)H.nnz + nf3,
                                                  -1, CHOLMOD_REAL, cm);
    if (!T) {
        pl_triplets_free(&H);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    }
    int *Ti = T->i, *Tj = T->j;
    double *Tx = T->x;
    for (int e = 0; e < H.nnz; ++e) {
        int fi = d->free_index[H.i[e] / 3], fj = d->free_index[H.j[e] / 3];
        if (fi < 0 || fj < 0) continue;
        int r = 3 * fi + H.i[e] % 3, col = 3 * fj + H.j[e] % 3;
        if (r < col) continue;
        Ti[T->nnz] = r, Tj[T->nnz] = col, Tx[T->nnz] = H.x[e], T->nnz++;
    }
    /* a tiny shift keeps the factor defined where the projection left a zero
     * eigenvalue (e.g. quasi-static rigid modes are removed by the boundary) */
    for (int r = 0; r < nf3; ++r) Ti[T->nnz] = r, Tj[T->nnz] = r, Tx[T->nnz] = 1e-12, T->nnz++;
    pl_triplets_free(&H);
    cholmod_sparse *A = cholmod_triplet_to_sparse(T, T->nnz, cm);
    cholmod_free_triplet(&T, cm);
    cholmod_dense *b = cholmod_zeros((size_t)nf3, 1, CHOLMOD_REAL, cm);
    int rc = PL_OK;
    if (!A || !b) {
        rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    } else {
        double *bx = b->x;
        for (int f = 0; f < d->nfree; ++f)
            for (int k = 0; k < 3; ++k) bx[3 * f + k] = -w->grad[3 * d->free_vertex[f] + k];
        cholmod_factor *L = cholmod_analyze(A, cm);
        if (L) cholmod_factorize(A, L, cm);
        cholmod_dense *x = (L && cm->status == CHOLMOD_OK) ? cholmod_solve(CHOLMOD_A, L, b, cm)
                                                           : NULL;
        if (!x) {
            rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                              "NewtonSolver: the Hessian could not be factored (CHOLMOD status %d)",
                              cm->status);
        } else {
            memset(w->dx, 0, (size_t)d->n * 3 * sizeof(double));
            const double *xx = x->x;
            for (int f = 0; f < d->nfree; ++f)
                for (int k = 0; k < 3; ++k) w->dx[3 * d->free_vertex[f] + k] = xx[3 * f + k];
            cholmod_free_dense(&x, cm);
        }
        cholmod_free_factor(&L, cm);
    }
    cholmod_free_sparse(&A, cm);
    cholmod_free_dense(&b, cm);
    return rc;
}

static int ns_step(const pl_component *c, pl_ctx *ctx, double dt, pl_error *err)
{
    const newton_solver *s = (const newton_solver *)c;
    const pl_dynamics *d = &s->dyn;
    if (!s->ready) return pl_component_fail(c, err, PL_EINTERNAL, "not initialised");
    newton_ws *w = workspace(s, ctx->data);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    double *q = w->w.q;
    pl_dynamics_gather(d, &w->w, ctx->data);
    pl_dynamics_predict(d, &w->w);
    /* start from the current positions: a valid (non-inverted) configuration */
    memcpy(q, w->w.q_t, (size_t)d->n * 3 * sizeof(double));
    int rc = pl_dynamics_prescribe(d, &w->w, ctx->data, ctx->data->time + d->h, q, err);
    if (rc) return rc;
    double scale = pl_dynamics_bbox_diagonal(w->w.q_t, d->n), e = potential(s, w, ctx->data, q);
    int it;
    for (it = 0; it < s->max_iterations; ++it) {
        if ((rc = gradient(s, w, ctx->data, q, err)) ||
            (rc = newton_direction(s, w, ctx->data, q, err)))
            return rc;
        double slope = 0.0, step_max = 0.0;
        for (int i = 0; i < 3 * d->n; ++i) {
            slope += w->grad[i] * w->dx[i];
            step_max = fmax(step_max, fabs(w->dx[i]));
        }
        if (step_max < s->tolerance * scale) break;
        double alpha = 1.0, e_new = INFINITY;
        for (int ls = 0; ls < 40; ++ls, alpha *= 0.5) {
            for (int i = 0; i < 3 * d->n; ++i) w->trial[i] = q[i] + alpha * w->dx[i];
            e_new = potential(s, w, ctx->data, w->trial);
            if (isfinite(e_new) && e_new <= e + 1e-4 * alpha * slope) break;
        }
        if (!isfinite(e_new) || e_new > e + 1e-4 * alpha * slope) {
            /* no descent left: we are at the minimum to round-off */
            break;
        }
        memcpy(q, w->trial, (size_t)d->n * 3 * sizeof(double));
        /* round-off floor: once a step changes the energy only in its last
         * digits, the line search accepts noise and no step tolerance can be met */
        int stalled = e - e_new <= 1e-14 * fabs(e_new);
        e = e_new;
        if (stalled) break;
    }
    /* the reference solver says when it stopped short of its tolerance (the
     * round-off and no-descent exits above are convergence, not this) */
    if (it == s->max_iterations && s->max_iterations > 0) {
        char path[192];
        pl_log_warn("%s: stopped at maxIterations = %d before its tolerance (t = %g s)",
                    pl_component_path(c, path, sizeof path), s->max_iterations, ctx->data->time);
    }
    pl_stat_set(ctx->timers, "newton iterations", it);
    pl_stat_set(ctx->timers, "newton energy", e);
    pl_dynamics_scatter(d, &w->w, ctx->data, q, pl_input_double(ctx->data, c, &s->damping));
    return PL_OK;
}

static const pl_animation_loop_ops LOOP = {.version = PL_ANIMATION_LOOP_OPS_VERSION,
                                           .step = ns_step};

const pl_type pl_newton_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "NewtonSolver",
    .help = "Reference implicit-Euler (or quasi-static) solver: Newton with PSD-projected element "
            "Hessians, CHOLMOD and a backtracking line search, to a tight tolerance. Slow; for "
            "tests and convergence studies.",
    .size = sizeof(newton_solver),
    .workspace_size = sizeof(newton_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.reinit = ns_reinit, .destroy = ns_destroy, .workspace_free = ns_workspace_free},
    .roles = {[PL_ROLE_ANIMATION_LOOP] = &LOOP},
};
