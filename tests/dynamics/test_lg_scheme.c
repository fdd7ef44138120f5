/* test_lg_scheme.c - LocalGlobalSolver's firstOrder and rayleighStiffness
 * against closed forms.  One vertex of mass m on a linear spring of
 * stiffness k to the origin (PositionTarget) under gravity g: the step is
 * quadratic, so one local-global iteration solves it exactly, and every
 * step must follow the scheme's recurrence (per coordinate, c = rS k):
 *   second order:  (m/h^2 + k + c/h) x' = m (x + h v)/h^2 + m g + (c/h) x
 *   first order:   (m/h   + k + c/h) x' = m x/h + m g + (c/h) x
 * with v' = (x' - x)/h.  The force residual the solver reports for each
 * step (computeResidual="on") must be zero at that exact solution. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dyn_test_util.h"

static const double H = 0.01, M = 0.2, K = 50.0, G = -9.81;

static pl_sim *spring(int first_order, double rs)
{
    static char xml[4096];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"%g\" gravity=\"0 %g 0\">\n"
             "  <RequiredPlugin name=\"hyperelastic\"/>\n"
             "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
             "  <LocalGlobalSolver name=\"solver\" iterations=\"1\" firstOrder=\"%d\" "
             "rayleighStiffness=\"%.17g\" computeResidual=\"on\"/>\n"
             "  <SparseInverseSolver/>\n"
             "  <Node name=\"body\">\n"
             "    <MechanicalObject name=\"dofs\" position=\"0.03 0.02 -0.01\" "
             "velocity=\"0.5 0 0.2\" rest_position=\"0 0 0\"/>\n"
             "    <UniformMass totalMass=\"%.17g\"/>\n"
             "    <PositionTarget indices=\"0\" stiffness=\"%.17g\"/>\n"
             "  </Node>\n"
             "</Node>\n",
             H, G, first_order, rs, M, K);
    return dyn_load(xml);
}

/* Runs `steps` steps and compares with the recurrence; returns the largest
 * position error [m]; *res the largest reported force residual [N]. */
static double compare(int first_order, double rs, int steps, double *res, double *ymin)
{
    pl_sim *s = spring(first_order, rs);
    double x[3] = {0.03, 0.02, -0.01}, v[3] = {0.5, 0, 0.2}, g[3] = {0, G, 0}, worst = 0;
    double c = rs * K;
    *ymin = INFINITY;
    for (int step = 0; step < steps; ++step) {
        dyn_step(s, 1);
        int n;
        const double *q = dyn_positions(s, "body/dofs", &n), *qv = dyn_velocities(s, "body/dofs", &n);
        for (int k = 0; k < 3; ++k) {
            double xn = first_order
                            ? (M * x[k] / H + M * g[k] + c / H * x[k]) / (M / H + K + c / H)
                            : (M * (x[k] + H * v[k]) / (H * H) + M * g[k] + c / H * x[k]) /
                                  (M / (H * H) + K + c / H);
            v[k] = (xn - x[k]) / H;
            x[k] = xn;
            worst = fmax(worst, fabs(q[k] - x[k]));
            worst = fmax(worst, H * fabs(qv[k] - v[k]));
        }
        *ymin = fmin(*ymin, x[1]);
    }
    const double *r;
    int nr = pl_series_get(pl_sim_timers(s), "force residual", &r);
    ck_assert_int_eq(nr, steps);
    *res = 0;
    for (int k = 0; k < nr; ++k) *res = fmax(*res, r[k]);
    pl_sim_free(s);
    return worst;
}

START_TEST(first_order_follows_backward_euler_without_overshoot)
{
    double res, ymin, err = compare(1, 0.0, 40, &res, &ymin);
    fprintf(stderr, "firstOrder: largest error %.3g m, residual %.3g N\n", err, res);
    ck_assert_msg(err < 1e-12, "firstOrder: %g m from the recurrence", err);
    ck_assert_msg(res < 1e-9, "firstOrder: force residual %g N at the exact step", res);
    /* no velocity carried: y goes monotonically to m g / k, never past it */
    ck_assert(ymin >= M * G / K - 1e-15);
}
END_TEST

START_TEST(rayleigh_stiffness_follows_damped_implicit_euler)
{
    double res, ymin, err = compare(0, 0.05, 40, &res, &ymin);
    fprintf(stderr, "rayleighStiffness: largest error %.3g m, residual %.3g N\n", err, res);
    ck_assert_msg(err < 1e-12, "rayleighStiffness: %g m from the recurrence", err);
    ck_assert_msg(res < 1e-9, "rayleighStiffness: force residual %g N at the exact step", res);
    err = compare(1, 0.05, 40, &res, &ymin);
    ck_assert_msg(err < 1e-12 && res < 1e-9, "both: %g m, %g N", err, res);
    /* the undamped scheme still matches (c = 0) */
    err = compare(0, 0.0, 40, &res, &ymin);
    ck_assert_msg(err < 1e-12 && res < 1e-9, "undamped: %g m, %g N", err, res);
}
END_TEST

START_TEST(the_damping_dissipates)
{
    /* the damped oscillation's amplitude after 40 steps is below the
     * undamped one's (implicit Euler damps too, less) */
    double res, ymin0, ymin1;
    compare(0, 0.0, 40, &res, &ymin0);
    compare(0, 0.2, 40, &res, &ymin1);
    ck_assert_msg(ymin1 > ymin0, "undershoot %g with rS, %g without", ymin1, ymin0);
}
END_TEST

