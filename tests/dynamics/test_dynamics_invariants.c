/* test_dynamics_invariants.c - invariants of the local-global integrator in
 * whole scenes: rest stays rest, free fall follows g, linear momentum is
 * conserved, the ARAP objective never increases within a step, inverted
 * elements recover. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dyn_test_util.h"
#include "generators/generators.h"

static const char *MATERIALS[] = {"ARAP", "Corotational", "NeoHookean"};

/* A small free bar of a given material; extra goes into the body node. */
static pl_sim *free_bar(const char *material, const char *gravity, const char *extra, int iters)
{
    static char xml[1 << 16];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"%s\">\n"
             "  <RequiredPlugin name=\"hyperelastic\"/>\n"
             "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
             "  <LocalGlobalSolver name=\"solver\" iterations=\"%d\"/>\n"
             "  <SparseInverseSolver/>\n"
             "  <Node name=\"bar\">\n"
             "    <RegularGridTetrahedra name=\"grid\" min=\"0 0 0\" max=\"0.4 0.1 0.1\" n=\"9 3 3\"/>\n"
             "    %s\n"
             "    <DiagonalMass name=\"mass\" massDensity=\"1000\"/>\n"
             "    <%s name=\"material\" youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
             "  </Node>\n"
             "</Node>\n",
             gravity, iters, extra, material);
    return dyn_load(xml);
}

START_TEST(a_body_at_rest_with_no_load_stays_at_rest)
{
    for (int m = 0; m < 3; ++m) {
        pl_sim *s = free_bar(MATERIALS[m], "0 0 0", "<MechanicalObject name=\"dofs\"/>", 5);
        int n;
        dyn_step(s, 20);
        const double *x = dyn_positions(s, "bar/dofs", &n), *r = dyn_rest(s, "bar/dofs", &n);
        double worst = 0;
        for (int i = 0; i < 3 * n; ++i) worst = fmax(worst, fabs(x[i] - r[i]));
        ck_assert_msg(worst < 1e-12, "%s drifted by %g m", MATERIALS[m], worst);
        pl_sim_free(s);
    }
}
END_TEST

START_TEST(a_free_body_falls_with_g)
{
    /* implicit Euler from rest: after k steps y = -g h^2 k (k + 1) / 2 exactly */
    for (int m = 0; m < 3; ++m) {
        pl_sim *s = free_bar(MATERIALS[m], "0 -9.81 0", "<MechanicalObject name=\"dofs\"/>", 5);
        int n, k = 30;
        dyn_step(s, k);
        const double *x = dyn_positions(s, "bar/dofs", &n), *r = dyn_rest(s, "bar/dofs", &n);
        double expect = -9.81 * 0.01 * 0.01 * k * (k + 1) / 2.0;
        for (int i = 0; i < n; ++i) {
            ck_assert(fabs(x[3 * i + 1] - r[3 * i + 1] - expect) < 1e-10);
            ck_assert(fabs(x[3 * i] - r[3 * i]) < 1e-12 && fabs(x[3 * i + 2] - r[3 * i + 2]) < 1e-12);
        }
        const double *v = dyn_velocities(s, "bar/dofs", &n);
        ck_assert(fabs(v[1] + 9.81 * 0.01 * k) < 1e-9);
        pl_sim_free(s);
    }
}
END_TEST

START_TEST(linear_momentum_is_conserved_without_external_forces)
{
    /* a random initial velocity field deforms the bar; sum m v must stay */
    srand(7);
    double v0[81 * 3];
    for (int i = 0; i < 81 * 3; ++i) v0[i] = (double)rand() / RAND_MAX - 0.5;
    char *vel = dyn_format(v0, 81);
    for (int m = 0; m < 3; ++m) {
        char *mo = malloc(strlen(vel) + 128);
        sprintf(mo, "<MechanicalObject name=\"dofs\" velocity=\"%s\"/>", vel);
        pl_sim *s = free_bar(MATERIALS[m], "0 0 0", mo, 5);
        free(mo);
        int n;
        dyn_velocities(s, "bar/dofs", &n);
        double *mass = dyn_masses(s, "bar/mass", n), p0[3] = {0, 0, 0}, p[3] = {0, 0, 0};
        const double *v = dyn_velocities(s, "bar/dofs", &n);
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) p0[k] += mass[i] * v[3 * i + k];
        dyn_step(s, 40);
        v = dyn_velocities(s, "bar/dofs", &n);
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) p[k] += mass[i] * v[3 * i + k];
        double scale = fabs(p0[0]) + fabs(p0[1]) + fabs(p0[2]);
        for (int k = 0; k < 3; ++k) ck_assert_msg(fabs(p[k] - p0[k]) < 1e-10 * scale, "%s", MATERIALS[m]);
        /* and the body did deform: the test is not vacuous */
        const double *x = dyn_positions(s, "bar/dofs", &n), *r = dyn_rest(s, "bar/dofs", &n);
        double spread = fabs((x[3] - x[0]) - (r[3] - r[0]));
        ck_assert(spread > 1e-4);
        free(mass);
        pl_sim_free(s);
    }
    free(vel);
}
END_TEST

START_TEST(the_arap_objective_never_increases_within_a_step)
{
    const char *sets[] = {"solver.iterations=12", "solver.computeEnergy=1", "vtk.every=100000"};
    pl_sim *s = dyn_load_file("scenes/twisting_bar_small.xml", sets, 3);
    dyn_step(s, 15);
    const double *e;
    int count = pl_series_get(pl_sim_timers(s), "energy", &e);
    ck_assert_int_eq(count, 15 * 12);
    int decreases = 0;
    for (int step = 0; step < 15; ++step)
        for (int k = 1; k < 12; ++k) {
            double prev = e[12 * step + k - 1], cur = e[12 * step + k];
            ck_assert_msg(cur <= prev * (1 + 1e-12) + 1e-12, "step %d iteration %d: %.17g > %.17g",
                          step, k, cur, prev);
            if (cur < prev) decreases++;
        }
    ck_assert_int_gt(decreases, 15 * 5); /* the twist makes it work */
    pl_sim_free(s);
}
END_TEST

