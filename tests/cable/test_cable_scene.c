/* test_cable_scene.c - CableConstraint in scenes, solved by the
 * LocalGlobalSolver with the NonSmoothNewtonContactSolver.  A 0.1 m bar
 * (Neo-Hookean, E 1e5 Pa) is clamped at x = 0; a cable runs along its top
 * edge from a pull point behind the clamp.  No gravity unless stated.
 *  - displacement mode: once settled the cable's length, computed here from
 *    the vertex positions, is cableInitialLength - value within 1e-3 of
 *    value; the tension is positive (the cable pulls);
 *  - force mode: the reported force is the commanded tension, and the
 *    reaction of the clamp (the elastic forces on the clamped vertices)
 *    balances the cable's net pull T u (u: from the first cable point to
 *    the pull point) within 1e-3 T;
 *  - force mode with maxPositiveDisp: the displacement stops at the limit
 *    and the tension drops below the command;
 *  - maxDispVariation: the displacement moves by at most that much per step;
 *  - centers: points snapped to the nearest vertices give the same cable;
 *  - minForce = 0: commanded to push, the cable never pushes (lambda >= 0
 *    at every step, the bar stays at rest) while a bilateral cable does;
 *    ramped to pulling, it pulls;
 *  - the small finger scene bends while pulled and comes back after. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable_test_util.h"

static const char *BAR =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"
    "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
    "<RequiredPlugin name=\"ncp_contact\"/><RequiredPlugin name=\"cable\"/>\n"
    "<LocalGlobalSolver name=\"solver\" iterations=\"20\" damping=\"50\"/>\n"
    "<SparseInverseSolver/><NonSmoothNewtonContactSolver/>\n"
    "<Node name=\"bar\">\n"
    "<RegularGridTetrahedra min=\"0 0 0\" max=\"0.1 0.02 0.02\" n=\"11 3 3\"/>\n"
    "<MechanicalObject name=\"dofs\"/>\n"
    "<DiagonalMass massDensity=\"1000\"/>\n"
    "<NeoHookean name=\"material\" youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
    "<FixedConstraint name=\"clamp\" box=\"-0.001 -1 -1  0.001 1 1\"/>\n"
    "<CableConstraint name=\"cable\" %s pullPoint=\"-0.01 0.02 0.01\" %s/>\n"
    "%s\n"
    "</Node></Node>\n";

enum { NPTS = 10 };

/* Cable vertices: the top edge y = 0.02, z = 0.01, x = 0.01 .. 0.1. */
static void cable_indices(char *buf, size_t size, int *idx)
{
    pl_sim *s = ct_load("<Node name=\"root\"><RegularGridTetrahedra min=\"0 0 0\" "
                        "max=\"0.1 0.02 0.02\" n=\"11 3 3\"/><MechanicalObject name=\"dofs\"/>"
                        "</Node>");
    int n;
    const double *x = ct_positions(s, "dofs", 1, &n);
    size_t w = 0;
    for (int i = 0; i < NPTS; ++i) {
        idx[i] = ct_vertex_at(x, n, 0.01 * (i + 1), 0.02, 0.01);
        ck_assert_int_ge(idx[i], 0);
        w += (size_t)snprintf(buf + w, size - w, "%s%d", i ? " " : "", idx[i]);
    }
    pl_sim_free(s);
}

/* The bar with the cable on the vertices idx (or the points `points`
 * gives, e.g. centers="..."), more cable attributes and more components. */
static pl_sim *bar_points(const char *points, const char *cable_attrs, const char *extra, int *idx)
{
    char ind[256], pts[320], xml[4096];
    cable_indices(ind, sizeof ind, idx);
    snprintf(pts, sizeof pts, "indices=\"%s\"", ind);
    snprintf(xml, sizeof xml, BAR, points ? points : pts, cable_attrs, extra ? extra : "");
    return ct_load(xml);
}

static pl_sim *bar(const char *cable_attrs, const char *extra, int *idx)
{
    return bar_points(NULL, cable_attrs, extra, idx);
}

/* The cable's length from the vertex positions (pull point -> idx[0] -> ...). */
static double cable_length(pl_sim *s, const int *idx)
{
    int n;
    const double *x = ct_positions(s, "dofs", 0, &n);
    double prev[3] = {-0.01, 0.02, 0.01}, L = 0;
    for (int i = 0; i < NPTS; ++i) {
        const double *p = x + 3 * idx[i];
        L += sqrt((p[0] - prev[0]) * (p[0] - prev[0]) + (p[1] - prev[1]) * (p[1] - prev[1]) +
                  (p[2] - prev[2]) * (p[2] - prev[2]));
        memcpy(prev, p, sizeof prev);
    }
    return L;
}

static double max_speed(pl_sim *s)
{
    pl_component *c = pl_sim_component(s, "dofs");
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    pl_buffer b = ops->velocities(c, pl_sim_data(s));
    const double *v = pl_buffer_f64(&b);
    double m = 0;
    for (size_t i = 0; i < b.rows; ++i)
        m = fmax(m, sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]));
    return m;
}

