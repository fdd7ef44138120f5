/* test_ncp_functions.c - the NCP functions of Appendix B (values, derivatives,
 * the 0/0 cases), the complementarity scaling, the row checks and the
 * conjugate residual solver. */
#include <check.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "ncp.h"
#include "ncp_test_util.h"

static double fb_plain(double a, double b) { return a + b - sqrt(a * a + b * b); }

/* phi_FB vanishes exactly on the complementarity set and is the paper's
 * a + b - sqrt(a^2 + b^2) elsewhere; its derivatives match finite differences. */
START_TEST(test_fb_normal_values_and_derivatives)
{
    double phi, om, e;
    const double r = 0.7;
    ncp_eval_normal(PL_NCP_FB, 3.0, 0.0, r, 0.0, &phi, &om, &e);
    ck_assert_double_eq(phi, 0.0);
    ck_assert_double_eq_tol(om, 0.0, 1e-15);
    ck_assert_double_eq_tol(e, r, 1e-15);
    ncp_eval_normal(PL_NCP_FB, 0.0, 2.0, r, 0.0, &phi, &om, &e);
    ck_assert_double_eq(phi, 0.0);
    ck_assert_double_eq_tol(om, 1.0, 1e-15);
    ck_assert_double_eq_tol(e, 0.0, 1e-15);
    test_rng g = {11};
    for (int t = 0; t < 200; ++t) {
        double a = rng_range(&g, -2, 2), lam = rng_range(&g, -2, 2);
        ncp_eval_normal(PL_NCP_FB, a, lam, r, 0.0, &phi, &om, &e);
        ck_assert_double_eq_tol(phi, fb_plain(a, r * lam), 1e-13);
        double hs = 1e-6, p1, p2, o2, e2;
        ncp_eval_normal(PL_NCP_FB, a + hs, lam, r, 0.0, &p1, &o2, &e2);
        ncp_eval_normal(PL_NCP_FB, a - hs, lam, r, 0.0, &p2, &o2, &e2);
        ck_assert_double_eq_tol(om, (p1 - p2) / (2 * hs), 1e-6);
        ncp_eval_normal(PL_NCP_FB, a, lam + hs, r, 0.0, &p1, &o2, &e2);
        ncp_eval_normal(PL_NCP_FB, a, lam - hs, r, 0.0, &p2, &o2, &e2);
        ck_assert_double_eq_tol(e, (p1 - p2) / (2 * hs), 1e-6);
        ck_assert(om >= 0.0 && om <= 2.0 && e >= 0.0 && e <= 2.0 * r);
    }
    /* no cancellation: delta >> r lambda > 0 gives phi ~ r lambda, omega ~ (r lambda / delta)^2 / 2 */
    ncp_eval_normal(PL_NCP_FB, 1.0, 1e-9 / r, r, 0.0, &phi, &om, &e);
    ck_assert_double_eq_tol(phi / 1e-9, 1.0, 1e-8);
    ck_assert_double_eq_tol(om / 5e-19, 1.0, 1e-8);
}
END_TEST

/* A new resting contact (delta = lambda = 0) divides 0/0 in FB: the
 * regularised values are finite, with or without eps. */
START_TEST(test_fb_normal_zero_zero)
{
    double phi, om, e;
    ncp_eval_normal(PL_NCP_FB, 0.0, 0.0, 0.25, 1e-12, &phi, &om, &e);
    ck_assert(isfinite(phi) && isfinite(om) && isfinite(e));
    ck_assert_double_eq_tol(phi, -1e-12, 1e-24);
    ck_assert_double_eq(om, 1.0);
    ck_assert_double_eq(e, 0.25);
    ncp_eval_normal(PL_NCP_FB, 0.0, 0.0, 0.25, 0.0, &phi, &om, &e);
    ck_assert_double_eq(phi, 0.0);
    ck_assert_double_eq(om, 1.0);
    ck_assert_double_eq(e, 0.25);
    /* near (0, 0) the regularised derivatives stay bounded */
    ncp_eval_normal(PL_NCP_FB, 1e-300, 1e-300, 1.0, 1e-12, &phi, &om, &e);
    ck_assert(fabs(om - 1.0) < 1e-12 && fabs(e - 1.0) < 1e-12);
}
END_TEST