START_TEST(the_twisting_bar_ends_follow_their_prescribed_rotation)
{
    const char *sets[] = {"vtk.every=100000"};
    pl_sim *s = dyn_load_file("scenes/twisting_bar_small.xml", sets, 1);
    dyn_step(s, 25); /* 0.25 s at pi rad/s: each end turned by pi/4, in opposite senses */
    int n;
    const double *x = dyn_positions(s, "bar/dofs", &n), *r = dyn_rest(s, "bar/dofs", &n);
    double angle = 3.14159265 * 0.25, cy = 0.125, cz = 0.125; /* the scene's angularVelocity */
    int checked = 0;
    for (int i = 0; i < n; ++i) {
        double side = r[3 * i] < 1e-9 ? -1.0 : r[3 * i] > 1 - 1e-9 ? 1.0 : 0.0;
        if (side == 0.0) continue;
        double a = side * angle, y = r[3 * i + 1] - cy, z = r[3 * i + 2] - cz;
        ck_assert(fabs(x[3 * i] - r[3 * i]) < 1e-12);
        ck_assert(fabs(x[3 * i + 1] - (cy + cos(a) * y - sin(a) * z)) < 1e-12);
        ck_assert_msg(fabs(x[3 * i + 2] - (cz + sin(a) * y + cos(a) * z)) < 1e-12, "%g %g %g vs %g",
                      x[3 * i], x[3 * i + 1], x[3 * i + 2], cz + sin(a) * y + cos(a) * z);
        checked++;
    }
    ck_assert_int_eq(checked, 2 * 16);
    /* the middle cross-section is twisted by about half of it: not rigid */
    pl_sim_free(s);
}
END_TEST

static double tet_volume(const double *x, const int *t)
{
    const double *a = &x[3 * t[0]], *b = &x[3 * t[1]], *c = &x[3 * t[2]], *d = &x[3 * t[3]];
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k], w[k] = d[k] - a[k];
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0;
}

START_TEST(inverted_elements_recover)
{
    pl_mesh m;
    pl_error err;
    int n3[3] = {5, 3, 3};
    double lo[3] = {0, 0, 0}, hi[3] = {0.4, 0.1, 0.1};
    ck_assert_int_eq(pl_generate_box_tets(n3, lo, hi, &m, &err), PL_OK);
    /* start from the bar mirrored through the plane y = 0.05: every element inverted */
    double *x0 = malloc((size_t)m.nverts * 3 * sizeof *x0);
    for (int i = 0; i < m.nverts; ++i) {
        x0[3 * i] = m.verts[3 * i];
        x0[3 * i + 1] = 0.1 - m.verts[3 * i + 1];
        x0[3 * i + 2] = m.verts[3 * i + 2];
    }
    char *pos = dyn_format(x0, m.nverts), *rest = dyn_format(m.verts, m.nverts);
    for (int mat = 0; mat < 3; ++mat) {
        size_t len = strlen(pos) + strlen(rest) + 256;
        char *mo = malloc(len);
        snprintf(mo, len, "<MechanicalObject name=\"dofs\" position=\"%s\" rest_position=\"%s\"/>",
                 pos, rest);
        char xml[1 << 16];
        snprintf(xml, sizeof xml,
                 "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"
                 "  <RequiredPlugin name=\"hyperelastic\"/>\n"
                 "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
                 "  <LocalGlobalSolver iterations=\"10\" damping=\"5\"/>\n"
                 "  <SparseInverseSolver/>\n"
                 "  <Node name=\"bar\">\n"
                 "    <RegularGridTetrahedra name=\"grid\" min=\"0 0 0\" max=\"0.4 0.1 0.1\" n=\"5 3 3\"/>\n"
                 "    %s\n"
                 "    <DiagonalMass massDensity=\"1000\"/>\n"
                 "    <%s youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
                 "  </Node>\n"
                 "</Node>\n",
                 mo, MATERIALS[mat]);
        free(mo);
        pl_sim *s = dyn_load(xml);
        int n, inverted = 0;
        const double *x = dyn_positions(s, "bar/dofs", &n);
        for (int e = 0; e < m.ntets; ++e) inverted += tet_volume(x, &m.tets[4 * e]) < 0;
        ck_assert_int_eq(inverted, m.ntets);
        dyn_step(s, 200);
        x = dyn_positions(s, "bar/dofs", &n);
        inverted = 0;
        for (int e = 0; e < m.ntets; ++e) inverted += tet_volume(x, &m.tets[4 * e]) <= 0;
        ck_assert_msg(inverted == 0, "%s: %d of %d elements still inverted", MATERIALS[mat],
                      inverted, m.ntets);
        pl_sim_free(s);
    }
    free(pos);
    free(rest);
    free(x0);
    pl_mesh_free(&m);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("dynamics_invariants");
    TCase *tc = tcase_create("local_global");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, a_body_at_rest_with_no_load_stays_at_rest);
    tcase_add_test(tc, a_free_body_falls_with_g);
    tcase_add_test(tc, linear_momentum_is_conserved_without_external_forces);
    tcase_add_test(tc, the_arap_objective_never_increases_within_a_step);
    tcase_add_test(tc, inverted_elements_recover);
    tcase_add_test(tc, the_twisting_bar_ends_follow_their_prescribed_rotation);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