START_TEST(length_follows_commanded_displacement)
{
    int idx[NPTS];
    pl_sim *s = bar("value=\"0.004\"", NULL, idx);
    double L0 = ct_get(s, "cable.cableInitialLength");
    ck_assert_double_eq_tol(L0, 0.11, 1e-12); /* 0.02 to the first point + 9 x 0.01 */
    ck_assert_double_eq_tol(cable_length(s, idx), L0, 1e-15);
    /* the same points given as centers (snapped to the nearest vertex) */
    pl_sim *c = bar_points("centers=\"0.0104 0.0199 0.0102  0.0199 0.02 0.01  0.03 0.02 0.01 "
                           " 0.04 0.02 0.01  0.05 0.02 0.01  0.06 0.02 0.01  0.07 0.02 0.01 "
                           " 0.08 0.02 0.01  0.09 0.02 0.01  0.1 0.02 0.011\"",
                           "", NULL, idx);
    ck_assert_double_eq_tol(ct_get(c, "cable.cableInitialLength"), L0, 1e-15);
    pl_sim_free(c);
    ct_step(s, 80);
    double L = cable_length(s, idx), value = 0.004;
    ck_assert_double_lt(max_speed(s), 1e-3);
    ck_assert_double_lt(fabs((L0 - L) - value), 1e-3 * value);
    ck_assert_double_eq_tol(ct_get(s, "cable.cableLength"), L, 1e-12);
    ck_assert_double_eq_tol(ct_get(s, "cable.displacement"), L0 - L, 1e-12);
    ck_assert_double_gt(ct_get(s, "cable.force"), 0.0); /* pulling = positive tension */
    /* a new command at run time (value is RUNTIME): the length follows */
    pl_error err;
    ck_assert_int_eq(pl_sim_set(s, "cable.value", "0.002", &err), PL_OK);
    ct_step(s, 80);
    ck_assert_double_lt(fabs((L0 - cable_length(s, idx)) - 0.002), 1e-3 * 0.002);
    pl_sim_free(s);
}
END_TEST

/* Sum over the clamped vertices of the elastic force they take from the
 * body, dpsi/dx_a: the reaction the clamp must give. */
static void clamp_reaction(pl_sim *s, double R[3])
{
    int n;
    const double *x = ct_positions(s, "dofs", 0, &n);
    const double *x0 = ct_positions(s, "dofs", 1, &n);
    pl_component *mat = pl_sim_component(s, "material");
    const pl_local_term_ops *ops = pl_component_role(mat, PL_ROLE_LOCAL_TERM);
    ck_assert_ptr_nonnull(ops->add_gradient);
    double *g = calloc((size_t)n * 3, sizeof *g);
    pl_buffer qb = pl_buffer_host_f64((double *)x, (size_t)n, 3);
    pl_buffer gb = pl_buffer_host_f64(g, (size_t)n, 3);
    pl_error err;
    ck_assert_int_eq(ops->add_gradient(mat, pl_sim_data(s), 0, &qb, &gb, &err), PL_OK);
    R[0] = R[1] = R[2] = 0;
    for (int i = 0; i < n; ++i)
        if (fabs(x0[3 * i]) < 1e-12)
            for (int d = 0; d < 3; ++d) R[d] += g[3 * i + d];
    free(g);
}

START_TEST(force_mode_reaction_balances_tension)
{
    const double T = 0.3;
    int idx[NPTS];
    pl_sim *s = bar("valueType=\"force\" value=\"0.3\"", NULL, idx);
    ct_step(s, 100);
    ck_assert_double_lt(max_speed(s), 1e-4);
    ck_assert_double_eq_tol(ct_get(s, "cable.force"), T, 1e-12);
    int n;
    const double *x = ct_positions(s, "dofs", 0, &n);
    const double *p0 = x + 3 * idx[0];
    double u[3] = {-0.01 - p0[0], 0.02 - p0[1], 0.01 - p0[2]};
    double lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]), R[3];
    clamp_reaction(s, R);
    for (int d = 0; d < 3; ++d) ck_assert_double_lt(fabs(R[d] + T * u[d] / lu), 1e-3 * T);
    ck_assert_double_gt(ct_get(s, "cable.displacement"), 1e-4); /* it did pull */
    pl_sim_free(s);
}
END_TEST

START_TEST(force_mode_stops_at_max_positive_disp)
{
    int idx[NPTS];
    /* 0.3 N gives about 1.2 mm (see above); the limit stops it at 0.5 mm */
    pl_sim *s = bar("valueType=\"force\" value=\"0.3\" maxPositiveDisp=\"0.0005\"", NULL, idx);
    ct_step(s, 100);
    double disp = ct_get(s, "cable.displacement"), F = ct_get(s, "cable.force");
    ck_assert_double_lt(fabs(disp - 0.0005), 1e-3 * 0.0005);
    ck_assert_double_gt(F, 0.0);
    ck_assert_double_lt(F, 0.3 - 1e-3);
    pl_sim_free(s);
}
END_TEST

