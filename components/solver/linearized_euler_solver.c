/* linearized_euler_solver.c - LinearizedEulerSolver: SOFA's EulerImplicitSolver,
 * one linearised implicit-Euler step per time step (Baraff & Witkin 1998):
 *     [(1 + h rM) M + h (h + rS) K] dv = h [f(x_t) - (h + rS) K v_t - rM M v_t]
 *     v += dv,  x += h v
 * with K = -df/dx at x_t (each element's Hessian projected to PSD, as the
 * Newton reference does), rM and rS SOFA's Rayleigh factors; firstOrder
 * solves (M + h K) v = f(x_t), x += h v (SOFA's first-order scheme, the mass
 * acting as a viscosity).  The linear system is solved as the scene's SOFA
 * linear solver would: conjugate gradients with SOFA's iterations,
 * tolerance (|r| / |b|) and threshold (smallest p.Ap), or a direct
 * factorisation (CHOLMOD) for SparseLDLSolver and its kind.  Prescribed
 * vertices take their positions at t + h and are eliminated.  Unlike
 * LocalGlobalSolver and NewtonSolver it does not converge the implicit
 * step: this is the integrator SOFA scenes were tuned with (docs/sofa.md). */
#include <cholmod.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "solver.h"

typedef struct linearized_euler {
    pl_component base;
    double rayleigh_mass, rayleigh_stiffness;
    int first_order;
    int linear_solver; /* 0 cg, 1 direct */
    int stiffness;     /* 0 projected, 1 fixedRotation */
    int iterations;
    double tolerance, threshold;
    pl_dynamics dyn;
    int ready;
} linearized_euler;

/* Per data: the step's vectors and CHOLMOD's common. */
typedef struct le_ws {
    int ready;
    pl_dyn_work w;
    double *f, *kv, *b, *x, *r, *p, *ap; /* 3n (f, kv) or 3 nfree */
    int warned_threshold;                 /* the CG threshold warning was given */
    cholmod_common cm;
} le_ws;

static const char *const SOLVERS[] = {"cg", "direct", NULL};
static const char *const STIFFNESS[] = {"projected", "fixedRotation", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD(linearized_euler, rayleigh_mass, "rayleighMass", PL_F_DOUBLE, "0",
             "Rayleigh damping proportional to the mass [1/s] (SOFA's rayleighMass)",
             PL_FIELD_RUNTIME),
    PL_FIELD(linearized_euler, rayleigh_stiffness, "rayleighStiffness", PL_F_DOUBLE, "0",
             "Rayleigh damping proportional to the stiffness [s] (SOFA's rayleighStiffness)",
             PL_FIELD_RUNTIME),
    PL_FIELD(linearized_euler, first_order, "firstOrder", PL_F_BOOL, "0",
             "SOFA's first-order scheme: (M + h K) v = f, x += h v (no inertia carried over; the "
             "mass acts as a viscosity)",
             0),
    PL_FIELD_ENUM(linearized_euler, linear_solver, "linearSolver", SOLVERS, "cg",
                  "how the step's linear system is solved: cg (conjugate gradients, as SOFA's "
                  "CGLinearSolver) or direct (Cholesky, as SparseLDLSolver)",
                  0),
    PL_FIELD_ENUM(linearized_euler, stiffness, "stiffness", STIFFNESS, "projected",
                  "K: projected (each element's Hessian, rotation's derivative included, "
                  "projected to PSD) or fixedRotation (corotational elements with their rotation "
                  "held fixed, R K0 R^T: SOFA's TetrahedronFEMForceField stiffness; other terms "
                  "projected)",
                  0),
    PL_FIELD(linearized_euler, iterations, "iterations", PL_F_INT, "25",
             "cg: iterations at most [count] (SOFA's CGLinearSolver iterations)", PL_FIELD_RUNTIME),
    PL_FIELD(linearized_euler, tolerance, "tolerance", PL_F_DOUBLE, "1e-5",
             "cg: stop when |r| / |b| is below it [1] (SOFA's tolerance)", PL_FIELD_RUNTIME),
    PL_FIELD(linearized_euler, threshold, "threshold", PL_F_DOUBLE, "1e-5",
             "cg: stop when p.Ap falls below it (SOFA's threshold)", PL_FIELD_RUNTIME),
};

