/* test_sofa_vocab.c - SOFA's names and conventions mean in Pliant what they
 * mean in SOFA:
 *  - MechanicalObject dx dy dz and a loader's scale place the vertices as
 *    translation and scale3d do (compared with Pliant's own scene);
 *  - BoxROI selects the vertices whose rest positions lie in its box,
 *    bounds included, min and max in any order, and the FixedProjective-
 *    Constraint linked to its indices holds exactly those: under gravity
 *    they stay put, the others fall;
 *  - ConstantForceField force= on every point (no indices, as SOFA): the
 *    mean velocity after k steps is k h n f / M (momentum balance);
 *  - stiff RestShapeSprings without points hold the whole body; soft ones
 *    on indices are PositionTarget springs of that stiffness;
 *  - a triangle DiagonalMass has SOFA's per-area density (thickness 1);
 *  - SOFA modules and solver tuning are noted once, not per element;
 *  - Pliant's own scenes are left alone (a Pliant scene that names no SOFA
 *    component loads as before). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable/cable_test_util.h"

#define GMSH PL_SOURCE_DIR "/scenes/meshes/cube_low_res.msh"

static const char *SOFA_HEAD =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"%s\">\n"
    "<RequiredPlugin pluginName=\"Sofa.Component.Mass Sofa.Component.StateContainer\"/>\n"
    "<RequiredPlugin name=\"Sofa.Component.LinearSolver.Iterative\"/>\n"
    "<DefaultAnimationLoop/>\n"
    "<Node name=\"body\">\n"
    "<EulerImplicitSolver name=\"ode\"/><CGLinearSolver iterations=\"200\" tolerance=\"1e-12\" threshold=\"1e-30\"/>\n";

static pl_sim *sofa(const char *gravity, const char *body)
{
    static char xml[8192];
    int w = snprintf(xml, sizeof xml, SOFA_HEAD, gravity);
    snprintf(xml + w, sizeof xml - (size_t)w, "%s</Node></Node>\n", body);
    return ct_load(xml);
}

START_TEST(state_offsets_and_loader_scale)
{
    pl_sim *a = sofa("0 0 0", "<MeshGmshLoader name=\"loader\" filename=\"" GMSH "\" scale=\"2\"/>"
                              "<MechanicalObject name=\"dofs\" dx=\"1\" dy=\"-2\" dz=\"3\" "
                              "scale=\"0.5\"/>"
                              "<UniformMass totalMass=\"1\"/>");
    pl_sim *b = ct_load("<Node name=\"root\"><Node name=\"body\">"
                        "<MeshLoader filename=\"" GMSH "\" scale3d=\"2 2 2\"/>"
                        "<MechanicalObject name=\"dofs\" translation=\"1 -2 3\" "
                        "scale3d=\"0.5 0.5 0.5\"/></Node></Node>");
    int na, nb;
    const double *xa = ct_positions(a, "body/dofs", 1, &na);
    const double *xb = ct_positions(b, "body/dofs", 1, &nb);
    ck_assert_int_eq(na, nb);
    for (int i = 0; i < 3 * na; ++i) ck_assert_double_eq_tol(xa[i], xb[i], 1e-12);
    /* the cube spans [-3.5, 3.5]: scaled by 2 then 0.5 and moved by dx = 1 */
    double xmax = -1e300;
    for (int i = 0; i < na; ++i) xmax = fmax(xmax, xa[3 * i]);
    ck_assert_double_eq_tol(xmax, 4.5, 1e-6);
    pl_sim_free(a);
    pl_sim_free(b);
}
END_TEST

