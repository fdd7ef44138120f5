/* test_viewer_window.c - pliant view's window (GLFW) on a virtual screen
 * (ctest runs it under xvfb-run): the window opens, the falling ball is
 * stepped and the window's picture shows the body at its centroid,
 * projected with the viewer's camera, before and after it fell. */
#include <check.h>
#include <stdlib.h>

#include "viewer_test_util.h"
#include "window.h"

typedef struct win_read {
    int w, h;
} win_read;

static void read_window(void *user, unsigned char *rgb)
{
    win_read *r = user;
    vw_read_pixels(r->w, r->h, rgb);
}

START_TEST(test_window_pixels)
{
    pl_error err;
    vw_window *win = vw_window_open(320, 240, "pliant view test", &err);
    ck_assert_msg(win != NULL, "%s", err.msg);
    vw_renderer *r = vw_renderer_create(&err);
    ck_assert_msg(r != NULL, "%s", err.msg);
    vw_app a;
    pl_sim *s = vt_load(VT_FALLING_BALL, 0, &a);
    int w, h;
    vw_window_size(win, &w, &h);
    ck_assert_int_eq(vw_app_init(&a, s, w, h, &err), PL_OK);
    vw_window_attach(win, &a);
    ck_assert_int_eq(vw_window_poll(win, &err), PL_OK);
    a.draw.field = VW_FIELD_NONE;
    a.overlay = 0;
    win_read rd = {w, h};
    double before[2], after[2];
    vt_check_centroid(&a, r, read_window, &rd, before);
    vw_window_swap(win);
    ck_assert_int_eq(vw_app_step(&a, 30, &err), PL_OK);
    vt_check_centroid(&a, r, read_window, &rd, after);
    ck_assert_double_gt(after[1] - before[1], 30.0);
    vw_window_attach(win, NULL);
    vw_app_free(&a);
    pl_sim_free(s);
    vw_renderer_free(r);
    vw_window_close(win);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("viewer window");
    TCase *tc = tcase_create("window");
    tcase_set_timeout(tc, 100);
    tcase_add_test(tc, test_window_pixels);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