static int le_reinit(pl_component *c, pl_ctx *ctx)
{
    linearized_euler *s = (linearized_euler *)c;
    s->ready = 0;
    if (s->iterations < 1 || s->tolerance < 0 || s->threshold < 0 || s->rayleigh_mass < 0 ||
        s->rayleigh_stiffness < 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "iterations must be >= 1 and tolerance, threshold and the "
                                  "Rayleigh factors >= 0");
    pl_work_limits lim;
    pl_work_limits_of(ctx->model, c->node, &lim);
    if (pl_work_limit_check(c, ctx, s->iterations, lim.max_iterations,
                            "iterations (CG, per time step)", "iterations"))
        return PL_EINPUT;
    pl_dynamics_free(&s->dyn);
    int rc = pl_dynamics_setup(&s->dyn, c, ctx, pl_node_dt(c->node), 0, NULL);
    if (rc) return rc;
    for (int t = 0; t < s->dyn.nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(s->dyn.terms[t], PL_ROLE_LOCAL_TERM);
        if (!ops->add_gradient || !ops->add_hessian)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "%s '%s' provides no forces/stiffness (gradient, Hessian): "
                                      "LinearizedEulerSolver cannot use it",
                                      s->dyn.terms[t]->type->name, s->dyn.terms[t]->name);
    }
    s->ready = 1;
    return PL_OK;
}

static void le_destroy(pl_component *c) { pl_dynamics_free(&((linearized_euler *)c)->dyn); }

static void le_workspace_free(const pl_component *c, void *ws)
{
    le_ws *w = ws;
    (void)c;
    pl_dyn_work_free(&w->w);
    double **v[] = {&w->f, &w->kv, &w->b, &w->x, &w->r, &w->p, &w->ap};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k) free(*v[k]), *v[k] = NULL;
    if (w->ready) cholmod_finish(&w->cm);
    w->ready = 0;
}

static le_ws *workspace(const linearized_euler *s, pl_data *d)
{
    le_ws *w = pl_data_workspace(d, &s->base);
    if (!w || w->ready) return w;
    le_workspace_free(&s->base, w);
    size_t n3 = (size_t)(s->dyn.n ? s->dyn.n : 1) * 3;
    double **v[] = {&w->f, &w->kv, &w->b, &w->x, &w->r, &w->p, &w->ap};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k)
        if (!(*v[k] = calloc(n3, sizeof(double)))) return NULL;
    if (pl_dyn_work_alloc(&w->w, &s->dyn) != PL_OK) return NULL;
    cholmod_start(&w->cm);
    w->cm.print = 0;
    w->ready = 1;
    return w;
}

/* f <- M g - grad psi(x_t) (3n); K (3n x 3n, PSD blocks) at x_t into H. */
static int forces_and_stiffness(const pl_dynamics *d, le_ws *w, const pl_data *data,
                                int psd, pl_triplets *H, pl_error *err)
{
    memset(w->f, 0, (size_t)d->n * 3 * sizeof(double));
    pl_buffer qb = pl_buffer_host_f64(w->w.q_t, (size_t)d->n, 3);
    pl_buffer gb = pl_buffer_host_f64(w->f, (size_t)d->n, 3);
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        int rc = ops->add_gradient(d->terms[t], data, d->term_offset[t], &qb, &gb, err);
        if (!rc) rc = ops->add_hessian(d->terms[t], data, d->term_offset[t], &qb, psd, H, err);
        if (rc) return rc;
    }
    for (int i = 0; i < 3 * d->n; ++i) w->f[i] = d->mass[i / 3] * d->gravity[i] - w->f[i];
    return PL_OK;
}

/* y = A x over the free DOFs (A in CSC, both triangles). */
static void csc_mul(const pl_csc *A, const double *x, double *y)
{
    memset(y, 0, (size_t)A->nrows * sizeof *y);
    for (int j = 0; j < A->ncols; ++j)
        for (int p = A->p[j]; p < A->p[j + 1]; ++p) y[A->i[p]] += A->x[p] * x[j];
}

static double dot(const double *a, const double *b, int n)
{
    double s = 0;
    for (int i = 0; i < n; ++i) s += a[i] * b[i];
    return s;
}

/* SOFA's CGLinearSolver: x = 0; stops at `iterations`, |r|/|b| <= tolerance
 * or p.Ap < threshold.  Returns the iterations done; *short_stop is set when
 * the threshold stopped it with |r|/|b| still above the tolerance. */
