/* test_ncp_fc3d.c - the standalone 3D frictional contact solver against
 * Siconos (fc3d_driver, SICONOS_FRICTION_3D_NSN_FB) on random problems, the
 * exact stick/slide of one contact, FB against min-map, and the
 * Signorini-Coulomb residual itself. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "FrictionContactProblem.h"
#include "Friction_cst.h"
#include "NonSmoothDrivers.h"
#include "NumericsMatrix.h"
#include "SolverOptions.h"

#include "ncp.h"
#include "ncp_test_util.h"

/* Siconos' reaction and velocity for (W, q, mu); returns the driver's info. */
static int siconos_solve(int nc, const double *W, const double *q, const double *mu, double *r, double *u)
{
    int n = 3 * nc;
    NumericsMatrix *M = NM_create(NM_DENSE, n, n);
    memcpy(M->matrix0, W, sizeof(double) * (size_t)n * (size_t)n); /* symmetric: column-major = row-major */
    FrictionContactProblem prob = {3, nc, M, (double *)q, (double *)mu};
    SolverOptions *opt = solver_options_create(SICONOS_FRICTION_3D_NSN_FB);
    opt->iparam[SICONOS_IPARAM_MAX_ITER] = 500;
    opt->dparam[SICONOS_DPARAM_TOL] = 1e-14;
    memset(r, 0, sizeof(double) * (size_t)n);
    memset(u, 0, sizeof(double) * (size_t)n);
    int info = fc3d_driver(&prob, r, u, opt);
    /* Siconos 4.4: solver_options_delete frees the members, not the struct.
     * (fc3d_nonsmooth_Newton_solvers_solve also leaks the 64-byte matrix
     * header of an NM_preserve copy that the caller cannot reach:
     * lsan_siconos.supp silences that one under the sanitizers.) */
    solver_options_delete(opt);
    free(opt);
    NM_free(M);
    return info;
}

static double norm2(int n, const double *x)
{
    double s = 0;
    for (int i = 0; i < n; ++i)
        s += x[i] * x[i];
    return sqrt(s);
}

static double qscale(int n, const double *q)
{
    double s = 0;
    for (int i = 0; i < n; ++i)
        s = fmax(s, fabs(q[i]));
    return s > 0 ? s : 1.0;
}

/* A random problem: W = B B^T / n + eps I, mu in [0, 1], q with about a
 * third of the contacts separating (q_n > 0) and half of them pushed only
 * gently along the tangents (so that many stick). */
static void random_problem(test_rng *g, int nc, double *W, double *q, double *mu)
{
    int n = 3 * nc;
    random_spd(g, n, rng_range(g, 0.05, 0.5), W);
    for (int i = 0; i < nc; ++i) {
        mu[i] = rng_uniform(g);
        q[3 * i] = rng_uniform(g) < 0.33 ? rng_range(g, 0.1, 1.0) : -rng_range(g, 0.1, 1.0);
        double ts = rng_uniform(g) < 0.5 ? 0.1 : 1.0;
        q[3 * i + 1] = ts * rng_normal(g);
        q[3 * i + 2] = ts * rng_normal(g);
    }
}

/* ~300 random problems: our reactions equal Siconos' within 1e-6 relative;
 * both satisfy Signorini-Coulomb; our r_t stays in the cone as solved. */
