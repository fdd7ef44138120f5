/* test_components.c - built-in components in real scenes: a mesh file is
 * loaded into a MechanicalObject, masses integrate the density exactly,
 * boxes select the right vertices, broken mesh files stop the scene with
 * the component's line, exporters write where they are told. */
#include <check.h>
#include <math.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "test_tmp.h"

#define MESHES PL_SOURCE_DIR "/scenes/meshes"

static pl_diag diag;
static void setup(void) { pl_diag_init(&diag); }
static void teardown(void) { pl_diag_free(&diag); }

static pl_sim *load(const char *xml)
{
    pl_sim *s = pl_sim_load_string(xml, PL_SOURCE_DIR "/scenes/inline.xml", NULL, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    return s;
}

static double total_mass(pl_sim *s, const char *path, int n)
{
    pl_component *m = pl_sim_component(s, path);
    ck_assert_ptr_nonnull(m);
    const pl_mass_ops *ops = pl_component_role(m, PL_ROLE_MASS);
    double *mass = calloc((size_t)n, sizeof *mass), sum = 0;
    pl_error err;
    ck_assert_int_eq(ops->add_vertex_masses(m, mass, n, &err), PL_OK);
    for (int i = 0; i < n; ++i) sum += mass[i];
    free(mass);
    return sum;
}

static int state_count(pl_sim *s, const char *path)
{
    pl_component *c = pl_sim_component(s, path);
    ck_assert_ptr_nonnull(c);
    return ((const pl_state_ops *)pl_component_role(c, PL_ROLE_STATE))->count(c);
}

START_TEST(a_gmsh_liver_loads_into_a_mechanical_object_with_its_mass)
{
    pl_sim *s = load("<Node name=\"root\">\n"
                     "  <Node name=\"liver\">\n"
                     "    <MeshLoader name=\"mesh\" filename=\"meshes/liver.msh\"/>\n"
                     "    <MechanicalObject name=\"dofs\" src=\"@mesh\"/>\n"
                     "    <UniformMass name=\"mass\" totalMass=\"2.5\"/>\n"
                     "  </Node>\n"
                     "</Node>\n");
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(state_count(s, "liver/dofs"), 181);
    ck_assert(fabs(total_mass(s, "liver/mass", 181) - 2.5) < 1e-12);
    pl_sim_free(s);
}
END_TEST

START_TEST(diagonal_mass_integrates_density_over_a_scaled_box)
{
    /* 0.2 x 0.1 x 0.1 m box scaled x2 -> 0.4 x 0.2 x 0.2 = 0.016 m^3 */
    pl_sim *s = load("<Node name=\"root\">\n"
                     "  <RegularGridTetrahedra name=\"grid\" min=\"0 0 0\" max=\"0.2 0.1 0.1\" "
                     "n=\"5 3 4\"/>\n"
                     "  <MechanicalObject name=\"dofs\" scale3d=\"2 2 2\"/>\n"
                     "  <DiagonalMass name=\"mass\" massDensity=\"1000\"/>\n"
                     "</Node>\n");
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(state_count(s, "dofs"), 60);
    ck_assert(fabs(total_mass(s, "mass", 60) - 16.0) < 1e-9);
    pl_sim_free(s);
}
END_TEST

START_TEST(cloth_mass_uses_thickness)
{
    pl_sim *s = load("<Node name=\"root\">\n"
                     "  <RegularGridTriangles min=\"0 0 0\" max=\"1 0 2\" n=\"4 1 5\"/>\n"
                     "  <MechanicalObject name=\"dofs\"/>\n"
                     "  <DiagonalMass name=\"mass\" massDensity=\"1000\" thickness=\"0.002\"/>\n"
                     "</Node>\n");
    ck_assert_ptr_nonnull(s);
    ck_assert(fabs(total_mass(s, "mass", 20) - 1000 * 0.002 * 2.0) < 1e-12);
    pl_sim_free(s);
}
END_TEST

START_TEST(fixed_constraint_selects_a_box_face)
{
    pl_sim *s = load("<Node name=\"root\">\n"
                     "  <RegularGridTetrahedra min=\"0 0 0\" max=\"1 0.2 0.2\" n=\"6 3 3\"/>\n"
                     "  <MechanicalObject name=\"dofs\"/>\n"
                     "  <FixedConstraint name=\"fix\" box=\"-0.01 -1 -1 0.01 1 1\" indices=\"53\"/>\n"
                     "</Node>\n");
    ck_assert_ptr_nonnull(s);
    pl_component *f = pl_sim_component(s, "fix");
    const pl_prescribed_ops *ops = pl_component_role(f, PL_ROLE_PRESCRIBED);
    const int *idx;
    int n = ops->indices(f, &idx);
    ck_assert_int_eq(n, 10); /* the 3x3 vertices at x = 0, plus vertex 53 */
    ck_assert_int_eq(idx[n - 1], 53);
    double *x = malloc(3 * (size_t)n * sizeof *x);
    pl_error err;
    ck_assert_int_eq(ops->positions_at(f, pl_sim_data(s), 1.0, x, &err), PL_OK);
    for (int k = 0; k < n - 1; ++k) ck_assert(x[3 * k] == 0.0);
    free(x);
    pl_sim_free(s);
}
END_TEST

START_TEST(prescribed_motion_rotates_about_its_axis)
{
    pl_sim *s = load("<Node name=\"root\">\n"
                     "  <RegularGridTetrahedra min=\"0 -1 -1\" max=\"1 1 1\" n=\"2 3 3\"/>\n"
                     "  <MechanicalObject name=\"dofs\"/>\n"
                     "  <PrescribedMotion name=\"turn\" box=\"0.9 -2 -2 1.1 2 2\" axis=\"1 0 0\" "
                     "angularVelocity=\"1.5707963267948966\" velocity=\"0 0 0.5\"/>\n"
                     "</Node>\n");
    ck_assert_ptr_nonnull(s);
    pl_component *p = pl_sim_component(s, "turn");
    const pl_prescribed_ops *ops = pl_component_role(p, PL_ROLE_PRESCRIBED);
    const int *idx;
    int n = ops->indices(p, &idx);
    ck_assert_int_eq(n, 9);
    double x[27];
    pl_error err;
    ck_assert_int_eq(ops->positions_at(p, pl_sim_data(s), 1.0, x, &err), PL_OK);
    /* after 1 s: a quarter turn about x through the face centre (1, 0, 0),
     * then 0.5 m along z: (1, y, z) -> (1, -z, y + 0.5) */
    int n_rest;
    pl_component *st = pl_sim_component(s, "dofs");
    const pl_state_ops *so = pl_component_role(st, PL_ROLE_STATE);
    pl_buffer rb = so->rest_positions(st);
    const double *r = rb.data;
    n_rest = (int)rb.rows;
    ck_assert_int_eq(n_rest, 18);
    for (int k = 0; k < n; ++k) {
        const double *x0 = &r[3 * idx[k]];
        ck_assert(fabs(x[3 * k] - 1.0) < 1e-12);
        ck_assert(fabs(x[3 * k + 1] + x0[2]) < 1e-12);
        ck_assert(fabs(x[3 * k + 2] - (x0[1] + 0.5)) < 1e-12);
    }
    pl_sim_free(s);
}
END_TEST

START_TEST(prescribed_motion_plays_keyframed_poses)
{
    /* a quarter turn about z through (0, 0, 0) and a move along x then y,
     * keyed at 0, 1, 2 s, on top of a constant velocity along z */
    pl_sim *s = load("<Node name=\"root\">\n"
                     "  <RegularGridTetrahedra min=\"0 0 0\" max=\"1 1 1\" n=\"2 2 2\"/>\n"
                     "  <MechanicalObject name=\"dofs\"/>\n"
                     "  <PrescribedMotion name=\"base\" indices=\"1 7\" axis=\"0 0 1\" center=\"0 0 0\" "
                     "velocity=\"0 0 0.25\" times=\"0 1 2\" translations=\"0 0 0  1 0 0  1 1 0\" "
                     "angles=\"0 0 1.5707963267948966\"/>\n"
                     "</Node>\n");
    ck_assert_ptr_nonnull(s);
    pl_component *p = pl_sim_component(s, "base");
    const pl_prescribed_ops *ops = pl_component_role(p, PL_ROLE_PRESCRIBED);
    const int *idx;
    ck_assert_int_eq(ops->indices(p, &idx), 2);
    pl_component *st = pl_sim_component(s, "dofs");
    pl_buffer rb = ((const pl_state_ops *)pl_component_role(st, PL_ROLE_STATE))->rest_positions(st);
    const double *r = rb.data;
    const double ts[4] = {0.5, 1.5, 2.0, 3.0};
    for (int k = 0; k < 4; ++k) {
        double t = ts[k], x[6];
        pl_error err;
        ck_assert_int_eq(ops->positions_at(p, pl_sim_data(s), t, x, &err), PL_OK);
        /* expected: translation and angle interpolated, held after 2 s */
        double sx = t < 1 ? t : 1.0, sy = t < 1 ? 0.0 : (t < 2 ? t - 1 : 1.0);
        double th = t < 1 ? 0.0 : (t < 2 ? (t - 1) : 1.0) * 1.5707963267948966;
        for (int i = 0; i < 2; ++i) {
            const double *x0 = &r[3 * idx[i]];
            double ex = cos(th) * x0[0] - sin(th) * x0[1] + sx;
            double ey = sin(th) * x0[0] + cos(th) * x0[1] + sy;
            double ez = x0[2] + 0.25 * t;
            ck_assert_double_eq_tol(x[3 * i], ex, 1e-12);
            ck_assert_double_eq_tol(x[3 * i + 1], ey, 1e-12);
            ck_assert_double_eq_tol(x[3 * i + 2], ez, 1e-12);
        }
    }
    pl_sim_free(s);
}
END_TEST

/* A keyframe mistake stops the scene naming line 3 and the component. */
static void expect_motion_error(const char *attrs, const char *needle)
{
    char xml[512];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\">\n  <RegularGridTetrahedra min=\"0 0 0\" max=\"1 1 1\" n=\"2 2 2\"/>"
             "<MechanicalObject name=\"dofs\"/>\n  <PrescribedMotion name=\"base\" indices=\"1\" %s/>\n"
             "</Node>\n",
             attrs);
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, "keys.xml", NULL, &diag);
    ck_assert_ptr_null(s);
    int found = 0;
    for (int k = 0; k < diag.count; ++k)
        found |= diag.items[k].line == 3 && strstr(diag.items[k].msg, needle) != NULL &&
                 strstr(diag.items[k].where, "root/base") != NULL;
    if (!found) pl_diag_print(&diag, stderr);
    ck_assert_msg(found, "no error with '%s' at line 3", needle);
}

