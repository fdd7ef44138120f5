/* test_ncp_component.c - NonSmoothNewtonContactSolver in scenes (a
 * LocalGlobalSolver over an ARAP box of 1 kg, rows from TestConstraint):
 *  - a box resting on y = 0 carries its weight (sum lambda_n = m g), no
 *    vertex penetrates, the friction forces stay in the cone, and the
 *    Fischer-Burmeister and minimum-map functions agree;
 *  - a new resting contact (delta = lambda = 0, the 0/0 case) gives finite,
 *    exact steps;
 *  - bilateral rows hold the weight exactly (with compliance, delta + E
 *    lambda = 0), bounded rows saturate at their bound (the box then falls
 *    with (W - sum hi) / m) or hold when the bound allows;
 *  - the warm-start records live in the state: save / restore replays a
 *    run bit for bit. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact.h"
#include "contact_test_component.h"
#include "test_tmp.h"

static const double G = 9.81;

/* A 0.1 m ARAP box (4 x 4 x 4 vertices, 1000 kg/m^3: 1 kg). */
static void scene(test_scene *t, const char *gravity, int iters, const char *lg_extra, const char *contact,
                  const char *translation, const char *constraints)
{
    static char xml[8192];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"%s\">\n"
             "  <RequiredPlugin name=\"hyperelastic\"/>\n"
             "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
             "  <RequiredPlugin name=\"ncp_contact\"/>\n"
             "  <LocalGlobalSolver name=\"solver\" iterations=\"%d\" %s/>\n"
             "  <SparseInverseSolver/>\n"
             "  <NonSmoothNewtonContactSolver name=\"contact\" %s/>\n"
             "  <Node name=\"box\">\n"
             "    <RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.1 0.1\" n=\"4 4 4\" translation=\"%s\"/>\n"
             "    <MechanicalObject name=\"dofs\"/>\n"
             "    <DiagonalMass name=\"mass\" massDensity=\"1000\"/>\n"
             "    <ARAP youngModulus=\"1e6\" poissonRatio=\"0.3\"/>\n"
             "    %s\n"
             "  </Node>\n"
             "</Node>\n",
             gravity, iters, lg_extra, contact, translation, constraints);
    ts_load(t, xml, NULL, 0);
}

static double *copy_positions(test_scene *t, int *n)
{
    const double *x = ts_positions(t, "box/dofs", n);
    double *c = malloc(sizeof(double) * 3 * (size_t)*n);
    memcpy(c, x, sizeof(double) * 3 * (size_t)*n);
    return c;
}

/* Runs the resting box; returns its final positions and sum lambda_n. */
static double *resting_box(const char *ncp, int steps, double *sum_n)
{
    test_scene t;
    char opts[128];
    snprintf(opts, sizeof opts, "ncp=\"%s\"", ncp);
    scene(&t, "0 -9.81 0", 10, "", opts, "0 0 0", "<TestConstraint name=\"plane\" mode=\"plane\" mu=\"0.5\"/>");
    double worst_pen = 0.0, worst_cone = -INFINITY, err20 = 0.0;
    for (int k = 1; k <= steps; ++k) {
        ts_step(&t, 1);
        test_probe *c = ts_constraint(&t, "box/plane");
        double W = c->total_mass * G;
        ck_assert_double_eq_tol(c->total_mass, 1.0, 1e-12);
        ck_assert_int_eq(c->ncontacts, 16);
        worst_pen = fmin(worst_pen, ts_min_y(&t, "box/dofs"));
        worst_cone = fmax(worst_cone, c->cone_excess);
        ck_assert_double_ge(c->min_normal, 0.0);
        if (k >= 20) err20 = fmax(err20, fabs(c->sum_normal - W) / W);
        *sum_n = c->sum_normal;
    }
    printf("resting box (%s): max |sum lambda_n - m g| / m g after step 20: %.2e, deepest vertex %.2e m, "
           "max (|lambda_f| - mu lambda_n (1 + 1e-6)) %.2e N\n",
           ncp, err20, worst_pen, worst_cone);
    ck_assert_double_le(err20, 0.01);
    ck_assert_double_ge(worst_pen, -1e-4);
    ck_assert_double_le(worst_cone, 0.0);
    int n;
    double *x = copy_positions(&t, &n);
    ck_assert_int_eq(n, 64);
    ts_free(&t);
    return x;
}

