/* test_hyper_local_global.c - a tiny local-global loop written here (dense
 * Cholesky, no prescribed DOFs) against a plain Newton iteration on the same
 * incremental potential
 *     f(x) = 1/(2 h^2) |x - sn|_M^2 + E(x):
 *  - ARAP (PD): f never increases across iterations;
 *  - ADMM-PD (corotational, Neo-Hookean, tets and membranes with bending)
 *    converges to Newton's minimiser, and without the dual it does not;
 *  - the local step is deterministic (1 thread = 2 threads, bit for bit). */
#include <check.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hyper_test_util.h"
#include "hyperelastic.h"

typedef struct problem {
    int nv;
    double h;
    double *rest, *mass, *sn; /* nv x 3, nv, nv x 3 */
    pl_hyper_elements el;
    pl_hyper_stencils bend;   /* optional (bend.n = 0 when unused) */
    pl_hyper_stencils tgt;    /* optional position targets */
    double *targets;          /* tgt.n x 3 */
} problem;

static double objective(const problem *P, const double *x)
{
    double f = 0.0;
    for (int i = 0; i < P->nv; ++i)
        for (int a = 0; a < 3; ++a) f += 0.5 * P->mass[i] * pow(x[3 * i + a] - P->sn[3 * i + a], 2);
    f /= P->h * P->h;
    f += hyper_elements_energy(&P->el, 0, x);
    if (P->bend.n) f += hyper_stencils_energy(&P->bend, 0, x, NULL);
    if (P->tgt.n) f += hyper_stencils_energy(&P->tgt, 0, x, P->targets);
    return f;
}

static void gradient(const problem *P, const double *x, double *g)
{
    for (int i = 0; i < P->nv; ++i)
        for (int a = 0; a < 3; ++a)
            g[3 * i + a] = P->mass[i] * (x[3 * i + a] - P->sn[3 * i + a]) / (P->h * P->h);
    hyper_elements_add_gradient(&P->el, 0, x, g, NULL);
    if (P->bend.n) hyper_stencils_add_gradient(&P->bend, 0, x, NULL, g, NULL);
    if (P->tgt.n) hyper_stencils_add_gradient(&P->tgt, 0, x, P->targets, g, NULL);
}

