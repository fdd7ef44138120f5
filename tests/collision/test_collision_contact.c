/* test_collision_contact.c - obstacles with the real contact solver
 * (NonSmoothNewtonContactSolver of the ncp_contact plugin) in the scenes of
 * scenes/, read through the obstacles' exported contact forces:
 *  - resting_box: the contact forces add up to the cube's weight (9.81 N)
 *    within 1%, with no net horizontal force, and the cube stays put;
 *  - sliding_box (mu 0.1 on 20 degrees): every contact's friction stays
 *    inside the Coulomb cone and points up the slope (against the motion),
 *    adds up to at least 0.9 mu N (the fixed 10 local-global iterations
 *    leave some edge contacts short of the cone), and the total normal
 *    force is m g cos 20 within 1%;
 *  - stick_slip with mu = 0.3, far above tan 10 deg: the cube sticks and
 *    the total contact force is exactly its weight, straight up. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"

static pl_sim *load_file(const char *rel, const char *const *ov, int nov)
{
    char *text = ct_read_source(rel);
    char *xml = ct_replace_lines(text, "<VTKExporter", ""); /* write nothing */
    pl_sim *sim = ct_load(xml, ov, nov);
    free(text), free(xml);
    return sim;
}

static void step(pl_sim *sim, int n)
{
    pl_error err;
    int rc = pl_sim_step(sim, n, &err);
    if (rc) {
        char b[1600];
        fprintf(stderr, "%s\n", pl_error_format(&err, b, sizeof b));
    }
    ck_assert_int_eq(rc, PL_OK);
}

/* Sum of the obstacle's contact forces; returns the contact count. */
static int total_force(pl_sim *sim, const char *obstacle, double F[3])
{
    char path[128];
    double *f;
    snprintf(path, sizeof path, "%s.contactForces", obstacle);
    int n = ct_get_doubles(sim, path, &f) / 3;
    F[0] = F[1] = F[2] = 0.0;
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 3; ++i) F[i] += f[3 * k + i];
    free(f);
    return n;
}

static double mean_x(pl_sim *sim)
{
    int n;
    double *x = ct_positions(sim, "box/dofs", &n), s = 0.0;
    for (int i = 0; i < n; ++i) s += x[3 * i];
    return s / n;
}

START_TEST(test_resting_box_forces_balance_weight)
{
    pl_sim *sim = load_file("scenes/resting_box.xml", NULL, 0);
    double x0 = mean_x(sim), F[3];
    step(sim, 20);
    ck_assert_int_eq(total_force(sim, "floor", F), 25);
    ck_assert_double_eq_tol(F[1], 9.81, 0.0981);
    ck_assert_double_le(hypot(F[0], F[2]), 1e-3 * 9.81);
    ck_assert_double_le(fabs(mean_x(sim) - x0), 1e-4);
    pl_sim_free(sim);
}
END_TEST

START_TEST(test_sliding_box_coulomb_friction)
{
    pl_sim *sim = load_file("scenes/sliding_box.xml", NULL, 0);
    step(sim, 20);
    const double t = 20 * M_PI / 180, n[3] = {-sin(t), cos(t), 0}, up[3] = {cos(t), sin(t), 0};
    double *f, *nn;
    int k = ct_get_doubles(sim, "slope.contactForces", &f) / 3;
    ck_assert_int_eq(ct_get_doubles(sim, "slope.contactNormals", &nn) / 3, k);
    double Fn = 0.0, Ft = 0.0;
    for (int c = 0; c < k; ++c) {
        const double *fc = &f[3 * c];
        double fn = fc[0] * n[0] + fc[1] * n[1] + fc[2] * n[2];
        double ft[3] = {fc[0] - fn * n[0], fc[1] - fn * n[1], fc[2] - fn * n[2]};
        double tmag = sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(nn[3 * c + i], n[i], 1e-12);
        ck_assert_double_ge(fn, 0.0);
        /* inside the cone as solved (to the solver's residual: the scene does
         * not project the iterates), pointing up the slope (against the motion) */
        ck_assert_double_le(tmag, 0.1 * fn * (1 + 1e-4) + 1e-12);
        if (tmag > 1e-6) ck_assert_double_ge((ft[0] * up[0] + ft[1] * up[1]) / tmag, 0.999);
        Fn += fn;
        Ft += tmag;
    }
    ck_assert_double_eq_tol(Fn, 9.81 * cos(t), 0.01 * 9.81);
    /* sliding: the friction is (nearly) mu N in total; 10 local-global
     * iterations leave a few edge contacts short of the cone */
    ck_assert_double_ge(Ft, 0.9 * 0.1 * Fn);
    free(f), free(nn);
    pl_sim_free(sim);
}
END_TEST

START_TEST(test_stick_slip_sticks_far_above_threshold)
{
    const char *ov[1] = {"slope.mu=0.3"};
    pl_sim *sim = load_file("scenes/stick_slip.xml", ov, 1);
    double x0 = mean_x(sim), F[3];
    step(sim, 50);
    ck_assert_int_eq(total_force(sim, "slope", F), 36);
    ck_assert_double_le(fabs(mean_x(sim) - x0), 1e-4);
    ck_assert_double_eq_tol(F[1], 9.81, 1e-3);
    ck_assert_double_le(hypot(F[0], F[2]), 1e-3);
    pl_sim_free(sim);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_contact");
    TCase *tc = tcase_create("contact");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_resting_box_forces_balance_weight);
    tcase_add_test(tc, test_sliding_box_coulomb_friction);
    tcase_add_test(tc, test_stick_slip_sticks_far_above_threshold);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *sr = srunner_create(suite());
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
