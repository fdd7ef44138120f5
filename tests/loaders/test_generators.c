/* test_generators.c - generated meshes: counts, orientation, closed
 * boundaries, exact volumes and areas (box, cloth, cylinder polygons) and
 * volumes within a few percent of the analytic sphere and cylinder. */
#include "loader_test_util.h"

#include "generators/generators.h"


/* Scale-free tetrahedron quality: 6 sqrt(2) V / l_max^3 (1 for a regular one). */
static double min_quality(const pl_mesh *m)
{
    double q = INFINITY;
    for (int t = 0; t < m->ntets; ++t) {
        double lmax = 0;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) {
                const double *p = m->verts + 3 * m->tets[4 * t + a], *r = m->verts + 3 * m->tets[4 * t + b];
                double d = sqrt((p[0] - r[0]) * (p[0] - r[0]) + (p[1] - r[1]) * (p[1] - r[1]) +
                                (p[2] - r[2]) * (p[2] - r[2]));
                lmax = fmax(lmax, d);
            }
        q = fmin(q, 6 * sqrt(2.0) * tu_tet_volume(m, t) / (lmax * lmax * lmax));
    }
    return q;
}

/* Boundary of a tet mesh: closed, outward, enclosing the tets' volume. */
static void check_boundary(const pl_mesh *m, double *area, int *nbnd)
{
    int *tris, ntris;
    ck_assert_int_eq(pl_mesh_boundary_triangles(m, &tris, &ntris), PL_OK);
    ck_assert_int_eq(tu_open_edges(tris, ntris), 0);
    double vol = tu_total_volume(m, NULL);
    ck_assert_double_eq_tol(tu_surface_volume(m->verts, tris, ntris), vol, 1e-10 * vol);
    *area = tu_surface_area(m->verts, tris, ntris);
    *nbnd = ntris;
    free(tris);
}

START_TEST(box_is_exact_positive_and_closed)
{
    const int n[3] = {4, 3, 6};
    const double lo[3] = {-1, 0.5, 2}, hi[3] = {2, 1.5, 7};
    pl_mesh m;
    ck_assert_int_eq(pl_generate_box_tets(n, lo, hi, &m, NULL), PL_OK);
    ck_assert_int_eq(m.nverts, 4 * 3 * 6);
    ck_assert_int_eq(m.ntets, 6 * 3 * 2 * 5);
    const double a = 3, b = 1, c = 5, cell = (a / 3) * (b / 2) * (c / 5);
    for (int t = 0; t < m.ntets; ++t) /* every Kuhn tetrahedron is 1/6 of its cell */
        ck_assert_double_eq_tol(tu_tet_volume(&m, t), cell / 6, 1e-14);
    ck_assert_double_eq_tol(tu_total_volume(&m, NULL), a * b * c, 1e-12);
    double area;
    int nbnd;
    check_boundary(&m, &area, &nbnd);
    ck_assert_double_eq_tol(area, 2 * (a * b + b * c + c * a), 1e-12);
    ck_assert_int_eq(nbnd, 4 * (3 * 2 + 2 * 5 + 5 * 3)); /* 2 triangles per boundary quad */
    /* vertex (i,j,k) sits at index i + n0 (j + n1 k); the far corner is exact */
    ck_assert_double_eq(m.verts[3 * (m.nverts - 1) + 2], 7.0);
    ck_assert_double_eq(m.verts[3 * 1], 0.0); /* i = 1: -1 + 3/3 */
    pl_mesh_free(&m);
}
END_TEST

START_TEST(box_rejects_bad_parameters)
{
    pl_mesh m;
    pl_error e;
    const int bad_n[3] = {2, 1, 2}, n[3] = {2, 2, 2};
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, flat[3] = {1, 0, 1};
    ck_assert_int_eq(pl_generate_box_tets(bad_n, lo, hi, &m, &e), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(e.msg, "n[1] = 1"));
    ck_assert_int_eq(pl_generate_box_tets(n, lo, flat, &m, &e), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(e.msg, "expected finite lo < hi"));
    ck_assert(m.verts == NULL && m.nverts == 0);
}
END_TEST

