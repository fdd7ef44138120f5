/* test_sofa_euler.c - LinearizedEulerSolver, SOFA's EulerImplicitSolver:
 *  - one vertex on a spring (PositionTarget, a quadratic energy: K is exact)
 *    follows SOFA's recurrence
 *        [(1 + h rM) m + h (h + rS) k] dv = h [-k x - (h + rS) k v - rM m v]
 *    to round-off, with the direct and the CG linear solver, and the
 *    first-order recurrence (m + h k) v = -k x with firstOrder;
 *  - on a hanging Corotational bar at a small step it follows the converged
 *    implicit Euler of NewtonSolver (the linearisation error is second order
 *    in h), and CG run to convergence equals the direct solve;
 *  - a SOFA scene with EulerImplicitSolver + CGLinearSolver and no
 *    constraint gets it, with SOFA's settings. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cable/cable_test_util.h"

static const char *SPRING =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"
    "<RequiredPlugin name=\"hyperelastic\"/>\n"
    "<LinearizedEulerSolver name=\"ode\" %s/>\n"
    "<Node name=\"p\"><MechanicalObject name=\"dofs\" position=\"0.1 0 -0.05\" "
    "rest_position=\"0 0 0\" velocity=\"0 0.5 0\"/>\n"
    "<UniformMass vertexMass=\"2\"/>\n"
    "<PositionTarget indices=\"0\" stiffness=\"50\"/></Node></Node>\n";

static void spring_case(const char *attrs, double rm, double rs, int first)
{
    char xml[2048];
    snprintf(xml, sizeof xml, SPRING, attrs);
    pl_sim *s = ct_load(xml);
    const double m = 2, k = 50, h = 0.01;
    double x[3] = {0.1, 0, -0.05}, v[3] = {0, 0.5, 0};
    for (int step = 0; step < 40; ++step) {
        for (int j = 0; j < 3; ++j) {
            if (first) {
                v[j] = -k * x[j] / (m + h * k);
            } else {
                double A = (1 + h * rm) * m + h * (h + rs) * k;
                v[j] += h * (-k * x[j] - (h + rs) * k * v[j] - rm * m * v[j]) / A;
            }
            x[j] += h * v[j];
        }
    }
    ct_step(s, 40);
    int n;
    const double *q = ct_positions(s, "p/dofs", 0, &n);
    for (int j = 0; j < 3; ++j) ck_assert_double_eq_tol(q[j], x[j], 1e-13);
    ck_assert_double_gt(fabs(q[0] - 0.1) + fabs(q[1]), 1e-2); /* it moved */
    pl_sim_free(s);
}

START_TEST(spring_follows_sofas_recurrence)
{
    spring_case("linearSolver=\"direct\"", 0, 0, 0);
    spring_case("linearSolver=\"direct\" rayleighMass=\"0.3\" rayleighStiffness=\"0.05\"", 0.3,
                0.05, 0);
    spring_case("linearSolver=\"cg\" rayleighMass=\"0.3\" rayleighStiffness=\"0.05\" "
                "threshold=\"1e-30\" tolerance=\"1e-14\"",
                0.3, 0.05, 0);
    spring_case("linearSolver=\"direct\" firstOrder=\"1\"", 0, 0, 1);
}
END_TEST

static const char *BAR =
    "<Node name=\"root\" dt=\"0.001\" gravity=\"0 -9.81 0\">\n"
    "<RequiredPlugin name=\"hyperelastic\"/>\n"
    "%s\n"
    "<Node name=\"bar\"><RegularGridTetrahedra min=\"0 0 0\" max=\"0.2 0.04 0.04\" "
    "n=\"6 2 2\"/>\n"
    "<MechanicalObject name=\"dofs\"/><DiagonalMass massDensity=\"1000\"/>\n"
    "<Corotational youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
    "<FixedConstraint box=\"-0.001 -1 -1 0.001 1 1\"/></Node></Node>\n";

static void run_bar(const char *solver, double *out, int *n)
{
    char xml[2048];
    snprintf(xml, sizeof xml, BAR, solver);
    pl_sim *s = ct_load(xml);
    ct_step(s, 60);
    const double *q = ct_positions(s, "bar/dofs", 0, n);
    memcpy(out, q, (size_t)*n * 3 * sizeof *out);
    pl_sim_free(s);
}

