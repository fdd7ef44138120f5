/* jacobi_solver.c - JacobiSolver: the paper's "incomplete" baseline
 * (Wang 2015, "A Chebyshev semi-iterative approach for accelerating
 * projective and position-based dynamics").  Instead of solving A q = b,
 * each local-global iteration takes ONE Jacobi sweep from the current
 * iterate q^k:
 *     q^ = q^k + gamma D^-1 (b^k - A q^k),   D = diag(A),
 * optionally followed by Wang's Chebyshev step
 *     q^{k+1} = omega_{k+1} (q^ - q^{k-1}) + q^{k-1},
 *     omega = 1 for k < delay,  2 / (2 - rho^2) at k = delay,
 *     omega_{k+1} = 4 / (4 - rho^2 omega_k) after,
 * rho the spectral radius of the Jacobi iteration I - gamma D^-1 A.
 * It plays the global-solver role through solve_from (version 4: the
 * current iterate is the initial guess); it has no exact solve, so scenes
 * with constraints (which need W = H A^-1 H^T) are refused by the
 * LocalGlobalSolver.  Host float64 only. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "solver.h"

typedef struct jacobi_solver {
    pl_component base;
    int chebyshev;
    double rho;          /* field: spectral radius for Chebyshev, 0 = estimate */
    double relaxation;   /* gamma */
    int delay;
    int power_iterations;
    /* built by factor */
    int n;
    pl_csc A;            /* both triangles: column i is row i */
    double *inv_diag;    /* gamma / A_ii */
    double rho_used;
    double omega;
    double *prev;        /* q^{k-1} (n x cols) for the Chebyshev step */
    double *swept;       /* q^ (n x cols) */
    int cols;            /* columns prev and swept hold */
} jacobi_solver;

static const pl_field FIELDS[] = {
    PL_FIELD(jacobi_solver, chebyshev, "chebyshev", PL_F_BOOL, "0",
             "Chebyshev acceleration of the iterates (Wang 2015); off in the paper's comparison",
             0),
    PL_FIELD(jacobi_solver, rho, "rho", PL_F_DOUBLE, "0",
             "spectral radius of the Jacobi iteration for the Chebyshev step, in [0, 1) (0: "
             "estimated at factorisation by power iteration; a lower estimate)",
             0),
    PL_FIELD(jacobi_solver, relaxation, "relaxation", PL_F_DOUBLE, "1",
             "gamma of the sweep q + gamma D^-1 (b - A q) (1: plain Jacobi)", 0),
    PL_FIELD(jacobi_solver, delay, "delay", PL_F_INT, "10",
             "local-global iterations of each step before the Chebyshev step starts (Wang's S)",
             0),
    PL_FIELD(jacobi_solver, power_iterations, "powerIterations", PL_F_INT, "1000",
             "power iterations of the estimate of rho (chebyshev with rho = 0)", 0),
};

static int js_init(pl_component *c, pl_ctx *ctx)
{
    jacobi_solver *s = (jacobi_solver *)c;
    if (!(s->rho >= 0 && s->rho < 1))
        return pl_component_error(c, ctx, PL_EINPUT, "rho must be in [0, 1), got %g", s->rho);
    if (!(s->relaxation > 0 && s->relaxation <= 2))
        return pl_component_error(c, ctx, PL_EINPUT, "relaxation must be in (0, 2], got %g",
                                  s->relaxation);
    if (s->delay < 0) return pl_component_error(c, ctx, PL_EINPUT, "delay must be >= 0");
    if (s->power_iterations < 1)
        return pl_component_error(c, ctx, PL_EINPUT, "powerIterations must be >= 1");
    return PL_OK;
}

static void js_clear(jacobi_solver *s)
{
    pl_csc_free(&s->A);
    free(s->inv_diag);
    free(s->prev);
    free(s->swept);
    s->inv_diag = s->prev = s->swept = NULL;
    s->n = s->cols = 0;
}

static void js_destroy(pl_component *c) { js_clear((jacobi_solver *)c); }

