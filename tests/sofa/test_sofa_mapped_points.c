/* test_sofa_mapped_points.c - a SOFA mapped node that only follows its body
 * is kept as MappedPoints (collision plugin), which pliant regress records
 * like SOFA's mapped MechanicalObjects (mapped 1):
 *  - one tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1) falls and deforms with
 *    one vertex fixed; a point p inside it and one outside follow
 *    (1 - px - py - pz) x0 + px x1 + py x2 + pz x3 (the barycentric weights
 *    of the unit tetrahedron, extrapolated outside) after 5 steps, and they
 *    did move;
 *  - under an IdentityMapping the points are the body's vertices;
 *  - a mapped node whose points come from nowhere Pliant reads, or whose
 *    mapping does not map the body's state, is dropped as before (drawing only), and
 *    a broken .sph file is refused by name. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cable/cable_test_util.h"
#include "test_tmp.h"

static char dir[1024];

static void write_file(const char *name, const char *text)
{
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    fputs(text, f);
    fclose(f);
}

static void setup(void)
{
    test_tmp_template(dir, sizeof dir, "mapped_points");
    ck_assert_ptr_nonnull(mkdtemp(dir));
    write_file("tet.vtk", "# vtk DataFile Version 2.0\none tetrahedron\nASCII\n"
                          "DATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
                          "0 0 0\n1 0 0\n0 1 0\n0 0 1\nCELLS 1 5\n4 0 1 2 3\n"
                          "CELL_TYPES 1\n10\n");
    write_file("pts.sph", "sph 1.0\n#nums 2\n\nsphe 1 0.2 0.3 0.1 0.05\n"
                          "sphe 2 -0.1 0.4 0.2 0.05\n");
    write_file("bad.sph", "sph 1.0\nsphe 1 0.2 zero 0.1 0.05\n");
}

static void teardown(void) { test_tmp_rmtree(dir); }

/* The body and a child node holding `child`. */
static pl_sim *load(const char *child, pl_diag *d)
{
    char xml[8192];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
             "<DefaultAnimationLoop/>\n"
             "<Node name=\"body\"><EulerImplicitSolver/>\n"
             "<CGLinearSolver iterations=\"200\" tolerance=\"1e-12\" threshold=\"1e-12\"/>\n"
             "<MeshVTKLoader name=\"loader\" filename=\"%s/tet.vtk\"/>\n"
             "<MechanicalObject name=\"dofs\" src=\"@loader\"/><UniformMass totalMass=\"1\"/>\n"
             "<TetrahedronFEMForceField youngModulus=\"300\" poissonRatio=\"0.3\"/>\n"
             "<FixedProjectiveConstraint indices=\"0\"/>\n"
             "<Node name=\"map\">%s</Node></Node></Node>\n",
             dir, child);
    pl_diag_init(d);
    pl_sim *s = pl_sim_load_string(xml, "scene.scn", NULL, d);
    return s;
}

static void mapped_positions(pl_sim *s, const char *path, double *x, int n)
{
    char buf[4096];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, path, buf, sizeof buf, &err), PL_OK);
    char *p = buf, *end;
    for (int i = 0; i < 3 * n; ++i, p = end) {
        x[i] = strtod(p, &end);
        ck_assert_ptr_ne(end, p);
    }
    while (*p == ' ') ++p;
    ck_assert_int_eq(*p, '\0'); /* exactly n points */
}

static void check_barycentric(pl_sim *s, const char *path, const double *p, int n)
{
    ct_step(s, 5);
    int nv;
    const double *x = ct_positions(s, "body/dofs", 0, &nv);
    ck_assert_int_eq(nv, 4);
    double y[6];
    mapped_positions(s, path, y, n);
    for (int i = 0; i < n; ++i) {
        const double *q = p + 3 * i;
        double w[4] = {1.0 - q[0] - q[1] - q[2], q[0], q[1], q[2]};
        for (int k = 0; k < 3; ++k) {
            double e = 0.0;
            for (int j = 0; j < 4; ++j) e += w[j] * x[3 * j + k];
            ck_assert_double_eq_tol(y[3 * i + k], e, 1e-12);
        }
        ck_assert_double_gt(fabs(y[3 * i + 1] - q[1]), 1e-6); /* it fell */
    }
}

