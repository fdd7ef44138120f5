/* test_cable_keyframes.c - the Keyframes controller and the per-step
 * callback of the embedding API:
 *  - interpolation: exact at keyframes, linear in between, held before the
 *    first and after the last, stepwise when asked, k values per time;
 *  - in a scene it writes the value at the start of each step (time t) into
 *    the target: a list (cable.value), a vec3 (cable.pullPoint, k = 3), an
 *    int (cable.valueIndex, stepwise) and a built-in component's field
 *    (LocalGlobalSolver.damping); at load the target holds the value at t = 0;
 *  - after pl_sim_reset the values follow the time again (they are model
 *    values recomputed from the state's time);
 *  - a pl_sim_set_callback callback drives cable.value itself. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable_test_util.h"
#include "controller/controller.h"

START_TEST(interpolation)
{
    const double t[] = {0.0, 1.0, 3.0};
    const double v[] = {0.0, 2.0, -2.0};
    double out;
    pl_keyframes_eval(t, 3, v, 1, 0, -1.0, &out);
    ck_assert_double_eq(out, 0.0);
    pl_keyframes_eval(t, 3, v, 1, 0, 1.0, &out);
    ck_assert_double_eq(out, 2.0);
    pl_keyframes_eval(t, 3, v, 1, 0, 0.25, &out);
    ck_assert_double_eq_tol(out, 0.5, 1e-15);
    pl_keyframes_eval(t, 3, v, 1, 0, 2.5, &out);
    ck_assert_double_eq_tol(out, -1.0, 1e-15);
    pl_keyframes_eval(t, 3, v, 1, 0, 7.0, &out);
    ck_assert_double_eq(out, -2.0);
    pl_keyframes_eval(t, 3, v, 1, 1, 2.9, &out); /* step: the last keyframe at or before t */
    ck_assert_double_eq(out, 2.0);
    pl_keyframes_eval(t, 3, v, 1, 1, 3.0, &out);
    ck_assert_double_eq(out, -2.0);
    /* k = 3 values per time */
    const double v3[] = {0, 0, 0, 1, 2, 3, 1, 2, 3};
    double o3[3];
    pl_keyframes_eval(t, 3, v3, 3, 0, 0.5, o3);
    for (int j = 0; j < 3; ++j) ck_assert_double_eq_tol(o3[j], 0.5 * (j + 1), 1e-15);
    /* one keyframe: a constant */
    pl_keyframes_eval(t + 1, 1, v + 1, 1, 0, -5.0, &out);
    ck_assert_double_eq(out, 2.0);
}
END_TEST

static const char *SCENE =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"
    "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
    "<RequiredPlugin name=\"ncp_contact\"/><RequiredPlugin name=\"cable\"/>\n"
    "<LocalGlobalSolver name=\"solver\" iterations=\"5\"/>\n"
    "<SparseInverseSolver/><NonSmoothNewtonContactSolver/>\n"
    "<Node name=\"bar\">\n"
    "<RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.02 0.02\" n=\"6 2 2\"/>\n"
    "<MechanicalObject name=\"dofs\"/><DiagonalMass massDensity=\"1000\"/>\n"
    "<NeoHookean youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
    "<FixedConstraint box=\"-0.001 -1 -1  0.001 1 1\"/>\n"
    "<CableConstraint name=\"cable\" indices=\"9 13 17 21\" value=\"0 0\" "
    "pullPoint=\"-0.01 0.01 0.01\"/>\n"
    "%s\n"
    "</Node></Node>\n";

static pl_sim *scene(const char *controllers)
{
    char xml[4096];
    snprintf(xml, sizeof xml, SCENE, controllers);
    return ct_load(xml);
}

/* The numbers of a field (at most max). */
static int get_list(pl_sim *s, const char *path, double *v, int max)
{
    char buf[512], *p = buf, *end;
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, path, buf, sizeof buf, &err), PL_OK);
    int n = 0;
    for (double x = strtod(p, &end); end != p && n < max; x = strtod(p = end, &end)) v[n++] = x;
    return n;
}