START_TEST(max_disp_variation_limits_the_rate)
{
    int idx[NPTS];
    pl_sim *s = bar("value=\"0.004\" maxDispVariation=\"0.0001\"", NULL, idx);
    double prev = 0;
    for (int k = 0; k < 10; ++k) {
        ct_step(s, 1);
        double disp = ct_get(s, "cable.displacement");
        ck_assert_double_le(disp - prev, 0.0001 * (1 + 1e-2)); /* at most 0.1 mm per step */
        prev = disp;
    }
    ck_assert_double_gt(prev, 0.00095); /* and it does move at that rate */
    ct_step(s, 60);
    ck_assert_double_lt(fabs(ct_get(s, "cable.displacement") - 0.004), 1e-3 * 0.004);
    pl_sim_free(s);
}
END_TEST

START_TEST(min_force_zero_never_pushes)
{
    int idx[NPTS];
    /* commanded to push (negative displacement: longer than at rest) */
    pl_sim *s = bar("value=\"-0.003\" minForce=\"0\"", NULL, idx);
    double L0 = ct_get(s, "cable.cableInitialLength");
    for (int k = 0; k < 60; ++k) {
        ct_step(s, 1);
        ck_assert_double_ge(ct_get(s, "cable.force"), 0.0);
    }
    ck_assert_double_lt(fabs(cable_length(s, idx) - L0), 1e-9); /* slack: nothing moved */
    pl_sim_free(s);
    /* a bilateral cable given the same command pushes */
    s = bar("value=\"-0.003\"", NULL, idx);
    ct_step(s, 60);
    ck_assert_double_lt(ct_get(s, "cable.force"), -1e-3);
    ck_assert_double_gt(cable_length(s, idx) - L0, 0.002);
    pl_sim_free(s);
    /* ramped from pushing to pulling: lambda >= 0 all along, > 0 at the end */
    s = bar("minForce=\"0\"",
            "<Keyframes target=\"@cable.value\" times=\"0 0.4\" values=\"-0.003 0.003\"/>", idx);
    double F = 0;
    for (int k = 0; k < 100; ++k) {
        ct_step(s, 1);
        F = ct_get(s, "cable.force");
        ck_assert_double_ge(F, 0.0);
    }
    ck_assert_double_gt(F, 0.01);
    ck_assert_double_lt(fabs((L0 - cable_length(s, idx)) - 0.003), 1e-3 * 0.003);
    pl_sim_free(s);
}
END_TEST

/* Tip: the vertex farthest along -x. */
static int tip_vertex(const double *x, int n)
{
    int t = 0;
    for (int i = 1; i < n; ++i)
        if (x[3 * i] < x[3 * t]) t = i;
    return t;
}

START_TEST(finger_bends_and_comes_back)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/cable_finger_small.xml", PL_SOURCE_DIR);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = PL_BINARY_DIR "/tests/cable_out";
    const char *still = "pull.values=0 0 0 0"; /* the same finger with the cable left alone */
    pl_sim_options opt0 = opt;
    opt0.overrides = &still;
    opt0.noverrides = 1;
    pl_sim *s = pl_sim_load_file(path, &opt, &diag);
    pl_sim *r = pl_sim_load_file(path, &opt0, &diag);
    if (!s || !r) pl_diag_print(&diag, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_nonnull(r);
    pl_diag_free(&diag);
    int n;
    const double *x = ct_positions(s, "dofs", 0, &n), *y = ct_positions(r, "dofs", 0, &n);
    int tip = tip_vertex(ct_positions(s, "dofs", 1, &n), n);
    double peak = 0;
    for (int k = 0; k < 120; ++k) { /* released at 0.7 s, settled by 1.2 s */
        ct_step(s, 1);
        ct_step(r, 1);
        double d = 0;
        for (int j = 0; j < 3; ++j) d += (x[3 * tip + j] - y[3 * tip + j]) * (x[3 * tip + j] - y[3 * tip + j]);
        peak = fmax(peak, sqrt(d));
        if (k == 49) /* t = 0.5 s: 10 mm pulled and held */
            ck_assert_double_lt(fabs(ct_get(s, "cable.displacement") - 0.01), 1e-5);
    }
    double d = 0;
    for (int j = 0; j < 3; ++j) d += (x[3 * tip + j] - y[3 * tip + j]) * (x[3 * tip + j] - y[3 * tip + j]);
    ck_assert_double_gt(peak, 0.01);     /* the tip moved by more than 1 cm */
    ck_assert_double_lt(sqrt(d), 1e-3);  /* and came back within 1 mm */
    pl_sim_free(s);
    pl_sim_free(r);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cable_scene");
    TCase *tc = tcase_create("scene");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, length_follows_commanded_displacement);
    tcase_add_test(tc, force_mode_reaction_balances_tension);
    tcase_add_test(tc, force_mode_stops_at_max_positive_disp);
    tcase_add_test(tc, max_disp_variation_limits_the_rate);
    tcase_add_test(tc, min_force_zero_never_pushes);
    tcase_add_test(tc, finger_bends_and_comes_back);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
