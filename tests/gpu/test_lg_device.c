/* test_lg_device.c - the LocalGlobalSolver's device path (device="cuda" /
 * "auto") without a GPU, through a device service in host memory
 * (lg_device_fakes.h): the same scene stepped on the CPU path and on the
 * device path gives bitwise the same positions, velocities and energies
 * (the device path runs the same operations in the same order: M sn, the
 * local step, the restriction to the unknowns minus A_fp q_p row by row,
 * the solve, the scatter), also with a tolerance and with per-phase
 * profiling, and with a ConstantForceField (its device path goes through
 * the device service alone); two pl_data of one model, each with its own
 * device vectors (in its workspace), stepped interleaved with different
 * damping and spin of the prescribed end (input fields) end bitwise where
 * each ends alone; forceTolerance stops at the CPU's iteration with the
 * CPU's residual; the device loop (pl_device_ops.loop) stops at the CPU's
 * iterations, with or without tolerances, and reports a NaN at the CPU's
 * iteration; and every
 * part that cannot run on the device is refused at load with its name, or
 * (auto) sends the loop back to the CPU. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lg_device_fakes.h"
#include "test_tmp.h"

/* A bar of springs, its left end fixed, its right end turning, under
 * gravity: prescribed vertices that move make A_fp q_p matter. */
static const char *SCENE =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">"
    "%s"
    "<LocalGlobalSolver name=\"solver\" iterations=\"6\" device=\"%s\" tolerance=\"%s\" "
    "computeEnergy=\"%s\" %s/>"
    "<TestDenseSolver name=\"global\" deviceOk=\"%s\"/>"
    "%s"
    "<Node name=\"bar\">"
    "<RegularGridTetrahedra name=\"grid\" min=\"0 0 0\" max=\"1 0.2 0.2\" n=\"6 3 3\"/>"
    "<MechanicalObject name=\"dofs\" src=\"@grid\"/>"
    "<UniformMass totalMass=\"2\"/>"
    "<TestSprings name=\"springs\" stiffness=\"800\" deviceOk=\"%s\"/>"
    "<FixedConstraint name=\"left\" box=\"-0.01 -1 -1 0.01 1 1\"/>"
    "<PrescribedMotion name=\"right\" box=\"0.99 -1 -1 1.01 1 1\" axis=\"1 0 0\" "
    "angularVelocity=\"3\"/>"
    "%s"
    "</Node></Node>";

typedef struct setup {
    const char *device;        /* cpu, cuda, auto */
    const char *tolerance;
    const char *energy;
    const char *before;        /* text before the solver (a HostDevice) */
    const char *after;         /* after the global solver */
    const char *solver_ok, *springs_ok;
    const char *extra;         /* more components in the bar */
    const char *scheme;        /* more solver attributes (firstOrder, ...) */
} setup;

