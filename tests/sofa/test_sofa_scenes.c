/* test_sofa_scenes.c - the project's own SOFA-style scene files
 * (tests/sofa/scenes/, written for Pliant; SOFA's and SoftRobots' scenes
 * are not part of the project), so that the SOFA path is tested without them:
 *  - liver_falling.scn: a liver falling freely under SOFA's implicit Euler
 *    (no damping, nothing holding it): a uniform translation has no elastic
 *    force and K v = 0, so every vertex moves by g h^2 n (n + 1) / 2 after n
 *    steps (v_k = k g h, x_n = x_0 + h sum v_k), to the CG's precision;
 *  - liver_hanging.scn: a damped liver hanging from three vertices: those
 *    stay exactly where they are, the rest sags, every value finite; its
 *    method="large" FEM takes SOFA's rotation from the edges;
 *  - broken scenes: each refused with its file, its line and the component,
 *    what it changes and what to use instead; a drawing component is one
 *    warning, not an error; an unknown Pliant type names the plugin that
 *    provides it. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable/cable_test_util.h"

#define SCENES PL_SOURCE_DIR "/tests/sofa/scenes/"

static pl_sim *load(const char *file, pl_diag *d)
{
    pl_diag_init(d);
    pl_sim *s = pl_sim_load_file(file, NULL, d);
    if (!s) pl_diag_print(d, stderr);
    ck_assert_ptr_nonnull(s);
    return s;
}

START_TEST(falling_liver_moves_as_free_fall)
{
    pl_diag d;
    pl_sim *s = load(SCENES "liver_falling.scn", &d);
    /* the SOFA names became SOFA's integrator and Pliant's corotational FEM */
    ck_assert_str_eq(pl_sim_component(s, "odesolver")->type->name, "LinearizedEulerSolver");
    ck_assert_str_eq(pl_sim_component(s, "Liver/FEM")->type->name, "Corotational");
    enum { N = 10 };
    const double h = 0.02, g = -9.81, fall = g * h * h * N * (N + 1) / 2.0;
    int n;
    ct_step(s, N);
    const double *x = ct_positions(s, "Liver/dofs", 0, &n);
    const double *r = ct_positions(s, "Liver/dofs", 1, &n);
    ck_assert_int_eq(n, 181);
    double worst = 0;
    for (int i = 0; i < n; ++i) {
        worst = fmax(worst, fabs(x[3 * i + 1] - r[3 * i + 1] - fall));
        worst = fmax(worst, fabs(x[3 * i] - r[3 * i]) + fabs(x[3 * i + 2] - r[3 * i + 2]));
    }
    printf("liver_falling.scn: %d steps fell %.6f (g h^2 n (n+1)/2 = %.6f), largest vertex "
           "deviation %.2e\n", N, x[1] - r[1], fall, worst);
    ck_assert_double_lt(worst, 1e-9 * fabs(fall));
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

START_TEST(hanging_liver_keeps_its_fixed_vertices)
{
    pl_diag d;
    pl_sim *s = load(SCENES "liver_hanging.scn", &d);
    ck_assert_double_eq(ct_get(s, "odesolver.rayleighMass"), 0.1);
    ck_assert_double_eq(ct_get(s, "odesolver.rayleighStiffness"), 0.1);
    /* method="large" under SOFA's integrator: the rotation from the element's edges, as SOFA's */
    char rot[64];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, "Liver/FEM.rotation", rot, sizeof rot, &err), PL_OK);
    ck_assert_str_eq(rot, "edges");
    ct_step(s, 20);
    int n;
    const double *x = ct_positions(s, "Liver/dofs", 0, &n);
    const double *r = ct_positions(s, "Liver/dofs", 1, &n);
    static const int fixed[] = {3, 39, 64};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) ck_assert_double_eq(x[3 * fixed[k] + j], r[3 * fixed[k] + j]);
    double sag = 0;
    for (int i = 0; i < 3 * n; ++i) ck_assert(isfinite(x[i]));
    for (int i = 0; i < n; ++i) sag = fmin(sag, x[3 * i + 1] - r[3 * i + 1]);
    ck_assert_double_lt(sag, -1e-2); /* it hangs: the free part went down */
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

/* Mean x displacement of the vertices at rest x = at. */
static double mean_dx(const double *x, const double *r, int n, double at)
{
    double sum = 0;
    int count = 0;
    for (int i = 0; i < n; ++i)
        if (fabs(r[3 * i] - at) < 1e-9) sum += x[3 * i] - r[3 * i], ++count;
    ck_assert_int_gt(count, 0);
    return sum / count;
}

/* bar_two_moduli.scn: IndexValueMapper over BoxROI tetrahedronIndices gives
 * the FEM one value per element: the values read back, and at rest under
 * the 10 N pull each half stretches by F (L/2) / (E A), the stiff one ten
 * times less. */