START_TEST(test_minmap_normal_branches)
{
    double phi, om, e;
    ncp_eval_normal(PL_NCP_MINMAP, 0.1, 1.0, 0.5, 0.0, &phi, &om, &e); /* delta <= r lambda */
    ck_assert(phi == 0.1 && om == 1.0 && e == 0.0);
    ncp_eval_normal(PL_NCP_MINMAP, 0.9, 1.0, 0.5, 0.0, &phi, &om, &e); /* delta > r lambda */
    ck_assert(phi == 0.5 && om == 0.0 && e == 0.5);
    ncp_eval_normal(PL_NCP_MINMAP, 0.0, 0.0, 0.5, 0.0, &phi, &om, &e); /* new contact: position row */
    ck_assert(phi == 0.0 && om == 1.0 && e == 0.0);
}
END_TEST

/* Appendix B's FB friction compliance r (s - b) / (a + r mu ln - s), direct. */
static double paper_fb_friction(double a, double L, double ln, double mu, double rho)
{
    double b = rho * (mu * ln - L), s = sqrt(a * a + b * b);
    return rho * (s - b) / (a + rho * mu * ln - s);
}

START_TEST(test_fb_friction_compliance)
{
    test_rng g = {5};
    const double ln = 2.0, mu = 0.4, rho = 0.3;
    double phi[2], om, e;
    for (int t = 0; t < 500; ++t) {
        double y[2] = {rng_range(&g, -1, 1), rng_range(&g, -1, 1)};
        double L = rng_range(&g, 0.0, 3.0 * mu * ln), ang = rng_range(&g, 0, 6.283185307179586);
        double lf[2] = {L * cos(ang), L * sin(ang)};
        ncp_eval_friction(PL_NCP_FB, 2, y, lf, ln, mu, rho, phi, &om, &e);
        ck_assert(om == 1.0);
        ck_assert_msg(e >= 0.0 && isfinite(e), "e = %g", e);
        ck_assert_double_eq_tol(phi[0], y[0] + e * lf[0], 1e-15);
        double a = hypot(y[0], y[1]);
        if (L < mu * ln - 1e-3) /* inside the cone: exactly Appendix B */
            ck_assert_double_eq_tol(e, paper_fb_friction(a, L, ln, mu, rho), 1e-9 * (1 + e));
        else if (L >= mu * ln)  /* on or outside: (s - b) / (mu ln) */
            ck_assert_double_eq_tol(e, (hypot(a, rho * (mu * ln - L)) - rho * (mu * ln - L)) / (mu * ln),
                                    1e-12 * (1 + e));
    }
    /* both forms agree on the cone: e = |y| / (mu ln), continuous across it */
    double y[2] = {0.3, -0.4}, lf_in[2] = {mu * ln * (1 - 1e-9), 0}, lf_out[2] = {mu * ln * (1 + 1e-9), 0};
    double e_in, e_out;
    ncp_eval_friction(PL_NCP_FB, 2, y, lf_in, ln, mu, rho, phi, &om, &e_in);
    ncp_eval_friction(PL_NCP_FB, 2, y, lf_out, ln, mu, rho, phi, &om, &e_out);
    ck_assert_double_eq_tol(e_in, 0.5 / (mu * ln), 1e-8);
    ck_assert_double_eq_tol(e_out, 0.5 / (mu * ln), 1e-8);
    /* where Appendix B's denominator changes sign (|lf| > 2 mu ln, y = 0) */
    ck_assert(paper_fb_friction(0.0, 3.0 * mu * ln, ln, mu, rho) < 0.0);
    double y0[2] = {0, 0}, lf3[2] = {0, 3.0 * mu * ln};
    ncp_eval_friction(PL_NCP_FB, 2, y0, lf3, ln, mu, rho, phi, &om, &e);
    ck_assert_double_eq_tol(e, 4.0 * rho, 1e-12); /* (s - b)/(mu ln) = 2 rho 2 mu ln / (mu ln) */
}
END_TEST

/* Stick with lf = 0 and y = 0 (a new resting contact that got a normal
 * force) is 0/0 in Appendix B; e = 0 there and e -> 0 as y -> 0. */
START_TEST(test_friction_stick_zero_zero)
{
    double y[2] = {0, 0}, lf[2] = {0, 0}, phi[2], om, e;
    for (int fn = 0; fn < 2; ++fn) {
        ncp_eval_friction((pl_ncp_function)fn, 2, y, lf, 1.0, 0.5, 0.2, phi, &om, &e);
        ck_assert(om == 1.0 && e == 0.0 && phi[0] == 0.0 && phi[1] == 0.0);
    }
    double prev = INFINITY;
    for (double a = 1e-2; a > 1e-12; a *= 0.1) {
        double ya[2] = {a, 0};
        ncp_eval_friction(PL_NCP_FB, 2, ya, lf, 1.0, 0.5, 0.2, phi, &om, &e);
        ck_assert(isfinite(e) && e >= 0.0 && e < prev);
        prev = e;
    }
    ck_assert(prev < 1e-10);
}
END_TEST