static pl_registry *registry(void)
{
    pl_registry *r = pl_registry_create();
    pl_error err;
    ck_assert_ptr_nonnull(r);
    ck_assert_int_eq(pl_register_builtin_components(r, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(r, &fake_host_device_type, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(r, &fake_host_device_v3_type, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(r, &fake_springs_type, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(r, &fake_dense_solver_type, &err), PL_OK);
    return r;
}

static setup plain(const char *device)
{
    setup s = {device, "0", "0", "<HostDevice name=\"dev\"/>", "", "1", "1", "", ""};
    return s;
}

/* Loads the scene; NULL with the first message in msg when it fails. */
static pl_sim *load(pl_registry *r, const setup *s, char *msg, size_t size)
{
    char xml[4096];
    snprintf(xml, sizeof xml, SCENE, s->before, s->device, s->tolerance, s->energy, s->scheme,
             s->solver_ok, s->after, s->springs_ok, s->extra);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.registry = r;
    opt.out_dir = test_tmp_dir();
    /* no implicit CudaDevice: on a machine with a GPU the loader would add
     * one to the scenes without a HostDevice, and the fake springs and
     * solver, which read device memory as host memory, would run on it */
    opt.device = "cpu";
    pl_sim *sim = pl_sim_load_string(xml, "lg_device.xml", &opt, &diag);
    if (msg) snprintf(msg, size, "%s", diag.count ? diag.items[0].msg : "");
    pl_diag_free(&diag);
    return sim;
}

typedef struct result {
    double x[3 * 200], v[3 * 200];
    size_t m;
    int nenergy;
    double energy[64];
} result;

static void run(pl_registry *r, const setup *s, int steps, result *out, pl_sim **keep)
{
    char msg[1024];
    pl_sim *sim = load(r, s, msg, sizeof msg);
    ck_assert_msg(sim != NULL, "load failed: %s", msg);
    pl_error err;
    ck_assert_msg(pl_sim_step(sim, steps, &err) == PL_OK, "step failed: %s", err.msg);
    pl_component *c = pl_sim_component(sim, "bar/dofs");
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    pl_buffer x = ops->positions(c, pl_sim_data(sim)), v = ops->velocities(c, pl_sim_data(sim));
    out->m = x.rows * 3;
    ck_assert_uint_le(out->m, 600);
    memcpy(out->x, x.data, out->m * sizeof(double));
    memcpy(out->v, v.data, out->m * sizeof(double));
    const double *e = NULL;
    out->nenergy = pl_series_get(pl_sim_timers(sim), "energy", &e);
    if (out->nenergy > 64) out->nenergy = 64;
    if (e) memcpy(out->energy, e, (size_t)out->nenergy * sizeof(double));
    if (keep)
        *keep = sim;
    else
        pl_sim_free(sim);
}

static void assert_same(const result *a, const result *b)
{
    ck_assert_uint_eq(a->m, b->m);
    ck_assert_msg(!memcmp(a->x, b->x, a->m * sizeof(double)), "positions differ");
    ck_assert_msg(!memcmp(a->v, b->v, a->m * sizeof(double)), "velocities differ");
    ck_assert_int_eq(a->nenergy, b->nenergy);
    ck_assert_msg(!memcmp(a->energy, b->energy, (size_t)a->nenergy * sizeof(double)),
                  "energies differ");
}

/* The bar moved: not a trivial agreement of two states at rest. */
static void assert_moved(const result *a, const result *rest)
{
    double d = 0;
    for (size_t i = 0; i < a->m; ++i) d = fmax(d, fabs(a->x[i] - rest->x[i]));
    ck_assert_msg(d > 1e-3, "the bar did not move (%g m)", d);
}

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

/* A series of the run's timings, copied (n values at most). */
static int series(pl_sim *sim, const char *name, double *out, int n)
{
    const double *v = NULL;
    int got = pl_series_get(pl_sim_timers(sim), name, &v);
    if (got > n) got = n;
    if (v) memcpy(out, v, (size_t)got * sizeof(double));
    return got;
}

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
    ck_assert_msg(!memcmp(it_dev, it_cpu, (size_t)n * sizeof(double)), "iteration counts differ");
    /* the residuals to round-off: the device sums the gradient from zero and
     * adds the inertia term after it, the CPU adds the gradient onto it */
    for (int k = 0; k < nr; ++k)
        ck_assert_msg(fabs(res_dev[k] - res_cpu[k]) <= 1e-12 * res_cpu[k],
                      "step %d: residual %.17g on the device, %.17g on the CPU", k, res_dev[k],
                      res_cpu[k]);
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
            ck_assert_msg(!memcmp(it_dev, it_cpu, (size_t)n * sizeof(double)),
                          "case %d, loops %d: iteration counts differ", k, loops);
            for (int j = 0; j < nr; ++j)
                ck_assert_msg(fabs(res_dev[j] - res_cpu[j]) <= 1e-12 * res_cpu[j],
                              "case %d step %d: residual %.17g, CPU %.17g", k, j, res_dev[j],
                              res_cpu[j]);
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
        s.springs_ok = "1\" nanCall=\"15"; /* 6 iterations a step: step 3, iteration 3 */
        setenv("PLIANT_DEVICE_LOOP", "device", 1);
        char msg[1024];
        pl_sim *sim = load(r, &s, msg, sizeof msg);
        ck_assert_msg(sim != NULL, "load failed: %s", msg);
        pl_error err;
        ck_assert_int_eq(pl_sim_step(sim, 2, &err), PL_OK);
        ck_assert_int_ne(pl_sim_step(sim, 1, &err), PL_OK);
        ck_assert_msg(strstr(err.msg, "NaN/inf at iteration 3 of step 3"), "%s: %s", devices[k],
                      err.msg);
        if (k == 0) ck_assert_int_eq(fake_device_rules(pl_sim_component(sim, "dev")), 2 * 6 + 3);
        unsetenv("PLIANT_DEVICE_LOOP");
        pl_sim_free(sim);
    }
    ck_assert_int_eq(fake_device_leaks, 0);
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
        setup n = s;
        n.springs_ok = "1\" nanCall=\"15"; /* step 3, iteration 3 */
        char msg[1024];
        pl_sim *sim = load(r, &n, msg, sizeof msg);
        ck_assert_msg(sim != NULL, "load failed: %s", msg);
        pl_error err;
        ck_assert_int_eq(pl_sim_step(sim, 2, &err), PL_OK);
        ck_assert_int_ne(pl_sim_step(sim, 1, &err), PL_OK);
        snprintf(msgs[k], sizeof msgs[k], "%s", err.msg);
        ck_assert_msg(strstr(err.msg, "became NaN/inf during step 3 (vertex "), "%s", err.msg);
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
    tcase_add_test(tc, tolerance_energy_and_profiling_agree);
    tcase_add_test(tc, auto_runs_on_the_device_when_it_can_and_on_the_cpu_otherwise);
    tcase_add_test(tc, constant_force_field_on_the_device_equals_the_cpu_bitwise);
    tcase_add_test(tc, two_data_on_the_device_interleave_exactly);
    tcase_add_test(tc, cuda_refuses_what_cannot_run_on_the_device_by_name);
    tcase_add_test(tc, stick_start_no_longer_keeps_the_loop_on_the_cpu);
    tcase_add_test(tc, force_tolerance_on_the_device_stops_where_the_cpu_stops);
    tcase_add_test(tc, device_loop_stops_where_the_cpu_stops);
    tcase_add_test(tc, device_loop_reports_a_nan_at_the_cpus_iteration);
    tcase_add_test(tc, step_start_and_end_on_the_device_equal_the_hosts);
    suite_add_tcase(su, tc);
    SRunner *sr = srunner_create(su);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
