/* test_ncp_full_force.c - the core's additions for the plugin:
 *  - ncp_step with full_force (S = 1) solves the unsymmetric Newton
 *    system Omega h^2 W dlambda + E dlambda = rhs exactly (CR on its
 *    Omega^-1-symmetrised form), and iterated at the corrected point it
 *    reaches the same solutions as ncp_solve_fc3d (paper mode);
 *  - ncp_project maps onto the admissible set and fixes its points;
 *  - ncp_line_search halves a step that jumps between the bounds of
 *    coupled bounded rows and keeps a full step that decreases. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ncp.h"
#include "ncp_test_util.h"

static void matvec(int m, const double *W, const double *x, double *y)
{
    for (int i = 0; i < m; ++i) {
        double s = 0.0;
        for (int j = 0; j < m; ++j) s += W[i * m + j] * x[j];
        y[i] = s;
    }
}

/* fc3d rows: 3i normal, 3i+1, 3i+2 friction */
static void fc3d_rows(int nc, const double *mu, pl_row_kind *kind, int *pair, double *rmu)
{
    for (int i = 0; i < nc; ++i) {
        kind[3 * i] = PL_ROW_NORMAL;
        kind[3 * i + 1] = kind[3 * i + 2] = PL_ROW_FRICTION;
        pair[3 * i] = 3 * i + 1;
        pair[3 * i + 1] = pair[3 * i + 2] = 3 * i;
        rmu[3 * i] = mu[i];
        rmu[3 * i + 1] = rmu[3 * i + 2] = 0.0;
    }
}

START_TEST(full_force_step_solves_the_unsymmetric_newton_system)
{
    enum { NC = 4, M = 3 * NC };
    test_rng g = {42};
    double W[M * M], mu[NC], rmu[M], r[M], diag[M];
    pl_row_kind kind[M];
    int pair[M];
    random_spd(&g, M, 0.2, W);
    for (int i = 0; i < NC; ++i) mu[i] = rng_range(&g, 0.1, 0.6);
    fc3d_rows(NC, mu, kind, pair, rmu);
    pl_ncp_rows rows = {M, kind, pair, rmu, NULL, NULL, NULL};
    pl_ncp_work *w;
    pl_error err;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    for (int j = 0; j < M; ++j) diag[j] = W[j * M + j];
    const double h = 0.01;
    ck_assert_int_eq(ncp_scaling(w, diag, h, r, &err), PL_OK);
    pl_ncp_operator op = {M, W, NULL, NULL, diag};
    for (int trial = 0; trial < 20; ++trial) {
        double delta[M], dfree[M], lambda[M], dl[M], S[M], Wl[M], Wd[M];
        for (int j = 0; j < M; ++j) {
            delta[j] = rng_range(&g, -1e-3, 1e-3);
            dfree[j] = rng_range(&g, -1e-3, 1e-3);
            lambda[j] = rng_range(&g, -1, 3);
        }
        pl_ncp_params par;
        ncp_params_default(&par);
        par.fn = trial % 2 ? PL_NCP_MINMAP : PL_NCP_FB;
        par.h = h;
        par.full_force = 1;
        par.cr_max_iter = 200;
        par.cr_rtol = 1e-15;
        pl_ncp_step_info info;
        ck_assert_int_eq(ncp_step(w, &par, &op, r, delta, dfree, lambda, dl, S, &info, &err), PL_OK);
        matvec(M, W, lambda, Wl);
        matvec(M, W, dl, Wd);
        /* compare in the symmetrised form CR solves: row j divided by Omega_j */
        double rs[M], scale = 0.0;
        for (int j = 0; j < M; ++j) {
            double p = delta[j] - dfree[j] - h * h * Wl[j];
            rs[j] = -w->phi[j] + w->omega[j] * p;
            scale = fmax(scale, fabs(w->is_clamped[j] ? rs[j] / w->e[j] : rs[j] / w->omega[j]));
        }
        for (int j = 0; j < M; ++j) {
            ck_assert_double_eq(S[j], 1.0);
            if (w->is_clamped[j]) {
                ck_assert_double_le(fabs(dl[j] - rs[j] / w->e[j]), 1e-12 * scale);
            } else {
                double lhs = h * h * Wd[j] + w->e[j] / w->omega[j] * dl[j];
                ck_assert_msg(fabs(lhs - rs[j] / w->omega[j]) <= 1e-9 * scale, "trial %d row %d: %.17g vs %.17g",
                              trial, j, lhs, rs[j] / w->omega[j]);
            }
            if (w->is_clamped[j]) ck_assert_double_le(w->omega[j], 1e-3);
        }
    }
    ncp_work_destroy(w);
}
END_TEST

/* Iterates lambda with full_force at the corrected point delta = q + W
 * lambda (h = 1), with line search and projection as the plugin does. */