START_TEST(prescribed_motion_keyframe_errors_name_the_line)
{
    expect_motion_error("times=\"0 1\" translations=\"0 0 0 1 0\"", "3 values per time");
    expect_motion_error("times=\"0 1\" angles=\"0\"", "one value per time");
    expect_motion_error("times=\"0 0\" angles=\"0 1\"", "strictly increasing");
    expect_motion_error("translations=\"1 2 3\"", "need times");
    expect_motion_error("times=\"0 1\"", "without translations or angles");
}
END_TEST

START_TEST(a_broken_mesh_file_stops_the_scene_naming_the_loader)
{
    char path[1024];
    int fd = test_tmp_file(path, sizeof path, "broken");
    ck_assert_int_ge(fd, 0);
    const char *bad = "# vtk DataFile Version 2.0\nbroken\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                      "POINTS 4 double\n0 0 0\n1 0 0\n0 nan 0\n";
    ck_assert_int_eq(write(fd, bad, strlen(bad)), (ssize_t)strlen(bad));
    close(fd);
    char xml[1600];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\">\n  <MeshLoader name=\"mesh\" filename=\"%s\"/>\n"
             "  <MechanicalObject/>\n</Node>\n",
             path);
    ck_assert_ptr_null(pl_sim_load_string(xml, "broken.xml", NULL, &diag));
    int found_file = 0, found_component = 0;
    for (int k = 0; k < diag.count; ++k) {
        if (strstr(diag.items[k].file, "pliant_broken") && diag.items[k].line > 0) found_file = 1;
        if (!strcmp(diag.items[k].file, "broken.xml") && diag.items[k].line == 2 &&
            strstr(diag.items[k].where, "root/mesh"))
            found_component = 1;
    }
    ck_assert(found_file);
    ck_assert(found_component);
    unlink(path);
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    ck_assert_ptr_null(load("<Node>\n  <MeshLoader filename=\"meshes/nope.vtk\"/>\n</Node>\n"));
    ck_assert_int_eq(diag.items[0].line, 2);
    ck_assert_ptr_nonnull(strstr(diag.items[0].msg, "cannot find"));
}
END_TEST