START_TEST(test_random_against_siconos)
{
    enum { NPROB = 300, NCMAX = 20 };
    test_rng g = {2024};
    int nmax = 3 * NCMAX;
    double *W = malloc(sizeof(double) * nmax * nmax), *q = malloc(sizeof(double) * nmax);
    double *mu = malloc(sizeof(double) * NCMAX), *r = malloc(sizeof(double) * nmax);
    double *u = malloc(sizeof(double) * nmax), *rs = malloc(sizeof(double) * nmax);
    double *us = malloc(sizeof(double) * nmax), *d = malloc(sizeof(double) * nmax);
    int degenerate = 0, siconos_failed = 0, max_it = 0, sliding = 0, sticking = 0, separated = 0;
    double worst_rel = 0, worst_res = 0, worst_sres = 0, total_it = 0;
    for (int p = 0; p < NPROB; ++p) {
        int nc = 1 + (int)(rng_uniform(&g) * NCMAX), n = 3 * nc;
        random_problem(&g, nc, W, q, mu);
        pl_ncp_solve_opts o;
        ncp_solve_opts_default(&o);
        o.tol = 1e-11;
        o.max_iter = 2000; /* Appendix B's friction compliance is a fixed point: linear convergence */
        pl_ncp_solve_info info;
        pl_error err;
        memset(r, 0, sizeof(double) * n);
        ck_assert_int_eq(ncp_solve_fc3d(nc, W, q, mu, r, u, &o, &info, &err), PL_OK);
        ck_assert_msg(info.converged, "problem %d (nc %d): residual %g after %d iterations", p, nc, info.residual,
                      info.iters);
        max_it = info.iters > max_it ? info.iters : max_it;
        total_it += info.iters;
        worst_res = fmax(worst_res, info.residual);
        double rmax = 0; /* force scale: separated contacts end at |r| ~ 1e-12 of it, of either sign */
        for (int i = 0; i < n; ++i)
            rmax = fmax(rmax, fabs(r[i]));
        for (int i = 0; i < nc; ++i) {
            double rt = hypot(r[3 * i + 1], r[3 * i + 2]);
            ck_assert_msg(rt <= mu[i] * r[3 * i] * (1 + 1e-6) + 1e-11 * rmax,
                          "problem %d contact %d: |r_t| %g > mu r_n %g", p, i, rt, mu[i] * r[3 * i]);
            ck_assert(r[3 * i] >= -1e-11 * rmax);
            if (r[3 * i] <= 1e-9)
                ++separated;
            else if (rt >= mu[i] * r[3 * i] * (1 - 1e-9))
                ++sliding;
            else
                ++sticking;
        }
        int sinfo = siconos_solve(nc, W, q, mu, rs, us);
        pl_ncp_residual res;
        ck_assert_int_eq(ncp_residual_fc3d(nc, W, mu, rs, us, &res, &err), PL_OK);
        double sres = res.total / qscale(n, q);
        if (sinfo != 0) {
            ++siconos_failed; /* reported below; our residual is checked regardless */
            continue;
        }
        worst_sres = fmax(worst_sres, sres);
        ck_assert_msg(sres <= 1e-8, "problem %d: Siconos' solution residual %g", p, sres);
        for (int i = 0; i < n; ++i)
            d[i] = r[i] - rs[i];
        double rel = norm2(n, d) / fmax(norm2(n, rs), 1e-300);
        if (norm2(n, rs) == 0.0)
            rel = norm2(n, d) / qscale(n, q);
        if (rel > 1e-6) {
            /* two solutions with small residuals: a degenerate instance */
            ++degenerate;
            fprintf(stderr, "problem %d (nc %d): reactions differ by %g, residuals %g (ours) %g (Siconos)\n", p, nc,
                    rel, info.residual, sres);
            continue;
        }
        worst_rel = fmax(worst_rel, rel);
    }
    fprintf(stderr,
            "fc3d vs Siconos NSN_FB: %d problems, worst relative reaction difference %.2e, our worst residual %.2e, "
            "Siconos' %.2e, iterations mean %.1f max %d; contacts sliding %d sticking %d separated %d; degenerate %d, "
            "Siconos not converged %d\n",
            NPROB, worst_rel, worst_res, worst_sres, total_it / NPROB, max_it, sliding, sticking, separated,
            degenerate, siconos_failed);
    ck_assert_int_le(degenerate, NPROB / 50);
    ck_assert_int_le(siconos_failed, NPROB / 50);
    ck_assert(sliding > 300 && sticking > 300 && separated > 300); /* all regimes are exercised */
    free(W); free(q); free(mu); free(r); free(u); free(rs); free(us); free(d);
}
END_TEST

/* One contact, W = I / m: a tangential push below mu sticks, above slides,
 * with the exact reactions. */
START_TEST(test_one_contact_stick_slide)
{
    const double m = 2.0, W[9] = {1 / m, 0, 0, 0, 1 / m, 0, 0, 0, 1 / m}, mu = 0.4;
    for (int fn = 0; fn < 2; ++fn) {
        pl_ncp_solve_opts o;
        ncp_solve_opts_default(&o);
        o.fn = (pl_ncp_function)fn;
        pl_ncp_solve_info info;
        pl_error err;
        double q[3] = {-1.0, 0.1, -0.15}, r[3] = {0, 0, 0}, u[3]; /* |q_t| m = 0.36 < mu m = 0.8 */
        ck_assert_int_eq(ncp_solve_fc3d(1, W, q, &mu, r, u, &o, &info, &err), PL_OK);
        ck_assert(info.converged);
        ck_assert_double_eq_tol(r[0], m, 1e-12);
        ck_assert_double_eq_tol(r[1], -m * 0.1, 1e-12);
        ck_assert_double_eq_tol(r[2], m * 0.15, 1e-12);
        ck_assert(fabs(u[0]) < 1e-12 && fabs(u[1]) < 1e-12 && fabs(u[2]) < 1e-12);
        double qs[3] = {-1.0, 0.6, -0.8}; /* |q_t| m = 2 > 0.8: slides */
        memset(r, 0, sizeof(r));
        ck_assert_int_eq(ncp_solve_fc3d(1, W, qs, &mu, r, u, &o, &info, &err), PL_OK);
        ck_assert(info.converged);
        ck_assert_double_eq_tol(r[0], m, 1e-12);
        ck_assert_double_eq_tol(r[1], -mu * m * 0.6, 1e-12);
        ck_assert_double_eq_tol(r[2], mu * m * 0.8, 1e-12);
        double f = 1 - mu * m / (m * 1.0); /* u_t = q_t (1 - mu r_n / (m |q_t|)) */
        ck_assert_double_eq_tol(u[1], 0.6 * f, 1e-12);
        ck_assert_double_eq_tol(u[2], -0.8 * f, 1e-12);
        double qo[3] = {0.5, 0.6, -0.8}; /* separating: no force */
        memset(r, 0, sizeof(r));
        ck_assert_int_eq(ncp_solve_fc3d(1, W, qo, &mu, r, u, &o, &info, &err), PL_OK);
        ck_assert(r[0] == 0.0 && r[1] == 0.0 && r[2] == 0.0);
        ck_assert_double_eq_tol(u[0], 0.5, 1e-15);
    }
}
END_TEST