static int solve_cg(const linearized_euler *s, const pl_csc *A, le_ws *w, int n, double *short_stop)
{
    memset(w->x, 0, (size_t)n * sizeof(double));
    memcpy(w->r, w->b, (size_t)n * sizeof(double));
    double normb = sqrt(dot(w->b, w->b, n)), rho_old = 0;
    int it;
    *short_stop = 0.0;
    for (it = 0; it < s->iterations; ++it) {
        double rho = dot(w->r, w->r, n);
        if (normb == 0 || sqrt(rho) / normb <= s->tolerance) break;
        if (it == 0)
            memcpy(w->p, w->r, (size_t)n * sizeof(double));
        else
            for (int i = 0; i < n; ++i) w->p[i] = w->r[i] + rho / rho_old * w->p[i];
        csc_mul(A, w->p, w->ap);
        double den = dot(w->p, w->ap, n);
        if (fabs(den) < s->threshold) {
            *short_stop = sqrt(rho) / normb;
            break;
        }
        double alpha = rho / den;
        for (int i = 0; i < n; ++i) w->x[i] += alpha * w->p[i], w->r[i] -= alpha * w->ap[i];
        rho_old = rho;
    }
    return it;
}

static int solve_direct(const pl_csc *A, le_ws *w, int n, pl_error *err)
{
    cholmod_common *cm = &w->cm;
    cholmod_sparse *S = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)A->p[n], 1, 1, -1,
                                                CHOLMOD_REAL, cm);
    cholmod_dense *b = cholmod_zeros((size_t)n, 1, CHOLMOD_REAL, cm);
    int rc = PL_OK;
    if (!S || !b) {
        rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    } else {
        memcpy(S->p, A->p, (size_t)(n + 1) * sizeof(int));
        memcpy(S->i, A->i, (size_t)A->p[n] * sizeof(int));
        memcpy(S->x, A->x, (size_t)A->p[n] * sizeof(double));
        memcpy(b->x, w->b, (size_t)n * sizeof(double));
        cholmod_factor *L = cholmod_analyze(S, cm);
        if (L) cholmod_factorize(S, L, cm);
        cholmod_dense *x = (L && cm->status == CHOLMOD_OK) ? cholmod_solve(CHOLMOD_A, L, b, cm)
                                                           : NULL;
        if (!x)
            rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                              "LinearizedEulerSolver: the system could not be factored "
                              "(CHOLMOD status %d)",
                              cm->status);
        else
            memcpy(w->x, x->x, (size_t)n * sizeof(double));
        cholmod_free_dense(&x, cm);
        cholmod_free_factor(&L, cm);
    }
    cholmod_free_sparse(&S, cm);
    cholmod_free_dense(&b, cm);
    return rc;
}

/* The free block of mfac M + kfac K in CSC (both triangles), and the rhs
 * minus the prescribed columns times their known unknowns u (3n). */
static int build_system(const linearized_euler *s, const pl_triplets *H, le_ws *w,
                        const double *u, pl_csc *A, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    double h = d->h, mfac = s->first_order ? 1.0 : 1.0 + h * s->rayleigh_mass;
    double kfac = s->first_order ? h : h * (h + s->rayleigh_stiffness);
    int nf3 = 3 * d->nfree;
    pl_triplets T;
    if (pl_triplets_init(&T, nf3, nf3, H->nnz + nf3) != PL_OK)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    int rc = PL_OK;
    for (int f = 0; f < d->nfree && !rc; ++f)
        for (int k = 0; k < 3 && !rc; ++k)
            rc = pl_triplets_add(&T, 3 * f + k, 3 * f + k, mfac * d->mass[d->free_vertex[f]]);
    for (int e = 0; e < H->nnz && !rc; ++e) {
        int fi = d->free_index[H->i[e] / 3], fj = d->free_index[H->j[e] / 3];
        if (fi < 0) continue;
        int r = 3 * fi + H->i[e] % 3;
        if (fj < 0)
            w->b[r] -= kfac * H->x[e] * u[H->j[e]];
        else
            rc = pl_triplets_add(&T, r, 3 * fj + H->j[e] % 3, kfac * H->x[e]);
    }
    if (!rc && pl_triplets_to_csc(&T, A) != 0)
        rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    pl_triplets_free(&T);
    return rc;
}

