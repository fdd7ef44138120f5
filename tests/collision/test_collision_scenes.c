/* test_collision_scenes.c - obstacles and collision models as a user meets
 * them in scene files:
 *  - broken inputs are errors naming the scene line and what is wrong: a
 *    zero normal, a negative radius, contactDistance > alarmDistance,
 *    keyframe times not increasing, a translation count that does not match,
 *    a spin without an axis, a bad mu on a collision model, a surface model
 *    without a mesh;
 *  - run-time edits (--set style) of an obstacle's fields are checked at the
 *    next step: a bad value stops the step with a message;
 *  - the contact scenes of scenes/ (stick_slip, resting_box, sliding_box,
 *    ball_on_plane) start as their comments say: the cube rests exactly at
 *    the kept gap on the slope (every bottom vertex in contact with
 *    H q - d = 0, normal turned 10 or 20 degrees), slope.mu can be set from
 *    outside, the ball starts clear of the floor.  The contact solver is
 *    swapped for the built-in NewtonSolver here (only the start is read). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"

static void expect_error(const char *element, const char *needle)
{
    char xml[2048];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\">\n"                       /* line 1 */
             "<RequiredPlugin name=\"collision\"/>\n"        /* line 2 */
             "<NewtonSolver/>\n"                             /* line 3 */
             "<Node name=\"body\">\n"                        /* line 4 */
             "<RegularGridTetrahedra n=\"2 2 2\"/>\n"        /* line 5 */
             "<MechanicalObject/>\n"                         /* line 6 */
             "<UniformMass totalMass=\"1\"/>\n"              /* line 7 */
             "</Node>\n"                                     /* line 8 */
             "%s\n"                                          /* line 9 */
             "</Node>\n",
             element);
    pl_error e;
    ct_load_fail(xml, &e);
    ck_assert_msg(e.line == 9, "expected line 9, got %d (%s)", e.line, e.msg);
    ck_assert_msg(strstr(e.msg, needle) != NULL, "'%s' not in: %s", needle, e.msg);
    ck_assert_str_eq(e.file, "scene");
}

START_TEST(test_broken_obstacles_name_the_line)
{
    expect_error("<PlaneObstacle normal=\"0 0 0\"/>", "normal");
    expect_error("<SphereObstacle radius=\"-0.1\"/>", "radius must be");
    expect_error("<CapsuleObstacle start=\"0 0 0\" end=\"1 0 0\" radius=\"-1\"/>", "radius");
    expect_error("<CylinderObstacle axis=\"0 0 0\" radius=\"1\" length=\"1\"/>", "axis");
    expect_error("<BoxObstacle halfExtents=\"1 -1 1\"/>", "halfExtents");
    expect_error("<PlaneObstacle alarmDistance=\"0.001\" contactDistance=\"0.002\"/>",
                 "contactDistance (0.002 m) exceeds alarmDistance (0.001 m)");
    expect_error("<PlaneObstacle times=\"0 1 0.5\" translations=\"0 0 0  1 0 0  2 0 0\"/>",
                 "strictly increasing");
    expect_error("<PlaneObstacle times=\"0 1\" translations=\"0 0 0  1 0\"/>", "translations");
    expect_error("<SphereObstacle radius=\"1\" angularVelocity=\"2\"/>", "rotationAxis");
    expect_error("<PlaneObstacle mu=\"-0.2\"/>", "mu must be >= 0");
    expect_error("<PlaneObstacle rotationCenter=\"1 2\"/>", "rotationCenter");
    expect_error("<SphereObstacle/>", "radius");
}
END_TEST

START_TEST(test_broken_models_name_the_line)
{
    const char *xml = "<Node name=\"root\">\n"
                      "<RequiredPlugin name=\"collision\"/>\n"
                      "<NewtonSolver/>\n"
                      "<PlaneObstacle/>\n"
                      "<Node name=\"body\">\n"
                      "<RegularGridTetrahedra n=\"2 2 2\"/>\n"
                      "<MechanicalObject/>\n"
                      "<UniformMass totalMass=\"1\"/>\n"
                      "<SurfaceCollisionModel mu=\"-2\"/>\n"
                      "</Node></Node>\n";
    pl_error e;
    ct_load_fail(xml, &e);
    ck_assert_int_eq(e.line, 9);
    ck_assert_ptr_nonnull(strstr(e.msg, "mu must be >= 0, or -1"));
    /* a point cloud has no surface */
    const char *cloud = "<Node name=\"root\">\n"
                        "<RequiredPlugin name=\"collision\"/>\n"
                        "<NewtonSolver/>\n"
                        "<Node name=\"body\">\n"
                        "<MechanicalObject position=\"0 0 0  1 0 0\"/>\n"
                        "<UniformMass totalMass=\"1\"/>\n"
                        "<SurfaceCollisionModel/>\n"
                        "</Node></Node>\n";
    ct_load_fail(cloud, &e);
    ck_assert_int_eq(e.line, 7);
    ck_assert_ptr_nonnull(strstr(e.msg, "mesh"));
}
END_TEST

