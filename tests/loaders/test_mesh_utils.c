/* test_mesh_utils.c - pl_mesh utilities: transform order and mirroring,
 * deep copy, validation, orientation fix, unused-vertex removal and the
 * boundary extraction's refusals. */
#include "loader_test_util.h"

#include "generators/generators.h"

static pl_mesh unit_box(void)
{
    pl_mesh m;
    const int n[3] = {3, 3, 3};
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 2, 3};
    ck_assert_int_eq(pl_generate_box_tets(n, lo, hi, &m, NULL), PL_OK);
    return m;
}

START_TEST(transform_scales_then_rotates_x_y_z_then_translates)
{
    double v[3 * 3] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    pl_mesh m = {.nverts = 3, .verts = v};
    const double s[3] = {2, 3, 4}, r[3] = {90, 90, 0}, t[3] = {10, 20, 30};
    pl_mesh_transform(&m, s, r, t);
    /* e_y scaled to (0,3,0); Rx(90) -> (0,0,3); Ry(90) -> (3,0,0); + t */
    ck_assert_double_eq_tol(v[3], 13, 1e-12);
    ck_assert_double_eq_tol(v[4], 20, 1e-12);
    ck_assert_double_eq_tol(v[5], 30, 1e-12);
    /* e_x scaled to (2,0,0); Rx keeps it; Ry(90) -> (0,0,-2) */
    ck_assert_double_eq_tol(v[0], 10, 1e-12);
    ck_assert_double_eq_tol(v[2], 28, 1e-12);
    /* z last: Rz(90) maps e_x to e_y */
    double w[3] = {1, 0, 0};
    pl_mesh p = {.nverts = 1, .verts = w};
    const double rz[3] = {0, 0, 90};
    pl_mesh_transform(&p, NULL, rz, NULL);
    ck_assert_double_eq_tol(w[0], 0, 1e-12);
    ck_assert_double_eq_tol(w[1], 1, 1e-12);
}
END_TEST

START_TEST(mirroring_scale_keeps_tets_positive_and_surfaces_outward)
{
    pl_mesh m = unit_box(), surf;
    int *tris, ntris;
    ck_assert_int_eq(pl_mesh_boundary_triangles(&m, &tris, &ntris), PL_OK);
    ck_assert_int_eq(pl_mesh_copy(&surf, &m), PL_OK);
    free(surf.tets);
    surf.tets = NULL;
    surf.ntets = 0;
    surf.tris = tris;
    surf.ntris = ntris;
    const double s[3] = {-1, 2, 1}, r[3] = {30, -20, 10}, t[3] = {5, 6, 7};
    pl_mesh_transform(&m, s, r, t);
    pl_mesh_transform(&surf, s, r, t);
    double min_vol; /* |det S| = 2: the 1 x 2 x 3 box becomes 12 */
    ck_assert_double_eq_tol(tu_total_volume(&m, &min_vol), 12.0, 1e-12);
    ck_assert(min_vol > 0);
    ck_assert_double_eq_tol(tu_surface_volume(surf.verts, surf.tris, surf.ntris), 12.0, 1e-9);
    pl_mesh_free(&m);
    pl_mesh_free(&surf);
}
END_TEST

START_TEST(copy_is_deep)
{
    pl_mesh m = unit_box(), c, e;
    ck_assert_int_eq(pl_mesh_copy(&c, &m), PL_OK);
    ck_assert(c.verts != m.verts && c.tets != m.tets);
    ck_assert_int_eq(memcmp(c.verts, m.verts, 3 * sizeof(double) * (size_t)m.nverts), 0);
    c.verts[0] = 42;
    c.tets[0] = 7;
    ck_assert_double_eq(m.verts[0], 0);
    ck_assert_int_ne(m.tets[0], 7);
    pl_mesh empty;
    pl_mesh_init(&empty);
    ck_assert_int_eq(pl_mesh_copy(&e, &empty), PL_OK);
    ck_assert(e.verts == NULL && e.nverts == 0);
    pl_mesh_free(&m);
    pl_mesh_free(&c);
    pl_mesh_free(&e);
    pl_mesh_free(&e); /* freeing twice is harmless: free resets the struct */
}
END_TEST