START_TEST(cloth_spans_its_parallelogram_facing_u_cross_v)
{
    const double o[3] = {1, 2, 3}, u[3] = {2, 0, 0}, v[3] = {0.5, 1, 0};
    pl_mesh m;
    ck_assert_int_eq(pl_generate_triangle_grid(5, 4, o, u, v, &m, NULL), PL_OK);
    ck_assert_int_eq(m.nverts, 20);
    ck_assert_int_eq(m.ntris, 2 * 4 * 3);
    ck_assert_double_eq_tol(tu_surface_area(m.verts, m.tris, m.ntris), 2.0, 1e-12); /* |u x v| */
    int diag_ac = 0;
    for (int f = 0; f < m.ntris; ++f) {
        const double *a = m.verts + 3 * m.tris[3 * f], *b = m.verts + 3 * m.tris[3 * f + 1];
        const double *c = m.verts + 3 * m.tris[3 * f + 2];
        double nz = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        ck_assert(nz > 0); /* u x v = +z */
        ck_assert_double_eq(a[2], 3.0);
    }
    for (int cell = 0; cell < 12; ++cell) /* a-c diagonal: cells (a b c)(a c d) */
        diag_ac += m.tris[6 * cell + 2] == m.tris[6 * cell + 4];
    ck_assert_int_eq(diag_ac, 6); /* half the cells each way: no preferred shear */
    ck_assert_double_eq(m.verts[3 * 19 + 0], 1 + 2 + 0.5);
    pl_mesh_free(&m);

    ck_assert_int_eq(pl_generate_cloth_xz(3, 5, -1, 1, 0, 4, 0.5, &m, NULL), PL_OK);
    ck_assert_double_eq_tol(tu_surface_area(m.verts, m.tris, m.ntris), 8.0, 1e-12);
    for (int f = 0; f < m.ntris; ++f) {
        const double *a = m.verts + 3 * m.tris[3 * f], *b = m.verts + 3 * m.tris[3 * f + 1];
        const double *c = m.verts + 3 * m.tris[3 * f + 2];
        double ny = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]);
        ck_assert(ny > 0); /* normals +y */
        ck_assert_double_eq(a[1], 0.5);
    }
    pl_mesh_free(&m);
    pl_error e;
    ck_assert_int_eq(pl_generate_triangle_grid(3, 3, o, u, u, &m, &e), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(e.msg, "parallel"));
}
END_TEST

START_TEST(icosphere_counts_radius_and_volume)
{
    const double c[3] = {1, -2, 0.5}, R = 2;
    for (int level = 0; level <= 4; ++level) {
        pl_mesh m;
        ck_assert_int_eq(pl_generate_sphere_surface(c, R, level, &m, NULL), PL_OK);
        ck_assert_int_eq(m.nverts, 10 * (1 << (2 * level)) + 2);
        ck_assert_int_eq(m.ntris, 20 * (1 << (2 * level)));
        for (int i = 0; i < m.nverts; ++i) {
            double *p = m.verts + 3 * i;
            double r = sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                            (p[2] - c[2]) * (p[2] - c[2]));
            ck_assert_double_eq_tol(r, R, 1e-12);
        }
        ck_assert_int_eq(tu_open_edges(m.tris, m.ntris), 0);
        /* inscribed polyhedron: below the ball's volume, converging to it */
        double vol = tu_surface_volume(m.verts, m.tris, m.ntris); /* translation-invariant */
        double ball = 4.0 / 3.0 * acos(-1.0) * R * R * R;
        ck_assert(vol > 0 && vol < ball);
        if (level == 0) ck_assert_double_eq_tol(vol / ball, 0.6055, 1e-3); /* icosahedron */
        if (level == 4) ck_assert(vol / ball > 0.995);
        pl_mesh_free(&m);
    }
}
END_TEST

