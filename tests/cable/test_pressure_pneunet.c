/* test_pressure_pneunet.c - scenes/pneunet_small.xml, the small variant of
 * the PneuNet-style bending actuator scenes/pneunet.xml (888 tetrahedra, 50
 * steps: seconds): under its chambers' pressure the bar bends towards its
 * thick bottom (-y; the sign of the actuator), the cavity grows, and when the
 * pressure is released the bar comes back to rest. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cable_test_util.h"

/* y displacement of the tip (mean over the vertices at x = 0.05). */
static double tip_dy(pl_sim *s)
{
    int n, n0;
    const double *x = ct_positions(s, "finger/dofs", 0, &n);
    const double *x0 = ct_positions(s, "finger/dofs", 1, &n0);
    double sum = 0;
    int count = 0;
    for (int i = 0; i < n; ++i)
        if (fabs(x0[3 * i] - 0.05) < 1e-9) sum += x[3 * i + 1] - x0[3 * i + 1], ++count;
    ck_assert_int_gt(count, 0);
    return sum / count;
}

START_TEST(pneunet_bends_down_and_comes_back)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/pneunet_small.xml", PL_SOURCE_DIR);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = PL_BINARY_DIR "/tests/pneunet_out";
    pl_sim *s = pl_sim_load_file(path, &opt, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(s);
    double V0 = ct_get(s, "finger/cavity.initialCavityVolume");
    /* three chambers of 10 x 5 x 10 mm */
    ck_assert_double_eq_tol(V0, 3 * 0.01 * 0.005 * 0.01, 1e-12);
    ct_step(s, 20); /* 40 kPa from t = 0.1 s */
    double bent = tip_dy(s), p = ct_get(s, "finger/cavity.pressure");
    double growth = ct_get(s, "finger/cavity.volumeGrowth");
    printf("pneunet at t = 0.2 s: tip dy %.4g mm, pressure %.6g Pa, volume growth %.3g%%\n",
           1e3 * bent, p, 100 * growth / V0);
    ck_assert_double_eq_tol(p, 4e4, 1e-6);
    ck_assert_double_gt(growth, 0.05 * V0);
    ck_assert_msg(bent < -1e-3, "the tip should bend down (towards the thick side) by mm: %g m",
                  bent);
    ct_step(s, 30); /* released at 0.3 s, rest until 0.5 s */
    double back = tip_dy(s);
    printf("pneunet at t = 0.5 s: tip dy %.4g mm, pressure %.3g Pa\n", 1e3 * back,
           ct_get(s, "finger/cavity.pressure"));
    ck_assert_msg(fabs(back) < 0.05 * fabs(bent), "the tip should come back: %g m (bent %g m)",
                  back, bent);
    pl_sim_free(s);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("pressure_pneunet");
    TCase *tc = tcase_create("pneunet");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, pneunet_bends_down_and_comes_back);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