START_TEST(validate_names_the_bad_element)
{
    pl_mesh m = unit_box();
    pl_diag d;
    pl_diag_init(&d);
    ck_assert_int_eq(pl_mesh_validate(&m, "box", &d), PL_OK);
    m.tets[4 * 5 + 2] = m.nverts;
    ck_assert_int_eq(pl_mesh_validate(&m, "box", &d), PL_EINPUT);
    ck_assert_ptr_nonnull(tu_find(&d, PL_EINPUT, "tetrahedron 5 uses vertex 27: expected an index in 0..26"));
    m.tets[4 * 5 + 2] = m.tets[4 * 5 + 1];
    ck_assert_int_eq(pl_mesh_validate(&m, "box", &d), PL_EINPUT);
    ck_assert_ptr_nonnull(tu_find(&d, PL_EINPUT, "tetrahedron 5 repeats a vertex"));
    m.tets[4 * 5 + 2] = m.tets[4 * 5 + 3] ^ 1;
    m.verts[3 * 4 + 1] = NAN;
    ck_assert_int_eq(pl_mesh_validate(&m, "box", &d), PL_EINPUT);
    ck_assert_ptr_nonnull(tu_find(&d, PL_EINPUT, "vertex 4 has a non-finite coordinate"));
    ck_assert_str_eq(d.items[0].file, "box");
    pl_diag_free(&d);
    pl_mesh_free(&m);
}
END_TEST

START_TEST(fix_inverted_flips_exactly_the_negative_ones)
{
    pl_mesh m = unit_box();
    for (int t = 0; t < m.ntets; t += 3) { /* invert every third tetrahedron */
        int s = m.tets[4 * t];
        m.tets[4 * t] = m.tets[4 * t + 1];
        m.tets[4 * t + 1] = s;
    }
    ck_assert_int_eq(pl_mesh_fix_inverted(&m), (m.ntets + 2) / 3);
    double min_vol;
    ck_assert_double_eq_tol(tu_total_volume(&m, &min_vol), 6.0, 1e-12);
    ck_assert(min_vol > 0);
    ck_assert_int_eq(pl_mesh_fix_inverted(&m), 0);
    pl_mesh_free(&m);
}
END_TEST

START_TEST(drop_unused_renumbers_and_counts)
{
    pl_mesh m = unit_box();
    /* keep only the tetrahedra of the first cell: 8 vertices used of 27 */
    m.ntets = 6;
    double before[6];
    for (int t = 0; t < 6; ++t) before[t] = tu_tet_volume(&m, t);
    ck_assert_int_eq(pl_mesh_drop_unused(&m), 27 - 8);
    ck_assert_int_eq(m.nverts, 8);
    for (int t = 0; t < 6; ++t) ck_assert_double_eq_tol(tu_tet_volume(&m, t), before[t], 1e-15);
    ck_assert_int_eq(pl_mesh_validate(&m, NULL, NULL), PL_OK);
    ck_assert_int_eq(pl_mesh_drop_unused(&m), 0);
    m.tets[0] = 99; /* invalid input is refused, not written out of bounds */
    ck_assert_int_eq(pl_mesh_drop_unused(&m), -1);
    pl_mesh_free(&m);
}
END_TEST

START_TEST(boundary_refuses_non_manifold_and_bad_indices)
{
    /* three tetrahedra on the same face (0,1,2) */
    double v[3 * 6] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 2, 0, 0, -1};
    int t[12] = {0, 1, 2, 3, 0, 1, 2, 4, 0, 2, 1, 5};
    pl_mesh m = {.nverts = 6, .verts = v, .ntets = 3, .tets = t};
    int *tris, ntris;
    ck_assert_int_eq(pl_mesh_boundary_triangles(&m, &tris, &ntris), PL_EINPUT);
    ck_assert_ptr_null(tris);
    m.ntets = 1;
    t[1] = 6;
    ck_assert_int_eq(pl_mesh_boundary_triangles(&m, &tris, &ntris), PL_EINPUT);
    m.ntets = 0;
    ck_assert_int_eq(pl_mesh_boundary_triangles(&m, &tris, &ntris), PL_OK);
    ck_assert_int_eq(ntris, 0);
    /* two tetrahedra sharing face (0,1,2): 6 boundary faces, the shared one gone */
    int u[8] = {0, 1, 2, 3, 0, 2, 1, 5};
    pl_mesh two = {.nverts = 6, .verts = v, .ntets = 2, .tets = u};
    ck_assert_int_eq(pl_mesh_boundary_triangles(&two, &tris, &ntris), PL_OK);
    ck_assert_int_eq(ntris, 6);
    ck_assert_int_eq(tu_open_edges(tris, ntris), 0);
    free(tris);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("mesh_utils");
    TCase *tc = tcase_create("utils");
    tcase_add_test(tc, transform_scales_then_rotates_x_y_z_then_translates);
    tcase_add_test(tc, mirroring_scale_keeps_tets_positive_and_surfaces_outward);
    tcase_add_test(tc, copy_is_deep);
    tcase_add_test(tc, validate_names_the_bad_element);
    tcase_add_test(tc, fix_inverted_flips_exactly_the_negative_ones);
    tcase_add_test(tc, drop_unused_renumbers_and_counts);
    tcase_add_test(tc, boundary_refuses_non_manifold_and_bad_indices);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
