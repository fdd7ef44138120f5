/* test_interaction.c - the components an interactive viewer uses, without
 * any window:
 *  - KeyboardController: key events (pl_sim_send_event) step the target by
 *    `step` within [min, max], other keys are not used, and it drives the
 *    target at every step from the first press on (over a Keyframes before it);
 *  - PickSpring: a stiff spring (k = 1e5 N/m) pulls a free particle-like
 *    cube's vertex to its target: after the steps it sits within 1 mm of it,
 *    while with vertex = -1 the cube only falls;
 *  - bad input: KeyboardController keys, step and limits, InteractiveCamera
 *    field of view, points and orientation, PickSpring's vertex, each an
 *    error naming file, line and component. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/pliant.h"
#include "test_tmp.h"

static const char *BAR =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
    "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
    "<RequiredPlugin name=\"ncp_contact\"/>\n"
    "<LocalGlobalSolver name=\"solver\" iterations=\"20\"/>\n"
    "<SparseInverseSolver/><NonSmoothNewtonContactSolver/>\n"
    "<Node name=\"cube\">\n"
    "<RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.1 0.1\" n=\"3 3 3\"/>\n"
    "<MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"0.1\"/>\n"
    "<NeoHookean name=\"material\" youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
    "%s\n"
    "</Node></Node>\n";

static pl_sim *load(const char *extra, pl_diag *diag)
{
    char xml[4096];
    snprintf(xml, sizeof xml, BAR, extra);
    pl_sim_options opt = {.out_dir = test_tmp_dir(), .device = "cpu"};
    return pl_sim_load_string(xml, "interaction.xml", &opt, diag);
}

static void expect_error(const char *extra, const char *msg, int line)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = load(extra, &diag);
    ck_assert_ptr_null(s);
    ck_assert_int_ge(diag.nerrors, 1);
    int found = 0;
    for (int k = 0; k < diag.count; ++k)
        if (strstr(diag.items[k].msg, msg) && diag.items[k].line == line) found = 1;
    if (!found) pl_diag_print(&diag, stderr);
    ck_assert_msg(found, "expected '%s' at line %d", msg, line);
    pl_diag_free(&diag);
}

static double number(pl_sim *s, const char *path)
{
    char buf[4096];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, path, buf, sizeof buf, &err), PL_OK);
    return strtod(buf, NULL);
}

static int press(pl_sim *s, int key)
{
    pl_event ev = {PL_EVENT_KEY_PRESSED, key};
    int used = -1;
    pl_error err;
    ck_assert_int_eq(pl_sim_send_event(s, &ev, &used, &err), PL_OK);
    return used;
}

START_TEST(test_keyboard)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = load("<PickSpring name=\"pick\"/>"
                     "<Keyframes target=\"@pick.stiffness\" times=\"0 1\" values=\"100 200\"/>"
                     "<KeyboardController name=\"keys\" target=\"@pick.stiffness\" keys=\"up down\" "
                     "step=\"25\" min=\"50\" max=\"160\"/>",
                     &diag);
    if (!s) pl_diag_print(&diag, stderr);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 10, &err), PL_OK);
    ck_assert_double_eq_tol(number(s, "pick.stiffness"), 109.0, 1e-9); /* keyframes at t = 0.09 */
    ck_assert_int_eq(press(s, 'x'), 0);
    ck_assert_int_eq(press(s, PL_KEY_UP), 1);
    ck_assert_double_eq_tol(number(s, "pick.stiffness"), 134.0, 1e-9); /* 109 + 25 */
    press(s, PL_KEY_UP);
    ck_assert_double_eq_tol(number(s, "pick.stiffness"), 159.0, 1e-9);
    press(s, PL_KEY_UP);
    ck_assert_double_eq_tol(number(s, "pick.stiffness"), 160.0, 1e-9); /* max */
    for (int k = 0; k < 5; ++k) press(s, PL_KEY_DOWN);
    ck_assert_double_eq_tol(number(s, "pick.stiffness"), 50.0, 1e-9); /* min */
    ck_assert_int_eq(pl_sim_step(s, 20, &err), PL_OK);
    ck_assert_double_eq_tol(number(s, "pick.stiffness"), 50.0, 1e-9); /* keys hold it */
    pl_sim_free(s);
    pl_diag_free(&diag);
}
END_TEST