/* A contact that barely touches (mu ln tiny, lf = 0) while its tangent
 * moves: b = rho mu ln << a = |y|.  Appendix B's s + b - a cancels there
 * (s = hypot(a, b) rounds to a, or an ulp below it on a GPU, which gave a
 * negative compliance); the exact value is rho a (s + a) / (b (s + a + b))
 * ~ rho a / b, positive and finite (below the cap while a / b < 1e20). */
START_TEST(test_friction_barely_touching)
{
    const double mu = 0.5, rho = 0.004;
    double lf[2] = {0, 0}, phi[2], om, e;
    for (double a = 1e-2; a > 1e-7; a *= 0.1)
        for (double ln = 1e-3; ln > 1e-19; ln *= 1e-2) {
            double y[2] = {0.6 * a, -0.8 * a};
            ncp_eval_friction(PL_NCP_FB, 2, y, lf, ln, mu, rho, phi, &om, &e);
            long double b = (long double)rho * mu * ln, A = a, s = sqrtl(A * A + b * b);
            long double ref = rho * A * (s + A) / (b * (s + A + b));
            ck_assert_msg(e > 0.0 && isfinite(e), "a %g ln %g: e = %g", a, ln, e);
            ck_assert_msg(fabsl(e - ref) <= 1e-12L * ref, "a %g ln %g: e = %.17g, exact %.17Lg", a, ln, e, ref);
        }
}
END_TEST

/* Coulomb solutions are roots of phi_f for both NCP functions; an inactive
 * contact resets lf (omega = 0, e = rho). */
START_TEST(test_friction_roots)
{
    const double ln = 3.0, mu = 0.6, rho = 0.1;
    double phi[2], om, e;
    for (int fn = 0; fn < 2; ++fn) {
        double y[2] = {0.3, 0.4}; /* slide: lf = -mu ln y / |y| */
        double lf[2] = {-mu * ln * 0.6, -mu * ln * 0.8};
        ncp_eval_friction((pl_ncp_function)fn, 2, y, lf, ln, mu, rho, phi, &om, &e);
        ck_assert_double_eq_tol(phi[0], 0.0, 1e-14);
        ck_assert_double_eq_tol(phi[1], 0.0, 1e-14);
        ck_assert_double_eq_tol(e, 0.5 / (mu * ln), 1e-14);
        double ys[2] = {0, 0}, ls[2] = {0.5, -0.7}; /* stick inside the cone */
        ncp_eval_friction((pl_ncp_function)fn, 2, ys, ls, ln, mu, rho, phi, &om, &e);
        ck_assert(phi[0] == 0.0 && phi[1] == 0.0 && e == 0.0);
        double lz[2] = {0.5, -0.7}; /* inactive */
        ncp_eval_friction((pl_ncp_function)fn, 2, ys, lz, 0.0, mu, rho, phi, &om, &e);
        ck_assert(om == 0.0 && e == rho);
        ck_assert_double_eq_tol(phi[0], rho * 0.5, 1e-15);
        ncp_eval_friction((pl_ncp_function)fn, 2, ys, lz, 1.0, 0.0, rho, phi, &om, &e); /* mu = 0 */
        ck_assert(om == 0.0 && e == rho);
        /* one tangent row (2D contact) */
        double y1 = -0.2, l1 = mu * ln;
        ncp_eval_friction((pl_ncp_function)fn, 1, &y1, &l1, ln, mu, rho, phi, &om, &e);
        ck_assert_double_eq_tol(phi[0], 0.0, 1e-14);
    }
}
END_TEST

/* The minimum-map compliance of Appendix B: max(|y| - b, 0) / (mu ln). */
START_TEST(test_minmap_friction_compliance)
{
    double y[2] = {0.3, 0.4}, lf[2] = {0.1, 0.0}, phi[2], om, e;
    const double ln = 2.0, mu = 0.5, rho = 0.2; /* b = 0.2 (1 - 0.1) = 0.18 */
    ncp_eval_friction(PL_NCP_MINMAP, 2, y, lf, ln, mu, rho, phi, &om, &e);
    ck_assert_double_eq_tol(e, (0.5 - 0.18) / 1.0, 1e-15);
    double ys[2] = {0.1, 0.0};
    ncp_eval_friction(PL_NCP_MINMAP, 2, ys, lf, ln, mu, rho, phi, &om, &e);
    ck_assert(e == 0.0);
}
END_TEST