static double inf_norm(int n, const double *v)
{
    double m = 0.0;
    for (int i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
    return m;
}

/* Projected Newton with backtracking from sn, until the gradient stops
 * shrinking; returns the iterations, *gratio the final |grad| / |grad(sn)|. */
static int newton(const problem *P, double *x, double *gratio)
{
    const int n = 3 * P->nv;
    double *g = malloc(sizeof(double) * n), *H = malloc(sizeof(double) * n * n);
    double *xt = malloc(sizeof(double) * n), *dir = malloc(sizeof(double) * n);
    memcpy(x, P->sn, sizeof(double) * n);
    gradient(P, x, g);
    double g0 = inf_norm(n, g);
    int it;
    for (it = 0; it < 100 && inf_norm(n, g) > 1e-11 * g0; ++it) {
        pl_triplets T;
        pl_triplets_init(&T, n, n, 1024);
        memset(H, 0, sizeof(double) * n * n);
        hyper_elements_add_hessian(&P->el, 0, x, 1, &T, NULL);
        if (P->bend.n) hyper_stencils_add_hessian(&P->bend, 0, x, 1, &T, NULL);
        if (P->tgt.n) hyper_stencils_add_hessian(&P->tgt, 0, x, 1, &T, NULL);
        ht_triplets_to_dense(&T, H, n);
        pl_triplets_free(&T);
        for (int i = 0; i < n; ++i) H[i * n + i] += P->mass[i / 3] / (P->h * P->h);
        ck_assert_int_eq(ht_cholesky(n, H), 0);
        for (int i = 0; i < n; ++i) dir[i] = -g[i];
        ht_cholesky_solve(n, H, 1, dir);
        double f = objective(P, x), slope = 0.0, alpha = 1.0;
        for (int i = 0; i < n; ++i) slope += g[i] * dir[i];
        int ok = 0;
        for (int ls = 0; ls < 40 && !ok; ++ls, alpha *= 0.5) {
            for (int i = 0; i < n; ++i) xt[i] = x[i] + alpha * dir[i];
            ok = objective(P, xt) <= f + 1e-4 * alpha * slope;
        }
        if (!ok) { /* round-off: accept a full step only if it shrinks the gradient */
            double *gt = H; /* the factor is no longer needed */
            for (int i = 0; i < n; ++i) xt[i] = x[i] + dir[i];
            gradient(P, xt, gt);
            if (!(inf_norm(n, gt) < inf_norm(n, g))) break;
        }
        memcpy(x, xt, sizeof(double) * n);
        gradient(P, x, g);
    }
    *gratio = inf_norm(n, g) / g0;
    free(g);
    free(H);
    free(xt);
    free(dir);
    return it;
}

/* The factored scalar A = M + h^2 sum w G^T G (dense lower Cholesky). */
static double *factor_system(const problem *P)
{
    const int n = P->nv;
    const double h2 = P->h * P->h;
    double *A = calloc((size_t)n * n, sizeof *A);
    pl_triplets T;
    pl_triplets_init(&T, n, n, 1024);
    ck_assert_int_eq(hyper_elements_add_matrix(&P->el, 0, h2, &T, NULL), PL_OK);
    if (P->bend.n) hyper_stencils_add_matrix(&P->bend, 0, h2, &T, NULL);
    if (P->tgt.n) hyper_stencils_add_matrix(&P->tgt, 0, h2, &T, NULL);
    ht_triplets_to_dense(&T, A, n);
    pl_triplets_free(&T);
    for (int i = 0; i < n; ++i) A[i * n + i] += P->mass[i];
    ck_assert_int_eq(ht_cholesky(n, A), 0);
    return A;
}

/* Runs up to `iters` local-global iterations from sn, stopping early when
 * an iteration moves no vertex by more than tol.  keep_dual = 0 zeroes the
 * ADMM dual before every local step (plain PD with the prox: the bug that
 * PAPER_NOTES item 2 describes).  f_hist (iters + 1 values) may be NULL.
 * Returns the iterations run. */
static int local_global(problem *P, int iters, int keep_dual, double tol, double *x, double *f_hist)
{
    const int n = P->nv;
    const double h2 = P->h * P->h;
    double *L = factor_system(P);
    int nd = hyper_elements_dual_size(&P->el), k;
    double *u = calloc((size_t)P->el.n * (nd ? nd : 1), sizeof *u);
    double *rhs = malloc(sizeof(double) * 3 * n);
    double *work = malloc(sizeof(double) * hyper_elements_work_size(&P->el));
    double *bwork = malloc(sizeof(double) * (hyper_stencils_work_size(&P->bend) +
                                             hyper_stencils_work_size(&P->tgt)));
    memcpy(x, P->sn, sizeof(double) * 3 * n);
    if (f_hist) f_hist[0] = objective(P, x);
    for (k = 0; k < iters; ++k) {
        if (!keep_dual) memset(u, 0, sizeof(double) * P->el.n * nd);
        for (int i = 0; i < n; ++i)
            for (int a = 0; a < 3; ++a) rhs[3 * i + a] = P->mass[i] * P->sn[3 * i + a];
        ck_assert_int_eq(hyper_elements_project(&P->el, 0, h2, x, nd ? u : NULL, NULL, work, rhs, NULL,
                                                   NULL),
                         PL_OK);
        if (P->bend.n) hyper_stencils_project(&P->bend, 0, h2, x, NULL, bwork, rhs, NULL);
        if (P->tgt.n) hyper_stencils_project(&P->tgt, 0, h2, x, P->targets, bwork, rhs, NULL);
        ht_cholesky_solve(n, L, 3, rhs);
        double step = 0.0;
        for (int i = 0; i < 3 * n; ++i) step = fmax(step, fabs(rhs[i] - x[i]));
        memcpy(x, rhs, sizeof(double) * 3 * n);
        if (f_hist) f_hist[k + 1] = objective(P, x);
        if (step <= tol) {
            ++k;
            break;
        }
    }
    free(L);
    free(u);
    free(rhs);
    free(work);
    free(bwork);
    return k;
}

/* A tet bar 5 x 4 x 3 (60 vertices), twisted and stretched predicted state. */
static void make_tet_problem(problem *P, pl_hyper_material mat, double E, double nu)
{
    memset(P, 0, sizeof *P);
    int *tets, nt;
    const double a = 0.05, rho = 1000.0;
    P->nv = ht_tet_grid(5, 4, 3, a, &P->rest, &tets, &nt);
    P->h = 0.02;
    ck_assert_int_eq(hyper_elements_build(&P->el, mat, 4, tets, nt, P->rest, P->nv, &E, 1, &nu,
                                             1, 1.0, NULL), PL_OK);
    P->mass = calloc(P->nv, sizeof *P->mass);
    for (int e = 0; e < nt; ++e)
        for (int c = 0; c < 4; ++c) P->mass[tets[4 * e + c]] += rho * P->el.volume[e] / 4.0;
    P->sn = malloc(sizeof(double) * 3 * P->nv);
    unsigned long long st = 12;
    for (int i = 0; i < P->nv; ++i) {
        const double *r = P->rest + 3 * i;
        double ang = 3.0 * r[0], c = cos(ang), s = sin(ang), y = r[1] - 0.075, z = r[2] - 0.05;
        P->sn[3 * i + 0] = 1.25 * r[0] + 0.004 * ht_rand(&st);
        P->sn[3 * i + 1] = c * y - s * z + 0.004 * ht_rand(&st);
        P->sn[3 * i + 2] = s * y + c * z + 0.004 * ht_rand(&st);
    }
    free(tets);
}

/* A 7 x 7 membrane, stretched in-plane with small out-of-plane noise, with
 * isometric bending. */
static void make_cloth_problem(problem *P, pl_hyper_material mat, double E, double nu)
{
    memset(P, 0, sizeof *P);
    int *tris, nt;
    P->nv = ht_tri_grid(7, 7, 0.05, &P->rest, &tris, &nt);
    P->h = 0.01;
    ck_assert_int_eq(hyper_elements_build(&P->el, mat, 3, tris, nt, P->rest, P->nv, &E, 1, &nu,
                                             1, 1e-3, NULL), PL_OK);
    ck_assert_int_eq(hyper_isometric_bending_build(&P->bend, tris, nt, P->rest, P->nv, 1e-4,
                                                      NULL, NULL), PL_OK);
    P->mass = malloc(sizeof(double) * P->nv);
    for (int i = 0; i < P->nv; ++i) P->mass[i] = 0.1 / P->nv;
    P->sn = malloc(sizeof(double) * 3 * P->nv);
    unsigned long long st = 13;
    for (int i = 0; i < P->nv; ++i) {
        P->sn[3 * i + 0] = 1.4 * P->rest[3 * i + 0];
        P->sn[3 * i + 1] = 1.2 * P->rest[3 * i + 1];
        P->sn[3 * i + 2] = 0.003 * ht_rand(&st);
    }
    free(tris);
}

static void free_problem(problem *P)
{
    hyper_elements_free(&P->el);
    hyper_stencils_free(&P->bend);
    hyper_stencils_free(&P->tgt);
    free(P->rest);
    free(P->mass);
    free(P->sn);
    free(P->targets);
}

START_TEST(arap_objective_never_increases)
{
    problem P;
    make_tet_problem(&P, PL_HYPER_ARAP, 1e5, 0.3);
    /* plus two soft position targets */
    int idx[2] = {0, P.nv - 1};
    ck_assert_int_eq(hyper_point_targets_build(&P.tgt, idx, 2, P.nv, 500.0, NULL), PL_OK);
    P.targets = malloc(sizeof(double) * 6);
    for (int a = 0; a < 3; ++a) {
        P.targets[a] = P.rest[a] - 0.02;
        P.targets[3 + a] = P.rest[3 * (P.nv - 1) + a] + 0.03;
    }
    const int K = 60;
    double f[61], *x = malloc(sizeof(double) * 3 * P.nv);
    local_global(&P, K, 1, 0.0, x, f);
    for (int k = 0; k < K; ++k)
        ck_assert_msg(f[k + 1] <= f[k] * (1 + 1e-13), "iteration %d: f rose %.17g -> %.17g", k, f[k], f[k + 1]);
    ck_assert(f[K] < 0.5 * f[0]);
    /* and it heads for the Newton minimiser */
    double *xn = malloc(sizeof(double) * 3 * P.nv);
    double gr;
    newton(&P, xn, &gr);
    double fn = objective(&P, xn);
    printf("ARAP: f(sn) %.6g, after %d PD iterations %.6g, Newton minimum %.6g\n", f[0], K, f[K], fn);
    ck_assert(fn <= f[K] * (1 + 1e-12));
    free(x);
    free(xn);
    free_problem(&P);
}
END_TEST

/* ADMM-PD with the dual reaches Newton's minimiser; without it, it does not. */
static void admm_matches_newton(problem *P, const char *name)
{
    const int n = 3 * P->nv;
    double *xn = malloc(sizeof(double) * n), *xa = malloc(sizeof(double) * n);
    double *x0 = malloc(sizeof(double) * n), *g = malloc(sizeof(double) * n);
    double gr;
    int nit = newton(P, xn, &gr);
    ck_assert_msg(gr <= 1e-10, "%s: Newton reached only %g", name, gr);
    double disp = 0.0;
    for (int i = 0; i < n; ++i) disp = fmax(disp, fabs(xn[i] - P->sn[i]));
    const int K = 3000;
    int ka = local_global(P, K, 1, 1e-14 * disp, xa, NULL);
    int k0 = local_global(P, 400, 0, 1e-14 * disp, x0, NULL);
    double err = 0.0, err0 = 0.0;
    for (int i = 0; i < n; ++i) {
        err = fmax(err, fabs(xa[i] - xn[i]));
        err0 = fmax(err0, fabs(x0[i] - xn[i]));
    }
    gradient(P, P->sn, g);
    double gsn = inf_norm(n, g);
    gradient(P, xa, g);
    double ga = inf_norm(n, g);
    printf("%s: Newton %d its (|grad| ratio %.2g); |x_newton - sn| %.3g; ADMM %d its: error %.3g, "
           "|grad| ratio %.3g; without dual (%d its): error %.3g\n", name, nit, gr, disp, ka,
           err / disp, ga / gsn, k0, err0 / disp);
    ck_assert_msg(err <= 1e-7 * disp, "%s: ADMM error %g (displacement %g)", name, err, disp);
    ck_assert_msg(ga <= 1e-6 * gsn, "%s: gradient %g of %g", name, ga, gsn);
    ck_assert_msg(err0 >= 1e3 * err, "%s: no dual should be clearly worse (%g vs %g)", name, err0, err);
    free(xn);
    free(xa);
    free(x0);
    free(g);
}

START_TEST(admm_corotational_tets_converge_to_newton)
{
    problem P;
    make_tet_problem(&P, PL_HYPER_COROTATIONAL, 1e5, 0.3);
    admm_matches_newton(&P, "corotational tets");
    free_problem(&P);
}
END_TEST

START_TEST(admm_neohookean_tets_converge_to_newton)
{
    problem P;
    make_tet_problem(&P, PL_HYPER_NEOHOOKEAN, 1e5, 0.4);
    admm_matches_newton(&P, "Neo-Hookean tets");
    free_problem(&P);
}
END_TEST

START_TEST(admm_membranes_with_bending_converge_to_newton)
{
    problem P;
    make_cloth_problem(&P, PL_HYPER_NEOHOOKEAN, 1e5, 0.3);
    admm_matches_newton(&P, "Neo-Hookean membrane + isometric bending");
    free_problem(&P);
    make_cloth_problem(&P, PL_HYPER_COROTATIONAL, 1e5, 0.3);
    admm_matches_newton(&P, "corotational membrane + isometric bending");
    free_problem(&P);
}
END_TEST

START_TEST(local_step_is_deterministic_across_thread_counts)
{
    double *rest;
    int *tets, nt;
    int nv = ht_tet_grid(14, 14, 14, 0.01, &rest, &tets, &nt);
    double E = 1e5, nu = 0.45, *q = malloc(sizeof(double) * 3 * nv);
    unsigned long long st = 14;
    for (int i = 0; i < 3 * nv; ++i) q[i] = 1.1 * rest[i] + 0.001 * ht_rand(&st);
    for (int mat = 0; mat < 3; ++mat) {
        pl_hyper_elements el;
        ck_assert_int_eq(hyper_elements_build(&el, (pl_hyper_material)mat, 4, tets, nt, rest, nv,
                                                 &E, 1, &nu, 1, 1.0, NULL), PL_OK);
        int nd = hyper_elements_dual_size(&el);
        double *rhs[2], *u[2], *work = malloc(sizeof(double) * hyper_elements_work_size(&el));
        for (int r = 0; r < 2; ++r) {
            rhs[r] = calloc((size_t)3 * nv, sizeof(double));
            u[r] = calloc((size_t)nt * (nd ? nd : 1), sizeof(double));
            omp_set_num_threads(r + 1);
            for (int k = 0; k < 2; ++k) /* twice: the second uses non-zero duals */
                ck_assert_int_eq(hyper_elements_project(&el, 0, 1e-4, q, nd ? u[r] : NULL, NULL, work,
                                                           rhs[r], NULL, NULL),
                                 PL_OK);
        }
        ck_assert_int_eq(memcmp(rhs[0], rhs[1], sizeof(double) * 3 * nv), 0);
        ck_assert_int_eq(memcmp(u[0], u[1], sizeof(double) * nt * nd), 0);
        for (int r = 0; r < 2; ++r) {
            free(rhs[r]);
            free(u[r]);
        }
        free(work);
        hyper_elements_free(&el);
    }
    omp_set_num_threads(2);
    free(q);
    free(rest);
    free(tets);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("hyper_local_global");
    TCase *tc = tcase_create("local_global");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, arap_objective_never_increases);
    tcase_add_test(tc, admm_corotational_tets_converge_to_newton);
    tcase_add_test(tc, admm_neohookean_tets_converge_to_newton);
    tcase_add_test(tc, admm_membranes_with_bending_converge_to_newton);
    tcase_add_test(tc, local_step_is_deterministic_across_thread_counts);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