START_TEST(bar_with_two_moduli_stretches_per_half)
{
    pl_diag d;
    pl_sim *s = load(SCENES "bar_two_moduli.scn", &d);
    char text[2048];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, "Bar/FEM.youngModulus", text, sizeof text, &err), PL_OK);
    int soft = 0, stiff = 0, other = 0;
    for (char *p = text, *end;; p = end) {
        double v = strtod(p, &end);
        if (end == p) break;
        if (v == 1e5) ++soft;
        else if (v == 1e6) ++stiff;
        else ++other;
    }
    printf("bar_two_moduli.scn: %d elements at 1e5 Pa, %d at 1e6 Pa, %d other\n", soft, stiff,
           other);
    ck_assert_int_eq(soft, 24); /* 8 cells x 6 tetrahedra, half each side of x = 0.4 */
    ck_assert_int_eq(stiff, 24);
    ck_assert_int_eq(other, 0);
    ct_step(s, 150);
    int n;
    const double *x = ct_positions(s, "Bar/dofs", 0, &n);
    const double *r = ct_positions(s, "Bar/dofs", 1, &n);
    double mid = mean_dx(x, r, n, 0.4), end = mean_dx(x, r, n, 0.8);
    const double F = 10, A = 0.01, half = 0.4;
    printf("bar_two_moduli.scn: soft half stretched %.4e m (F L/2 / (E A) = %.4e), stiff half "
           "%.4e m (%.4e)\n", mid, F * half / (1e5 * A), end - mid, F * half / (1e6 * A));
    ck_assert_double_eq_tol(mid, F * half / (1e5 * A), 0.01 * F * half / (1e5 * A));
    /* the end load is 4 equal vertex forces, not a uniform traction: 1% */
    ck_assert_double_eq_tol(end - mid, F * half / (1e6 * A), 0.03 * F * half / (1e6 * A));
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

/* block_on_plane.scn: at rest on SOFA's penalty plane the 18 bottom vertices
 * of a stiff block sink by m g / (k 18); the same block under Pliant's
 * LocalGlobalSolver (the half-space projection) and NewtonSolver
 * (gradient and Hessian) rests at the same depth. */
static double block_depth(pl_sim *s, double *spread)
{
    int n;
    const double *x = ct_positions(s, "Block/dofs", 0, &n);
    const double *r = ct_positions(s, "Block/dofs", 1, &n);
    double sum = 0, lo = 1e300, hi = -1e300;
    int count = 0;
    for (int i = 0; i < n; ++i)
        if (r[3 * i + 1] == 0) {
            sum += x[3 * i + 1], ++count;
            lo = fmin(lo, x[3 * i + 1]), hi = fmax(hi, x[3 * i + 1]);
        }
    ck_assert_int_eq(count, 18);
    *spread = hi - lo;
    return -sum / count;
}

static const char *PLIANT_BLOCK =
    "<Node name=\"root\" gravity=\"0 -9.81 0\" dt=\"0.01\">\n"
    "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
    "%s\n"
    "<Node name=\"Block\">\n"
    "<MeshLoader name=\"loader\" filename=\"" PL_SOURCE_DIR "/tests/sofa/scenes/meshes/bar_9x2x2.vtk\"/>\n"
    "<MechanicalObject name=\"dofs\"/><UniformMass totalMass=\"0.5\"/>\n"
    "<Corotational youngModulus=\"1e8\" poissonRatio=\"0.3\"/>\n"
    "<PlaneForceField name=\"floor\" normal=\"0 1 0\" d=\"0\" stiffness=\"1000\"/>\n"
    "</Node></Node>\n";

START_TEST(block_rests_on_penalty_plane)
{
    const double depth = 0.5 * 9.81 / (1000 * 18);
    double spread;
    pl_diag d;
    pl_sim *s = load(SCENES "block_on_plane.scn", &d);
    ck_assert_str_eq(pl_sim_component(s, "Block/floor")->type->name, "PlaneForceField");
    ct_step(s, 60);
    double sofa = block_depth(s, &spread);
    printf("block_on_plane.scn (LinearizedEulerSolver): depth %.6e m, m g / (k 18) = %.6e, "
           "spread %.1e\n", sofa, depth, spread);
    fflush(stdout);
    ck_assert_double_eq_tol(sofa, depth, 1e-3 * depth);
    pl_sim_free(s);
    pl_diag_free(&d);
    static const char *const loops[] = {
        "<NewtonSolver/>",
        "<LocalGlobalSolver iterations=\"200\" damping=\"20\"/><SparseInverseSolver/>",
    };
    for (int k = 0; k < 2; ++k) {
        char xml[4096];
        snprintf(xml, sizeof xml, PLIANT_BLOCK, loops[k]);
        pl_diag_init(&d);
        s = pl_sim_load_string(xml, "block.xml", NULL, &d);
        if (!s) pl_diag_print(&d, stderr);
        ck_assert_ptr_nonnull(s);
        ct_step(s, 60);
        double got = block_depth(s, &spread);
        printf("block on PlaneForceField (%s): depth %.6e m (m g / (k 18) = %.6e)\n",
               k ? "LocalGlobalSolver" : "NewtonSolver", got, depth);
        fflush(stdout);
        ck_assert_double_eq_tol(got, depth, 1e-3 * depth);
        pl_sim_free(s);
        pl_diag_free(&d);
    }
}
END_TEST

