/* test_pressure_errors.c - broken SurfacePressureConstraint inputs are
 * refused at load naming the problem, the scene file and the line: an open
 * or non-manifold cavity, neighbours facing opposite ways, indices out of
 * range, bad bounds, non-finite numbers.  An inward-facing (but otherwise
 * sound) cavity is turned around with a warning. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable_test_util.h"

/* A cube of one grid cell (vertex (i,j,k) = i + 2j + 4k, side 0.1 m); the
 * constraint on line 12. */
static const char *SCENE =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"                                /* 1 */
    "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"   /* 2 */
    "<RequiredPlugin name=\"ncp_contact\"/><RequiredPlugin name=\"cable\"/>\n"             /* 3 */
    "<LocalGlobalSolver name=\"solver\" iterations=\"5\"/>\n"                              /* 4 */
    "<SparseInverseSolver/><NonSmoothNewtonContactSolver/>\n"                              /* 5 */
    "<Node name=\"cube\">\n"                                                               /* 6 */
    "<RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.1 0.1\" n=\"2 2 2\"/>\n"            /* 7 */
    "<MechanicalObject name=\"dofs\"/>\n"                                                  /* 8 */
    "<DiagonalMass massDensity=\"1000\"/>\n"                                               /* 9 */
    "<NeoHookean name=\"material\" youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"         /* 10 */
    "\n"                                                                                   /* 11 */
    "<SurfacePressureConstraint name=\"p\" %s/>\n"                                         /* 12 */
    "</Node></Node>\n";

/* The cube's 12 boundary triangles, facing out. */
#define CUBE "0 2 3 0 3 1  4 5 7 4 7 6  0 1 5 0 5 4  2 6 7 2 7 3  0 4 6 0 6 2  1 3 7 1 7 5"
#define CUBE_OPEN "0 2 3 0 3 1  4 5 7 4 7 6  0 1 5 0 5 4  2 6 7 2 7 3  0 4 6 0 6 2  1 3 7"
#define CUBE_FLIPPED_ONE "0 3 2 0 3 1  4 5 7 4 7 6  0 1 5 0 5 4  2 6 7 2 7 3  0 4 6 0 6 2  1 3 7 1 7 5"
#define CUBE_INWARD "0 3 2 0 1 3  4 7 5 4 6 7  0 5 1 0 4 5  2 7 6 2 3 7  0 6 4 0 2 6  1 7 3 1 5 7"

static void expect_error(const char *attrs, const char *what)
{
    char xml[4096];
    snprintf(xml, sizeof xml, SCENE, attrs);
    pl_diag d = ct_load_fail(xml);
    const pl_error *e = ct_find_error(&d, what);
    if (!e) {
        pl_diag_print(&d, stderr);
        ck_abort_msg("no error containing '%s'", what);
    }
    ck_assert_str_eq(e->file, "scene.xml");
    ck_assert_int_eq(e->line, 12);
    pl_diag_free(&d);
}

START_TEST(cavity_not_closed)
{
    expect_error("triangles=\"" CUBE_OPEN "\"", "is not closed: the edge");
    /* a fourth triangle on the edge 0-1 */
    expect_error("triangles=\"" CUBE " 0 1 6\"", "is not a manifold");
    expect_error("triangles=\"" CUBE_FLIPPED_ONE "\"", "is not consistently oriented");
    expect_error("triangles=\"0 0 1 " CUBE "\"", "degenerate triangle");
}
END_TEST

START_TEST(cavity_bad_indices)
{
    expect_error("", "no cavity");
    expect_error("triangles=\"0 1\"", "triangles: expected 3 indices each");
    expect_error("triangles=\"" CUBE "\" box=\"0 0 0 1 1 1\"", "give the cavity once");
    expect_error("triangles=\"0 2 3 0 3 1 4 5 7 4 7 99\"", "index 99 (triangle 3) is out of range");
    expect_error("position=\"0 0\" triangles=\"0 1 2\"", "position: expected x y z");
    expect_error("surface=\"@nothing\"", "nothing");
}
END_TEST