START_TEST(bar_follows_converged_implicit_euler)
{
    double a[300], b[300], c[300], r[300];
    int n;
    run_bar("<LinearizedEulerSolver linearSolver=\"direct\"/>", a, &n);
    run_bar("<LinearizedEulerSolver iterations=\"500\" tolerance=\"1e-13\" threshold=\"1e-30\"/>",
            c, &n);
    run_bar("<NewtonSolver tolerance=\"1e-12\"/>", b, &n);
    pl_sim *s;
    char xml[2048];
    snprintf(xml, sizeof xml, BAR, "");
    s = ct_load(xml);
    int nr;
    const double *rest = ct_positions(s, "bar/dofs", 1, &nr);
    ck_assert_int_eq(nr, n);
    memcpy(r, rest, (size_t)nr * 3 * sizeof *r);
    pl_sim_free(s);
    double disp = 0, diff = 0, cg = 0;
    for (int i = 0; i < 3 * n; ++i) {
        disp = fmax(disp, fabs(b[i] - r[i]));
        diff = fmax(diff, fabs(a[i] - b[i]));
        cg = fmax(cg, fabs(a[i] - c[i]));
    }
    printf("bar: tip displacement %.3e m; linearised vs Newton %.3e m; CG vs direct %.3e m\n",
           disp, diff, cg);
    ck_assert_double_gt(disp, 1e-3);
    ck_assert_double_lt(diff, 1e-2 * disp);
    ck_assert_double_lt(cg, 1e-9 * disp);
}
END_TEST

START_TEST(sofa_scene_gets_sofas_integrator)
{
    pl_sim *s = ct_load(
        "<Node name=\"root\" dt=\"0.01\">\n"
        "<RequiredPlugin name=\"Sofa.Component.ODESolver.Backward\"/>\n"
        "<DefaultAnimationLoop/>\n"
        "<Node name=\"body\"><EulerImplicitSolver name=\"cg_odesolver\" rayleighStiffness=\"0.1\" "
        "rayleighMass=\"0.2\"/>\n"
        "<CGLinearSolver name=\"linear solver\" iterations=\"30\" tolerance=\"1e-09\" "
        "threshold=\"1e-08\"/>\n"
        "<RegularGridTetrahedra min=\"0 0 0\" max=\"1 0.2 0.2\" n=\"3 2 2\"/>\n"
        "<MechanicalObject/><UniformMass totalMass=\"1\"/>\n"
        "<TetrahedralCorotationalFEMForceField youngModulus=\"3000\" poissonRatio=\"0.3\"/>\n"
        "<FixedProjectiveConstraint indices=\"0\"/></Node></Node>\n");
    pl_component *c = pl_sim_component(s, "cg_odesolver");
    ck_assert_ptr_nonnull(c);
    ck_assert_str_eq(c->type->name, "LinearizedEulerSolver");
    ck_assert_double_eq(ct_get(s, "cg_odesolver.rayleighStiffness"), 0.1);
    ck_assert_double_eq(ct_get(s, "cg_odesolver.rayleighMass"), 0.2);
    ck_assert_double_eq(ct_get(s, "cg_odesolver.iterations"), 30);
    ck_assert_double_eq(ct_get(s, "cg_odesolver.tolerance"), 1e-9);
    ck_assert_double_eq(ct_get(s, "cg_odesolver.threshold"), 1e-8);
    ct_step(s, 5);
    pl_sim_free(s);
}
END_TEST

/* A SOFA cable scene's EulerImplicitSolver: with a Lagrangian constraint it
 * becomes LocalGlobalSolver, with firstOrder and rayleighStiffness as its
 * fields; under firstOrder SOFA uses no Rayleigh factor, and neither does
 * Pliant (a warning says so). */
static pl_sim *cable_scene(const char *ode, pl_diag *d)
{
    char xml[4096];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
             "<FreeMotionAnimationLoop/><GenericConstraintSolver/>\n"
             "<Node name=\"finger\"><EulerImplicitSolver name=\"odesolver\" %s/>\n"
             "<SparseLDLSolver/>\n"
             "<MeshVTKLoader name=\"loader\" filename=\"" PL_SOURCE_DIR
             "/scenes/meshes/finger.vtk\"/>\n"
             "<MechanicalObject name=\"tetras\"/><UniformMass totalMass=\"0.5\"/>\n"
             "<TetrahedronFEMForceField youngModulus=\"18000\" poissonRatio=\"0.3\"/>\n"
             "<BoxROI name=\"ROI\" box=\"-15 0 0 5 10 15\"/>\n"
             "<RestShapeSpringsForceField points=\"@ROI.indices\" stiffness=\"1e12\"/>\n"
             "<Node name=\"cable\"><MechanicalObject position=\"-17.5 12.5 2.5 -32.5 12.5 2.5\"/>\n"
             "<CableConstraint name=\"aCable\" indices=\"0 1\" pullPoint=\"0 12.5 2.5\"/>\n"
             "<BarycentricMapping/></Node></Node></Node>\n",
             ode);
    pl_diag_init(d);
    pl_sim *s = pl_sim_load_string(xml, "scene.scn", NULL, d);
    if (!s) pl_diag_print(d, stderr);
    ck_assert_ptr_nonnull(s);
    return s;
}