/* A TetrahedronFEMForceField without method is SOFA's default, "large": the
 * rotation from the element's edges under SOFA's integrator. */
START_TEST(fem_without_method_is_large)
{
    pl_diag d = {0};
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_string(
        "<Node name=\"root\" dt=\"0.01\">\n"
        "<RequiredPlugin pluginName=\"Sofa.Component.ODESolver.Backward\"/>\n"
        "<Node name=\"b\"><EulerImplicitSolver/><SparseLDLSolver/>\n"
        "<MeshVTKLoader name=\"loader\" filename=\"" SCENES "meshes/bar_9x2x2.vtk\"/>\n"
        "<MechanicalObject/><UniformMass totalMass=\"1\"/>\n"
        "<TetrahedronFEMForceField name=\"FEM\" youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
        "</Node></Node>\n",
        "fem.scn", NULL, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    char rot[32];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, "b/FEM.rotation", rot, sizeof rot, &err), PL_OK);
    ck_assert_str_eq(rot, "edges");
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

/* PlaneForceField's damping is SOFA's explicit force damping * d * v (d < 0
 * below the plane), held through the step; its spring is implicit.  One
 * point of mass m, 1 cm below the plane, sliding along it at 1 m/s, one step
 * h without gravity: vx = 1 + h damping d0 / m, y = d0 / (1 + h^2 k / m),
 * under NewtonSolver and LinearizedEulerSolver alike. */
START_TEST(plane_damping_is_explicit)
{
    static const char *const loops[] = {"<NewtonSolver/>",
                                        "<LinearizedEulerSolver linearSolver=\"direct\"/>"};
    const double h = 0.01, m = 2, k = 1000, c = 50, d0 = -0.01;
    for (int l = 0; l < 2; ++l) {
        char xml[1024];
        snprintf(xml, sizeof xml,
                 "<Node name=\"root\" gravity=\"0 0 0\" dt=\"0.01\">%s\n<Node name=\"p\">\n"
                 "<MechanicalObject name=\"dofs\" position=\"0 -0.01 0\" velocity=\"1 0 0\"/>\n"
                 "<UniformMass totalMass=\"2\"/>\n<PlaneForceField normal=\"0 1 0\" d=\"0\" "
                 "stiffness=\"1000\" damping=\"50\"/>\n</Node></Node>\n",
                 loops[l]);
        pl_diag d;
        pl_diag_init(&d);
        pl_sim *s = pl_sim_load_string(xml, "point.xml", NULL, &d);
        if (!s) pl_diag_print(&d, stderr);
        ck_assert_ptr_nonnull(s);
        ct_step(s, 1);
        int n;
        const double *x = ct_positions(s, "p/dofs", 0, &n);
        double vx = x[0] / h, y = x[1];
        printf("PlaneForceField, one step (%s): vx %.10f (1 + h c d0 / m = %.10f), y %.10f "
               "(d0 / (1 + h^2 k / m) = %.10f)\n", loops[l], vx, 1 + h * c * d0 / m, y,
               d0 / (1 + h * h * k / m));
        ck_assert_double_eq_tol(vx, 1 + h * c * d0 / m, 1e-9);
        ck_assert_double_eq_tol(y, d0 / (1 + h * h * k / m), 1e-9);
        pl_sim_free(s);
        pl_diag_free(&d);
    }
}
END_TEST

/* grid_on_floor.scn: SOFA's grid split into tetrahedra is Pliant's
 * RegularGridTetrahedra with SOFA's vertex numbering (x fastest, then y, then
 * z); the still inline floor a MeshObstacle, the surface's models a
 * SurfaceCollisionModel, the pipeline a CollisionPipeline with the
 * response's mu.  The beam falls 5 mm and rests contactDistance (1 mm) above
 * the floor. */