START_TEST(test_bounded_and_bilateral)
{
    double phi, om, e, pn, on, en;
    const double r = 0.5;
    ncp_eval_bounded(0.0, 1.0, -1.0, 2.0, r, &phi, &om, &e); /* inside: delta row */
    ck_assert(phi == 0.0 && om == 1.0 && e == 0.0);
    ncp_eval_bounded(0.3, 2.0, -1.0, 2.0, r, &phi, &om, &e); /* 2 - 0.6 inside */
    ck_assert(phi == 0.3 && om == 1.0);
    ncp_eval_bounded(-0.3, 2.0, -1.0, 2.0, r, &phi, &om, &e); /* at hi, pushed beyond */
    ck_assert(phi == 0.0 && om == 0.0 && e == r);
    ncp_eval_bounded(5.0, 0.0, -1.0, 2.0, r, &phi, &om, &e); /* beyond lo */
    ck_assert_double_eq_tol(phi, 0.5, 1e-15);
    ck_assert(om == 0.0 && e == r);
    /* with [0, inf) it is the min-map normal row */
    test_rng g = {3};
    for (int t = 0; t < 100; ++t) {
        double d = rng_range(&g, -1, 1), l = rng_range(&g, -1, 1);
        ncp_eval_bounded(d, l, 0.0, INFINITY, r, &phi, &om, &e);
        ncp_eval_normal(PL_NCP_MINMAP, d, l, r, 0.0, &pn, &on, &en);
        ck_assert_double_eq_tol(phi, pn, 1e-15);
        ck_assert(om == on && e == en);
    }
    ncp_eval_bilateral(0.2, 3.0, 0.1, &phi, &om, &e);
    ck_assert_double_eq_tol(phi, 0.5, 1e-15);
    ck_assert(om == 1.0 && e == 0.1);
}
END_TEST

/* Two contacts (normal + 2 tangents), one bilateral and one bounded row. */
static const pl_row_kind kinds7[8] = {PL_ROW_NORMAL, PL_ROW_FRICTION, PL_ROW_FRICTION, PL_ROW_BILATERAL,
                                      PL_ROW_FRICTION, PL_ROW_NORMAL, PL_ROW_FRICTION, PL_ROW_BOUNDED};
static const int pair7[8] = {1, 0, 0, -1, 5, 4, 5, -1};
static const double mu7[8] = {0.3, 0, 0, 0, 0, 0.5, 0, 0};

START_TEST(test_scaling_one_per_contact)
{
    pl_ncp_rows rows = {8, kinds7, pair7, mu7, NULL, NULL, NULL};
    pl_ncp_work *w;
    pl_error err;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    ck_assert_int_eq(w->nc, 2);
    double d[8] = {1, 2, 4, 8, 3, 5, 7, 9}, r[8];
    const double h = 0.01;
    ck_assert_int_eq(ncp_scaling(w, d, h, r, &err), PL_OK);
    ck_assert_double_eq_tol(r[0], h * h * 1, 1e-18);
    ck_assert_double_eq_tol(r[1], h * 3.0, 1e-15); /* mean of 2 and 4 */
    ck_assert_double_eq_tol(r[2], h * 3.0, 1e-15);
    ck_assert_double_eq_tol(r[5], h * h * 5, 1e-18);
    ck_assert_double_eq_tol(r[4], h * 5.0, 1e-15); /* mean of 3 and 7 */
    ck_assert_double_eq_tol(r[6], h * 5.0, 1e-15);
    ck_assert_double_eq_tol(r[7], h * h * 9, 1e-18);
    d[5] = 0.0;
    ck_assert_int_eq(ncp_scaling(w, d, h, r, &err), PL_EINPUT);
    ncp_work_destroy(w);
}
END_TEST

