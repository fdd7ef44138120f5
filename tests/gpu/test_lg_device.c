/* test_lg_device.c - the LocalGlobalSolver's device path (device="cuda" /
 * "auto") without a GPU, through a device service in host memory
 * (lg_device_fakes.h): the same scene stepped on the CPU path and on the
 * device path gives bitwise the same positions and velocities (the device
 * path runs the same operations in the same order: M sn, the local step,
 * the restriction to the unknowns minus A_fp q_p row by row, the solve,
 * the scatter), also with SOFA's schemes and with a ConstantForceField (its
 * device path goes through the device service alone); two pl_data of one
 * model, each with its own device vectors (in its workspace), stepped
 * interleaved with different damping and spin of the prescribed end (input
 * fields) end bitwise where each ends alone; a step's start and end on the
 * device equal the host's; and every part that cannot run on the device is
 * refused at load with its name, or (auto) sends the loop back to the CPU.
 * The stopping rules on the device: test_lg_device_stop.c. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lg_device_scene.h"

START_TEST(device_path_equals_cpu_path_bitwise)
{
    pl_registry *r = registry();
    static result cpu, dev, start;
    setup s = plain("cpu");
    run(r, &s, 0, &start, NULL);
    run(r, &s, 8, &cpu, NULL);
    s.device = "cuda";
    pl_sim *sim;
    run(r, &s, 8, &dev, &sim);
    assert_moved(&cpu, &start);
    assert_same(&dev, &cpu);
    /* the loop did run on the device service: 3 kernels per iteration (M sn,
     * gather_sub_csr, scatter), 6 iterations, 8 steps; and 3 a step for its
     * start and end (step_begin, the prescribed vertices' scatter, step_end) */
    ck_assert_int_eq(fake_device_calls(pl_sim_component(sim, "dev")), 8 * (6 * 3 + 3));
    pl_sim_free(sim);
    ck_assert_int_eq(fake_device_leaks, 0);
    pl_registry_free(r);
}
END_TEST

/* SOFA's schemes (firstOrder, rayleighStiffness) live in the inertia masses
 * and the inertial target, which the host prepares: the device path
 * follows them bitwise too (and they change the motion). */
START_TEST(first_order_and_rayleigh_stiffness_on_the_device_equal_the_cpu)
{
    pl_registry *r = registry();
    static result plain_cpu, cpu, dev;
    const char *schemes[] = {"firstOrder=\"1\"", "rayleighStiffness=\"0.05\"",
                             "firstOrder=\"1\" rayleighStiffness=\"0.05\""};
    setup s = plain("cpu");
    s.energy = "1";
    run(r, &s, 8, &plain_cpu, NULL);
    for (int k = 0; k < 3; ++k) {
        s.scheme = schemes[k];
        s.device = "cpu";
        run(r, &s, 8, &cpu, NULL);
        s.device = "cuda";
        run(r, &s, 8, &dev, NULL);
        assert_same(&dev, &cpu);
        double d = 0;
        for (size_t i = 0; i < cpu.m; ++i) d = fmax(d, fabs(cpu.x[i] - plain_cpu.x[i]));
        ck_assert_msg(d > 1e-4, "%s changed nothing (%g m)", schemes[k], d);
    }
    ck_assert_int_eq(fake_device_leaks, 0);
    pl_registry_free(r);
}
END_TEST

START_TEST(auto_runs_on_the_device_when_it_can_and_on_the_cpu_otherwise)
{
    pl_registry *r = registry();
    static result cpu, dev;
    setup s = plain("cpu");
    s.springs_ok = "0"; /* a term without a device local step */
    run(r, &s, 4, &cpu, NULL);
    s.device = "auto";
    pl_sim *sim;
    run(r, &s, 4, &dev, &sim);
    assert_same(&dev, &cpu);
    ck_assert_int_eq(fake_device_calls(pl_sim_component(sim, "dev")), 0);
    pl_sim_free(sim);
    s = plain("auto");
    run(r, &s, 2, &dev, &sim);
    ck_assert_int_gt(fake_device_calls(pl_sim_component(sim, "dev")), 0);
    pl_sim_free(sim);
    s.before = "";
    run(r, &s, 2, &dev, NULL); /* no device at all: the CPU */
    pl_registry_free(r);
}
END_TEST

/* ConstantForceField on device buffers: rhs -= R (h^2 f) through the
 * service's sub_csr adds h^2 f with the CPU's rounding: bitwise equal. */
