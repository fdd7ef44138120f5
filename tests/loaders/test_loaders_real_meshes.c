/* test_loaders_real_meshes.c - every loader on the shipped meshes: the
 * vertex and element counts of scenes/meshes/README.md, orientation,
 * volumes, and cross-checks between files that describe the same shape. */
#include "loader_test_util.h"


typedef struct expect {
    const char *file;
    int nverts, ntets, ntris;
} expect;

/* The counts of the README table (STL: after welding identical positions). */
static const expect table[] = {
    {"liver.msh", 181, 596, 0},
    {"torus_low_res.msh", 264, 862, 408},
    {"cylinder.msh", 510, 2430, 0},
    {"cube_low_res.msh", 26, 44, 0},
    {"single_tetra.msh", 4, 1, 0},
    {"msh4_cube.msh", 14, 24, 24},
    {"SOFA_volume.vtk", 959, 2564, 6057},
    {"raptorTetra_8418.vtu", 2996, 8418, 0},
    {"raptorTetra_19409.vtu", 5992, 19409, 0},
    {"finger.vtk", 158, 389, 306},
    {"trunk.vtk", 709, 1972, 1322},
    {"Hollow_Stanford_Bunny.vtu", 1911, 5897, 0},
    {"liver.vtk", 5008, 0, 10000},
    {"liver.obj", 181, 0, 274},
    {"torus.obj", 800, 0, 1600},
    {"torus2.obj", 800, 0, 1600},
    {"torus_for_collision.obj", 200, 0, 400},
    {"torus2_for_collision.obj", 200, 0, 400},
    {"floorFlat.obj", 4, 0, 2},
    {"cube.obj", 8, 0, 12},
    {"dragon.obj", 1190, 0, 2564},
    {"finger.stl", 155, 0, 306},
    {"fingerCollision_part1.stl", 16, 0, 14},
    {"fingerCollision_part2.stl", 16, 0, 14},
};

static void load_ok(const char *path, const pl_mesh_load_options *opt, pl_mesh *m, pl_diag *d)
{
    pl_diag_init(d);
    int rc = pl_mesh_load(path, opt, m, d);
    if (rc) pl_diag_print(d, stderr);
    ck_assert_msg(rc == PL_OK, "loading %s failed", path);
}

START_TEST(counts_match_the_readme_table)
{
    const expect *e = &table[_i];
    char path[512];
    snprintf(path, sizeof path, MESH_DIR "%s", e->file);
    pl_mesh m;
    pl_diag d;
    load_ok(path, NULL, &m, &d);
    ck_assert_msg(m.nverts == e->nverts && m.ntets == e->ntets && m.ntris == e->ntris,
                  "%s: %d verts %d tets %d tris, expected %d %d %d", e->file, m.nverts, m.ntets,
                  m.ntris, e->nverts, e->ntets, e->ntris);
    ck_assert_int_eq(pl_mesh_validate(&m, path, NULL), PL_OK);
    double min_vol;
    double vol = tu_total_volume(&m, &min_vol);
    if (m.ntets) {
        ck_assert_msg(min_vol > 0, "%s: a tetrahedron has volume %g", e->file, min_vol);
        ck_assert(vol > 0);
    }
    pl_mesh_free(&m);
    pl_diag_free(&d);
}
END_TEST

START_TEST(mixed_cells_are_reported_by_kind)
{
    pl_mesh m;
    pl_diag d;
    load_ok(MESH_DIR "finger.vtk", NULL, &m, &d);
    const pl_error *w = tu_find(&d, PL_OK, "skipped 114 cells");
    ck_assert_msg(w != NULL, "no skipped-cells warning");
    ck_assert_ptr_nonnull(strstr(w->msg, "26 vertex (VTK type 1)"));
    ck_assert_ptr_nonnull(strstr(w->msg, "88 line (VTK type 3)"));
    ck_assert_int_eq(d.nerrors, 0);
    pl_mesh_free(&m);
    pl_diag_free(&d);

    load_ok(MESH_DIR "msh4_cube.msh", NULL, &m, &d);
    w = tu_find(&d, PL_OK, "skipped 20 cells");
    ck_assert_ptr_nonnull(w);
    ck_assert_ptr_nonnull(strstr(w->msg, "12 line (Gmsh type 1)"));
    ck_assert_ptr_nonnull(strstr(w->msg, "8 point (Gmsh type 15)"));
    pl_mesh_free(&m);
    pl_diag_free(&d);

    load_ok(MESH_DIR "SOFA_volume.vtk", NULL, &m, &d);
    ck_assert_ptr_nonnull(tu_find(&d, PL_OK, "4451 line"));
    pl_mesh_free(&m);
    pl_diag_free(&d);
}
END_TEST

