/* test_hyper_scene.c - the hyperelastic plugin's components inside scenes,
 * solved to equilibrium by the built-in NewtonSolver (quasi-static):
 *  - a bar hanging under its own weight (nu = 0) stretches by
 *    rho g L^2 / (2 E) for ARAP, Corotational and NeoHookean;
 *  - held by PositionTarget springs instead, its top sags on average by
 *    exactly W / (n k) (the springs carry the weight), plus the targets'
 *    prescribed motion;
 *  - a cloth strip clamped at one end bends under its weight as a
 *    cantilever plate of stiffness D = LaplaceBeltramiBending's stiffness
 *    (its free long edges exercise the boundary rows). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/pliant.h"

static pl_sim *load(const char *xml)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, "scene", NULL, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    ck_assert_ptr_nonnull(s);
    pl_diag_free(&diag);
    return s;
}

/* Reads a component's n x 3 block field ("position", "rest_position"). */
static double *get_block(pl_sim *s, const char *path, int *n)
{
    size_t size = 1 << 20;
    char *buf = malloc(size), *p = buf;
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, path, buf, size, &err), PL_OK);
    int cap = 1024, k = 0;
    double *x = malloc(sizeof(double) * cap);
    for (char *end;; p = end) {
        double v = strtod(p, &end);
        if (end == p) break;
        if (k == cap) x = realloc(x, sizeof(double) * (cap *= 2));
        x[k++] = v;
    }
    free(buf);
    *n = k / 3;
    return x;
}

static void step(pl_sim *s, int n)
{
    pl_error err;
    int rc = pl_sim_step(s, n, &err);
    if (rc) {
        char b[1600];
        fprintf(stderr, "%s\n", pl_error_format(&err, b, sizeof b));
    }
    ck_assert_int_eq(rc, PL_OK);
}

static const double RHO = 1000.0, G = 9.81, L = 0.2, E = 1e6;

static const char *BAR =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">"
    "<RequiredPlugin name=\"hyperelastic\"/>"
    "<NewtonSolver quasiStatic=\"1\" tolerance=\"1e-12\"/>"
    "<Node name=\"bar\">"
    "<RegularGridTetrahedra min=\"0 0 0\" max=\"0.02 0.2 0.02\" n=\"3 11 3\"/>"
    "<MechanicalObject name=\"dofs\"/>"
    "<DiagonalMass massDensity=\"1000\"/>"
    "<%s youngModulus=\"1e6\" poissonRatio=\"0\"/>"
    "%s"
    "</Node></Node>";

/* Mean y displacement of the vertices with rest y near `y`. */
static double mean_dy(const double *x, const double *x0, int n, double y)
{
    double s = 0.0;
    int k = 0;
    for (int i = 0; i < n; ++i)
        if (fabs(x0[3 * i + 1] - y) < 1e-9) {
            s += x[3 * i + 1] - x0[3 * i + 1];
            ++k;
        }
    ck_assert_int_gt(k, 0);
    return s / k;
}

START_TEST(hanging_bar_stretches_by_rho_g_L2_over_2E)
{
    const char *mats[3] = {"ARAP", "Corotational", "NeoHookean"};
    char xml[2048];
    for (int m = 0; m < 3; ++m) {
        snprintf(xml, sizeof xml, BAR, mats[m], "<FixedConstraint box=\"-1 0.199 -1 1 1 1\"/>");
        pl_sim *s = load(xml);
        step(s, 1);
        int n, n0;
        double *x = get_block(s, "bar/dofs.position", &n);
        double *x0 = get_block(s, "bar/dofs.rest_position", &n0);
        ck_assert_int_eq(n, 99);
        double stretch = mean_dy(x, x0, n, L) - mean_dy(x, x0, n, 0.0);
        double expect = RHO * G * L * L / (2 * E);
        printf("hanging bar (%s): stretch %.6g m, rho g L^2/(2E) = %.6g m, ratio %.5f\n", mats[m],
               stretch, expect, stretch / expect);
        ck_assert_double_eq_tol(stretch / expect, 1.0, 0.01);
        free(x);
        free(x0);
        pl_sim_free(s);
    }
}
END_TEST