START_TEST(a_resting_box_carries_its_weight)
{
    double sfb, smm;
    double *xfb = resting_box("fischer-burmeister", 40, &sfb);
    double *xmm = resting_box("minimum-map", 40, &smm);
    double dx = 0.0;
    for (int i = 0; i < 3 * 64; ++i) dx = fmax(dx, fabs(xfb[i] - xmm[i]));
    printf("resting box: FB vs min-map: positions differ by %.2e m, sum lambda_n by %.2e N\n", dx, fabs(sfb - smm));
    ck_assert_double_le(dx, 1e-7);
    ck_assert_double_le(fabs(sfb - smm), 1e-6 * G);
    free(xfb);
    free(xmm);
}
END_TEST

START_TEST(a_new_resting_contact_gives_finite_steps)
{
    const char *opts[4] = {"ncp=\"fischer-burmeister\"", "ncp=\"minimum-map\"",
                           "ncp=\"fischer-burmeister\" preconditioner=\"mass\"",
                           "ncp=\"fischer-burmeister\" correction=\"jacobian\""};
    for (int o = 0; o < 4; ++o) {
        /* no gravity, every bottom vertex exactly on the plane at rest:
         * delta = lambda = 0 on all 16 contacts */
        test_scene t;
        scene(&t, "0 0 0", 5, "", opts[o], "0 0 0", "<TestConstraint name=\"plane\" mode=\"plane\" mu=\"0.5\"/>");
        int n;
        double *x0 = copy_positions(&t, &n);
        ts_step(&t, 3);
        test_probe *c = ts_constraint(&t, "box/plane");
        ck_assert_int_eq(c->nrows, 48);
        double lmax = 0.0, dx = 0.0;
        for (int j = 0; j < c->nrows; ++j) {
            ck_assert(isfinite(c->lambda[j]));
            lmax = fmax(lmax, fabs(c->lambda[j]));
        }
        const double *x = ts_positions(&t, "box/dofs", &n);
        for (int i = 0; i < 3 * n; ++i) dx = fmax(dx, fabs(x[i] - x0[i]));
        printf("0/0 (%s): max |lambda| %.2e N, max displacement %.2e m\n", opts[o], lmax, dx);
        /* the FB regularisation eps = 1e-12 m leaves lambda ~ eps / r */
        ck_assert_double_le(lmax, 1e-6);
        ck_assert_double_le(dx, 1e-10);
        free(x0);
        ts_free(&t);
    }
}
END_TEST

START_TEST(pins_hold_the_weight_and_compliance_sets_the_offset)
{
    const double E[2] = {0.0, 1e-4};
    for (int pairs = 0; pairs < 2; ++pairs)
        for (int e = 0; e < 2; ++e) {
            test_scene t;
            char rows[256];
            snprintf(rows, sizeof rows,
                     "<TestConstraint name=\"pin\" mode=\"pin\" above=\"0.0999\" height=\"0.1\" "
                     "compliance=\"%g\" pairs=\"%d\"/>",
                     E[e], pairs);
            /* mass damping settles the hanging box; CR runs to its tolerance */
            scene(&t, "0 -9.81 0", 10, "damping=\"20\"", "crIterations=\"40\" crTolerance=\"1e-14\"", "0 0 0", rows);
            ts_step(&t, 150);
            test_probe *c = ts_constraint(&t, "box/pin");
            ck_assert_int_eq(c->nrows, pairs ? 8 : 16);
            double W = c->total_mass * G, worst = 0.0;
            int n;
            const double *x = ts_positions(&t, "box/dofs", &n);
            for (int j = 0; j < c->nrows; ++j) {
                double y = 0.0;
                for (int s = 0; s <= pairs; ++s) y += x[3 * c->selected[(pairs + 1) * j + s] + 1] / (pairs + 1);
                worst = fmax(worst, fabs(y - 0.1 + E[e] * c->lambda[j]));
            }
            printf("pins (pairs %d, E %g m/N): sum lambda %.9f N (m g %.9f), max |delta + E lambda| %.2e m\n", pairs,
                   E[e], c->sum_rows, W, worst);
            ck_assert_double_le(fabs(c->sum_rows - W) / W, 1e-3);
            ck_assert_double_le(worst, 1e-9);
            ts_free(&t);
        }
}
END_TEST