START_TEST(unit_cubes_have_their_analytic_volume)
{
    pl_mesh m;
    pl_diag d;
    load_ok(MESH_DIR "msh4_cube.msh", NULL, &m, &d); /* the unit cube */
    ck_assert_double_eq_tol(tu_total_volume(&m, NULL), 1.0, 1e-6);
    /* its 24 triangles are the closed outer surface */
    ck_assert_double_eq_tol(tu_surface_area(m.verts, m.tris, m.ntris), 6.0, 1e-6);
    pl_mesh_free(&m);
    pl_diag_free(&d);
    load_ok(MESH_DIR "cube_low_res.msh", NULL, &m, &d); /* [-3.5, 3.5]^3 */
    ck_assert_double_eq_tol(tu_total_volume(&m, NULL), 343.0, 343.0 * 1e-6);
    pl_mesh_free(&m);
    pl_diag_free(&d);
}
END_TEST

START_TEST(single_tetra_is_inverted_then_fixed_with_a_warning)
{
    pl_mesh m;
    pl_diag d;
    pl_mesh_load_options keep = {.keep_inverted = 1};
    load_ok(MESH_DIR "single_tetra.msh", &keep, &m, &d);
    double v_in = tu_tet_volume(&m, 0);
    ck_assert(v_in < 0);
    ck_assert_ptr_null(tu_find(&d, PL_OK, "inverted"));
    pl_mesh_free(&m);
    pl_diag_free(&d);

    load_ok(MESH_DIR "single_tetra.msh", NULL, &m, &d);
    const pl_error *w = tu_find(&d, PL_OK, "inverted");
    ck_assert_ptr_nonnull(w);
    ck_assert_ptr_nonnull(strstr(w->msg, "1 of 1"));
    /* |volume| of (5,5,0) (0,5,0) (0,0,0) (2.5,3.5,-3): base 12.5, height 3 */
    ck_assert_double_eq_tol(tu_tet_volume(&m, 0), 12.5, 1e-12);
    ck_assert_double_eq_tol(v_in, -12.5, 1e-12);
    pl_mesh_free(&m);
    pl_diag_free(&d);
}
END_TEST

START_TEST(raptor_unused_vertices_are_dropped_only_on_request)
{
    static const struct { const char *file; int nverts, unused, boundary; } r[] = {
        {"raptorTetra_8418.vtu", 2996, 3, 5750}, {"raptorTetra_19409.vtu", 5992, 2, 10416}};
    for (int k = 0; k < 2; ++k) {
        char path[512];
        snprintf(path, sizeof path, MESH_DIR "%s", r[k].file);
        pl_mesh m, dropped;
        pl_diag d;
        load_ok(path, NULL, &m, &d);
        ck_assert_int_eq(m.nverts, r[k].nverts);
        ck_assert_ptr_nonnull(tu_find(&d, PL_OK, "belong to no element"));
        pl_diag_free(&d);
        pl_mesh_load_options opt = {.drop_unused = 1};
        load_ok(path, &opt, &dropped, &d);
        ck_assert_int_eq(dropped.nverts, r[k].nverts - r[k].unused);
        ck_assert_int_eq(dropped.ntets, m.ntets);
        /* renumbering keeps every tetrahedron at the same place */
        for (int t = 0; t < m.ntets; ++t)
            ck_assert_double_eq_tol(tu_tet_volume(&dropped, t), tu_tet_volume(&m, t), 1e-15);
        int *tris, ntris;
        ck_assert_int_eq(pl_mesh_boundary_triangles(&m, &tris, &ntris), PL_OK);
        ck_assert_int_eq(ntris, r[k].boundary); /* README: raptor boundary sizes */
        /* closed and consistently oriented; 9 edges of the 8418 raptor are
         * shared by 4 boundary faces (the surface touches itself there) */
        ck_assert_int_eq(tu_unbalanced_edges(tris, ntris), 0);
        double vs = tu_surface_volume(m.verts, tris, ntris), vt = tu_total_volume(&m, NULL);
        ck_assert_double_eq_tol(vs, vt, 1e-9 * vt);
        free(tris);
        pl_mesh_free(&m);
        pl_mesh_free(&dropped);
        pl_diag_free(&d);
    }
}
END_TEST

START_TEST(vtu_named_vtk_is_detected_from_content)
{
    pl_mesh a, b;
    pl_diag d;
    load_ok(PL_SOURCE_DIR "/tests/loaders/data/bunny_is_vtu.vtk", NULL, &a, &d);
    pl_diag_free(&d);
    load_ok(MESH_DIR "Hollow_Stanford_Bunny.vtu", NULL, &b, &d);
    ck_assert_int_eq(a.nverts, 1911);
    ck_assert_int_eq(a.ntets, 5897);
    ck_assert_int_eq(memcmp(a.verts, b.verts, 3 * sizeof(double) * 1911), 0);
    ck_assert_int_eq(memcmp(a.tets, b.tets, 4 * sizeof(int) * 5897), 0);
    pl_mesh_free(&a);
    pl_mesh_free(&b);
    pl_diag_free(&d);
}
END_TEST