START_TEST(orphan_vertices_without_mass_are_an_error_unless_dropped)
{
    const char *xml = "<Node name=\"root\">\n"
                      "  <MeshLoader filename=\"meshes/raptorTetra_8418.vtu\" onlyAttachedPoints=\"%d\"/>\n"
                      "  <MechanicalObject name=\"dofs\"/>\n"
                      "  <DiagonalMass massDensity=\"10\"/>\n"
                      "</Node>\n";
    char buf[512];
    snprintf(buf, sizeof buf, xml, 0);
    ck_assert_ptr_null(load(buf));
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    snprintf(buf, sizeof buf, xml, 1);
    pl_sim *s = load(buf);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(state_count(s, "dofs"), 2993);
    pl_sim_free(s);
}
END_TEST

START_TEST(vtk_exporter_writes_a_series_into_the_output_folder)
{
    char *dir = test_tmp_mkdtemp("out");
    ck_assert_ptr_nonnull(dir);
    pl_sim_options opt = {.out_dir = dir};
    pl_sim *s = pl_sim_load_string("<Node name=\"root\">\n"
                                   "  <MeshLoader filename=\"meshes/liver.msh\"/>\n"
                                   "  <MechanicalObject/>\n"
                                   "  <VTKExporter filename=\"liver\"/>\n"
                                   "</Node>\n",
                                   PL_SOURCE_DIR "/scenes/inline.xml", &opt, &diag);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 2, &err), PL_OK);
    const char *outs[4];
    ck_assert_int_eq(pl_sim_outputs(s, outs, 4), 1);
    ck_assert_ptr_nonnull(strstr(outs[0], dir));
    pl_sim_free(s);
    char path[1200];
    struct stat st;
    for (int k = 0; k < 3; ++k) {
        snprintf(path, sizeof path, "%s/liver_%04d.vtu", dir, k);
        ck_assert_int_eq(stat(path, &st), 0);
        ck_assert_int_gt(st.st_size, 1000);
        unlink(path);
    }
    snprintf(path, sizeof path, "%s/liver.pvd", dir);
    ck_assert_int_eq(stat(path, &st), 0);
    unlink(path);
    test_tmp_rmtree(dir);
    free(dir);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("components");
    TCase *tc = tcase_create("scenes");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, a_gmsh_liver_loads_into_a_mechanical_object_with_its_mass);
    tcase_add_test(tc, diagonal_mass_integrates_density_over_a_scaled_box);
    tcase_add_test(tc, cloth_mass_uses_thickness);
    tcase_add_test(tc, fixed_constraint_selects_a_box_face);
    tcase_add_test(tc, prescribed_motion_rotates_about_its_axis);
    tcase_add_test(tc, prescribed_motion_plays_keyframed_poses);
    tcase_add_test(tc, prescribed_motion_keyframe_errors_name_the_line);
    tcase_add_test(tc, a_broken_mesh_file_stops_the_scene_naming_the_loader);
    tcase_add_test(tc, orphan_vertices_without_mass_are_an_error_unless_dropped);
    tcase_add_test(tc, vtk_exporter_writes_a_series_into_the_output_folder);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
