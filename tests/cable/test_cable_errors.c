/* test_cable_errors.c - broken CableConstraint and Keyframes inputs are
 * refused at load with a message that names the problem, the scene file
 * and the line of the offending element; run-time mistakes (a valueIndex
 * set out of range while running) stop the step with the component's path. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable_test_util.h"

/* A bar scene with the cable element on line 12 and room for a controller
 * on line 13. */
static const char *SCENE =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"                                /* 1 */
    "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"   /* 2 */
    "<RequiredPlugin name=\"ncp_contact\"/><RequiredPlugin name=\"cable\"/>\n"             /* 3 */
    "<LocalGlobalSolver name=\"solver\" iterations=\"5\"/>\n"                              /* 4 */
    "<SparseInverseSolver/><NonSmoothNewtonContactSolver/>\n"                              /* 5 */
    "<Node name=\"bar\">\n"                                                                /* 6 */
    "<RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.02 0.02\" n=\"6 2 2\"/>\n"          /* 7 */
    "<MechanicalObject name=\"dofs\"/>\n"                                                  /* 8 */
    "<DiagonalMass massDensity=\"1000\"/>\n"                                               /* 9 */
    "<NeoHookean name=\"material\" youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"         /* 10 */
    "<FixedConstraint box=\"-0.001 -1 -1  0.001 1 1\"/>\n"                                 /* 11 */
    "<CableConstraint name=\"cable\" %s/>\n"                                               /* 12 */
    "%s\n"                                                                                 /* 13 */
    "</Node></Node>\n";

/* Loads the scene (cable attributes, controller) expecting an error that
 * contains `what` on line `line` of scene.xml. */
static void expect_error(const char *cable, const char *controller, const char *what, int line)
{
    char xml[4096];
    snprintf(xml, sizeof xml, SCENE, cable, controller ? controller : "");
    pl_diag d = ct_load_fail(xml);
    const pl_error *e = ct_find_error(&d, what);
    if (!e) {
        pl_diag_print(&d, stderr);
        ck_abort_msg("no error containing '%s'", what);
    }
    ck_assert_str_eq(e->file, "scene.xml");
    ck_assert_int_eq(e->line, line);
    pl_diag_free(&d);
}

START_TEST(cable_indices_out_of_range)
{
    /* the grid has 6 x 2 x 2 = 24 vertices */
    expect_error("indices=\"5 24 7\"", NULL, "indices: 24 (entry 1) is out of range", 12);
    expect_error("indices=\"-1\"", NULL, "indices: -1 (entry 0) is out of range", 12);
}
END_TEST

START_TEST(cable_empty_or_ambiguous)
{
    expect_error("", NULL, "the cable is empty", 12);
    expect_error("indices=\"1 2\" centers=\"0 0 0\"", NULL, "give the cable points once", 12);
    expect_error("position=\"0.01 0.01\"", NULL, "position: expected x y z per point", 12);
    expect_error("indices=\"3\" hasPullPoint=\"0\"", NULL, "needs at least two points", 12);
}
END_TEST

START_TEST(cable_bad_values)
{
    expect_error("indices=\"1 2\" value=\"0.01 0.02\" valueIndex=\"2\"", NULL,
                 "valueIndex: 2 is out of range", 12);
    expect_error("indices=\"1 2\" minForce=\"2\" maxForce=\"1\"", NULL, "is above maxForce", 12);
    expect_error("indices=\"1 2\" maxForce=\"1 2\"", NULL, "maxForce: expected one number", 12);
    expect_error("indices=\"1 2\" valueType=\"torque\"", NULL, "valueType", 12);
    expect_error("indices=\"1 2\" cableInitialLength=\"-1\"", NULL, "cableInitialLength", 12);
}
END_TEST

START_TEST(keyframes_broken)
{
    const char *cable = "indices=\"1 2\"";
    expect_error(cable, "<Keyframes target=\"@cable.value\" times=\"0 1 1\" values=\"0 1 2\"/>",
                 "times: must increase", 13);
    expect_error(cable, "<Keyframes target=\"@cable.value\" times=\"0 1\" values=\"0 1 2\"/>",
                 "values: 3 numbers for 2 times", 13);
    expect_error(cable, "<Keyframes target=\"@wire.value\" times=\"0 1\" values=\"0 1\"/>",
                 "target: no component 'wire'", 13);
    expect_error(cable, "<Keyframes target=\"@cable.valeu\" times=\"0 1\" values=\"0 1\"/>",
                 "did you mean value?", 13);
    expect_error(cable, "<Keyframes target=\"cable\" times=\"0 1\" values=\"0 1\"/>",
                 "target: expected @component.field", 13);
    /* a model field (changing it would rebuild the model), and a RUNTIME one
     * that is still the model's (shared by every data): only inputs, whose
     * value lives in each data, may be driven; the message lists them */
    expect_error(cable, "<Keyframes target=\"@material.youngModulus\" times=\"0 1\" values=\"1 2\"/>",
                 "is not an input field", 13);
    expect_error(cable, "<Keyframes target=\"@cable.compliance\" times=\"0 1\" values=\"1 2\"/>",
                 "(pullPoint, value, valueIndex, valueType)", 13);
    expect_error(cable, "<Keyframes target=\"@cable.force\" times=\"0 1\" values=\"0 1\"/>",
                 "is an output", 13);
    /* a vec3 takes 3 numbers per time */
    expect_error(cable, "<Keyframes target=\"@cable.pullPoint\" times=\"0 1\" values=\"0 1\"/>",
                 "takes 3 number(s) per time, found 1", 13);
    expect_error(cable, "<Keyframes target=\"@cable.value\" times=\"\" values=\"\"/>",
                 "times: expected at least one time", 13);
}
END_TEST

START_TEST(runtime_value_index_out_of_range)
{
    char xml[4096];
    snprintf(xml, sizeof xml, SCENE, "indices=\"10 20\" value=\"0.001\"", "");
    pl_sim *s = ct_load(xml);
    pl_error err;
    ck_assert_int_eq(pl_sim_set(s, "cable.valueIndex", "3", &err), PL_OK); /* an input: accepted */
    ck_assert_int_eq(pl_sim_step(s, 1, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "valueIndex: 3 is out of range"));
    ck_assert_ptr_nonnull(strstr(err.where, "bar/cable"));
    /* outputs cannot be set */
    ck_assert_int_eq(pl_sim_set(s, "cable.force", "1", &err), PL_EINPUT);
    pl_sim_free(s);
}
END_TEST

START_TEST(constraint_without_contact_solver)
{
    const char *xml =
        "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"
        "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
        "<RequiredPlugin name=\"cable\"/>\n"
        "<LocalGlobalSolver/><SparseInverseSolver/>\n"
        "<Node name=\"bar\">\n"
        "<RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.02 0.02\" n=\"6 2 2\"/>\n"
        "<MechanicalObject/><DiagonalMass massDensity=\"1000\"/>\n"
        "<NeoHookean youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
        "<CableConstraint indices=\"1 2\"/>\n"
        "</Node></Node>\n";
    pl_diag d = ct_load_fail(xml);
    ck_assert_ptr_nonnull(ct_find_error(&d, "no contact solver"));
    pl_diag_free(&d);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cable_errors");
    TCase *tc = tcase_create("errors");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, cable_indices_out_of_range);
    tcase_add_test(tc, cable_empty_or_ambiguous);
    tcase_add_test(tc, cable_bad_values);
    tcase_add_test(tc, keyframes_broken);
    tcase_add_test(tc, runtime_value_index_out_of_range);
    tcase_add_test(tc, constraint_without_contact_solver);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
