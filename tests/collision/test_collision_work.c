/* test_collision_work.c - the CollisionPipeline's broad phase does the work
 * its contacts need and no more (issue 16 item 5, the frame-time spikes):
 *  - a grid body spinning fast about the vertical (rim speed 4.5 m/s) 4 cm
 *    above a MeshObstacle quad, alarmDistance 1 cm: no pair can come within
 *    alarm in the step (the motion is horizontal), so the broad phase gives
 *    no candidate pair ("detection candidates max" = 0) and there is no row.
 *    The boxes used to be inflated by the models' velocity spreads times h
 *    (4.5 cm here), which gave candidates in every such step: a cookie's
 *    arms springing back after a plate's hole made 17x the candidates and
 *    15x the detection time (gingerbread_small.xml);
 *  - the same body 5 mm above: its 9 bottom vertices have contacts, each
 *    from a candidate pair (the counter counts); no second pass (no third
 *    body strikes either model: "detection margin max [mm]" = 0);
 *  - PLIANT_DETECT (where the candidates are made, pipeline_device.c):
 *    host and auto agree with the default, anything else is bad input;
 *  - the threads change no row: a fine cloth (60 x 60 vertices) resting
 *    within alarm over a quad makes 3600 contacts, prepared by the threads
 *    (coll_pipeline_emit), and 4 threads give the 1 thread's rows entry by
 *    entry. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"
#include "rows_compare.h"
#ifdef _OPENMP
#include <omp.h>
#endif

static const double H = 0.01;

/* the grid body (0.2 x 0.1 x 0.1 m, 27 vertices) with its bottom at y0 */
static pl_sim *load(double y0)
{
    char xml[2048];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
             "<RequiredPlugin name=\"collision\"/>\n"
             "<NewtonSolver/>\n"
             "<CollisionPipeline name=\"pipeline\" alarmDistance=\"0.01\" "
             "contactDistance=\"0.001\"/>\n"
             "<Node name=\"floor\"><MeshObstacle name=\"quad\" "
             "position=\"-1 0 -1  1 0 -1  1 0 1  -1 0 1\" triangles=\"0 2 1  0 3 2\"/></Node>\n"
             "<Node name=\"body\">\n"
             "<RegularGridTetrahedra name=\"grid\" min=\"0 %.17g 0\" max=\"0.2 %.17g 0.1\" "
             "n=\"3 3 3\"/>\n"
             "<MechanicalObject name=\"dofs\"/>\n"
             "<DiagonalMass massDensity=\"1000\"/>\n"
             "<SurfaceCollisionModel name=\"surface\"/>\n"
             "</Node></Node>\n",
             y0, y0 + 0.1);
    return ct_load(xml, NULL, 0);
}

/* Spins the body about the vertical through its centre at w rad/s. */
static void spin(pl_sim *sim, double w)
{
    pl_component *st = pl_sim_component(sim, "body/dofs");
    ck_assert_ptr_nonnull(st);
    const pl_state_ops *ops = pl_component_role(st, PL_ROLE_STATE);
    pl_buffer xb = ops->positions(st, pl_sim_data(sim)), vb = ops->velocities(st, pl_sim_data(sim));
    const double *x = pl_buffer_f64(&xb);
    double *v = pl_buffer_f64(&vb);
    for (size_t i = 0; i < xb.rows; ++i) {
        double rx = x[3 * i] - 0.1, rz = x[3 * i + 2] - 0.05;
        v[3 * i] = w * rz;
        v[3 * i + 1] = 0.0;
        v[3 * i + 2] = -w * rx;
    }
}

/* One build_rows of the pipeline on the spinning body: its status, *nrows
 * the rows' count. */
static int build_rows(pl_sim *sim, int *nrows, pl_error *err)
{
    int n;
    double *q = ct_positions(sim, "body/dofs", &n);
    ct_system sys;
    ct_system_make(&sys, n, H, NULL);
    pl_rows rows;
    pl_rows_init(&rows);
    int st = ct_build_rows(sim, "pipeline", &sys.sys, q, n, &rows, err);
    *nrows = rows.n;
    pl_rows_free(&rows);
    ct_system_free(&sys);
    return st;
}

/* The same, which must succeed; returns the rows' count, *cand and *margin
 * the step's statistics. */
static int step_rows(pl_sim *sim, double *cand, double *margin)
{
    int nrows;
    pl_error err;
    pl_timers_clear(pl_sim_timers(sim));
    ck_assert_int_eq(build_rows(sim, &nrows, &err), PL_OK);
    ck_assert_int_eq(pl_stat_get(pl_sim_timers(sim), "detection candidates max", cand), 0);
    ck_assert_int_eq(pl_stat_get(pl_sim_timers(sim), "detection margin max [mm]", margin), 0);
    return nrows;
}

START_TEST(test_spinning_body_far_has_no_candidates)
{
    pl_sim *sim = load(0.04);
    spin(sim, 40.0); /* rim 0.112 m from the axis: 4.5 m/s */
    double cand = -1.0, margin = -1.0;
    ck_assert_int_eq(step_rows(sim, &cand, &margin), 0);
    ck_assert_double_eq(cand, 0.0);
    ck_assert_double_eq(margin, 0.0);
    pl_sim_free(sim);
}
END_TEST