START_TEST(grid_falls_onto_inline_floor)
{
    pl_diag d;
    pl_sim *s = load(SCENES "grid_on_floor.scn", &d);
    ck_assert_str_eq(pl_sim_component(s, "Beam/topo")->type->name, "RegularGridTetrahedra");
    ck_assert_str_eq(pl_sim_component(s, "Floor/floorModel")->type->name, "MeshObstacle");
    ck_assert_str_eq(pl_sim_component(s, "Beam/surface")->type->name,
                     "SurfaceCollisionModel");
    ck_assert_double_eq(ct_get(s, "collisionPipeline.mu"), 0.5);
    ck_assert_double_eq(ct_get(s, "collisionPipeline.alarmDistance"), 0.02);
    int n;
    const double *r = ct_positions(s, "Beam/dofs", 1, &n);
    ck_assert_int_eq(n, 9 * 3 * 3);
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 9; ++i) {
                const double *p = r + 3 * (i + 9 * (j + 3 * k));
                ck_assert_double_eq_tol(p[0], 0.4 * i / 8, 1e-15);
                ck_assert_double_eq_tol(p[1], 0.1 * j / 2, 1e-15);
                ck_assert_double_eq_tol(p[2], 0.006 + 0.1 * k / 2, 1e-15);
            }
    ct_step(s, 40);
    const double *x = ct_positions(s, "Beam/dofs", 0, &n);
    double low = 1e300, high = -1e300;
    for (int i = 0; i < 27; ++i) /* the bottom layer (k = 0) */
        low = fmin(low, x[3 * i + 2]), high = fmax(high, x[3 * i + 2]);
    printf("grid_on_floor.scn after 40 steps: bottom at z in [%.6f, %.6f] (contactDistance "
           "0.001 above the floor z = 0)\n", low, high);
    ck_assert_double_gt(low, 0.001 - 2e-4);
    ck_assert_double_lt(high, 0.001 + 2e-4);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

typedef struct {
    const char *file;
    int line;
    const char *where; /* the component named */
    const char *what;  /* the message contains it */
} broken_case;

static const broken_case BROKEN[] = {
    {"broken_rigid_state.scn", 9, "rigid", "\"Rigid3\""},
    {"broken_physics.scn", 16, "PartialFixedProjectiveConstraint", "closest: PointOnPlaneConstraint"},
    {"broken_plugin_type.scn", 13, "PositionEffector", "SoftRobots.Inverse"},
    {"broken_plane_normal.scn", 12, "PlaneForceField", "non-zero, finite normal"},
    {"broken_value_mapper.scn", 11, "values", "48 is not an element of the node's mesh"},
};

START_TEST(broken_scene_is_refused_with_file_line_component)
{
    const broken_case *c = &BROKEN[_i];
    char path[512];
    snprintf(path, sizeof path, SCENES "%s", c->file);
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_file(path, NULL, &d);
    const pl_error *e = ct_find_error(&d, c->what);
    if (s || !e) pl_diag_print(&d, stderr);
    ck_assert_ptr_null(s);
    ck_assert_ptr_nonnull(e);
    ck_assert_ptr_nonnull(strstr(e->file, c->file));
    ck_assert_int_eq(e->line, c->line);
    char text[1024];
    pl_error_format(e, text, sizeof text);
    ck_assert_msg(strstr(text, c->where), "'%s' does not name %s", text, c->where);
    /* a drawing component is a warning, once, not an error */
    int visual_warnings = 0;
    for (int k = 0; k < d.count; ++k) {
        const pl_error *w = &d.items[k];
        if (strstr(w->msg, "VisualStyle") || strstr(w->where, "VisualStyle")) {
            ck_assert_int_eq(w->code, PL_OK);
            ++visual_warnings;
        }
    }
    ck_assert_int_le(visual_warnings, 1);
    pl_diag_free(&d);
}
END_TEST

/* A Pliant scene using a plugin's type without requiring the plugin: the
 * error names the plugin to require. */
START_TEST(unknown_type_names_its_plugin)
{
    pl_diag d = ct_load_fail("<Node name=\"root\" dt=\"0.01\">\n"
                             "<Node name=\"b\">\n"
                             "<NeoHookean name=\"law\" youngModulus=\"1e4\"/>\n"
                             "</Node></Node>\n");
    const pl_error *e = ct_find_error(&d, "<RequiredPlugin name=\"hyperelastic\"/>");
    if (!e) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(e);
    ck_assert_int_eq(e->line, 3);
    pl_diag_free(&d);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_scenes");
    TCase *tc = tcase_create("scenes");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, falling_liver_moves_as_free_fall);
    tcase_add_test(tc, hanging_liver_keeps_its_fixed_vertices);
    tcase_add_test(tc, bar_with_two_moduli_stretches_per_half);
    tcase_add_test(tc, block_rests_on_penalty_plane);
    tcase_add_test(tc, plane_damping_is_explicit);
    tcase_add_test(tc, fem_without_method_is_large);
    tcase_add_test(tc, grid_falls_onto_inline_floor);
    tcase_add_loop_test(tc, broken_scene_is_refused_with_file_line_component, 0,
                        (int)(sizeof BROKEN / sizeof BROKEN[0]));
    tcase_add_test(tc, unknown_type_names_its_plugin);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
