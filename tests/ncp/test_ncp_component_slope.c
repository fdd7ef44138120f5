/* test_ncp_component_slope.c - friction of NonSmoothNewtonContactSolver in
 * scenes: a 1 kg ARAP box on the plane y = 0 with gravity tilted by the
 * slope angle a (g sin a, -g cos a, 0):
 *  - mu > tan a: it sticks, the friction carries m g sin a exactly;
 *  - mu = 0.1 on a 20 degree slope: it slides with g (sin a - mu cos a)
 *    (within 2 %), for both NCP functions and both complementarity
 *    scalings, with |lambda_f| <= mu lambda_n as solved;
 *  - near the stick-slip threshold mu* = tan 10 deg = 0.17633 (the
 *    paper's Stick-Sliding test) the Delassus scaling resolves mu to 0.001;
 *  - explicit and matrix-free W give the same trajectory to 1e-9 m (with
 *    two-vertex bounded rows, whose matrix-free diagonal needs A^-1's
 *    off-diagonal entries);
 *  - the Table 3 timers and the contact statistics are recorded. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact_test_component.h"

static const double G = 9.81, DEG = 3.14159265358979323846 / 180;

static void slope(test_scene *t, double a_deg, int iters, const char *contact, double mu, const char *extra)
{
    static char xml[8192];
    double a = a_deg * DEG;
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"%.17g %.17g 0\">\n"
             "  <RequiredPlugin name=\"hyperelastic\"/>\n"
             "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
             "  <RequiredPlugin name=\"ncp_contact\"/>\n"
             "  <LocalGlobalSolver name=\"solver\" iterations=\"%d\"/>\n"
             "  <SparseInverseSolver/>\n"
             "  <NonSmoothNewtonContactSolver name=\"contact\" %s/>\n"
             "  <Node name=\"box\">\n"
             "    <RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.1 0.1\" n=\"4 4 4\"/>\n"
             "    <MechanicalObject name=\"dofs\"/>\n"
             "    <DiagonalMass name=\"mass\" massDensity=\"1000\"/>\n"
             "    <ARAP youngModulus=\"1e6\" poissonRatio=\"0.3\"/>\n"
             "    <TestConstraint name=\"plane\" mode=\"plane\" mu=\"%.17g\"/>\n"
             "    %s\n"
             "  </Node>\n"
             "</Node>\n",
             G * sin(a), -G * cos(a), iters, contact, mu, extra);
    ts_load(t, xml, NULL, 0);
}

typedef struct run {
    double acc;        /* mean x acceleration between the two sample steps [m/s^2] */
    double pen;        /* deepest vertex over the run [m] */
    double cone;       /* max |lambda_f| - mu lambda_n (1 + 1e-6) over the run [N] */
    double sum_n, fx;  /* at the end: sum lambda_n, sum of friction x forces [N] */
    double mass;
} run;

static run slide(double a_deg, double mu, const char *contact, int k0, int k1)
{
    test_scene t;
    run r = {0, 0, -INFINITY, 0, 0, 0};
    slope(&t, a_deg, 10, contact, mu, "");
    int n;
    ts_positions(&t, "box/dofs", &n);
    double *mass = ts_masses(&t, "box/mass", n), v0 = 0;
    for (int k = 1; k <= k1; ++k) {
        ts_step(&t, 1);
        test_probe *c = ts_constraint(&t, "box/plane");
        r.pen = fmin(r.pen, ts_min_y(&t, "box/dofs"));
        r.cone = fmax(r.cone, c->cone_excess);
        if (k == k0) v0 = ts_mean_velocity(&t, "box/dofs", mass, 0);
        r.sum_n = c->sum_normal;
        r.fx = c->sum_friction[0];
        r.mass = c->total_mass;
    }
    r.acc = (ts_mean_velocity(&t, "box/dofs", mass, 0) - v0) / ((k1 - k0) * 0.01);
    free(mass);
    ts_free(&t);
    return r;
}

/* project="1": every iterate is projected onto the admissible set, so the
 * cone holds exactly at every step (r.cone <= 0 below); without it (the
 * default) it holds to the solver's residual. */