START_TEST(bounded_rows_saturate_or_hold)
{
    /* 16 top vertices: hi = 0.25 m g / 16 each cannot hold the box */
    test_scene t;
    double W = G, hi = 0.25 * W / 16;
    char rows[256];
    snprintf(rows, sizeof rows, "<TestConstraint name=\"cable\" mode=\"bounded\" above=\"0.0999\" height=\"0.1\" lo=\"0\" hi=\"%.17g\"/>", hi);
    scene(&t, "0 -9.81 0", 10, "", "", "0 0 0", rows);
    int n;
    ts_positions(&t, "box/dofs", &n);
    double *mass = ts_masses(&t, "box/mass", n);
    ts_step(&t, 20);
    double v1 = ts_mean_velocity(&t, "box/dofs", mass, 1);
    ts_step(&t, 20);
    double v2 = ts_mean_velocity(&t, "box/dofs", mass, 1);
    test_probe *c = ts_constraint(&t, "box/cable");
    for (int j = 0; j < c->nrows; ++j) ck_assert_double_eq(c->lambda[j], hi);
    double acc = (v2 - v1) / 0.2, expect = -(W - 16 * hi) / c->total_mass;
    printf("bounded rows at hi: acceleration %.6f m/s^2, (sum hi - m g) / m = %.6f\n", acc, expect);
    ck_assert_double_le(fabs(acc / expect - 1), 0.01);
    free(mass);
    ts_free(&t);
    /* hi = 2 m g / 8 on 8 midpoint rows: they hold (damped to rest) */
    snprintf(rows, sizeof rows,
             "<TestConstraint name=\"cable\" mode=\"bounded\" above=\"0.0999\" height=\"0.1\" lo=\"0\" hi=\"%.17g\" "
             "pairs=\"1\"/>",
             2 * W / 8);
    scene(&t, "0 -9.81 0", 10, "damping=\"20\"", "crIterations=\"40\" crTolerance=\"1e-14\"", "0 0 0", rows);
    ts_step(&t, 150);
    c = ts_constraint(&t, "box/cable");
    ck_assert_int_eq(c->nrows, 8);
    printf("bounded midpoint rows below hi: sum lambda %.9f N (m g %.9f)\n", c->sum_rows, W);
    ck_assert_double_le(fabs(c->sum_rows - W) / W, 1e-3);
    for (int j = 0; j < c->nrows; ++j) ck_assert(c->lambda[j] >= 0.0 && c->lambda[j] < 2 * W / 8);
    ts_free(&t);
}
END_TEST