START_TEST(constant_force_field_on_the_device_equals_the_cpu_bitwise)
{
    pl_registry *r = registry();
    static result cpu, dev, plain_cpu;
    setup s = plain("cpu");
    run(r, &s, 6, &plain_cpu, NULL);
    s.extra = "<ConstantForceField name=\"push\" indices=\"8 20 33\" forces=\"0 0 30  0 -20 0  "
              "10 0 0\"/>";
    run(r, &s, 6, &cpu, NULL);
    s.device = "cuda";
    pl_sim *sim;
    run(r, &s, 6, &dev, &sim);
    assert_same(&dev, &cpu);
    /* the force did act: the loaded run differs from the plain one */
    double d = 0;
    for (size_t i = 0; i < cpu.m; ++i) d = fmax(d, fabs(cpu.x[i] - plain_cpu.x[i]));
    ck_assert_msg(d > 1e-4, "the force moved nothing (%g m)", d);
    /* 4 kernels per iteration: M sn, the force's sub_csr, gather_sub_csr,
     * scatter; 3 a step for its start and end */
    ck_assert_int_eq(fake_device_calls(pl_sim_component(sim, "dev")), 6 * (6 * 4 + 3));
    pl_sim_free(sim);
    ck_assert_int_eq(fake_device_leaks, 0);
    pl_registry_free(r);
}
END_TEST

/* The bar's positions and velocities in d. */
static void take(pl_sim *sim, pl_data *d, result *out)
{
    pl_component *c = pl_sim_component(sim, "bar/dofs");
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    pl_buffer x = ops->positions(c, d), v = ops->velocities(c, d);
    out->m = x.rows * 3;
    memcpy(out->x, x.data, out->m * sizeof(double));
    memcpy(out->v, v.data, out->m * sizeof(double));
    out->nenergy = 0;
}

START_TEST(two_data_on_the_device_interleave_exactly)
{
    pl_registry *r = registry();
    static result alone[2], both[2];
    static const char *const DAMPING[2] = {"0", "30"}, *const SPIN[2] = {"3", "-2"};
    setup s = plain("cuda");
    s.extra = "<ConstantForceField name=\"push\" indices=\"8 20\" forces=\"0 0 30  0 -20 0\"/>";
    char msg[1024];
    pl_error err;
    for (int k = 0; k < 2; ++k) {
        pl_sim *sim = load(r, &s, msg, sizeof msg);
        ck_assert_msg(sim != NULL, "load failed: %s", msg);
        ck_assert_int_eq(pl_sim_set(sim, "solver.damping", DAMPING[k], &err), PL_OK);
        ck_assert_int_eq(pl_sim_set(sim, "right.angularVelocity", SPIN[k], &err), PL_OK);
        ck_assert_int_eq(pl_sim_step(sim, 6, &err), PL_OK);
        take(sim, pl_sim_data(sim), &alone[k]);
        pl_sim_free(sim);
    }
    pl_sim *sim = load(r, &s, msg, sizeof msg);
    ck_assert_ptr_nonnull(sim);
    pl_data *d[2] = {pl_sim_data(sim), pl_data_clone(pl_sim_data(sim))};
    for (int k = 0; k < 2; ++k) {
        ck_assert_int_eq(pl_sim_set_data(sim, d[k], "solver.damping", DAMPING[k], &err), PL_OK);
        ck_assert_int_eq(pl_sim_set_data(sim, d[k], "right.angularVelocity", SPIN[k], &err), PL_OK);
    }
    for (int step = 0; step < 6; ++step)
        for (int k = 0; k < 2; ++k) ck_assert_int_eq(pl_sim_step_data(sim, d[k], 1, &err), PL_OK);
    for (int k = 0; k < 2; ++k) {
        take(sim, d[k], &both[k]);
        assert_same(&both[k], &alone[k]);
    }
    /* the inputs made a difference: the check is not vacuous */
    double diff = 0;
    for (size_t i = 0; i < alone[0].m; ++i) diff = fmax(diff, fabs(alone[0].x[i] - alone[1].x[i]));
    ck_assert_msg(diff > 1e-3, "the inputs changed nothing (%g m)", diff);
    /* each data made its own device vectors: both ran on the device */
    ck_assert_int_eq(fake_device_calls(pl_sim_component(sim, "dev")), 2 * 6 * (6 * 4 + 3));
    pl_data_free(d[1]); /* its device vectors go back to the device */
    pl_sim_free(sim);
    ck_assert_int_eq(fake_device_leaks, 0);
    pl_registry_free(r);
}
END_TEST

static void assert_refused(pl_registry *r, const setup *s, const char *a, const char *b)
{
    char msg[1024];
    pl_sim *sim = load(r, s, msg, sizeof msg);
    ck_assert_ptr_null(sim);
    ck_assert_msg(strstr(msg, a) != NULL, "'%s' not in: %s", a, msg);
    if (b) ck_assert_msg(strstr(msg, b) != NULL, "'%s' not in: %s", b, msg);
}

