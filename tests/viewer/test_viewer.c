/* test_viewer.c - the viewer drawn off screen (EGL: Mesa's software
 * renderer without a GPU) and driven through its input events, the same
 * path a window's keys and mouse take:
 *  - a falling ball is drawn where the simulation puts it: the pixel of its
 *    centroid, projected with the viewer's camera, shows the body before and
 *    after it fell, and its former place shows the background;
 *  - the scene's InteractiveCamera sets the viewer's camera;
 *  - keys reach a KeyboardController: '+' three times sets cable.value to
 *    3 step, clamped at max, and the cable then shortens the finger;
 *  - Shift + left drag pulls a vertex: the finger's tip follows the cursor
 *    (it ends far higher than without the drag);
 *  - scripts: a malformed line is an error naming file and line. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "offscreen.h"
#include "script.h"
#include "test_tmp.h"
#include "viewer_test_util.h"

enum { W = 320, H = 240 };

static vw_offscreen *off;
static vw_renderer *ren;

static void setup(void)
{
    pl_error err;
    off = vw_offscreen_create(W, H, &err);
    ck_assert_msg(off != NULL, "%s", err.msg);
    ren = vw_renderer_create(&err);
    ck_assert_msg(ren != NULL, "%s", err.msg);
    vw_offscreen_bind(off);
}

static void teardown(void)
{
    vw_renderer_free(ren);
    vw_offscreen_free(off);
}

static void read_off(void *user, unsigned char *rgb)
{
    vw_offscreen_read(user, rgb);
}

START_TEST(test_ball_pixels)
{
    vw_app a;
    pl_sim *s = vt_load(VT_FALLING_BALL, 0, &a);
    pl_error err;
    ck_assert_int_eq(vw_app_init(&a, s, W, H, &err), PL_OK);
    a.draw.field = VW_FIELD_NONE;
    a.overlay = 0;
    double before[2], after[2];
    vt_check_centroid(&a, ren, read_off, off, before);
    ck_assert_int_eq(vw_app_step(&a, 30, &err), PL_OK); /* falls ~0.44 m, 4 radii */
    vt_check_centroid(&a, ren, read_off, off, after);
    ck_assert_double_gt(after[1] - before[1], 30.0); /* lower on the screen */
    unsigned char *rgb = malloc((size_t)W * H * 3);
    vw_offscreen_read(off, rgb);
    ck_assert(!vt_not_background(rgb, W, H, (int)before[0], (int)before[1]));
    free(rgb);
    vw_app_free(&a);
    pl_sim_free(s);
}
END_TEST

START_TEST(test_scene_camera)
{
    vw_app a;
    pl_sim *s = vt_load(VT_FALLING_BALL, 0, &a);
    pl_error err;
    ck_assert_int_eq(vw_app_init(&a, s, W, H, &err), PL_OK);
    double eye[3];
    vw_camera_eye(&a.camera, eye);
    ck_assert_double_eq_tol(eye[0], 0.0, 1e-12);
    ck_assert_double_eq_tol(eye[1], -0.2, 1e-12);
    ck_assert_double_eq_tol(eye[2], 2.0, 1e-12);
    ck_assert_double_eq_tol(a.camera.fov, 36.0, 1e-12);
    vw_app_free(&a);
    pl_sim_free(s);
}
END_TEST

static double get_number(pl_sim *s, const char *path)
{
    char buf[256];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, path, buf, sizeof buf, &err), PL_OK);
    return strtod(buf, NULL);
}

static void key(vw_app *a, int k)
{
    vw_input in = {VW_IN_KEY, k, 0, 0, 0, 0.0, 0.0};
    pl_error err;
    ck_assert_int_eq(vw_app_input(a, &in, &err), PL_OK);
}

static pl_sim *finger(vw_app *a)
{
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/cable_finger_small.xml", PL_SOURCE_DIR);
    pl_sim *s = vt_load(path, 1, a);
    pl_error err;
    ck_assert_int_eq(vw_app_init(a, s, W, H, &err), PL_OK);
    ck_assert_msg(a->pick_path[0], "the viewer added no PickSpring");
    return s;
}