static int le_step(const pl_component *c, pl_ctx *ctx, double dt, pl_error *err)
{
    const linearized_euler *s = (const linearized_euler *)c;
    const pl_dynamics *d = &s->dyn;
    (void)dt;
    if (!s->ready) return pl_component_fail(c, err, PL_EINTERNAL, "not initialised");
    le_ws *w = workspace(s, ctx->data);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    double h = d->h, *q = w->w.q, *qt = w->w.q_t, *vt = w->w.v_t;
    int n3 = 3 * d->n, nf3 = 3 * d->nfree;
    pl_dynamics_gather(d, &w->w, ctx->data);
    memcpy(q, qt, (size_t)n3 * sizeof(double));
    int rc = pl_dynamics_prescribe(d, &w->w, ctx->data, ctx->data->time + h, q, err);
    if (rc) return rc;
    pl_triplets H;
    if (pl_triplets_init(&H, n3, n3, 64 * d->n + 16) != PL_OK)
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    rc = forces_and_stiffness(d, w, ctx->data, s->stiffness ? PL_HESSIAN_FIXED_ROTATION : 1, &H,
                              err);
    /* the unknown: dv (second order) or v (first order); on prescribed
     * vertices it is known from their motion (kept in w->p as scratch) */
    double *u = w->p;
    for (int i = 0; i < n3; ++i) {
        double v_new = (q[i] - qt[i]) / h;
        u[i] = s->first_order ? v_new : v_new - vt[i];
    }
    memset(w->kv, 0, (size_t)n3 * sizeof(double));
    for (int e = 0; e < H.nnz; ++e) w->kv[H.i[e]] += H.x[e] * vt[H.j[e]];
    for (int f = 0; f < d->nfree; ++f)
        for (int k = 0; k < 3; ++k) {
            int i = 3 * d->free_vertex[f] + k;
            w->b[3 * f + k] =
                s->first_order ? w->f[i]
                               : h * (w->f[i] - (h + s->rayleigh_stiffness) * w->kv[i] -
                                      s->rayleigh_mass * d->mass[i / 3] * vt[i]);
        }
    pl_csc A = {0};
    if (!rc) rc = build_system(s, &H, w, u, &A, err);
    pl_triplets_free(&H);
    if (!rc && nf3) {
        if (s->linear_solver == 1) {
            rc = solve_direct(&A, w, nf3, err);
        } else {
            double short_stop;
            int it = solve_cg(s, &A, w, nf3, &short_stop);
            pl_stat_set(ctx->timers, "cg iterations", it);
            /* threshold is SOFA's absolute bound on p.Ap: in SI units a light
             * body's p.Ap can be below the default 1e-5 from the first
             * iteration, and the step then leaves the velocity as it was.
             * SOFA does the same; Pliant says so (once). */
            if (short_stop > 0.0 && !w->warned_threshold) {
                char path[192];
                pl_log_warn("%s: CG stopped by threshold = %g (p.Ap below it) after %d iterations "
                            "with |r|/|b| = %.3g above tolerance = %g at t = %g s: the step is "
                            "inexact; lower threshold (p.Ap scales with the masses and h^2) or "
                            "use linearSolver=\"direct\"",
                            pl_component_path(c, path, sizeof path), s->threshold, it, short_stop,
                            s->tolerance, ctx->data->time);
                w->warned_threshold = 1;
            }
        }
    }
    pl_csc_free(&A);
    if (rc) return rc;
    for (int f = 0; f < d->nfree; ++f)
        for (int k = 0; k < 3; ++k) {
            int i = 3 * d->free_vertex[f] + k;
            double v_new = s->first_order ? w->x[3 * f + k] : vt[i] + w->x[3 * f + k];
            q[i] = qt[i] + h * v_new;
        }
    pl_dynamics_scatter(d, &w->w, ctx->data, q, 0.0);
    return PL_OK;
}

static const pl_animation_loop_ops LOOP = {.version = PL_ANIMATION_LOOP_OPS_VERSION,
                                           .step = le_step};

const pl_type pl_linearized_euler_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "LinearizedEulerSolver",
    .help = "SOFA's EulerImplicitSolver: one linearised implicit-Euler step per time step, "
            "[(1 + h rM) M + h (h + rS) K] dv = h [f - (h + rS) K v - rM M v], the system solved "
            "by conjugate gradients (SOFA's CGLinearSolver) or a direct factorisation; Rayleigh "
            "damping and SOFA's first-order scheme.",
    .size = sizeof(linearized_euler),
    .workspace_size = sizeof(le_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.reinit = le_reinit, .destroy = le_destroy, .workspace_free = le_workspace_free},
    .roles = {[PL_ROLE_ANIMATION_LOOP] = &LOOP},
};
