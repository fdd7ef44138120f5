/* test_export_scene.c - the exported files hold the whole scene:
 *  - the rollers of scenes/squeezing_ball_small.xml are written at each
 *    frame, turned: between the frames at t = 0 and t = 0.1 s every vertex of
 *    the left roller has turned by -0.4 rad (angularVelocity -4 rad/s) about
 *    the roller's axis, at the same radius and height, and the contacts part
 *    carries a force per point;
 *  - the cable of scenes/cable_finger_small.xml is part 1 of the finger's
 *    series: a polyline (line cells) from the pull point through its 14 points;
 *  - a VTKExporter next to a plane obstacle writes the plane as a finite
 *    patch in the plane (the error "no state in this node to export" of
 *    before is gone);
 *  - a VTKExporter with nothing to export is an error naming the component. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export_test_util.h"
#include "pliant/pliant.h"

static pl_sim *load(const char *xml, int is_file, const char *out, pl_diag *diag)
{
    pl_sim_options opt = {.out_dir = out, .device = "cpu"};
    return is_file ? pl_sim_load_file(xml, &opt, diag)
                   : pl_sim_load_string(xml, "export_scene.xml", &opt, diag);
}

static void read_mesh(const char *path, pl_mesh *m)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_mesh_init(m);
    int rc = pl_mesh_load(path, NULL, m, &diag);
    if (rc) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_int_eq(rc, PL_OK);
}

START_TEST(test_roller_turns)
{
    char *dir = tu_tmpdir(), scene[512];
    snprintf(scene, sizeof scene, "%s/scenes/squeezing_ball_small.xml", PL_SOURCE_DIR);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = load(scene, 1, dir, &diag);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 10, &err), PL_OK); /* frames at t = 0 and 0.1 s */
    ck_assert_int_eq(pl_sim_finish(s, &err), PL_OK);
    pl_mesh m0, m1;
    read_mesh(tu_path(dir, "squeezing_ball_small_scene_left_roller_0000.vtu"), &m0);
    read_mesh(tu_path(dir, "squeezing_ball_small_scene_left_roller_0001.vtu"), &m1);
    ck_assert_int_eq(m0.nverts, m1.nverts);
    ck_assert_int_gt(m0.ntris, 0);
    int turned = 0;
    for (int i = 0; i < m0.nverts; ++i) {
        const double *a = &m0.verts[3 * i], *b = &m1.verts[3 * i];
        double ra = hypot(a[0] + 0.13, a[1]), rb = hypot(b[0] + 0.13, b[1]);
        ck_assert_double_eq_tol(ra, rb, 1e-12);
        ck_assert_double_eq_tol(a[2], b[2], 1e-12);
        if (ra < 1e-6) continue; /* on the axis */
        double d = atan2(b[1], b[0] + 0.13) - atan2(a[1], a[0] + 0.13);
        d = remainder(d, 2.0 * M_PI);
        ck_assert_double_eq_tol(d, -0.4, 1e-9);
        turned++;
    }
    ck_assert_int_gt(turned, m0.nverts / 2);
    char *pvd = tu_read_file(tu_path(dir, "squeezing_ball_small_scene.pvd"), NULL);
    ck_assert_ptr_nonnull(pvd);
    ck_assert_ptr_nonnull(strstr(pvd, "part=\"2\" file=\"squeezing_ball_small_scene_right_roller_0001.vtu\""));
    free(pvd);
    char *contacts = tu_read_file(tu_path(dir, "squeezing_ball_small_scene_root_pipeline_contacts_0001.vtu"), NULL);
    ck_assert_ptr_nonnull(contacts);
    ck_assert_ptr_nonnull(strstr(contacts, "Name=\"force\" NumberOfComponents=\"3\""));
    free(contacts);
    pl_mesh_free(&m0);
    pl_mesh_free(&m1);
    pl_sim_free(s);
    pl_diag_free(&diag);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(test_cable_path)
{
    char *dir = tu_tmpdir(), scene[512];
    snprintf(scene, sizeof scene, "%s/scenes/cable_finger_small.xml", PL_SOURCE_DIR);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = load(scene, 1, dir, &diag);
    ck_assert_ptr_nonnull(s);
    pl_sim_free(s); /* frame 0 only */
    char *vtu = tu_read_file(tu_path(dir, "cable_finger_small_finger_cable_0000.vtu"), NULL);
    ck_assert_ptr_nonnull(vtu);
    /* the pull point and 14 cable points, 14 segments of VTK type 3 */
    ck_assert_ptr_nonnull(strstr(vtu, "NumberOfPoints=\"15\" NumberOfCells=\"14\""));
    ck_assert_ptr_nonnull(strstr(vtu, "3 3 3 3"));
    free(vtu);
    char *pvd = tu_read_file(tu_path(dir, "cable_finger_small.pvd"), NULL);
    ck_assert_ptr_nonnull(pvd);
    ck_assert_ptr_nonnull(strstr(pvd, "part=\"1\" file=\"cable_finger_small_finger_cable_0000.vtu\""));
    free(pvd);
    pl_diag_free(&diag);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(test_plane_patch)
{
    char *dir = tu_tmpdir();
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = load("<Node name=\"root\"><RequiredPlugin name=\"collision\"/>"
                     "<Node name=\"floor\"><PlaneObstacle name=\"plane\" point=\"0 -0.5 0\" "
                     "normal=\"0 1 0\"/><VTKExporter name=\"vtk\" filename=\"floor\"/></Node>"
                     "</Node>",
                     0, dir, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    ck_assert_ptr_nonnull(s);
    pl_sim_free(s); /* finishes the series */
    pl_mesh m;
    read_mesh(tu_path(dir, "floor_floor_plane_0000.vtu"), &m);
    ck_assert_int_eq(m.nverts, 81);
    ck_assert_int_eq(m.ntris, 128);
    for (int i = 0; i < m.nverts; ++i) ck_assert_double_eq_tol(m.verts[3 * i + 1], -0.5, 1e-12);
    ck_assert(tu_exists(tu_path(dir, "floor_floor_plane_contacts_0000.vtu")));
    pl_mesh_free(&m);
    pl_diag_free(&diag);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(test_nothing_to_export)
{
    pl_diag diag;
    pl_diag_init(&diag);
    char *dir = tu_tmpdir();
    pl_sim *s = load("<Node name=\"root\">\n<Node name=\"empty\">\n"
                     "<VTKExporter name=\"vtk\"/></Node></Node>",
                     0, dir, &diag);
    ck_assert_ptr_null(s);
    ck_assert_int_eq(diag.nerrors, 1);
    ck_assert_int_eq(diag.items[0].line, 3);
    ck_assert_ptr_nonnull(strstr(diag.items[0].msg, "nothing to export"));
    ck_assert_ptr_nonnull(strstr(diag.items[0].where, "empty/vtk"));
    pl_diag_free(&diag);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("export scene");
    TCase *tc = tcase_create("scene");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_roller_turns);
    tcase_add_test(tc, test_cable_path);
    tcase_add_test(tc, test_plane_patch);
    tcase_add_test(tc, test_nothing_to_export);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