START_TEST(cable_scene_maps_first_order_and_rayleigh_stiffness)
{
    pl_diag d;
    pl_sim *s = cable_scene("rayleighStiffness=\"0.1\" rayleighMass=\"0.2\"", &d);
    ck_assert_str_eq(pl_sim_component(s, "odesolver")->type->name, "LocalGlobalSolver");
    ck_assert_double_eq(ct_get(s, "odesolver.rayleighStiffness"), 0.1);
    ck_assert_double_eq(ct_get(s, "odesolver.damping"), 0.2);
    ck_assert_double_eq(ct_get(s, "odesolver.firstOrder"), 0);
    ct_step(s, 2);
    pl_sim_free(s);
    pl_diag_free(&d);
    s = cable_scene("firstOrder=\"true\" rayleighStiffness=\"0.1\" rayleighMass=\"0.2\"", &d);
    ck_assert_double_eq(ct_get(s, "odesolver.firstOrder"), 1);
    ck_assert_double_eq(ct_get(s, "odesolver.rayleighStiffness"), 0);
    ck_assert_double_eq(ct_get(s, "odesolver.damping"), 0);
    const pl_error *w = NULL; /* a warning (ct_find_error finds errors) */
    for (int k = 0; k < d.count && !w; ++k)
        if (strstr(d.items[k].msg, "not used with firstOrder")) w = &d.items[k];
    ck_assert_ptr_nonnull(w);
    ck_assert_int_eq(w->line, 3);
    ct_step(s, 2);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

START_TEST(bad_settings_are_refused)
{
    static const char *bad[] = {"iterations=\"0\"", "tolerance=\"-1\"",
                                "rayleighMass=\"-0.1\"", "linearSolver=\"lu\""};
    for (int k = 0; k < 4; ++k) {
        char xml[2048];
        snprintf(xml, sizeof xml, SPRING, bad[k]);
        pl_diag d = ct_load_fail(xml);
        ck_assert_int_eq(d.items[0].line, 3);
        ck_assert_int_eq(pl_diag_status(&d), PL_EINPUT);
        pl_diag_free(&d);
    }
}
END_TEST

/* The warnings of a run, counted by a log sink. */
static int threshold_warnings;
static void count_warnings(pl_log_level level, const char *msg, void *user)
{
    (void)user;
    if (level == PL_LOG_WARN && strstr(msg, "CG stopped by threshold")) ++threshold_warnings;
}

/* SOFA's CG threshold is an absolute bound on p.Ap: on this light SI bar the
 * default 1e-5 stops CG before its first iteration, so the step leaves the
 * body as it was (SOFA would too).  Pliant says so once, and a lower
 * threshold lets gravity act. */
START_TEST(cg_stopped_by_its_threshold_says_so)
{
    const char *cases[] = {"<LinearizedEulerSolver name=\"euler\"/>",
                           "<LinearizedEulerSolver name=\"euler\" threshold=\"1e-30\"/>"};
    for (int k = 0; k < 2; ++k) {
        char xml[2048];
        snprintf(xml, sizeof xml, BAR, cases[k]);
        pl_sim *s = ct_load(xml);
        int n;
        const double *q = ct_positions(s, "bar/dofs", 0, &n), *rest = ct_positions(s, "bar/dofs", 1, &n);
        threshold_warnings = 0;
        pl_log_set_sink(count_warnings, NULL);
        ct_step(s, 5);
        pl_log_set_sink(NULL, NULL);
        double moved = 0.0;
        for (int i = 0; i < 3 * n; ++i) moved = fmax(moved, fabs(q[i] - rest[i]));
        fprintf(stderr, "%s: %d warnings, moved %.3g m\n", cases[k], threshold_warnings, moved);
        ck_assert_int_eq(threshold_warnings, k == 0 ? 1 : 0);
        if (k == 0)
            ck_assert_double_eq(moved, 0.0);
        else
            ck_assert_double_gt(moved, 1e-7); /* 5 ms of gravity: about 1.2e-4 m at the tip */
        pl_sim_free(s);
    }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_euler");
    TCase *tc = tcase_create("euler");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, spring_follows_sofas_recurrence);
    tcase_add_test(tc, bar_follows_converged_implicit_euler);
    tcase_add_test(tc, sofa_scene_gets_sofas_integrator);
    tcase_add_test(tc, cable_scene_maps_first_order_and_rayleigh_stiffness);
    tcase_add_test(tc, bad_settings_are_refused);
    tcase_add_test(tc, cg_stopped_by_its_threshold_says_so);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