/* Fischer-Burmeister and the minimum map converge to the same solution. */
START_TEST(test_fb_and_minmap_agree)
{
    test_rng g = {7};
    double W[45 * 45], q[45], mu[15], r1[45], r2[45], u[45];
    int itfb = 0, itmin = 0;
    for (int p = 0; p < 40; ++p) {
        int nc = 1 + (int)(rng_uniform(&g) * 15), n = 3 * nc;
        random_problem(&g, nc, W, q, mu);
        pl_ncp_solve_opts o;
        ncp_solve_opts_default(&o);
        pl_ncp_solve_info i1, i2;
        pl_error err;
        memset(r1, 0, sizeof(r1));
        memset(r2, 0, sizeof(r2));
        o.fn = PL_NCP_FB;
        ck_assert_int_eq(ncp_solve_fc3d(nc, W, q, mu, r1, u, &o, &i1, &err), PL_OK);
        o.fn = PL_NCP_MINMAP;
        ck_assert_int_eq(ncp_solve_fc3d(nc, W, q, mu, r2, u, &o, &i2, &err), PL_OK);
        ck_assert_msg(i1.converged && i2.converged, "problem %d: FB %g, min map %g", p, i1.residual, i2.residual);
        itfb += i1.iters;
        itmin += i2.iters;
        double dn = 0, rn = 0;
        for (int i = 0; i < n; ++i) {
            dn += (r1[i] - r2[i]) * (r1[i] - r2[i]);
            rn += r1[i] * r1[i];
        }
        ck_assert_msg(sqrt(dn) <= 1e-6 * fmax(sqrt(rn), 1e-12), "problem %d: FB and min map differ by %g", p,
                      sqrt(dn / fmax(rn, 1e-300)));
    }
    fprintf(stderr, "FB vs min map: 40 problems, mean iterations FB %.1f, min map %.1f\n", itfb / 40.0,
            itmin / 40.0);
}
END_TEST

/* The residual is zero at known solutions and sees each kind of violation. */
START_TEST(test_residual_parts)
{
    const double W[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, mu = 0.5;
    pl_ncp_residual res;
    pl_error err;
    double r[3] = {2, -0.6, 0.8}, u[3] = {0, 0.3, -0.4}; /* sliding, opposed, on the cone */
    ck_assert_int_eq(ncp_residual_fc3d(1, W, &mu, r, u, &res, &err), PL_OK);
    ck_assert(res.total < 1e-15);
    double ua[3] = {0, 0.3, 0.4}; /* slip not opposed to the force */
    ncp_residual_fc3d(1, W, &mu, r, ua, &res, &err);
    ck_assert(res.friction > 0.1 && res.normal == 0.0 && res.cone == 0.0);
    double rc[3] = {1, -0.6, 0.8}; /* outside the cone by 0.5 */
    ncp_residual_fc3d(1, W, &mu, rc, u, &res, &err);
    ck_assert_double_eq_tol(res.cone, 0.5, 1e-15);
    double up[3] = {-0.1, 0.3, -0.4}; /* penetrating */
    ncp_residual_fc3d(1, W, &mu, r, up, &res, &err);
    ck_assert_double_eq_tol(res.normal, 0.1, 1e-15);
    double us[3] = {0.2, 0, 0}; /* separating with a force: complementarity broken */
    ncp_residual_fc3d(1, W, &mu, r, us, &res, &err);
    ck_assert_double_eq_tol(res.normal, 0.2, 1e-15);
    double rs[3] = {2, 0.1, 0.2}, u0[3] = {0, 0, 0}; /* stick inside the cone */
    ncp_residual_fc3d(1, W, &mu, rs, u0, &res, &err);
    ck_assert(res.total == 0.0);
    double uslip[3] = {0, 0.01, 0}; /* ... but slipping while inside the cone */
    ncp_residual_fc3d(1, W, &mu, rs, uslip, &res, &err);
    ck_assert_double_eq_tol(res.friction, 0.01, 1e-15);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("ncp_fc3d");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_one_contact_stick_slide);
    tcase_add_test(tc, test_residual_parts);
    tcase_add_test(tc, test_fb_and_minmap_agree);
    tcase_add_test(tc, test_random_against_siconos);
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