START_TEST(ball_is_positive_watertight_and_near_the_sphere_volume)
{
    const double c[3] = {0.5, 0, -1}, R = 3;
    const double ball = 4.0 / 3.0 * acos(-1.0) * R * R * R;
    const int targets[3] = {30, 1000, 8000};
    for (int k = 0; k < 3; ++k) {
        pl_mesh m;
        ck_assert_int_eq(pl_generate_sphere_tets(c, R, targets[k], &m, NULL), PL_OK);
        ck_assert(m.nverts > targets[k] / 2 && m.nverts < 2 * targets[k]);
        double min_vol, area;
        int nbnd;
        double vol = tu_total_volume(&m, &min_vol);
        ck_assert(min_vol > 0);
        /* no slivers: the worst tetrahedron keeps a fair share of a regular one */
        ck_assert_msg(min_quality(&m) > 0.2, "quality %g", min_quality(&m));
        check_boundary(&m, &area, &nbnd);
        if (targets[k] >= 1000) {
            ck_assert_msg(fabs(vol / ball - 1) < 0.03, "volume ratio %g", vol / ball);
            ck_assert_msg(fabs(area / (4 * acos(-1.0) * R * R) - 1) < 0.03, "area");
        }
        int *tris, ntris;
        ck_assert_int_eq(pl_mesh_boundary_triangles(&m, &tris, &ntris), PL_OK);
        for (int i = 0; i < 3 * ntris; ++i) { /* boundary vertices lie on the sphere */
            const double *p = m.verts + 3 * tris[i];
            double r = sqrt((p[0] - c[0]) * (p[0] - c[0]) + p[1] * p[1] + (p[2] - c[2]) * (p[2] - c[2]));
            ck_assert_double_eq_tol(r, R, 1e-12);
        }
        free(tris);
        pl_mesh_free(&m);
    }
}
END_TEST

START_TEST(cylinder_surface_is_closed_polygon_prism)
{
    const double c[3] = {0, 1, 0}, R = 0.5, h = 2;
    pl_mesh m;
    ck_assert_int_eq(pl_generate_cylinder_surface(c, R, h, 24, 5, &m, NULL), PL_OK);
    ck_assert_int_eq(m.nverts, 24 * 6 + 2);
    ck_assert_int_eq(m.ntris, 2 * 24 * 6);
    ck_assert_int_eq(tu_open_edges(m.tris, m.ntris), 0);
    const double pi = acos(-1.0), polygon = 12 * R * R * sin(2 * pi / 24);
    ck_assert_double_eq_tol(tu_surface_volume(m.verts, m.tris, m.ntris), polygon * h, 1e-12);
    ck_assert(fabs(polygon * h / (pi * R * R * h) - 1) < 0.02);
    double ymin = INFINITY, ymax = -INFINITY;
    for (int i = 0; i < m.nverts; ++i) {
        ymin = fmin(ymin, m.verts[3 * i + 1]);
        ymax = fmax(ymax, m.verts[3 * i + 1]);
    }
    ck_assert_double_eq(ymin, 0.0);
    ck_assert_double_eq(ymax, 2.0);
    pl_mesh_free(&m);
    pl_error e;
    ck_assert_int_eq(pl_generate_cylinder_surface(c, R, h, 2, 1, &m, &e), PL_EINPUT);
}
END_TEST

START_TEST(solid_cylinder_fills_its_polygon_prism_exactly)
{
    const double c[3] = {1, 0, -1}, R = 1, h = 3;
    const double pi = acos(-1.0);
    for (int rings = 1; rings <= 6; rings += 5) {
        pl_mesh m;
        ck_assert_int_eq(pl_generate_cylinder_tets(c, R, h, rings, 0, &m, NULL), PL_OK);
        int layers = (int)lround(h * rings / R);
        ck_assert_int_eq(m.nverts, (1 + 3 * rings * (rings + 1)) * (layers + 1));
        ck_assert_int_eq(m.ntets, 18 * rings * rings * layers);
        double min_vol, area;
        int nbnd;
        double vol = tu_total_volume(&m, &min_vol);
        ck_assert(min_vol > 0);
        ck_assert_msg(min_quality(&m) > 0.12, "quality %g", min_quality(&m));
        check_boundary(&m, &area, &nbnd); /* conforming: the split diagonals match */
        int n = 6 * rings;
        double polygon = n / 2.0 * R * R * sin(2 * pi / n);
        ck_assert_double_eq_tol(vol, polygon * h, 1e-12 * vol);
        if (rings == 6) ck_assert(fabs(vol / (pi * R * R * h) - 1) < 0.02);
        pl_mesh_free(&m);
    }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("generators");
    TCase *tc = tcase_create("generators");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, box_is_exact_positive_and_closed);
    tcase_add_test(tc, box_rejects_bad_parameters);
    tcase_add_test(tc, cloth_spans_its_parallelogram_facing_u_cross_v);
    tcase_add_test(tc, icosphere_counts_radius_and_volume);
    tcase_add_test(tc, ball_is_positive_watertight_and_near_the_sphere_volume);
    tcase_add_test(tc, cylinder_surface_is_closed_polygon_prism);
    tcase_add_test(tc, solid_cylinder_fills_its_polygon_prism_exactly);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