START_TEST(barycentric_points_follow_the_tetrahedron)
{
    pl_diag d;
    pl_sim *s = load("<MechanicalObject name=\"pts\" position=\"0.2 0.3 0.1  -0.1 0.4 0.2\"/>"
                     "<BarycentricMapping input=\"@../dofs\" output=\"@pts\"/>",
                     &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert_str_eq(pl_sim_component(s, "body/map/pts")->type->name, "MappedPoints");
    const double p[6] = {0.2, 0.3, 0.1, -0.1, 0.4, 0.2};
    check_barycentric(s, "body/map/pts.position", p, 2);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

START_TEST(sphere_centres_from_a_sphere_loader)
{
    pl_diag d;
    char child[2048];
    snprintf(child, sizeof child,
             "<SphereLoader filename=\"%s/pts.sph\"/>"
             "<MechanicalObject name=\"spheres\" position=\"@[-1].position\"/>"
             "<SphereCollisionModel listRadius=\"@[-2].listRadius\"/>"
             "<BarycentricMapping/>",
             dir);
    pl_sim *s = load(child, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    const double p[6] = {0.2, 0.3, 0.1, -0.1, 0.4, 0.2};
    check_barycentric(s, "body/map/spheres.position", p, 2);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

START_TEST(identity_points_are_the_vertices)
{
    pl_diag d;
    pl_sim *s = load("<MechanicalObject name=\"surf\"/><IdentityMapping/>", &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    ct_step(s, 3);
    int nv;
    const double *x = ct_positions(s, "body/dofs", 0, &nv);
    double y[12];
    mapped_positions(s, "body/map/surf.position", y, 4);
    for (int i = 0; i < 12; ++i) ck_assert_double_eq(y[i], x[i]);
    ck_assert_double_lt(x[4], -1e-6); /* vertex 1 fell */
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

START_TEST(unreadable_points_drop_or_fail)
{
    pl_diag d;
    /* points linked from something Pliant does not read: drawing only */
    pl_sim *s = load("<MechanicalObject name=\"pts\" position=\"@../dofs.position\"/>"
                     "<BarycentricMapping/>",
                     &d);
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_null(pl_sim_component(s, "body/map/pts"));
    pl_sim_free(s);
    pl_diag_free(&d);
    /* a mapping that does not drive these points: they do not follow the body */
    s = load("<MechanicalObject name=\"pts\" position=\"0.2 0.3 0.1\"/>"
             "<BarycentricMapping input=\"@../loader\" output=\"@pts\"/>",
             &d);
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_null(pl_sim_component(s, "body/map/pts"));
    pl_sim_free(s);
    pl_diag_free(&d);
    char child[2048];
    snprintf(child, sizeof child,
             "<SphereLoader filename=\"%s/bad.sph\"/>"
             "<MechanicalObject name=\"spheres\" position=\"@[-1].position\"/>"
             "<BarycentricMapping/>",
             dir);
    s = load(child, &d);
    ck_assert_ptr_null(s);
    const pl_error *e = ct_find_error(&d, "bad.sph:2: expected 'sphe index x y z radius'");
    ck_assert_ptr_nonnull(e);
    pl_diag_free(&d);
}
END_TEST

int main(void)
{
    Suite *su = suite_create("sofa_mapped_points");
    TCase *tc = tcase_create("mapped_points");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, barycentric_points_follow_the_tetrahedron);
    tcase_add_test(tc, sphere_centres_from_a_sphere_loader);
    tcase_add_test(tc, identity_points_are_the_vertices);
    tcase_add_test(tc, unreadable_points_drop_or_fail);
    suite_add_tcase(su, tc);
    SRunner *sr = srunner_create(su);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