/* Vertex 0's position after 30 steps pulled to (0.05, 0.3, 0.05). */
static void pulled(int vertex, double out[3])
{
    pl_diag diag;
    pl_diag_init(&diag);
    char extra[256];
    snprintf(extra, sizeof extra,
             "<PickSpring name=\"pick\" vertex=\"%d\" target=\"0.05 0.3 0.05\" stiffness=\"1e5\"/>",
             vertex);
    pl_sim *s = load(extra, &diag);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 30, &err), PL_OK);
    const pl_state_ops *so = pl_component_role(pl_sim_component(s, "cube/dofs"), PL_ROLE_STATE);
    pl_buffer x = so->positions(pl_sim_component(s, "cube/dofs"), pl_sim_data(s));
    memcpy(out, pl_buffer_f64(&x), 3 * sizeof *out);
    pl_sim_free(s);
    pl_diag_free(&diag);
}

START_TEST(test_pick_spring)
{
    double held[3], free_x[3];
    pulled(0, held);
    pulled(-1, free_x);
    double d = sqrt(pow(held[0] - 0.05, 2) + pow(held[1] - 0.3, 2) + pow(held[2] - 0.05, 2));
    ck_assert_msg(d < 1e-3, "the picked vertex is %g m from its target", d);
    ck_assert_double_lt(free_x[1], -0.04); /* unpicked, it fell (0.5 g t^2 = 0.044 m) */
}
END_TEST

/* The viewer's drag (pl_sim_set of the spring's vertex and target) changes
 * the data shown, not the model: no rebuild, and another data of the same
 * model, stepped alongside, is not pulled. */
START_TEST(test_pick_drag_is_data)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = load("<PickSpring name=\"pick\" stiffness=\"1e5\"/>", &diag);
    ck_assert_ptr_nonnull(s);
    pl_data *other = pl_data_clone(pl_sim_data(s));
    ck_assert_ptr_nonnull(other);
    unsigned long generation = pl_sim_model(s)->generation;
    pl_error err;
    ck_assert_int_eq(pl_sim_set(s, "pick.vertex", "0", &err), PL_OK);
    ck_assert_int_eq(pl_sim_set(s, "pick.target", "0.05 0.3 0.05", &err), PL_OK);
    ck_assert_uint_eq(pl_sim_model(s)->generation, generation);
    ck_assert_int_eq(pl_sim_step(s, 30, &err), PL_OK);
    ck_assert_int_eq(pl_sim_step_data(s, other, 30, &err), PL_OK);
    pl_component *dofs = pl_sim_component(s, "cube/dofs");
    const pl_state_ops *so = pl_component_role(dofs, PL_ROLE_STATE);
    pl_buffer xs = so->positions(dofs, pl_sim_data(s)), xo = so->positions(dofs, other);
    const double *a = pl_buffer_f64(&xs), *b = pl_buffer_f64(&xo);
    ck_assert_double_eq_tol(a[1], 0.3, 1e-3); /* held at the target's height */
    ck_assert_double_lt(b[1], -0.04);        /* the other data's vertex fell */
    pl_data_free(other);
    pl_sim_free(s);
    pl_diag_free(&diag);
}
END_TEST

START_TEST(test_bad_input)
{
    expect_error("<KeyboardController target=\"@dofs.position\" step=\"1\"/>",
                 "is not an input field", 10);
    expect_error("<PickSpring name=\"p\"/><KeyboardController target=\"@p.stiffness\" "
                 "keys=\"+\" step=\"1\"/>", "keys: expected two different keys", 10);
    expect_error("<PickSpring name=\"p\"/><KeyboardController target=\"@p.stiffness\" "
                 "keys=\"+ plus\" step=\"1\"/>", "keys: expected two keys", 10);
    expect_error("<PickSpring name=\"p\"/><KeyboardController target=\"@p.stiffness\" "
                 "step=\"0\"/>", "step must be > 0", 10);
    expect_error("<PickSpring name=\"p\"/><KeyboardController target=\"@p.stiffness\" "
                 "step=\"1\" min=\"3\" max=\"2\"/>", "min (3) exceeds max (2)", 10);
    expect_error("<PickSpring name=\"p\"/><KeyboardController target=\"@p.target\" "
                 "step=\"1\"/>", "is a vec3", 10);
    expect_error("<InteractiveCamera fieldOfView=\"200\"/>", "fieldOfView must be", 10);
    expect_error("<InteractiveCamera position=\"1 1 1\" lookAt=\"1 1 1\"/>", "the same point", 10);
    expect_error("<InteractiveCamera orientation=\"0 0 1\"/>", "quaternion", 10);
    /* a vertex beyond the scene is a step error */
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = load("<PickSpring name=\"p\" vertex=\"100000\"/>", &diag);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 1, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "vertex 100000"));
    ck_assert_ptr_nonnull(strstr(err.where, "cube/p"));
    pl_sim_free(s);
    pl_diag_free(&diag);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("interaction");
    TCase *tc = tcase_create("interaction");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_keyboard);
    tcase_add_test(tc, test_pick_spring);
    tcase_add_test(tc, test_pick_drag_is_data);
    tcase_add_test(tc, test_bad_input);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