static const char *VARIANTS[4] = {
    "ncp=\"fischer-burmeister\" preconditioner=\"delassus\" project=\"1\"",
    "ncp=\"fischer-burmeister\" preconditioner=\"mass\" project=\"1\"",
    "ncp=\"minimum-map\" preconditioner=\"delassus\" project=\"1\"",
    "ncp=\"minimum-map\" preconditioner=\"mass\" project=\"1\"",
};

START_TEST(a_box_sticks_when_mu_exceeds_tan_a)
{
    const double a = 20 * DEG;
    for (int v = 0; v < 4; ++v) {
        run r = slide(20, 0.5, VARIANTS[v], 30, 60);
        double W = r.mass * G;
        printf("stick, mu 0.5 on 20 deg (%s): acceleration %.2e m/s^2, friction %.9f N (m g sin a %.9f), "
               "sum lambda_n %.9f N (m g cos a %.9f)\n",
               VARIANTS[v], r.acc, -r.fx, W * sin(a), r.sum_n, W * cos(a));
        ck_assert_double_le(fabs(r.acc), 1e-6);
        ck_assert_double_le(fabs(-r.fx / (W * sin(a)) - 1), 1e-6);
        ck_assert_double_le(fabs(r.sum_n / (W * cos(a)) - 1), 1e-6);
        ck_assert_double_le(r.cone, 0.0);
        ck_assert_double_ge(r.pen, -1e-4);
    }
}
END_TEST

START_TEST(a_box_slides_with_coulomb_acceleration)
{
    const double a = 20 * DEG, mu = 0.1, expect = G * (sin(a) - mu * cos(a));
    for (int v = 0; v < 4; ++v) {
        run r = slide(20, mu, VARIANTS[v], 20, 100);
        printf("slide, mu 0.1 on 20 deg (%s): acceleration %.6f m/s^2 (g (sin a - mu cos a) = %.6f, "
               "error %.2e), deepest vertex %.2e m, max cone excess %.2e N\n",
               VARIANTS[v], r.acc, expect, r.acc / expect - 1, r.pen, r.cone);
        ck_assert_double_le(fabs(r.acc / expect - 1), 0.02);
        ck_assert_double_le(r.cone, 0.0);
        ck_assert_double_ge(r.pen, -1e-4);
    }
}
END_TEST

START_TEST(the_delassus_scaling_resolves_the_stick_slip_threshold)
{
    /* tan 10 deg = 0.17633: mu = 0.1755 slides, mu = 0.177 sticks */
    const double a = 10 * DEG;
    for (int v = 0; v < 4; v += 2) {
        run s = slide(10, 0.1755, VARIANTS[v], 50, 150);
        run k = slide(10, 0.177, VARIANTS[v], 50, 150);
        double expect = G * (sin(a) - 0.1755 * cos(a));
        printf("threshold (%s): mu 0.1755: acceleration %.6f m/s^2 (expected %.6f), mu 0.177: %.2e m/s^2\n",
               VARIANTS[v], s.acc, expect, k.acc);
        ck_assert_double_le(fabs(s.acc / expect - 1), 0.02);
        ck_assert_double_le(fabs(k.acc), 1e-4);
    }
}
END_TEST

static double *trajectory(const char *contact, int steps)
{
    test_scene t;
    /* eight two-vertex bounded rows pull the top up, saturated at 0.5 N */
    slope(&t, 20, 10, contact, 0.1,
          "<TestConstraint name=\"cable\" mode=\"bounded\" above=\"0.0999\" height=\"0.2\" lo=\"0\" hi=\"0.5\" "
          "pairs=\"1\"/>");
    ts_step(&t, steps);
    double mb;
    int explicit_w = pl_stat_get(pl_sim_timers(t.sim), "W memory [MB]", &mb) == 0;
    ck_assert_int_eq(explicit_w, strstr(contact, "explicit") != NULL);
    int n;
    const double *x = ts_positions(&t, "box/dofs", &n);
    double *c = malloc(sizeof(double) * 3 * (size_t)n);
    memcpy(c, x, sizeof(double) * 3 * (size_t)n);
    test_probe *cable = ts_constraint(&t, "box/cable");
    ck_assert_int_eq(cable->nrows, 8);
    ck_assert_double_eq_tol(cable->sum_rows, 4.0, 1e-12);
    ts_free(&t);
    return c;
}

/* With the default 10 CR iterations the inner solves are truncated: round-off
 * differences between the two products then grow where a row changes branch
 * (a rear contact whose lambda_n reaches 0): 1e-13 m after 10 steps, 3e-9 m
 * after 40.  With CR run to convergence the trajectories stay within
 * round-off of each other over the whole run. */