/* A with both triangles (the role may pass the lower one only). */
static int full_symmetric(const pl_csc *A, pl_csc *out)
{
    int n = A->ncols, upper = 0;
    for (int j = 0; j < n && !upper; ++j)
        for (int p = A->p[j]; p < A->p[j + 1]; ++p) upper |= A->i[p] < j;
    pl_triplets t;
    if (pl_triplets_init(&t, n, n, 2 * pl_csc_nnz(A)) != PL_OK) return PL_EINTERNAL;
    int rc = PL_OK;
    for (int j = 0; j < n && rc == PL_OK; ++j)
        for (int p = A->p[j]; p < A->p[j + 1] && rc == PL_OK; ++p) {
            rc = pl_triplets_add(&t, A->i[p], j, A->x[p]);
            if (!upper && A->i[p] != j && rc == PL_OK) rc = pl_triplets_add(&t, j, A->i[p], A->x[p]);
        }
    if (rc == PL_OK) rc = pl_triplets_to_csc(&t, out) ? PL_EINTERNAL : PL_OK;
    pl_triplets_free(&t);
    return rc;
}

/* y = (I - D^-1/2 A D^-1/2) x with r = (gamma / A_ii)^1/2: the symmetric
 * form of the Jacobi iteration matrix I - gamma D^-1 A (same eigenvalues). */
static void iteration_matrix_apply(const pl_csc *A, const double *r, const double *x, double *y)
{
#pragma omp parallel for schedule(static)
    for (int i = 0; i < A->ncols; ++i) {
        double ax = 0.0;
        for (int p = A->p[i]; p < A->p[i + 1]; ++p) ax += A->x[p] * r[A->i[p]] * x[A->i[p]];
        y[i] = x[i] - r[i] * ax;
    }
}

/* |largest eigenvalue| of the Jacobi iteration by power iteration (its
 * Rayleigh quotient, which approaches from below); -1 when out of memory. */
static double estimate_rho(const jacobi_solver *s)
{
    size_t n = s->n > 0 ? (size_t)s->n : 1;
    double *x = malloc(sizeof(double) * n), *y = malloc(sizeof(double) * n),
           *r = malloc(sizeof(double) * n);
    double lambda = -1.0;
    if (x && y && r) {
        for (int i = 0; i < s->n; ++i) r[i] = sqrt(s->inv_diag[i]);
        /* a smooth start (the slow modes are the smooth ones) with a little of everything */
        for (int i = 0; i < s->n; ++i) x[i] = 1.0 + 0.01 * ((i * 7919) % 101) / 101.0;
        for (int it = 0; it < s->power_iterations; ++it) {
            double xx = 0.0, xy = 0.0, yy = 0.0;
            iteration_matrix_apply(&s->A, r, x, y);
            for (int i = 0; i < s->n; ++i) xx += x[i] * x[i], xy += x[i] * y[i], yy += y[i] * y[i];
            lambda = fabs(xy / xx);
            if (!(yy > 0)) break;
            double scale = 1.0 / sqrt(yy);
            for (int i = 0; i < s->n; ++i) x[i] = y[i] * scale;
        }
    }
    free(x);
    free(y);
    free(r);
    return lambda;
}

static int js_factor(pl_component *c, const pl_csc *A, struct pl_timers *timers, pl_error *err)
{
    jacobi_solver *s = (jacobi_solver *)c;
    double t0 = pl_now();
    js_clear(s);
    if (A->nrows != A->ncols) return pl_component_fail(c, err, PL_EINPUT, "A is not square");
    if (full_symmetric(A, &s->A) != PL_OK) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    s->n = A->ncols;
    s->inv_diag = malloc(sizeof(double) * (size_t)(s->n ? s->n : 1));
    if (!s->inv_diag) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    for (int i = 0; i < s->n; ++i) {
        double aii = 0.0;
        for (int p = s->A.p[i]; p < s->A.p[i + 1]; ++p)
            if (s->A.i[p] == i) aii = s->A.x[p];
        if (!(aii > 0))
            return pl_component_fail(c, err, PL_EINPUT,
                                     "A_%d%d = %g: the Jacobi sweep needs a positive diagonal", i, i,
                                     aii);
        s->inv_diag[i] = s->relaxation / aii;
    }
    s->rho_used = s->rho;
    if (s->chebyshev && s->rho == 0) {
        s->rho_used = estimate_rho(s);
        if (s->rho_used < 0) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        if (!(s->rho_used < 1))
            return pl_component_fail(c, err, PL_EINPUT,
                                     "the Jacobi iteration does not converge on this system "
                                     "(spectral radius %g >= 1): lower relaxation",
                                     s->rho_used);
    }
    char path[256];
    pl_log_info("%s: n = %d, nnz(A) = %d%s%.6f, %.3f s", pl_component_path(c, path, sizeof path),
                s->n, pl_csc_nnz(&s->A), s->chebyshev ? ", Chebyshev with rho = " : ", rho unused: ",
                s->rho_used, pl_now() - t0);
    if (timers) {
        pl_stat_set(timers, "nnz(A)", pl_csc_nnz(&s->A));
        if (s->chebyshev) pl_stat_set(timers, "jacobi rho", s->rho_used);
    }
    return PL_OK;
}