START_TEST(test_rows_rejected)
{
    pl_ncp_work *w;
    pl_error err;
    pl_row_kind k[4] = {PL_ROW_NORMAL, PL_ROW_FRICTION, PL_ROW_FRICTION, PL_ROW_FRICTION};
    int p3[4] = {1, 0, 0, 0};
    double mu[4] = {0.2, 0, 0, 0};
    pl_ncp_rows rows = {4, k, p3, mu, NULL, NULL, NULL};
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_EINPUT); /* three tangents */
    ck_assert(w == NULL);
    int pbad[4] = {1, 2, 0, 0};
    rows.pair = pbad;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_EINPUT); /* pair not a normal row */
    rows.m = 3;
    rows.pair = p3;
    mu[0] = -0.1;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_EINPUT); /* mu < 0 */
    pl_row_kind kb[1] = {PL_ROW_BOUNDED};
    double lo = 1.0, hi = 0.0;
    pl_ncp_rows rb = {1, kb, NULL, NULL, NULL, &lo, &hi};
    ck_assert_int_eq(ncp_work_create(&rb, &w, &err), PL_EINPUT); /* empty box */
}
END_TEST

typedef struct dense_op {
    int n;
    const double *A;
    int calls;
} dense_op;

static int dense_apply(void *u, const double *x, double *y)
{
    dense_op *o = u;
    ++o->calls;
    for (int i = 0; i < o->n; ++i) {
        double s = 0;
        for (int j = 0; j < o->n; ++j)
            s += o->A[i * o->n + j] * x[j];
        y[i] = s;
    }
    return 0;
}

/* CR reaches its tolerance on an SPD system, agrees with Cholesky, and
 * works on a symmetric indefinite one too. */
START_TEST(test_cr_spd_and_indefinite)
{
    enum { N = 40 };
    test_rng g = {17};
    double *A = malloc(sizeof(double) * N * N), b[N], x[N], xr[N], y[N], work[4 * N];
    random_spd(&g, N, 0.05, A);
    for (int i = 0; i < N; ++i) {
        b[i] = rng_normal(&g);
        x[i] = 0.0;
    }
    dense_op o = {N, A, 0};
    int its;
    double rel;
    pl_error err;
    ck_assert_int_eq(ncp_cr(N, dense_apply, &o, b, x, 1000, 1e-12, work, &its, &rel, &err), PL_OK);
    ck_assert(rel <= 1e-12);
    ck_assert_int_eq(its, o.calls);
    dense_apply(&o, x, y);
    double rn = 0, bn = 0;
    for (int i = 0; i < N; ++i) {
        rn += (y[i] - b[i]) * (y[i] - b[i]);
        bn += b[i] * b[i];
    }
    ck_assert(sqrt(rn) <= 1.01e-12 * sqrt(bn)); /* the true residual, not the recurrence */
    ck_assert_int_eq(dense_cholesky_solve(N, A, b, xr), 0);
    for (int i = 0; i < N; ++i)
        ck_assert_double_eq_tol(x[i], xr[i], 1e-8 * (1 + fabs(xr[i])));
    /* symmetric indefinite: A - 0.5 I (eigenvalues of both signs) */
    for (int i = 0; i < N; ++i)
        A[i * N + i] -= 0.5;
    for (int i = 0; i < N; ++i)
        x[i] = 0.0;
    ck_assert_int_eq(ncp_cr(N, dense_apply, &o, b, x, 4000, 1e-10, work, &its, &rel, &err), PL_OK);
    ck_assert_msg(rel <= 1e-10, "indefinite CR relres %g after %d", rel, its);
    /* the cap is honoured and reported */
    for (int i = 0; i < N; ++i)
        x[i] = 0.0;
    ck_assert_int_eq(ncp_cr(N, dense_apply, &o, b, x, 3, 1e-14, work, &its, &rel, &err), PL_OK);
    ck_assert_int_eq(its, 3);
    ck_assert(rel > 1e-14);
    free(A);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("ncp_functions");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_fb_normal_values_and_derivatives);
    tcase_add_test(tc, test_fb_normal_zero_zero);
    tcase_add_test(tc, test_minmap_normal_branches);
    tcase_add_test(tc, test_fb_friction_compliance);
    tcase_add_test(tc, test_friction_stick_zero_zero);
    tcase_add_test(tc, test_friction_barely_touching);
    tcase_add_test(tc, test_friction_roots);
    tcase_add_test(tc, test_minmap_friction_compliance);
    tcase_add_test(tc, test_bounded_and_bilateral);
    tcase_add_test(tc, test_scaling_one_per_contact);
    tcase_add_test(tc, test_rows_rejected);
    tcase_add_test(tc, test_cr_spd_and_indefinite);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *sr = srunner_create(suite());
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