START_TEST(explicit_and_matrix_free_w_give_the_same_trajectory)
{
    const char *cr[2] = {"", "crIterations=\"48\" crTolerance=\"1e-13\""};
    const int steps[2] = {10, 40};
    for (int c = 0; c < 2; ++c)
        for (int p = 0; p < 2; ++p) {
            char a[160], b[160];
            const char *pre = p ? "preconditioner=\"mass\"" : "preconditioner=\"delassus\"";
            snprintf(a, sizeof a, "delassus=\"explicit\" %s %s", pre, cr[c]);
            snprintf(b, sizeof b, "delassus=\"matrix-free\" %s %s", pre, cr[c]);
            double *xe = trajectory(a, steps[c]), *xm = trajectory(b, steps[c]), d = 0.0, front = 0.0;
            for (int i = 0; i < 64; ++i) {
                for (int k = 0; k < 3; ++k) d = fmax(d, fabs(xe[3 * i + k] - xm[3 * i + k]));
                front = fmax(front, xe[3 * i]);
            }
            printf("explicit vs matrix-free W (%s %s), %d steps: max position difference %.2e m (box front "
                   "at x = %.4f m)\n",
                   pre, cr[c], steps[c], d, front);
            ck_assert_double_le(d, 1e-9);
            ck_assert_double_ge(front, 0.11); /* it did slide */
            free(xe);
            free(xm);
        }
}
END_TEST

START_TEST(table_3_timers_and_statistics)
{
    test_scene t;
    slope(&t, 20, 5, "", 0.1, "");
    ts_step(&t, 10);
    pl_timers *tm = pl_sim_timers(t.sim);
    const char *phases[] = {"Schur", "Local", "Global", "Assembly", "Constraint solve", "Correction",
                            "Constraint global"};
    for (int k = 0; k < 7; ++k) {
        int id = pl_timer_id(tm, phases[k]);
        ck_assert_int_eq(pl_timers_samples(tm, id), 10);
        ck_assert_double_ge(pl_timers_total_ms(tm, id), 0.0);
    }
    /* the constrained global step contains its parts */
    double cg = pl_timers_total_ms(tm, pl_timer_id(tm, "Constraint global"));
    double parts = pl_timers_total_ms(tm, pl_timer_id(tm, "Constraint solve")) +
                   pl_timers_total_ms(tm, pl_timer_id(tm, "Correction"));
    ck_assert_double_le(parts, cg);
    /* the rows are timed each step, inside the frame, apart from Schur (the
     * contact solver's begin, after them); a CPU run has no device phases */
    int rows = pl_timer_id(tm, "Rows"), frame = pl_timer_id(tm, "Frame");
    ck_assert_int_eq(pl_timers_samples(tm, rows), 10);
    ck_assert_double_gt(pl_timers_total_ms(tm, rows), 0.0);
    ck_assert_double_le(pl_timers_total_ms(tm, rows) +
                            pl_timers_total_ms(tm, pl_timer_id(tm, "Schur")),
                        pl_timers_total_ms(tm, frame));
    ck_assert_int_eq(pl_timers_samples(tm, pl_timer_id(tm, "Device wait")), 0);
    double v;
    ck_assert_int_eq(pl_stat_get(tm, "contacts max", &v), 0);
    ck_assert_double_eq(v, 16);
    ck_assert_int_eq(pl_stat_get(tm, "constraint rows max", &v), 0);
    ck_assert_double_eq(v, 48);
    ck_assert_int_eq(pl_stat_get(tm, "W memory [MB]", &v), 0);
    ck_assert_double_eq_tol(v, 48.0 * 48 * 8 / (1024 * 1024), 1e-15);
    ts_free(&t);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("ncp_component_slope");
    TCase *tc = tcase_create("slope");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, a_box_sticks_when_mu_exceeds_tan_a);
    tcase_add_test(tc, a_box_slides_with_coulomb_acceleration);
    tcase_add_test(tc, the_delassus_scaling_resolves_the_stick_slip_threshold);
    tcase_add_test(tc, explicit_and_matrix_free_w_give_the_same_trajectory);
    tcase_add_test(tc, table_3_timers_and_statistics);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf ? 1 : 0;
}