START_TEST(finger_stl_encloses_the_finger_vtk_volume)
{
    /* README: finger.stl's triangles are the boundary faces of finger.vtk */
    pl_mesh vol, surf;
    pl_diag d;
    load_ok(MESH_DIR "finger.vtk", NULL, &vol, &d);
    pl_diag_free(&d);
    load_ok(MESH_DIR "finger.stl", NULL, &surf, &d);
    int *tris, ntris;
    ck_assert_int_eq(pl_mesh_boundary_triangles(&vol, &tris, &ntris), PL_OK);
    ck_assert_int_eq(ntris, 306);
    double v_tets = tu_total_volume(&vol, NULL);
    double v_bnd = tu_surface_volume(vol.verts, tris, ntris);
    double v_stl = tu_surface_volume(surf.verts, surf.tris, surf.ntris);
    ck_assert_double_eq_tol(v_bnd, v_tets, 1e-9 * v_tets);
    /* STL stores float32: agreement to single precision */
    ck_assert_double_eq_tol(fabs(v_stl), v_tets, 1e-5 * v_tets);
    ck_assert_double_eq_tol(tu_surface_area(surf.verts, surf.tris, surf.ntris),
                            tu_surface_area(vol.verts, tris, ntris), 1e-5 * 1e4);
    ck_assert_int_eq(tu_open_edges(surf.tris, surf.ntris), 0); /* welding closed it */
    free(tris);
    pl_mesh_free(&vol);
    pl_mesh_free(&surf);
    pl_diag_free(&d);
}
END_TEST

START_TEST(liver_obj_shares_the_msh_vertices)
{
    pl_mesh msh, obj;
    pl_diag d;
    load_ok(MESH_DIR "liver.msh", NULL, &msh, &d);
    pl_diag_free(&d);
    load_ok(MESH_DIR "liver.obj", NULL, &obj, &d);
    ck_assert_int_eq(msh.nverts, obj.nverts);
    for (int i = 0; i < 3 * msh.nverts; ++i)
        ck_assert_double_eq_tol(msh.verts[i], obj.verts[i], 1e-5);
    int *tris, ntris;
    ck_assert_int_eq(pl_mesh_boundary_triangles(&msh, &tris, &ntris), PL_OK);
    ck_assert_int_eq(ntris, 276); /* README: the tetrahedra have 276 boundary faces */
    free(tris);
    pl_mesh_free(&msh);
    pl_mesh_free(&obj);
    pl_diag_free(&d);
}
END_TEST

START_TEST(floor_quad_becomes_two_triangles_of_the_same_area)
{
    pl_mesh m;
    pl_diag d;
    load_ok(MESH_DIR "floorFlat.obj", NULL, &m, &d);
    ck_assert_int_eq(m.ntris, 2);
    /* the quad's area from its corners (shoelace over the 4 vertices in file order) */
    double n[3] = {0, 0, 0};
    for (int i = 0; i < 4; ++i) {
        const double *p = m.verts + 3 * i, *q = m.verts + 3 * ((i + 1) % 4);
        n[0] += p[1] * q[2] - p[2] * q[1];
        n[1] += p[2] * q[0] - p[0] * q[2];
        n[2] += p[0] * q[1] - p[1] * q[0];
    }
    double quad = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    ck_assert(quad > 0);
    ck_assert_double_eq_tol(tu_surface_area(m.verts, m.tris, 2), quad, 1e-9 * quad);
    pl_mesh_free(&m);
    pl_diag_free(&d);
}
END_TEST

START_TEST(closed_obj_surfaces_are_watertight)
{
    static const char *files[] = {"cube.obj", "torus.obj", "torus_for_collision.obj"};
    for (int k = 0; k < 3; ++k) {
        char path[512];
        snprintf(path, sizeof path, MESH_DIR "%s", files[k]);
        pl_mesh m;
        pl_diag d;
        load_ok(path, NULL, &m, &d);
        ck_assert_msg(tu_open_edges(m.tris, m.ntris) == 0, "%s is not closed", files[k]);
        ck_assert(fabs(tu_surface_volume(m.verts, m.tris, m.ntris)) > 0);
        pl_mesh_free(&m);
        pl_diag_free(&d);
    }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("loaders_real_meshes");
    TCase *tc = tcase_create("real");
    tcase_set_timeout(tc, 60);
    tcase_add_loop_test(tc, counts_match_the_readme_table, 0,
                        (int)(sizeof table / sizeof table[0]));
    tcase_add_test(tc, mixed_cells_are_reported_by_kind);
    tcase_add_test(tc, unit_cubes_have_their_analytic_volume);
    tcase_add_test(tc, single_tetra_is_inverted_then_fixed_with_a_warning);
    tcase_add_test(tc, raptor_unused_vertices_are_dropped_only_on_request);
    tcase_add_test(tc, vtu_named_vtk_is_detected_from_content);
    tcase_add_test(tc, finger_stl_encloses_the_finger_vtk_volume);
    tcase_add_test(tc, liver_obj_shares_the_msh_vertices);
    tcase_add_test(tc, floor_quad_becomes_two_triangles_of_the_same_area);
    tcase_add_test(tc, closed_obj_surfaces_are_watertight);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
