/* lg_device_scene.c - the scene of the device-path tests and its helpers
 * (lg_device_scene.h). */
#include "lg_device_scene.h"

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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


pl_registry *registry(void)
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

setup plain(const char *device)
{
    setup s = {device, "0", "0", "<HostDevice name=\"dev\"/>", "", "1", "1", "", ""};
    return s;
}

/* Loads the scene; NULL with the first message in msg when it fails. */
pl_sim *load(pl_registry *r, const setup *s, char *msg, size_t size)
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


void run(pl_registry *r, const setup *s, int steps, result *out, pl_sim **keep)
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

void assert_same(const result *a, const result *b)
{
    ck_assert_uint_eq(a->m, b->m);
    ck_assert_msg(!memcmp(a->x, b->x, a->m * sizeof(double)), "positions differ");
    ck_assert_msg(!memcmp(a->v, b->v, a->m * sizeof(double)), "velocities differ");
    ck_assert_int_eq(a->nenergy, b->nenergy);
    ck_assert_msg(!memcmp(a->energy, b->energy, (size_t)a->nenergy * sizeof(double)),
                  "energies differ");
}

/* The bar moved: not a trivial agreement of two states at rest. */
void assert_moved(const result *a, const result *rest)
{
    double d = 0;
    for (size_t i = 0; i < a->m; ++i) d = fmax(d, fabs(a->x[i] - rest->x[i]));
    ck_assert_msg(d > 1e-3, "the bar did not move (%g m)", d);
}

/* A series of the run's timings, copied (n values at most). */
int series(pl_sim *sim, const char *name, double *out, int n)
{
    const double *v = NULL;
    int got = pl_series_get(pl_sim_timers(sim), name, &v);
    if (got > n) got = n;
    if (v) memcpy(out, v, (size_t)got * sizeof(double));
    return got;
}

/* Loads s with the springs' 15th project making a NaN (6 iterations a
 * step: step 3, iteration 3), takes two steps (they pass) and a third,
 * which must fail: its message in msg; the sim for the caller to look at
 * and free. */
pl_sim *run_into_nan(pl_registry *r, setup s, char *msg, size_t size)
{
    s.springs_ok = "1\" nanCall=\"15";
    pl_sim *sim = load(r, &s, msg, size);
    ck_assert_msg(sim != NULL, "load failed: %s", msg);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(sim, 2, &err), PL_OK);
    ck_assert_int_ne(pl_sim_step(sim, 1, &err), PL_OK);
    snprintf(msg, size, "%s", err.msg);
    return sim;
}