START_TEST(drives_fields_in_a_scene)
{
    pl_sim *s = scene(
        "<Keyframes name=\"pull\" target=\"@cable.value\" times=\"0 0.1\" "
        "values=\"0 0.001 0.004 0.002\"/>\n"
        "<Keyframes name=\"move\" target=\"@cable.pullPoint\" times=\"0.02 0.06\" "
        "values=\"-0.01 0.01 0.01  -0.03 0.01 0.05\"/>\n"
        "<Keyframes name=\"pick\" target=\"@cable.valueIndex\" times=\"0 0.05\" values=\"0 1\" "
        "interpolation=\"step\"/>\n"
        "<Keyframes name=\"damp\" target=\"@solver.damping\" times=\"0 0.1\" values=\"1 11\"/>");
    double v[4];
    /* at load: the values at t = 0 */
    ck_assert_int_eq(get_list(s, "cable.value", v, 4), 2);
    ck_assert_double_eq(v[0], 0.0);
    ck_assert_double_eq(v[1], 0.001);
    ck_assert_double_eq(ct_get(s, "solver.damping"), 1.0);
    for (int n = 0; n < 12; ++n) {
        double t = pl_sim_time(s); /* the step about to be taken starts at t */
        ct_step(s, 1);
        ck_assert_int_eq(get_list(s, "cable.value", v, 4), 2);
        double a = fmin(t / 0.1, 1.0);
        ck_assert_double_eq_tol(v[0], 0.004 * a, 1e-15);
        ck_assert_double_eq_tol(v[1], 0.001 + 0.001 * a, 1e-15);
        ck_assert_int_eq(get_list(s, "cable.pullPoint", v, 4), 3);
        double b = fmin(fmax((t - 0.02) / 0.04, 0.0), 1.0);
        ck_assert_double_eq_tol(v[0], -0.01 - 0.02 * b, 1e-15);
        ck_assert_double_eq_tol(v[1], 0.01, 1e-15);
        ck_assert_double_eq_tol(v[2], 0.01 + 0.04 * b, 1e-15);
        ck_assert_double_eq(ct_get(s, "cable.valueIndex"), t < 0.05 ? 0.0 : 1.0);
        ck_assert_double_eq_tol(ct_get(s, "solver.damping"), 1.0 + 10.0 * a, 1e-13);
    }
    /* reset: back to t = 0, the controller follows the state's time */
    ck_assert_int_eq(pl_sim_reset(s), PL_OK);
    ct_step(s, 1);
    ck_assert_int_eq(get_list(s, "cable.value", v, 4), 2);
    ck_assert_double_eq(v[0], 0.0);
    pl_sim_free(s);
}
END_TEST

static int drive_cable(pl_sim *sim, double t, void *user)
{
    int *calls = user;
    char value[64];
    pl_error err;
    snprintf(value, sizeof value, "%.17g", 0.01 * t); /* 10 mm/s */
    (*calls)++;
    return pl_sim_set(sim, "cable.value", value, &err);
}

START_TEST(callback_drives_the_cable)
{
    pl_sim *s = scene("");
    int calls = 0;
    pl_sim_set_callback(s, drive_cable, &calls);
    ct_step(s, 20);
    ck_assert_int_eq(calls, 20);
    ck_assert_double_eq_tol(ct_get(s, "cable.value"), 0.01 * 0.19, 1e-15);
    ck_assert_double_gt(ct_get(s, "cable.displacement"), 0.001); /* it pulled */
    pl_sim_set_callback(s, NULL, NULL);
    ct_step(s, 1);
    ck_assert_int_eq(calls, 20);
    pl_sim_free(s);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cable_keyframes");
    TCase *tc = tcase_create("keyframes");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, interpolation);
    tcase_add_test(tc, drives_fields_in_a_scene);
    tcase_add_test(tc, callback_drives_the_cable);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