START_TEST(test_runtime_edit_checked_at_step)
{
    const char *xml = "<Node name=\"root\" dt=\"0.01\">\n"
                      "<RequiredPlugin name=\"collision\"/>\n"
                      "<NewtonSolver/>\n"
                      "<PlaneObstacle name=\"floor\" alarmDistance=\"0.02\"/>\n"
                      "<Node name=\"body\">\n"
                      "<RegularGridTetrahedra min=\"0 0.01 0\" max=\"1 1 1\" n=\"2 2 2\"/>\n"
                      "<MechanicalObject name=\"dofs\"/>\n"
                      "<UniformMass totalMass=\"1\"/>\n"
                      "<SurfaceCollisionModel/>\n"
                      "</Node></Node>\n";
    pl_sim *sim = ct_load(xml, NULL, 0);
    pl_error err;
    ck_assert_int_eq(pl_sim_set(sim, "floor.contactDistance", "0.05", &err), PL_OK);
    ck_assert_int_ne(pl_sim_set(sim, "floor.contactForces", "1 2 3", &err), PL_OK); /* an output */
    int n;
    double *q = ct_positions(sim, "body/dofs", &n);
    ct_system sys;
    ct_system_make(&sys, n, 0.01, NULL);
    pl_rows rows;
    pl_rows_init(&rows);
    ck_assert_int_eq(ct_build_rows(sim, "floor", &sys.sys, q, n, &rows, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "exceeds alarmDistance"));
    ck_assert_int_eq(err.line, 4);
    ck_assert_int_eq(pl_sim_set(sim, "floor.contactDistance", "0.001", &err), PL_OK);
    ck_assert_int_eq(ct_build_rows(sim, "floor", &sys.sys, q, n, &rows, &err), PL_OK);
    ck_assert_int_eq(rows.n, 3 * 4); /* the bottom face: 4 vertices 1 cm up */
    pl_rows_free(&rows);
    ct_system_free(&sys);
    pl_sim_free(sim);
}
END_TEST

/* A scene file of scenes/ with its loop and contact solver replaced by a
 * NewtonSolver (which numbers the bodies and ignores constraints). */
static pl_sim *load_contact_scene(const char *file, const char *const *ov, int nov)
{
    char *text = ct_read_source(file);
    char *a = ct_replace_lines(text, "ncp_contact", "");
    char *b = ct_replace_lines(a, "<NonSmoothNewtonContactSolver", "");
    char *c = ct_replace_lines(b, "<LocalGlobalSolver", "<NewtonSolver name=\"solver\"/>");
    char *d = ct_replace_lines(c, "<VTKExporter", "");
    pl_sim *sim = ct_load(d, ov, nov);
    free(text), free(a), free(b), free(c), free(d);
    return sim;
}

/* Contacts of `obstacle` at the start: count, and the largest |H q - d|. */
static int start_contacts(pl_sim *sim, const char *obstacle, const char *state, double *max_delta,
                          double n_expect[3], double mu)
{
    int n;
    double *q = ct_positions(sim, state, &n);
    ct_system sys;
    ct_system_make(&sys, n, pl_node_dt(pl_sim_model(sim)->root), NULL);
    pl_rows rows;
    pl_rows_init(&rows);
    pl_error err;
    ck_assert_int_eq(ct_build_rows(sim, obstacle, &sys.sys, q, n, &rows, &err), PL_OK);
    *max_delta = 0.0;
    int k = 0;
    for (int r = 0; r < rows.n; ++r) {
        if (rows.kind[r] != PL_ROW_NORMAL) continue;
        k++;
        *max_delta = fmax(*max_delta, fabs(pl_rows_dot(&rows, r, q) - rows.d[r]));
        const double *c = &rows.coef[3 * rows.start[r]];
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(c[i], n_expect[i], 1e-12);
        ck_assert_double_eq(rows.mu[r], mu);
    }
    pl_rows_free(&rows);
    ct_system_free(&sys);
    return k;
}

START_TEST(test_stick_slip_scene_starts_at_rest_on_slope)
{
    double t = 10 * M_PI / 180, n[3] = {-sin(t), cos(t), 0}, dmax;
    pl_sim *sim = load_contact_scene("scenes/stick_slip.xml", NULL, 0);
    /* the 6 x 6 bottom vertices touch, exactly at contactDistance */
    ck_assert_int_eq(start_contacts(sim, "slope", "box/dofs", &dmax, n, 0.18), 36);
    ck_assert_double_le(dmax, 1e-9);
    pl_sim_free(sim);
    const char *ov[1] = {"slope.mu=0.1743"};
    sim = load_contact_scene("scenes/stick_slip.xml", ov, 1);
    ck_assert_int_eq(start_contacts(sim, "slope", "box/dofs", &dmax, n, 0.1743), 36);
    pl_sim_free(sim);
}
END_TEST

START_TEST(test_other_contact_scenes_start_as_described)
{
    double dmax, up[3] = {0, 1, 0};
    pl_sim *sim = load_contact_scene("scenes/resting_box.xml", NULL, 0);
    ck_assert_int_eq(start_contacts(sim, "floor", "box/dofs", &dmax, up, 0.5), 25);
    ck_assert_double_le(dmax, 1e-12);
    pl_sim_free(sim);
    double t = 20 * M_PI / 180, n20[3] = {-sin(t), cos(t), 0};
    sim = load_contact_scene("scenes/sliding_box.xml", NULL, 0);
    ck_assert_int_eq(start_contacts(sim, "slope", "box/dofs", &dmax, n20, 0.1), 25);
    ck_assert_double_le(dmax, 1e-9);
    pl_sim_free(sim);
    sim = load_contact_scene("scenes/ball_on_plane.xml", NULL, 0);
    ck_assert_int_eq(start_contacts(sim, "floor", "ball/dofs", &dmax, up, 0.3), 0);
    pl_sim_free(sim);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_scenes");
    TCase *tc = tcase_create("scenes");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_broken_obstacles_name_the_line);
    tcase_add_test(tc, test_broken_models_name_the_line);
    tcase_add_test(tc, test_runtime_edit_checked_at_step);
    tcase_add_test(tc, test_stick_slip_scene_starts_at_rest_on_slope);
    tcase_add_test(tc, test_other_contact_scenes_start_as_described);
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