/* swept = x + gamma D^-1 (b - A x), one row per thread (deterministic). */
static void sweep(const jacobi_solver *s, const double *b, const double *x, int cols)
{
    const pl_csc *A = &s->A;
#pragma omp parallel for schedule(static)
    for (int i = 0; i < s->n; ++i)
        for (int k = 0; k < cols; ++k) {
            double r = b[(size_t)i * cols + k];
            for (int p = A->p[i]; p < A->p[i + 1]; ++p) r -= A->x[p] * x[(size_t)A->i[p] * cols + k];
            s->swept[(size_t)i * cols + k] = x[(size_t)i * cols + k] + s->inv_diag[i] * r;
        }
}

static int js_solve_from(pl_component *c, const pl_buffer *b, pl_buffer *x, int iteration,
                         pl_error *err)
{
    jacobi_solver *s = (jacobi_solver *)c;
    const double *bd = pl_buffer_f64(b);
    double *xd = pl_buffer_f64(x);
    if (s->n == 0) return pl_component_fail(c, err, PL_EINPUT, "solve called before factor");
    if (!bd || !xd || b->rows != (size_t)s->n || x->rows != (size_t)s->n || b->cols != x->cols ||
        b->cols < 1 || b->cols > 1024 || bd == xd)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "solve_from: expected two distinct host float64 %d x k blocks",
                                 s->n);
    int cols = (int)b->cols;
    size_t len = (size_t)s->n * (size_t)cols;
    if (cols != s->cols) {
        free(s->prev);
        free(s->swept);
        s->prev = malloc(sizeof(double) * len);
        s->swept = malloc(sizeof(double) * len);
        s->cols = s->prev && s->swept ? cols : 0;
        if (!s->cols) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        iteration = 0; /* no q^{k-1} of this shape */
    }
    sweep(s, bd, xd, cols);
    int start = s->delay > 1 ? s->delay : 1; /* the first step has no q^{k-1} */
    if (!s->chebyshev || iteration < start) {
        s->omega = 1.0;
        if (s->chebyshev) memcpy(s->prev, xd, sizeof(double) * len);
        memcpy(xd, s->swept, sizeof(double) * len);
        return PL_OK;
    }
    double r2 = s->rho_used * s->rho_used;
    s->omega = iteration == start ? 2.0 / (2.0 - r2) : 4.0 / (4.0 - r2 * s->omega);
    for (size_t i = 0; i < len; ++i) {
        double qk = xd[i];
        xd[i] = s->omega * (s->swept[i] - s->prev[i]) + s->prev[i];
        s->prev[i] = qk;
    }
    return PL_OK;
}

static int js_solve(const pl_component *c, const pl_buffer *b, pl_buffer *x, pl_error *err)
{
    (void)b;
    (void)x;
    return pl_component_fail(c, err, PL_EINPUT,
                             "JacobiSolver gives one Jacobi sweep from the current iterate "
                             "(solve_from), not A^-1 b: use SparseInverseSolver where an exact "
                             "global solve is needed");
}

static int js_size(const pl_component *c) { return ((const jacobi_solver *)c)->n; }

static int js_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    (void)c;
    return where == PL_HOST && prec == PL_F64;
}

static int js_approximate(const pl_component *c)
{
    (void)c;
    return 1;
}

static const pl_global_solver_ops OPS = {
    .version = PL_GLOBAL_SOLVER_OPS_VERSION,
    .factor = js_factor,
    .solve = js_solve,
    .size = js_size,
    .accepts = js_accepts,
    .solve_from = js_solve_from,
    .approximate = js_approximate,
};

const pl_type pl_jacobi_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "JacobiSolver",
    .help = "The paper's incomplete baseline (Wang 2015): the global step is one Jacobi sweep "
            "from the current iterate, optionally Chebyshev-accelerated. No constraints.",
    .size = sizeof(jacobi_solver),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = js_init, .destroy = js_destroy},
    .roles = {[PL_ROLE_GLOBAL_SOLVER] = &OPS},
};