START_TEST(boxroi_holds_what_it_selects)
{
    /* a 1 m bar along x, vertices at x = 0, 0.25, ..., 1; the box (given max
     * corner first) ends exactly on the x = 0.25 layer, which it includes */
    pl_sim *s = sofa("0 -9.81 0", "<RegularGridTetrahedra min=\"0 0 0\" max=\"1 0.2 0.2\" "
                                  "n=\"5 2 2\"/>"
                                  "<MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"1\"/>"
                                  "<TetrahedronFEMForceField youngModulus=\"1e5\" "
                                  "poissonRatio=\"0.3\" method=\"polar\"/>"
                                  "<BoxROI name=\"ROI\" box=\"0.25 1 1  -0.1 -1 -1\"/>"
                                  "<FixedProjectiveConstraint indices=\"@ROI.indices\"/>");
    ct_step(s, 20);
    int n;
    const double *x = ct_positions(s, "body/dofs", 0, &n);
    const double *r = ct_positions(s, "body/dofs", 1, &n);
    int held = 0;
    for (int i = 0; i < n; ++i) {
        double d = fabs(x[3 * i + 1] - r[3 * i + 1]);
        if (r[3 * i] <= 0.25 + 1e-12) {
            ck_assert_double_eq(d, 0.0);
            ++held;
        } else if (r[3 * i] > 0.99) {
            ck_assert_double_gt(d, 1e-5); /* the free end sags */
        }
    }
    ck_assert_int_eq(held, 8); /* two layers of 2 x 2 */
    pl_sim_free(s);
}
END_TEST

START_TEST(constant_force_on_every_point)
{
    pl_sim *s = sofa("0 0 0", "<RegularGridTetrahedra min=\"0 0 0\" max=\"1 0.2 0.2\" "
                              "n=\"4 2 2\"/>"
                              "<MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"2\"/>"
                              "<TetrahedralCorotationalFEMForceField youngModulus=\"1e5\" "
                              "poissonRatio=\"0.3\" method=\"large\"/>"
                              "<ConstantForceField force=\"0 0 0.5\"/>");
    ct_step(s, 10);
    int n;
    pl_component *c = pl_sim_component(s, "body/dofs");
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    pl_buffer vb = ops->velocities(c, pl_sim_data(s));
    const double *v = pl_buffer_f64(&vb);
    n = (int)vb.rows;
    double mean = 0;
    for (int i = 0; i < n; ++i) mean += v[3 * i + 2] / n;
    ck_assert_int_eq(n, 16);
    ck_assert_double_eq_tol(mean, 10 * 0.01 * n * 0.5 / 2.0, 1e-9);
    pl_sim_free(s);
}
END_TEST

START_TEST(rest_shape_springs)
{
    pl_sim *s = sofa("0 -9.81 0", "<RegularGridTetrahedra min=\"0 0 0\" max=\"1 0.2 0.2\" "
                                  "n=\"3 2 2\"/>"
                                  "<MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"1\"/>"
                                  "<TetrahedronFEMForceField youngModulus=\"1e5\" "
                                  "poissonRatio=\"0.3\"/>"
                                  "<RestShapeSpringsForceField name=\"hold\" stiffness=\"1e12\"/>");
    ck_assert_str_eq(pl_sim_component(s, "body/hold")->type->name, "FixedConstraint");
    ct_step(s, 5);
    int n;
    const double *x = ct_positions(s, "body/dofs", 0, &n);
    const double *r = ct_positions(s, "body/dofs", 1, &n);
    for (int i = 0; i < 3 * n; ++i) ck_assert_double_eq(x[i], r[i]);
    pl_sim_free(s);
    s = sofa("0 -9.81 0", "<RegularGridTetrahedra min=\"0 0 0\" max=\"1 0.2 0.2\" n=\"3 2 2\"/>"
                          "<MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"1\"/>"
                          "<TetrahedronFEMForceField youngModulus=\"1e5\" poissonRatio=\"0.3\"/>"
                          "<RestShapeSpringsForceField name=\"soft\" points=\"0 1 2\" "
                          "stiffness=\"500\"/>");
    ck_assert_str_eq(pl_sim_component(s, "body/soft")->type->name, "PositionTarget");
    ck_assert_double_eq(ct_get(s, "body/soft.stiffness"), 500.0);
    pl_sim_free(s);
}
END_TEST

START_TEST(triangle_mass_per_area)
{
    pl_sim *s = sofa("0 0 0", "<RegularGridTriangles min=\"0 0 0\" max=\"1 0 1\" n=\"3 1 3\"/>"
                              "<MechanicalObject name=\"dofs\"/>"
                              "<DiagonalMass name=\"dm\" massDensity=\"2\"/>"
                              "<TriangleFEMForceField name=\"fem\" youngModulus=\"1e4\" "
                              "poissonRatio=\"0.3\" method=\"large\"/>");
    ck_assert_double_eq(ct_get(s, "body/dm.thickness"), 1.0);
    ck_assert_double_eq(ct_get(s, "body/fem.thickness"), 1.0);
    ck_assert_str_eq(pl_sim_component(s, "body/fem")->type->name, "Corotational");
    pl_sim_free(s);
}
END_TEST

