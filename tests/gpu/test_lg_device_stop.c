/* test_lg_device_stop.c - the LocalGlobalSolver's stopping rules on its
 * device path, without a GPU (lg_device_fakes.h's device service in host
 * memory): with a tolerance and computeEnergy, and with per-phase
 * profiling, the device path stops at the CPU's iterations with bitwise
 * the CPU's states and energies; forceTolerance stops at the CPU's
 * iteration with the CPU's residual; the device loop (pl_device_ops.loop)
 * stops at the CPU's iterations, with or without tolerances, and reports
 * a NaN at the CPU's iteration. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lg_device_scene.h"

/* The device run stopped where the CPU's did: the same iteration count at
 * each of the n steps, and the force residuals of the first nr steps to
 * round-off (the device sums the gradient from zero and adds the inertia
 * term after it, the CPU adds the gradient onto it). */
static void assert_same_stops(const char *what, const double *it_dev, const double *it_cpu, int n,
                              const double *res_dev, const double *res_cpu, int nr)
{
    ck_assert_msg(!memcmp(it_dev, it_cpu, (size_t)n * sizeof(double)),
                  "%s: iteration counts differ", what);
    for (int k = 0; k < nr; ++k)
        ck_assert_msg(fabs(res_dev[k] - res_cpu[k]) <= 1e-12 * res_cpu[k],
                      "%s, step %d: residual %.17g on the device, %.17g on the CPU", what, k,
                      res_dev[k], res_cpu[k]);
}

START_TEST(tolerance_energy_and_profiling_agree)
{
    pl_registry *r = registry();
    static result cpu, dev;
    setup s = plain("cpu");
    s.tolerance = "2e-3";
    s.energy = "1";
    run(r, &s, 6, &cpu, NULL);
    /* stopped early at least once, so the tolerance was tested */
    ck_assert_int_gt(cpu.nenergy, 0);
    ck_assert_int_lt(cpu.nenergy, 6 * 6);
    s.device = "cuda";
    s.before = "<HostDevice name=\"dev\" profile=\"1\"/>";
    pl_sim *sim;
    run(r, &s, 6, &dev, &sim);
    assert_same(&dev, &cpu);
    /* profiling: the phase timers have one sample per step */
    pl_timers *t = pl_sim_timers(sim);
    ck_assert_int_eq(pl_timers_samples(t, pl_timer_id(t, "Local")), 6);
    ck_assert_int_eq(pl_timers_samples(t, pl_timer_id(t, "Global")), 6);
    /* the host's part of a device step: queueing, then waiting, inside the frame */
    int queue = pl_timer_id(t, "Device queue"), wait = pl_timer_id(t, "Device wait");
    ck_assert_int_eq(pl_timers_samples(t, queue), 6);
    ck_assert_int_eq(pl_timers_samples(t, wait), 6);
    ck_assert_double_le(pl_timers_total_ms(t, queue) + pl_timers_total_ms(t, wait),
                        pl_timers_total_ms(t, pl_timer_id(t, "Frame")));
    pl_sim_free(sim);
    pl_registry_free(r);
}
END_TEST

/* forceTolerance on the device (local_global_device_residual.c): the
 * residual is computed by the device service after every iteration, with
 * the CPU's expression, so the same iterations stop at the same count and
 * the states, residuals and counts are bitwise the CPU's. */
START_TEST(force_tolerance_on_the_device_stops_where_the_cpu_stops)
{
    pl_registry *r = registry();
    static result cpu, dev;
    static double it_cpu[64], it_dev[64], res_cpu[64], res_dev[64];
    setup s = plain("cpu");
    s.scheme = "forceTolerance=\"3\"";
    pl_sim *sim;
    run(r, &s, 8, &cpu, &sim);
    int n = series(sim, "iterations", it_cpu, 64);
    int nr = series(sim, "force residual", res_cpu, 64);
    pl_sim_free(sim);
    ck_assert_int_eq(n, 8);
    ck_assert_int_eq(nr, 8);
    /* the tolerance did decide: some step stopped early, some did not */
    double lo = 99, hi = 0;
    for (int k = 0; k < n; ++k) lo = fmin(lo, it_cpu[k]), hi = fmax(hi, it_cpu[k]);
    ck_assert_msg(lo < 6 && hi > 1, "iterations %g .. %g: the tolerance decided nothing", lo, hi);
    s.device = "cuda";
    run(r, &s, 8, &dev, &sim);
    ck_assert_int_eq(series(sim, "iterations", it_dev, 64), n);
    ck_assert_int_eq(series(sim, "force residual", res_dev, 64), nr);
    assert_same_stops("forceTolerance", it_dev, it_cpu, n, res_dev, res_cpu, nr);
    assert_same(&dev, &cpu);
    ck_assert_int_gt(fake_device_calls(pl_sim_component(sim, "dev")), 0);
    pl_sim_free(sim);
    /* a service of device ops version 3 (the zero and the scale in two
     * calls): the same run */
    s.before = "<HostDeviceV3 name=\"dev\"/>";
    run(r, &s, 8, &dev, NULL);
    assert_same(&dev, &cpu);
    s.before = plain("cpu").before;
    ck_assert_int_eq(fake_device_leaks, 0);
    /* a term whose gradient cannot take device buffers: refused by name
     * (cuda), the CPU (auto); Rayleigh damping's L q: refused */
    s.springs_ok = "1\" deviceGradient=\"0";
    char msg[1024];
    ck_assert_ptr_null(load(r, &s, msg, sizeof msg));
    ck_assert_msg(strstr(msg, "root/bar/springs (TestSprings) has no gradient on device"),
                  "not named: %s", msg);
    s.device = "auto";
    run(r, &s, 2, &dev, &sim);
    ck_assert_int_eq(fake_device_calls(pl_sim_component(sim, "dev")), 0);
    pl_sim_free(sim);
    s = plain("cuda");
    s.scheme = "forceTolerance=\"0.05\" rayleighStiffness=\"0.01\"";
    ck_assert_ptr_null(load(r, &s, msg, sizeof msg));
    ck_assert_msg(strstr(msg, "rayleighStiffness"), "not named: %s", msg);
    pl_registry_free(r);
}
END_TEST