START_TEST(position_targets_carry_the_weight)
{
    char xml[4096], extra[1024];
    /* first load: find the top vertices */
    snprintf(xml, sizeof xml, BAR, "NeoHookean", "");
    pl_sim *s = load(xml);
    int n;
    double *x0 = get_block(s, "bar/dofs.rest_position", &n);
    pl_sim_free(s);
    int len = snprintf(extra, sizeof extra, "<PositionTarget name=\"hold\" stiffness=\"2000\" indices=\"");
    int ntop = 0;
    for (int i = 0; i < n; ++i)
        if (fabs(x0[3 * i + 1] - L) < 1e-9) {
            len += snprintf(extra + len, sizeof extra - len, "%d ", i);
            ++ntop;
        }
    /* the targets rise at 0.1 m/s: after 3 steps of 0.01 s, 3 mm */
    snprintf(extra + len, sizeof extra - len, "\" motion=\"velocity\" velocity=\"0 0.1 0\"/>");
    snprintf(xml, sizeof xml, BAR, "NeoHookean", extra);
    s = load(xml);
    step(s, 3);
    double *x = get_block(s, "bar/dofs.position", &n);
    double W = RHO * 0.02 * L * 0.02 * G;
    double expect = 0.003 - W / (ntop * 2000.0);
    double top = mean_dy(x, x0, n, L);
    printf("PositionTarget: mean top displacement %.8g m, expected 3 mm - W/(n k) = %.8g m\n", top,
           expect);
    ck_assert_double_eq_tol(top, expect, 1e-9);
    free(x);
    free(x0);
    pl_sim_free(s);
}
END_TEST

START_TEST(cloth_cantilever_bends_as_a_plate)
{
    /* strip 0.2 m x 0.05 m, 0.1 kg/m^2, clamped at x = 0 by two vertex rows.
     * The membrane is made nearly inextensible (E t = 1e7 N/m): the bending
     * energy (2H)^2 has no Gaussian-curvature term (a plate with nu = 1), so
     * a soft membrane lets the strip relax by anticlastic curvature (E t =
     * 1e5 N/m: 14% softer than the plate formula). */
    const double D = 0.05, h = 0.2 / 40, q = 100.0 * 1e-3 * G;
    const char *xml =
        "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">"
        "<RequiredPlugin name=\"hyperelastic\"/>"
        "<NewtonSolver quasiStatic=\"1\" tolerance=\"1e-12\"/>"
        "<Node name=\"cloth\">"
        "<RegularGridTriangles min=\"0 0 0\" max=\"0.2 0 0.05\" n=\"41 1 6\"/>"
        "<MechanicalObject name=\"dofs\"/>"
        "<DiagonalMass massDensity=\"100\" thickness=\"0.001\"/>"
        "<NeoHookean youngModulus=\"1e10\" poissonRatio=\"0.3\" thickness=\"0.001\"/>"
        "<LaplaceBeltramiBending stiffness=\"0.05\"/>"
        "<FixedConstraint box=\"-1 -1 -1 0.0051 1 1\"/>"
        "</Node></Node>";
    pl_sim *s = load(xml);
    step(s, 1);
    int n, n0;
    double *x = get_block(s, "cloth/dofs.position", &n);
    double *x0 = get_block(s, "cloth/dofs.rest_position", &n0);
    double tip = 0.0;
    int k = 0;
    for (int i = 0; i < n; ++i)
        if (x0[3 * i] > 0.2 - 1e-9) {
            tip += x[3 * i + 1] - x0[3 * i + 1];
            ++k;
        }
    tip /= k;
    /* Euler-Bernoulli per unit width, free length from the last clamped row */
    double Lf = 0.2 - h, expect = -q * pow(Lf, 4) / (8 * D);
    printf("cloth cantilever (LaplaceBeltramiBending): tip %.6g m, q L^4/(8D) = %.6g m, ratio %.4f\n",
           tip, expect, tip / expect);
    ck_assert_double_eq_tol(tip / expect, 1.0, 0.08);
    free(x);
    free(x0);
    pl_sim_free(s);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("hyper_scene");
    TCase *tc = tcase_create("scene");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, hanging_bar_stretches_by_rho_g_L2_over_2E);
    tcase_add_test(tc, position_targets_carry_the_weight);
    tcase_add_test(tc, cloth_cantilever_bends_as_a_plate);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