START_TEST(cuda_refuses_what_cannot_run_on_the_device_by_name)
{
    pl_registry *r = registry();
    setup s = plain("cuda");
    s.before = "";
    assert_refused(r, &s, "CudaDevice", "no device service");
    s.after = "<HostDevice name=\"dev\"/>";
    assert_refused(r, &s, "dev must come before the solver", NULL);
    s = plain("cuda");
    s.springs_ok = "0";
    assert_refused(r, &s, "root/bar/springs (TestSprings)", "local terms without a device");
    s = plain("cuda");
    s.solver_ok = "0";
    assert_refused(r, &s, "the global solver root/global (TestDenseSolver)", NULL);
    pl_registry_free(r);
}
END_TEST

/* NonSmoothNewtonContactSolver's stickStart runs in the device path too
 * (the step's first iterate, contact_solver_step.c): it no longer keeps the
 * loop on the CPU. */
START_TEST(stick_start_no_longer_keeps_the_loop_on_the_cpu)
{
    pl_registry *r = registry();
    char msg[1024];
    setup s = plain("cuda");
    s.before = "<RequiredPlugin name=\"ncp_contact\"/><HostDevice name=\"dev\"/>";
    s.after = "<NonSmoothNewtonContactSolver name=\"contact\" stickStart=\"1\"/>";
    pl_sim *sim = load(r, &s, msg, sizeof msg);
    ck_assert_msg(strstr(msg, "stickStart") == NULL, "refused for stickStart=1: %s", msg);
    if (sim) { /* a CUDA build (else the contact solver has no device path at all) */
        pl_sim_free(sim);
        s.device = "auto";
        static result dev;
        run(r, &s, 2, &dev, &sim);
        ck_assert_int_gt(fake_device_calls(pl_sim_component(sim, "dev")), 0);
    }
    pl_sim_free(sim);
    pl_registry_free(r);
}
END_TEST

/* A step's start and end on the device (device ops version 6,
 * local_global_device_state.c) against the host's (PLIANT_DEVICE_STATE=0):
 * the same values bitwise, 3 calls a step more on the device, and a NaN
 * found at the end of a step reported with the same vertex, leaving the
 * state as the step before left it. */
START_TEST(step_start_and_end_on_the_device_equal_the_hosts)
{
    pl_registry *r = registry();
    static result on, off, two;
    long calls[2];
    setup s = plain("cuda");
    for (int k = 0; k < 2; ++k) {
        if (k) setenv("PLIANT_DEVICE_STATE", "0", 1);
        pl_sim *sim;
        run(r, &s, 8, k ? &off : &on, &sim);
        calls[k] = fake_device_calls(pl_sim_component(sim, "dev"));
        pl_sim_free(sim);
    }
    unsetenv("PLIANT_DEVICE_STATE");
    assert_same(&on, &off);
    ck_assert_int_eq(calls[0] - calls[1], 8 * 3);
    /* a NaN in the last steps' positions (fixed iteration count: the loop
     * does not look at them; the step's end does) */
    char msgs[2][sizeof(((pl_error *)0)->msg)];
    run(r, &s, 2, &two, NULL);
    for (int k = 0; k < 2; ++k) {
        if (k) setenv("PLIANT_DEVICE_STATE", "0", 1);
        pl_sim *sim = run_into_nan(r, s, msgs[k], sizeof msgs[k]);
        ck_assert_msg(strstr(msgs[k], "became NaN/inf during step 3 (vertex "), "%s", msgs[k]);
        pl_component *c = pl_sim_component(sim, "bar/dofs");
        const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
        pl_buffer x = ops->positions(c, pl_sim_data(sim));
        ck_assert_msg(!memcmp(x.data, two.x, two.m * sizeof(double)),
                      "a failed step changed the state");
        pl_sim_free(sim);
    }
    unsetenv("PLIANT_DEVICE_STATE");
    ck_assert_str_eq(msgs[0], msgs[1]);
    ck_assert_int_eq(fake_device_leaks, 0);
    pl_registry_free(r);
}
END_TEST

int main(void)
{
    Suite *su = suite_create("lg_device");
    TCase *tc = tcase_create("device path");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, device_path_equals_cpu_path_bitwise);
    tcase_add_test(tc, first_order_and_rayleigh_stiffness_on_the_device_equal_the_cpu);
    tcase_add_test(tc, auto_runs_on_the_device_when_it_can_and_on_the_cpu_otherwise);
    tcase_add_test(tc, constant_force_field_on_the_device_equals_the_cpu_bitwise);
    tcase_add_test(tc, two_data_on_the_device_interleave_exactly);
    tcase_add_test(tc, cuda_refuses_what_cannot_run_on_the_device_by_name);
    tcase_add_test(tc, stick_start_no_longer_keeps_the_loop_on_the_cpu);
    tcase_add_test(tc, step_start_and_end_on_the_device_equal_the_hosts);
    suite_add_tcase(su, tc);
    SRunner *sr = srunner_create(su);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