/* The iterations of a run with the device loop (HostDevice loops="1", the
 * default: pl_device_ops.loop applies the shared stopping rule,
 * device_loop.h) and without it (one iteration at a time, the rule on the
 * host): both are the CPU's, bitwise, with the same iteration counts, for a
 * fixed count (the loop only with PLIANT_DEVICE_LOOP=device: nothing to
 * decide), a tolerance that stops early, forceTolerance and both; the
 * loop's rule counted every iteration (one read-back a step). */
START_TEST(device_loop_stops_where_the_cpu_stops)
{
    pl_registry *r = registry();
    static result cpu, dev;
    static double it_cpu[64], it_dev[64], res_cpu[64], res_dev[64];
    const char *tol[] = {"0", "2e-3", "0", "2e-3"};
    const char *scheme[] = {"", "", "forceTolerance=\"3\"", "forceTolerance=\"3\""};
    for (int k = 0; k < 4; ++k) {
        setup s = plain("cpu");
        s.tolerance = tol[k];
        s.scheme = scheme[k];
        pl_sim *sim;
        run(r, &s, 8, &cpu, &sim);
        int n = series(sim, "iterations", it_cpu, 64);
        int nr = series(sim, "force residual", res_cpu, 64);
        pl_sim_free(sim);
        double lo = 99, total = 0;
        for (int j = 0; j < n; ++j) lo = fmin(lo, it_cpu[j]), total += it_cpu[j];
        if (k > 0) ck_assert_msg(n == 8 && lo < 6, "case %d: no early stop (%d, %g)", k, n, lo);
        for (int loops = 0; loops < (k ? 2 : 3); ++loops) {
            s.device = "cuda";
            s.before = loops ? "<HostDevice name=\"dev\"/>" : "<HostDevice name=\"dev\" loops=\"0\"/>";
            if (loops == 2) setenv("PLIANT_DEVICE_LOOP", "device", 1);
            run(r, &s, 8, &dev, &sim);
            ck_assert_int_eq(series(sim, "iterations", it_dev, 64), n);
            /* without forceTolerance the device reports no residual (computeResidual
             * auto is off there): compare where both have them */
            int nd = series(sim, "force residual", res_dev, 64);
            if (k >= 2) ck_assert_int_eq(nd, nr);
            if (nd < nr) nr = nd;
            char what[32];
            snprintf(what, sizeof what, "case %d, loops %d", k, loops);
            assert_same_stops(what, it_dev, it_cpu, n, res_dev, res_cpu, nr);
            assert_same(&dev, &cpu);
            long rules = fake_device_rules(pl_sim_component(sim, "dev"));
            ck_assert_int_eq(rules, k ? (loops ? (long)total : 0) : (loops == 2 ? 8 * 6 : 0));
            double looped = 0; /* the stat says which way the steps took */
            pl_stat_get(pl_sim_timers(sim), "device loop steps", &looped);
            ck_assert_int_eq((int)looped, rules ? 8 : 0);
            unsetenv("PLIANT_DEVICE_LOOP");
            pl_sim_free(sim);
        }
    }
    ck_assert_int_eq(fake_device_leaks, 0);
    pl_registry_free(r);
}
END_TEST

/* A NaN in the third iteration of the third step: the device loop (forced
 * for this fixed count) stops there (its rule's nonfinite flag) and fails
 * the step with the CPU's iteration and step. */
START_TEST(device_loop_reports_a_nan_at_the_cpus_iteration)
{
    pl_registry *r = registry();
    const char *dev_before[2] = {"<HostDevice name=\"dev\"/>", ""};
    const char *devices[2] = {"cuda", "cpu"};
    for (int k = 0; k < 2; ++k) {
        setup s = plain(devices[k]);
        s.before = dev_before[k];
        setenv("PLIANT_DEVICE_LOOP", "device", 1);
        char msg[1024];
        pl_sim *sim = run_into_nan(r, s, msg, sizeof msg);
        ck_assert_msg(strstr(msg, "NaN/inf at iteration 3 of step 3"), "%s: %s", devices[k], msg);
        if (k == 0) ck_assert_int_eq(fake_device_rules(pl_sim_component(sim, "dev")), 2 * 6 + 3);
        unsetenv("PLIANT_DEVICE_LOOP");
        pl_sim_free(sim);
    }
    ck_assert_int_eq(fake_device_leaks, 0);
    pl_registry_free(r);
}
END_TEST

int main(void)
{
    Suite *su = suite_create("lg_device_stop");
    TCase *tc = tcase_create("stopping rules");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, tolerance_energy_and_profiling_agree);
    tcase_add_test(tc, force_tolerance_on_the_device_stops_where_the_cpu_stops);
    tcase_add_test(tc, device_loop_stops_where_the_cpu_stops);
    tcase_add_test(tc, device_loop_reports_a_nan_at_the_cpus_iteration);
    suite_add_tcase(su, tc);
    SRunner *sr = srunner_create(su);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