static int solve_full_force(int nc, const double *W, const double *q, const double *mu, pl_ncp_function fn,
                            double *lambda, double *res_out)
{
    int m = 3 * nc, k;
    pl_row_kind *kind = malloc(sizeof *kind * (size_t)m);
    int *pair = malloc(sizeof(int) * (size_t)m);
    double *rmu = malloc(sizeof(double) * (size_t)m), *r = malloc(sizeof(double) * (size_t)m);
    double *diag = malloc(sizeof(double) * (size_t)m), *delta = malloc(sizeof(double) * (size_t)m);
    double *dl = malloc(sizeof(double) * (size_t)m), *dd = malloc(sizeof(double) * (size_t)m);
    fc3d_rows(nc, mu, kind, pair, rmu);
    pl_ncp_rows rows = {m, kind, pair, rmu, NULL, NULL, NULL};
    pl_ncp_work *w;
    pl_error err;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    for (int j = 0; j < m; ++j) diag[j] = W[j * m + j];
    ncp_scaling(w, diag, 1.0, r, &err);
    pl_ncp_operator op = {m, W, NULL, NULL, diag};
    pl_ncp_params par;
    ncp_params_default(&par);
    par.fn = fn;
    par.full_force = 1;
    par.cr_rtol = 1e-14;
    par.fb_eps = 1e-16;
    memset(lambda, 0, sizeof(double) * (size_t)m);
    for (k = 0; k < 500; ++k) {
        matvec(m, W, lambda, delta);
        for (int j = 0; j < m; ++j) delta[j] += q[j];
        pl_ncp_residual res;
        ncp_residual_eval(w, r, 1.0, delta, lambda, &res, &err);
        *res_out = res.total;
        if (res.total <= 1e-13) break;
        pl_ncp_step_info info;
        ck_assert_int_eq(ncp_step(w, &par, &op, r, delta, q, lambda, dl, NULL, &info, &err), PL_OK);
        matvec(m, W, dl, dd);
        pl_ncp_line_info li;
        ck_assert_int_eq(ncp_line_search(w, r, 1.0, delta, dd, lambda, dl, 3, &li, &err), PL_OK);
        for (int j = 0; j < m; ++j) lambda[j] += li.alpha * dl[j];
        ncp_project(w, lambda);
    }
    ncp_work_destroy(w);
    free(kind); free(pair); free(rmu); free(r); free(diag); free(delta); free(dl); free(dd);
    return k;
}

START_TEST(full_force_iteration_agrees_with_the_fc3d_solver)
{
    test_rng g = {7};
    int solved = 0, total = 0, worst = 0;
    for (int trial = 0; trial < 40; ++trial) {
        int nc = 1 + trial % 5, m = 3 * nc;
        double *W = malloc(sizeof(double) * (size_t)(m * m)), q[15], mu[5], l1[15], l2[15], u[15];
        random_spd(&g, m, 0.5, W);
        for (int i = 0; i < nc; ++i) {
            mu[i] = rng_range(&g, 0.05, 0.3);
            q[3 * i] = rng_range(&g, -1, 0.2);
            q[3 * i + 1] = rng_range(&g, -1, 1);
            q[3 * i + 2] = rng_range(&g, -1, 1);
        }
        pl_ncp_solve_opts o;
        ncp_solve_opts_default(&o);
        pl_ncp_solve_info info;
        pl_error err;
        memset(l1, 0, sizeof l1);
        ck_assert_int_eq(ncp_solve_fc3d(nc, W, q, mu, l1, u, &o, &info, &err), PL_OK);
        double res;
        int its = solve_full_force(nc, W, q, mu, trial % 2 ? PL_NCP_MINMAP : PL_NCP_FB, l2, &res);
        ++total;
        if (info.converged && res <= 1e-13) {
            ++solved;
            worst = its > worst ? its : worst;
            for (int j = 0; j < m; ++j) ck_assert_double_le(fabs(l1[j] - l2[j]), 1e-8 * (1 + fabs(l1[j])));
        }
        free(W);
    }
    printf("full_force at the corrected point: %d of %d random fc3d problems to 1e-13 (at most %d iterations), "
           "equal to ncp_solve_fc3d\n",
           solved, total, worst);
    ck_assert_int_ge(solved, 36);
}
END_TEST

