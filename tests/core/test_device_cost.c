/* test_device_cost.c - device=auto's cost model (core/src/device_cost.c,
 * compiled into this test: its predictions are pure functions of the sizes,
 * and whether a GPU answers is an input, so it runs without one). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../../core/src/device_cost.h"

/* scenes/hanging_bar_small.xml as sim_device.c gathers it: a 3 x 11 x 3
 * grid (99 vertices, 240 Neo-Hookean tetrahedra), 10 iterations, no
 * constraints, a SparseInverseSolver. */
static pl_device_sizes tiny_neohookean(void)
{
    pl_device_sizes z;
    memset(&z, 0, sizeof z);
    z.vertices = 99;
    z.tets[PL_COST_NH] = 240;
    z.s_tet = pow(99, 4.0 / 3.0);
    z.iterations = z.iterations_max = 10;
    z.device_path = 1;
    z.sparse_inverse = 1;
    return z;
}

/* scenes/twisting_bar_20k.xml ("cost: ..." statistics of `pliant run
 * scenes/twisting_bar_20k.xml -n 1 --timings`): 20808 vertices, 109056 ARAP
 * tetrahedra, 5 iterations. */
static pl_device_sizes twisting_bar_20k(void)
{
    pl_device_sizes z;
    memset(&z, 0, sizeof z);
    z.vertices = 20808;
    z.tets[PL_COST_ARAP] = 109056;
    z.s_tet = pow(20808, 4.0 / 3.0);
    z.iterations = z.iterations_max = 5;
    z.device_path = 1;
    z.sparse_inverse = 1;
    return z;
}

START_TEST(a_tiny_neohookean_scene_stays_on_the_cpu)
{
    pl_device_sizes z = tiny_neohookean();
    pl_device_estimate e;
    char why[512];
    ck_assert_int_eq(pl_device_cost_choose(&z, 16, 1, &e, why, sizeof why), 0);
    ck_assert(e.cpu_ms > 0 && e.gpu_ms > e.cpu_ms);
    /* the log line says what was chosen, the two predictions and the sizes */
    ck_assert_msg(strstr(why, "CPU chosen: predicted") && strstr(why, "on 16 threads") &&
                      strstr(why, "240 tetrahedra Neo-Hookean") && strstr(why, "10 iterations"),
                  "%s", why);
    char num[32];
    snprintf(num, sizeof num, "%.3g ms/step", e.cpu_ms);
    ck_assert_msg(strstr(why, num), "%s lacks %s", why, num);
}
END_TEST

START_TEST(the_twisting_bar_20k_goes_to_the_gpu)
{
    pl_device_sizes z = twisting_bar_20k();
    pl_device_estimate e;
    char why[512];
    ck_assert_int_eq(pl_device_cost_choose(&z, 16, 1, &e, why, sizeof why), 1);
    ck_assert(e.gpu_ms < e.cpu_ms);
    ck_assert_msg(strstr(why, "GPU chosen: predicted") && strstr(why, "ARAP"), "%s", why);
}
END_TEST

START_TEST(without_a_gpu_the_cpu_always)
{
    pl_device_sizes z = twisting_bar_20k();
    pl_device_estimate e;
    char why[512];
    ck_assert_int_eq(pl_device_cost_choose(&z, 16, 0, &e, why, sizeof why), 0);
    ck_assert_msg(strstr(why, "CPU chosen (no GPU answers)"), "%s", why);
    z = tiny_neohookean();
    ck_assert_int_eq(pl_device_cost_choose(&z, 1, 0, &e, why, sizeof why), 0);
}
END_TEST

START_TEST(the_cpu_prediction_follows_threads_and_sizes)
{
    pl_device_sizes z = twisting_bar_20k();
    pl_device_estimate e16 = pl_device_cost_predict(&z, 16), e2 = pl_device_cost_predict(&z, 2);
    /* fewer threads: a slower CPU, the same GPU */
    ck_assert(e2.cpu_ms > e16.cpu_ms);
    ck_assert(fabs(e2.gpu_ms - e16.gpu_ms) <= 1e-12 * e16.gpu_ms);
    /* twice the iterations: at least as slow on both, and deterministic */
    pl_device_sizes z2 = z;
    z2.iterations *= 2;
    pl_device_estimate d = pl_device_cost_predict(&z2, 16);
    ck_assert(d.cpu_ms > e16.cpu_ms && d.gpu_ms > e16.gpu_ms);
    pl_device_estimate again = pl_device_cost_predict(&z, 16);
    ck_assert(again.cpu_ms == e16.cpu_ms && again.gpu_ms == e16.gpu_ms);
    /* nnz(S) grows faster than the vertex count */
    pl_device_sizes t = tiny_neohookean();
    pl_device_estimate et = pl_device_cost_predict(&t, 16);
    ck_assert(e16.nnz_s / z.vertices > et.nnz_s / t.vertices);
}
END_TEST

START_TEST(without_a_device_path_only_the_solves_move)
{
    /* forceTolerance: the iterations stay on the CPU, the iteration count is
     * an assumption (at most the field), and the GPU step is a fixed
     * fraction of the CPU's */
    pl_device_sizes z = twisting_bar_20k();
    ck_assert_int_eq(pl_device_cost_iterations(1000, 1) <= 1000, 1);
    ck_assert_int_eq(pl_device_cost_iterations(3, 1), 3);
    ck_assert_int_eq(pl_device_cost_iterations(1000, 0), 1000);
    z.device_path = 0;
    z.force_tolerance = 1;
    pl_device_estimate e = pl_device_cost_predict(&z, 16);
    ck_assert(e.gpu_ms <= e.cpu_ms);
    char why[512];
    pl_device_cost_choose(&z, 16, 1, &e, why, sizeof why);
    ck_assert_msg(strstr(why, "only the global solves"), "%s", why);
    /* a global solver without a device path: nothing to gain, the CPU */
    z = twisting_bar_20k();
    z.sparse_inverse = 0;
    ck_assert_int_eq(pl_device_cost_choose(&z, 16, 1, &e, why, sizeof why), 0);
    ck_assert(e.gpu_ms == e.cpu_ms);
    ck_assert_msg(strstr(why, "the global solver has no device path"), "%s", why);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("device_cost");
    TCase *tc = tcase_create("model");
    tcase_add_test(tc, a_tiny_neohookean_scene_stays_on_the_cpu);
    tcase_add_test(tc, the_twisting_bar_20k_goes_to_the_gpu);
    tcase_add_test(tc, without_a_gpu_the_cpu_always);
    tcase_add_test(tc, the_cpu_prediction_follows_threads_and_sizes);
    tcase_add_test(tc, without_a_device_path_only_the_solves_move);
    suite_add_tcase(s, tc);
    SRunner *r = srunner_create(s);
    srunner_run_all(r, CK_NORMAL);
    int failed = srunner_ntests_failed(r);
    srunner_free(r);
    return failed ? 1 : 0;
}