START_TEST(warm_start_records_are_part_of_the_state)
{
    test_scene t;
    scene(&t, "3.355 -9.218 0", 3, "", "", "0 0 0", "<TestConstraint name=\"plane\" mode=\"plane\" mu=\"0.1\"/>");
    ts_step(&t, 10);
    char path[1024];
    close(test_tmp_file(path, sizeof path, "ncp_state"));
    pl_error err;
    ck_assert_int_eq(pl_sim_save_state(t.sim, path, &err), PL_OK);
    int n;
    ts_step(&t, 5);
    double *x1 = copy_positions(&t, &n);
    ck_assert_int_eq(pl_sim_restore_state(t.sim, path, &err), PL_OK);
    ts_step(&t, 5);
    const double *x2 = ts_positions(&t, "box/dofs", &n);
    ck_assert_int_eq(memcmp(x1, x2, sizeof(double) * 3 * (size_t)n), 0);
    /* the slot holds one record per row, with the multipliers handed back */
    int slot = pl_model_find_slot(pl_sim_model(t.sim), "root/contact.warmStart");
    ck_assert_int_ge(slot, 0);
    test_probe *c = ts_constraint(&t, "box/plane");
    ck_assert_int_eq(c->nrows, 48);
    ck_assert_uint_eq(pl_data_slot_bytes(pl_sim_data(t.sim), slot), 48 * sizeof(pl_ncpc_key));
    const pl_ncpc_key *rec = pl_data_slot(pl_sim_data(t.sim), slot);
    for (int j = 0; j < 48; ++j) ck_assert_double_eq(rec[j].lambda, c->lambda[j]);
    remove(path);
    free(x1);
    ts_free(&t);
}
END_TEST

/* A box sliding down a 20 degree slope (mu = 0.1) with the
 * LocalGlobalSolver's default 5 iterations per step: warm-started
 * multipliers keep its acceleration at g (sin a - mu cos a), cold ones lag
 * behind by the unconverged friction. */
START_TEST(warm_start_converges_in_fewer_iterations)
{
    const double a = 20 * 3.14159265358979323846 / 180, mu = 0.1;
    double err[2], pen[2];
    char gravity[64];
    snprintf(gravity, sizeof gravity, "%.17g %.17g 0", G * sin(a), -G * cos(a));
    for (int w = 0; w < 2; ++w) {
        test_scene t;
        /* cold: from zero (without stickStart, whose holding forces would make a good start) */
        scene(&t, gravity, 5, "", w ? "warmStart=\"1\"" : "warmStart=\"0\" stickStart=\"0\"", "0 0 0",
              "<TestConstraint name=\"plane\" mode=\"plane\" mu=\"0.1\"/>");
        int n;
        ts_positions(&t, "box/dofs", &n);
        double *mass = ts_masses(&t, "box/mass", n), v[2];
        pen[w] = 0.0;
        for (int k = 1; k <= 100; ++k) {
            ts_step(&t, 1);
            pen[w] = fmin(pen[w], ts_min_y(&t, "box/dofs"));
            if (k == 20) v[0] = ts_mean_velocity(&t, "box/dofs", mass, 0);
        }
        v[1] = ts_mean_velocity(&t, "box/dofs", mass, 0);
        err[w] = fabs((v[1] - v[0]) / 0.8 / (G * (sin(a) - mu * cos(a))) - 1);
        free(mass);
        ts_free(&t);
    }
    printf("5 iterations per step, sliding box: acceleration error %.2e cold, %.2e warm; deepest vertex "
           "%.2e m cold, %.2e m warm\n",
           err[0], err[1], pen[0], pen[1]);
    ck_assert_double_le(err[1], 1e-3);
    ck_assert_double_le(err[1], 0.1 * err[0]);
    ck_assert_double_ge(pen[1], -1e-4);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("ncp_component");
    TCase *tc = tcase_create("scenes");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, a_resting_box_carries_its_weight);
    tcase_add_test(tc, a_new_resting_contact_gives_finite_steps);
    tcase_add_test(tc, pins_hold_the_weight_and_compliance_sets_the_offset);
    tcase_add_test(tc, bounded_rows_saturate_or_hold);
    tcase_add_test(tc, warm_start_records_are_part_of_the_state);
    tcase_add_test(tc, warm_start_converges_in_fewer_iterations);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf ? 1 : 0;
}