static int count_warnings(const pl_diag *d, const char *what)
{
    int n = 0;
    for (int k = 0; k < d->count; ++k)
        if (d->items[k].code == PL_OK && strstr(d->items[k].msg, what)) ++n;
    return n;
}

START_TEST(notes_once)
{
    const char *xml =
        "<Node name=\"root\">\n"
        "<RequiredPlugin pluginName=\"Sofa.Component.Mass Sofa.Component.StateContainer\"/>\n"
        "<RequiredPlugin name=\"Sofa.Component.Visual\"/>\n"
        "<VisualStyle/><DefaultAnimationLoop/>\n"
        "<Node name=\"a\"><EulerImplicitSolver/><CGLinearSolver iterations=\"10\"/>\n"
        "<RegularGridTetrahedra min=\"0 0 0\" max=\"1 1 1\" n=\"2 2 2\"/>\n"
        "<MechanicalObject showObject=\"1\"/><UniformMass totalMass=\"1\"/></Node>\n"
        "<Node name=\"b\"><EulerImplicitSolver/><CGLinearSolver iterations=\"10\"/>\n"
        "<RegularGridTetrahedra min=\"2 0 0\" max=\"3 1 1\" n=\"2 2 2\"/>\n"
        "<MechanicalObject showObject=\"1\"/><UniformMass totalMass=\"1\"/></Node>\n"
        "</Node>\n";
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_string(xml, "scene.xml", NULL, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(count_warnings(&d, "SOFA modules"), 1);
    ck_assert_int_eq(count_warnings(&d, "3 SOFA modules"), 1);
    ck_assert_int_eq(count_warnings(&d, "CGLinearSolver"), 1);
    ck_assert_int_eq(count_warnings(&d, "'showObject' is ignored"), 1);
    ck_assert_int_eq(count_warnings(&d, "VisualStyle is a visual component"), 1);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

START_TEST(pliant_scenes_untouched)
{
    /* Pliant's own spelling, including a MechanicalObject that SOFA shares:
     * no warning at all, and a Vec3 template is fine */
    const char *xml = "<Node name=\"root\"><RegularGridTetrahedra min=\"0 0 0\" max=\"1 1 1\" "
                      "n=\"2 2 2\"/><MechanicalObject template=\"Vec3d\"/>"
                      "<FixedConstraint fixAll=\"1\"/></Node>";
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_string(xml, "scene.xml", NULL, &d);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(d.count, 0);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

/* The table as programs read it (pliant/sofa.h): one line per entry. */
START_TEST(vocabulary_as_tsv)
{
    FILE *f = tmpfile();
    ck_assert_ptr_nonnull(f);
    ck_assert_int_eq(pl_sofa_write_vocabulary(f, "tsv"), 0);
    ck_assert_int_eq(pl_sofa_write_vocabulary(f, "yaml"), -1);
    long n = ftell(f);
    rewind(f);
    char *text = calloc(1, (size_t)n + 1);
    ck_assert_uint_eq(fread(text, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    ck_assert_ptr_nonnull(strstr(text, "component\tTetrahedronFEMForceField\trenamed\t"
                                       "Corotational\thyperelastic\t"));
    ck_assert_ptr_nonnull(strstr(text, "component\tPositionEffector\trefused\t"));
    ck_assert_ptr_nonnull(strstr(text, "component\tSurfacePressureConstraint\tsame\t"
                                       "SurfacePressureConstraint\tcable\t"));
    ck_assert_ptr_nonnull(strstr(text, "attribute\tCGLinearSolver\titerations\tlowered\t"));
    int lines = 0;
    for (char *p = text; *p; ++p) lines += *p == '\n';
    ck_assert_int_gt(lines, 150);
    free(text);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_vocab");
    TCase *tc = tcase_create("vocab");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, state_offsets_and_loader_scale);
    tcase_add_test(tc, boxroi_holds_what_it_selects);
    tcase_add_test(tc, constant_force_on_every_point);
    tcase_add_test(tc, rest_shape_springs);
    tcase_add_test(tc, triangle_mass_per_area);
    tcase_add_test(tc, notes_once);
    tcase_add_test(tc, pliant_scenes_untouched);
    tcase_add_test(tc, vocabulary_as_tsv);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