START_TEST(projection_onto_the_admissible_set)
{
    pl_row_kind kind[6] = {PL_ROW_NORMAL, PL_ROW_FRICTION, PL_ROW_FRICTION, PL_ROW_BOUNDED, PL_ROW_BILATERAL,
                           PL_ROW_NORMAL};
    int pair[6] = {1, 0, 0, -1, -1, -1};
    double mu[6] = {0.5, 0, 0, 0, 0, 0.3}, lo[6] = {0, 0, 0, -1, 0, 0}, hi[6] = {0, 0, 0, 2, 0, 0};
    pl_ncp_rows rows = {6, kind, pair, mu, NULL, lo, hi};
    pl_ncp_work *w;
    pl_error err;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    double l[6] = {2.0, 3.0, -4.0, 5.0, -7.0, -1.0};
    ck_assert_int_eq(ncp_project(w, l), 3);
    /* friction (3, -4) of norm 5 scaled to mu lambda_n = 1 */
    ck_assert_double_eq_tol(l[1], 0.6, 1e-15);
    ck_assert_double_eq_tol(l[2], -0.8, 1e-15);
    ck_assert_double_eq(l[0], 2.0);
    ck_assert_double_eq(l[3], 2.0);
    ck_assert_double_eq(l[4], -7.0);
    ck_assert_double_eq(l[5], 0.0);
    double in[6] = {1.0, 0.3, 0.2, -0.5, 4.0, 0.0}, copy[6];
    memcpy(copy, in, sizeof in);
    ck_assert_int_eq(ncp_project(w, in), 0);
    ck_assert_int_eq(memcmp(in, copy, sizeof in), 0);
    /* a negative normal force takes its friction to 0 */
    double neg[6] = {-1.0, 0.5, 0.5, 0.0, 0.0, 0.0};
    ncp_project(w, neg);
    ck_assert_double_eq(neg[1], 0.0);
    ck_assert_double_eq(neg[2], 0.0);
    ncp_work_destroy(w);
}
END_TEST

START_TEST(line_search_breaks_a_jump_between_bounds)
{
    /* four bounded rows in [0, 1] on one rigid point: delta(lambda) =
     * delta0 + W lambda with W = 1 1^T + 0.01 I (strong coupling), r =
     * W_jj: each row alone would clamp at hi, all together overshoot to the
     * other bound, where the residual is as large as before */
    enum { NB = 4 };
    pl_row_kind kind[NB];
    int pair[NB];
    double lo[NB], hi[NB], W[NB * NB], r[NB], lambda[NB], delta[NB], dl[NB], dd[NB];
    for (int i = 0; i < NB; ++i) {
        kind[i] = PL_ROW_BOUNDED;
        pair[i] = -1;
        lo[i] = 0.0;
        hi[i] = 1.0;
        r[i] = 1.01;
        lambda[i] = 0.0;
        delta[i] = -1.2;
        for (int j = 0; j < NB; ++j) W[i * NB + j] = 1.0 + (i == j ? 0.01 : 0.0);
    }
    pl_ncp_rows rows = {NB, kind, pair, NULL, NULL, lo, hi};
    pl_ncp_work *w;
    pl_error err;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    pl_ncp_operator op = {NB, W, NULL, NULL, r};
    pl_ncp_params par;
    ncp_params_default(&par);
    par.full_force = 1;
    pl_ncp_step_info info;
    ck_assert_int_eq(ncp_step(w, &par, &op, r, delta, delta, lambda, dl, NULL, &info, &err), PL_OK);
    /* every row clamps at hi: dlambda = 1, then delta = -1.2 + 4.01 > 0 */
    for (int i = 0; i < NB; ++i) ck_assert_double_eq_tol(dl[i], 1.0, 1e-15);
    matvec(NB, W, dl, dd);
    pl_ncp_line_info li;
    ck_assert_int_eq(ncp_line_search(w, r, 1.0, delta, dd, lambda, dl, 3, &li, &err), PL_OK);
    printf("bounded jump: residual %.3g, step length %g gives %.3g\n", li.merit0, li.alpha, li.merit);
    ck_assert_double_eq(li.alpha, 0.5);
    ck_assert_int_eq(li.decreased, 1);
    ck_assert_double_lt(li.merit, li.merit0);
    /* a bilateral row: the full Newton step solves it, alpha = 1 */
    pl_row_kind bk[1] = {PL_ROW_BILATERAL};
    pl_ncp_rows brows = {1, bk, pair, NULL, NULL, NULL, NULL};
    pl_ncp_work *wb;
    ck_assert_int_eq(ncp_work_create(&brows, &wb, &err), PL_OK);
    double Wb[1] = {2.0}, lb[1] = {0.0}, db[1] = {-0.5}, dlb[1], ddb[1];
    pl_ncp_operator opb = {1, Wb, NULL, NULL, Wb};
    ck_assert_int_eq(ncp_step(wb, &par, &opb, Wb, db, db, lb, dlb, NULL, &info, &err), PL_OK);
    ddb[0] = Wb[0] * dlb[0];
    ck_assert_int_eq(ncp_line_search(wb, Wb, 1.0, db, ddb, lb, dlb, 3, &li, &err), PL_OK);
    ck_assert_double_eq(li.alpha, 1.0);
    ck_assert_double_le(li.merit, 1e-15);
    ncp_work_destroy(wb);
    ncp_work_destroy(w);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("ncp_full_force");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, full_force_step_solves_the_unsymmetric_newton_system);
    tcase_add_test(tc, full_force_iteration_agrees_with_the_fc3d_solver);
    tcase_add_test(tc, projection_onto_the_admissible_set);
    tcase_add_test(tc, line_search_breaks_a_jump_between_bounds);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf ? 1 : 0;
}