/* A free ARAP cube falls without deforming under Rayleigh stiffness damping
 * (L's damping of a translation is zero) even with 2 iterations a step: the
 * iterations start from the free motion q_t + h v_t + h^2 g, which is the
 * solution here, not from sn, which with rS > 0 also holds the damping's
 * h rS M'^-1 L q_t (no position: it started the falling beam of
 * fallingBeamLagrangianCollision.scn 1 cm off, 2.3e-2 of its diagonal). */
START_TEST(a_falling_body_is_not_deformed_by_the_damping)
{
    static char xml[4096];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 -9.81\">"
             "<RequiredPlugin name=\"sparse_inverse\"/><RequiredPlugin name=\"hyperelastic\"/>"
             "<LocalGlobalSolver name=\"solver\" iterations=\"2\" rayleighStiffness=\"0.1\"/>"
             "<SparseInverseSolver/>"
             "<Node name=\"b\"><RegularGridTetrahedra min=\"0 0 0\" max=\"1 0.2 0.2\" "
             "n=\"6 2 2\"/><MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"1\"/>"
             "<ARAP youngModulus=\"6e4\"/></Node></Node>");
    pl_sim *s = dyn_load(xml);
    ck_assert_ptr_nonnull(s);
    dyn_step(s, 20);
    int n = 0;
    const double *x = dyn_positions(s, "b/dofs", &n), *x0 = dyn_rest(s, "b/dofs", &n);
    double worst = 0, drop = x[2] - x0[2];
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c)
            worst = fmax(worst, fabs(x[3 * i + c] - x0[3 * i + c] - (c == 2 ? drop : 0.0)));
    /* implicit Euler's free fall: g h^2 n (n + 1) / 2 */
    ck_assert_msg(fabs(drop + 9.81 * 1e-4 * 20 * 21 / 2) < 1e-12, "fell %.15g m", drop);
    ck_assert_msg(worst < 1e-9, "deformed by %g m while falling", worst);
    pl_sim_free(s);
}
END_TEST

/* Loads xml; returns the sim (or NULL) and every message in msg. */
static pl_sim *load_with_messages(const char *xml, char *msg, size_t size)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, PL_SOURCE_DIR "/scenes/test.xml", NULL, &diag);
    msg[0] = '\0';
    for (int k = 0; k < diag.count; ++k) {
        char line[1024];
        size_t len = strlen(msg);
        snprintf(msg + len, size - len, "%s\n", pl_error_format(&diag.items[k], line, sizeof line));
    }
    pl_diag_free(&diag);
    return s;
}

START_TEST(negative_rayleigh_stiffness_is_refused_and_an_unfixed_body_warned)
{
    const char *bad = "<Node name=\"root\"><RequiredPlugin name=\"sparse_inverse\"/>"
                      "<LocalGlobalSolver rayleighStiffness=\"-1\"/><SparseInverseSolver/>"
                      "<Node name=\"b\"><MechanicalObject position=\"0 0 0\"/>"
                      "<UniformMass totalMass=\"1\"/></Node></Node>";
    char msg[8192];
    pl_sim *s = load_with_messages(bad, msg, sizeof msg);
    ck_assert_ptr_null(s);
    ck_assert_msg(strstr(msg, "test.xml:1") && strstr(msg, "rayleighStiffness must be >= 0"),
                  "%s", msg);
    /* the spring's vertex is fixed by nothing: L damps its rotation */
    static char xml[4096];
    const char *fixed = "<FixedConstraint indices=\"0\"/>";
    for (int k = 0; k < 2; ++k) {
        snprintf(xml, sizeof xml,
                 "<Node name=\"root\"><RequiredPlugin name=\"sparse_inverse\"/>"
                 "<RequiredPlugin name=\"hyperelastic\"/>"
                 "<LocalGlobalSolver rayleighStiffness=\"0.1\"/><SparseInverseSolver/>"
                 "<Node name=\"b\"><RegularGridTetrahedra min=\"0 0 0\" max=\"1 1 1\" "
                 "n=\"2 2 2\"/><MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"1\"/>"
                 "<ARAP youngModulus=\"1e3\"/>%s</Node></Node>",
                 k ? fixed : "");
        s = load_with_messages(xml, msg, sizeof msg);
        ck_assert_msg(s, "%s", msg);
        int warned = strstr(msg, "dofs has no fixed vertex") != NULL;
        ck_assert_msg(warned == !k, "fixed=%d: %s", k, msg);
        pl_sim_free(s);
    }
}
END_TEST

int main(void)
{
    Suite *su = suite_create("lg_scheme");
    TCase *tc = tcase_create("closed forms");
    tcase_add_test(tc, first_order_follows_backward_euler_without_overshoot);
    tcase_add_test(tc, rayleigh_stiffness_follows_damped_implicit_euler);
    tcase_add_test(tc, the_damping_dissipates);
    tcase_add_test(tc, a_falling_body_is_not_deformed_by_the_damping);
    tcase_add_test(tc, negative_rayleigh_stiffness_is_refused_and_an_unfixed_body_warned);
    suite_add_tcase(su, tc);
    SRunner *sr = srunner_create(su);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