START_TEST(test_keys)
{
    vw_app a;
    pl_sim *s = finger(&a);
    pl_error err;
    double step = get_number(s, "finger/keys.step"), max = get_number(s, "finger/keys.max");
    for (int k = 0; k < 3; ++k) key(&a, '+');
    ck_assert_double_eq_tol(get_number(s, "finger/cable.value"), 3 * step, 1e-15);
    key(&a, '-');
    ck_assert_double_eq_tol(get_number(s, "finger/cable.value"), 2 * step, 1e-15);
    for (int k = 0; k < 100; ++k) key(&a, '+');
    ck_assert_double_eq_tol(get_number(s, "finger/cable.value"), max, 1e-15);
    /* the keyframes no longer drive it: the cable holds max and shortens */
    ck_assert_int_eq(vw_app_step(&a, 40, &err), PL_OK);
    ck_assert_double_eq_tol(get_number(s, "finger/cable.value"), max, 1e-15);
    ck_assert_double_gt(get_number(s, "finger/cable.displacement"), 0.5 * max);
    /* reset gives the keyframes back */
    ck_assert_int_eq(vw_app_reset(&a, &err), PL_OK);
    ck_assert_int_eq(vw_app_step(&a, 1, &err), PL_OK);
    ck_assert_double_lt(get_number(s, "finger/cable.value"), step);
    vw_app_free(&a);
    pl_sim_free(s);
}
END_TEST

/* The finger's tip (its vertex of smallest x) after `steps` steps, dragged
 * `up` pixels upwards from where it is drawn (0: no drag). */
static double tip_height(double up, int steps, double *target)
{
    vw_app a;
    pl_sim *s = finger(&a);
    pl_error err;
    const vw_body *b = &a.scene.bodies[0];
    int tip = 0;
    for (int i = 1; i < b->n; ++i)
        if (b->x[3 * i] < b->x[3 * tip]) tip = i;
    double px, py, depth;
    ck_assert(vw_camera_project(&a.camera, W, H, &b->x[3 * tip], &px, &py, &depth));
    if (up > 0.0) {
        vw_input in[] = {{VW_IN_MOVE, 0, 0, 0, 0, px, py},
                         {VW_IN_BUTTON, 0, VW_MOD_SHIFT, 0, 1, px, py},
                         {VW_IN_MOVE, 0, VW_MOD_SHIFT, 0, 0, px, py - up}};
        for (int k = 0; k < 3; ++k) ck_assert_int_eq(vw_app_input(&a, &in[k], &err), PL_OK);
        ck_assert_int_eq(a.picking, 1);
        double p[3];
        vw_camera_unproject_at(&a.camera, W, H, px, py - up, a.pick_plane, p);
        *target = p[1];
    }
    ck_assert_int_eq(vw_app_step(&a, steps, &err), PL_OK);
    ck_assert_int_eq(vw_scene_update(&a.scene, a.draw.field, &err), PL_OK);
    double y = a.scene.bodies[0].x[3 * tip + 1];
    vw_app_free(&a);
    pl_sim_free(s);
    return y;
}

START_TEST(test_drag)
{
    double target, free_y = tip_height(0.0, 30, NULL), dragged_y = tip_height(40.0, 30, &target);
    /* the tip follows the cursor: more than half way from where it hangs
     * without the drag to the height of the point under the cursor */
    ck_assert_msg(dragged_y - free_y > 0.5 * (target - free_y),
                  "dragged tip at %g m, undragged %g m, cursor at %g m", dragged_y, free_y,
                  target);
}
END_TEST

START_TEST(test_script_errors)
{
    char path[1024];
    int fd = test_tmp_file(path, sizeof path, "viewer_script");
    ck_assert_int_ge(fd, 0);
    FILE *f = fdopen(fd, "w");
    ck_assert_ptr_nonnull(f);
    fputs("# a script\nstep 2\nkey +\njump 3\n", f);
    fclose(f);
    vw_script sc;
    pl_error err;
    ck_assert_int_eq(vw_script_load(&sc, path, &err), PL_EINPUT);
    ck_assert_int_eq(err.line, 4);
    ck_assert_ptr_nonnull(strstr(err.msg, "jump 3"));
    vw_script_free(&sc);
    remove(path);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("viewer");
    TCase *tc = tcase_create("offscreen");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_ball_pixels);
    tcase_add_test(tc, test_scene_camera);
    tcase_add_test(tc, test_keys);
    tcase_add_test(tc, test_drag);
    tcase_add_test(tc, test_script_errors);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