START_TEST(cavity_bad_bounds)
{
    expect_error("triangles=\"" CUBE "\" minPressure=\"2\" maxPressure=\"1\"",
                 "minPressure (2 Pa) is above maxPressure (1 Pa)");
    expect_error("triangles=\"" CUBE "\" minVolumeGrowth=\"1\" maxVolumeGrowth=\"0\"",
                 "minVolumeGrowth (1) is above maxVolumeGrowth (0)");
    expect_error("triangles=\"" CUBE "\" eqPressure=\"5\" maxPressure=\"10\"",
                 "eqPressure fixes the pressure");
    expect_error("triangles=\"" CUBE "\" maxPressure=\"1 2\"", "maxPressure: expected one number");
    expect_error("triangles=\"" CUBE "\" value=\"1 2\" valueIndex=\"2\"",
                 "valueIndex: 2 is out of range");
    expect_error("triangles=\"" CUBE "\" valueType=\"torque\"", "valueType");
    expect_error("triangles=\"" CUBE "\" maxVolumeGrowthVariation=\"-1\"", "must be >= 0");
}
END_TEST

START_TEST(cavity_not_finite)
{
    char xml[4096];
    const char *attrs[] = {"triangles=\"" CUBE "\" value=\"nan\"",
                           "triangles=\"" CUBE "\" maxPressure=\"inf\"",
                           "triangles=\"0 1 2\" position=\"0 0 0 nan 0 0 0 1 0\""};
    for (int k = 0; k < 3; ++k) {
        snprintf(xml, sizeof xml, SCENE, attrs[k]);
        pl_diag d = ct_load_fail(xml);
        int found = 0;
        for (int i = 0; i < d.count; ++i)
            found |= d.items[i].code != PL_OK &&
                     !strcmp(d.items[i].file, "scene.xml") && d.items[i].line == 12;
        if (!found) pl_diag_print(&d, stderr);
        ck_assert_msg(found, "no error on line 12 for %s", attrs[k]);
        pl_diag_free(&d);
    }
}
END_TEST

START_TEST(cavity_inward_turned_around)
{
    char xml[4096];
    snprintf(xml, sizeof xml, SCENE, "triangles=\"" CUBE_INWARD "\"");
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, "scene.xml", NULL, &diag);
    ck_assert_ptr_nonnull(s);
    int warned = 0;
    for (int i = 0; i < diag.count; ++i)
        warned |= strstr(diag.items[i].msg, "face into it") != NULL && diag.items[i].line == 12;
    ck_assert(warned);
    pl_diag_free(&diag);
    ck_assert_double_eq_tol(ct_get(s, "cube/p.initialCavityVolume"), 1e-3, 1e-15);
    pl_sim_free(s);
    /* the same cube facing out: the same volume, no warning needed */
    snprintf(xml, sizeof xml, SCENE, "triangles=\"" CUBE "\"");
    s = ct_load(xml);
    ck_assert_double_eq_tol(ct_get(s, "cube/p.initialCavityVolume"), 1e-3, 1e-15);
    ck_assert_double_eq_tol(ct_get(s, "cube/p.volumeGrowth"), 0, 1e-15);
    pl_sim_free(s);
    /* flipNormal says the given triangles face in: no warning either way */
    snprintf(xml, sizeof xml, SCENE, "triangles=\"" CUBE_INWARD "\" flipNormal=\"1\"");
    s = ct_load(xml);
    ck_assert_double_eq_tol(ct_get(s, "cube/p.cavityVolume"), 1e-3, 1e-15);
    pl_sim_free(s);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("pressure_errors");
    TCase *tc = tcase_create("errors");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, cavity_not_closed);
    tcase_add_test(tc, cavity_bad_indices);
    tcase_add_test(tc, cavity_bad_bounds);
    tcase_add_test(tc, cavity_not_finite);
    tcase_add_test(tc, cavity_inward_turned_around);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