START_TEST(test_spinning_body_near_counts_its_candidates)
{
    pl_sim *sim = load(0.005);
    spin(sim, 40.0);
    double cand = -1.0, margin = -1.0;
    int nrows = step_rows(sim, &cand, &margin);
    /* each bottom vertex 5 mm over the quad: a normal and two friction rows */
    ck_assert_int_eq(nrows, 27);
    ck_assert_double_ge(cand, 9.0);
    ck_assert_double_eq(margin, 0.0);
    pl_sim_free(sim);
}
END_TEST

/* PLIANT_DETECT=host and auto (no device loop here: the host) give the
 * unset variable's rows and counts; the box overlaps are recorded (the
 * input of auto's rule) and equal the candidates statistic. */
START_TEST(test_detect_policy_host_and_auto_agree)
{
    const char *policy[] = {NULL, "host", "auto"};
    int nrows[3];
    double cand[3];
    for (int k = 0; k < 3; ++k) {
        if (policy[k])
            setenv("PLIANT_DETECT", policy[k], 1);
        else
            unsetenv("PLIANT_DETECT");
        pl_sim *sim = load(0.005);
        spin(sim, 40.0);
        double margin;
        nrows[k] = step_rows(sim, &cand[k], &margin);
        const double *v;
        ck_assert_int_eq(pl_series_get(pl_sim_timers(sim), "detection box overlaps", &v), 1);
        ck_assert_double_eq(v[0], cand[k]);
        double gpu;
        ck_assert_int_ne(pl_stat_get(pl_sim_timers(sim), "detection steps on the GPU", &gpu), 0);
        pl_sim_free(sim);
    }
    unsetenv("PLIANT_DETECT");
    ck_assert_int_eq(nrows[0], 27);
    ck_assert_int_eq(nrows[1], nrows[0]);
    ck_assert_int_eq(nrows[2], nrows[0]);
    ck_assert_double_eq(cand[1], cand[0]);
    ck_assert_double_eq(cand[2], cand[0]);
}
END_TEST

/* Any other value is bad input, named in the error (as PLIANT_DEVICE's). */
START_TEST(test_detect_policy_unknown_is_bad_input)
{
    setenv("PLIANT_DETECT", "gpu", 1);
    pl_sim *sim = load(0.005);
    int nrows;
    pl_error err;
    ck_assert_int_eq(build_rows(sim, &nrows, &err), PL_EINPUT);
    ck_assert_msg(strstr(err.msg, "PLIANT_DETECT='gpu'") != NULL, "message: %s", err.msg);
    pl_sim_free(sim);
    unsetenv("PLIANT_DETECT");
}
END_TEST

/* The rows of the fine cloth over the quad with `threads` threads. */
static void cloth_rows(int threads, pl_rows *rows)
{
    const char *xml =
        "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
        "<RequiredPlugin name=\"collision\"/>\n"
        "<NewtonSolver/>\n"
        "<CollisionPipeline name=\"pipeline\" alarmDistance=\"0.01\" contactDistance=\"0.001\"/>\n"
        "<Node name=\"floor\"><MeshObstacle name=\"quad\" "
        "position=\"-1 0 -1  1 0 -1  1 0 1  -1 0 1\" triangles=\"0 2 1  0 3 2\"/></Node>\n"
        "<Node name=\"cloth\">\n"
        "<RegularGridTriangles name=\"grid\" min=\"-0.5 0.004 -0.5\" max=\"0.5 0.004 0.5\" "
        "n=\"60 1 60\"/>\n"
        "<MechanicalObject name=\"dofs\" src=\"@grid\"/>\n"
        "<DiagonalMass massDensity=\"1000\" thickness=\"0.001\"/>\n"
        "<SurfaceCollisionModel name=\"surface\"/>\n"
        "</Node></Node>\n";
#ifdef _OPENMP
    int saved = omp_get_max_threads();
    omp_set_num_threads(threads);
#else
    (void)threads;
#endif
    pl_sim *sim = ct_load(xml, NULL, 0);
    int n;
    double *q = ct_positions(sim, "cloth/dofs", &n);
    ct_system sys;
    ct_system_make(&sys, n, H, NULL);
    pl_error err;
    ck_assert_int_eq(ct_build_rows(sim, "pipeline", &sys.sys, q, n, rows, &err), PL_OK);
    ct_system_free(&sys);
    pl_sim_free(sim);
#ifdef _OPENMP
    omp_set_num_threads(saved);
#endif
}

START_TEST(test_threads_emit_the_serial_rows)
{
    pl_rows r1, r4;
    pl_rows_init(&r1);
    pl_rows_init(&r4);
    cloth_rows(1, &r1);
    cloth_rows(4, &r4);
    ck_assert_int_eq(r1.n, 3 * 60 * 60); /* every vertex: a normal and two friction rows */
    same_rows(&r4, &r1, 0);
    pl_rows_free(&r1);
    pl_rows_free(&r4);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_work");
    TCase *tc = tcase_create("broad phase");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_spinning_body_far_has_no_candidates);
    tcase_add_test(tc, test_spinning_body_near_counts_its_candidates);
    tcase_add_test(tc, test_detect_policy_host_and_auto_agree);
    tcase_add_test(tc, test_detect_policy_unknown_is_bad_input);
    tcase_add_test(tc, test_threads_emit_the_serial_rows);
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
