/* test_collision_narrow.c - the narrow phase, the BVH and the barycentric
 * mapping of the collision core against brute force:
 *  - closest point of a triangle: never farther than the best of a dense
 *    barycentric sampling, within the sampling resolution of it, and an
 *    exact point of the triangle; analytic cases (face, edge, vertex
 *    regions, degenerate triangles);
 *  - closest points of two segments: the same against a dense sampling of
 *    both parameters, with exact parallel and crossing cases;
 *  - BVH queries give exactly the brute-force list of overlapping boxes,
 *    also after the boxes move and the tree is refitted;
 *  - barycentric mapping into a tetrahedral grid reproduces every point
 *    exactly, with non-negative weights inside and the nearest tetrahedron
 *    (brute force) outside. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "detect.h"

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / (double)0xffffff;
}

static void rand_point(unsigned *s, double p[3], double scale)
{
    for (int k = 0; k < 3; ++k) p[k] = scale * (2.0 * urand(s) - 1.0);
}

static double dist2(const double a[3], const double b[3])
{
    double d = 0;
    for (int k = 0; k < 3; ++k) d += (a[k] - b[k]) * (a[k] - b[k]);
    return d;
}

static double brute_triangle(const double p[3], const double *a, const double *b,
                             const double *c, int n)
{
    double best = INFINITY;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            double u = (double)i / n, v = (double)j / n, q[3];
            for (int k = 0; k < 3; ++k) q[k] = (1 - u - v) * a[k] + u * b[k] + v * c[k];
            double d = dist2(p, q);
            if (d < best) best = d;
        }
    return sqrt(best);
}

START_TEST(test_closest_point_triangle_matches_dense_sampling)
{
    unsigned s = 12345u;
    const int n = 120;
    for (int trial = 0; trial < 300; ++trial) {
        double a[3], b[3], c[3], p[3], w[3];
        rand_point(&s, a, 1.0);
        rand_point(&s, b, 1.0);
        rand_point(&s, c, 1.0);
        if (trial % 10 == 0) /* skinny: c almost on a b */
            for (int k = 0; k < 3; ++k) c[k] = 0.5 * (a[k] + b[k]) + 1e-3 * c[k];
        rand_point(&s, p, 2.0);
        double d = sqrt(closest_point_triangle(p, a, b, c, w));
        ck_assert(w[0] >= 0 && w[1] >= 0 && w[2] >= 0);
        ck_assert_double_eq_tol(w[0] + w[1] + w[2], 1.0, 1e-12);
        double q[3];
        for (int k = 0; k < 3; ++k) q[k] = w[0] * a[k] + w[1] * b[k] + w[2] * c[k];
        ck_assert_double_eq_tol(sqrt(dist2(p, q)), d, 1e-12);
        double ref = brute_triangle(p, a, b, c, n);
        double diam = sqrt(fmax(dist2(a, b), fmax(dist2(b, c), dist2(a, c))));
        ck_assert_msg(d <= ref + 1e-12, "trial %d: %.17g > sampled %.17g", trial, d, ref);
        ck_assert_msg(d >= ref - diam / n, "trial %d: %.17g far below sampled %.17g", trial, d,
                      ref);
    }
}
END_TEST

START_TEST(test_closest_point_triangle_regions)
{
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    double w[3];
    /* above the face: the height, weights of the foot point */
    double p1[3] = {0.25, 0.25, 0.7};
    ck_assert_double_eq_tol(closest_point_triangle(p1, a, b, c, w), 0.49, 1e-15);
    ck_assert_double_eq_tol(w[1], 0.25, 1e-15);
    ck_assert_double_eq_tol(w[2], 0.25, 1e-15);
    /* beyond vertex b */
    double p2[3] = {2, -1, 0};
    ck_assert_double_eq_tol(closest_point_triangle(p2, a, b, c, w), 2.0, 1e-15);
    ck_assert_double_eq(w[1], 1.0);
    /* beside the hypotenuse b c: distance to the line x + y = 1 */
    double p3[3] = {1, 1, 0};
    ck_assert_double_eq_tol(closest_point_triangle(p3, a, b, c, w), 0.5, 1e-15);
    ck_assert_double_eq_tol(w[1], 0.5, 1e-15);
    ck_assert_double_eq_tol(w[2], 0.5, 1e-15);
    /* a degenerate triangle (all on the x axis) is its longest edge */
    const double d0[3] = {0, 0, 0}, d1[3] = {1, 0, 0}, d2[3] = {2, 0, 0};
    double p4[3] = {1.5, 2, 0};
    ck_assert_double_eq_tol(closest_point_triangle(p4, d0, d1, d2, w), 4.0, 1e-15);
}
END_TEST

START_TEST(test_closest_segments_match_dense_sampling)
{
    unsigned s = 777u;
    const int n = 300;
    for (int trial = 0; trial < 200; ++trial) {
        double p0[3], p1[3], q0[3], q1[3], st, tt;
        rand_point(&s, p0, 1.0);
        rand_point(&s, p1, 1.0);
        rand_point(&s, q0, 1.0);
        rand_point(&s, q1, 1.0);
        if (trial % 8 == 0) /* parallel */
            for (int k = 0; k < 3; ++k) q1[k] = q0[k] + 0.7 * (p1[k] - p0[k]);
        double d = sqrt(closest_segments(p0, p1, q0, q1, &st, &tt));
        ck_assert(st >= 0 && st <= 1 && tt >= 0 && tt <= 1);
        double pa[3], pb[3];
        for (int k = 0; k < 3; ++k) {
            pa[k] = p0[k] + st * (p1[k] - p0[k]);
            pb[k] = q0[k] + tt * (q1[k] - q0[k]);
        }
        ck_assert_double_eq_tol(sqrt(dist2(pa, pb)), d, 1e-12);
        double best = INFINITY;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n; ++j) {
                double u = (double)i / n, v = (double)j / n, x[3], y[3];
                for (int k = 0; k < 3; ++k) {
                    x[k] = p0[k] + u * (p1[k] - p0[k]);
                    y[k] = q0[k] + v * (q1[k] - q0[k]);
                }
                best = fmin(best, dist2(x, y));
            }
        best = sqrt(best);
        double len = sqrt(dist2(p0, p1)) + sqrt(dist2(q0, q1));
        ck_assert_msg(d <= best + 1e-12, "trial %d: %.17g > sampled %.17g", trial, d, best);
        ck_assert_msg(d >= best - len / n, "trial %d: %.17g far below %.17g", trial, d, best);
    }
    /* crossing segments: distance 0 at the crossing */
    double a0[3] = {-1, 0, 0}, a1[3] = {1, 0, 0}, b0[3] = {0.25, -1, 0}, b1[3] = {0.25, 1, 0};
    double st, tt;
    ck_assert_double_eq_tol(closest_segments(a0, a1, b0, b1, &st, &tt), 0.0, 1e-30);
    ck_assert_double_eq_tol(st, 0.625, 1e-15);
    ck_assert_double_eq_tol(tt, 0.5, 1e-15);
    /* skew lines 0.3 apart */
    double c0[3] = {0.25, -1, 0.3}, c1[3] = {0.25, 1, 0.3};
    ck_assert_double_eq_tol(closest_segments(a0, a1, c0, c1, &st, &tt), 0.09, 1e-15);
}
END_TEST

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static void random_boxes(unsigned *s, pl_aabb *b, int n, double spread)
{
    for (int i = 0; i < n; ++i) {
        double c[3];
        rand_point(s, c, spread);
        for (int k = 0; k < 3; ++k) {
            double h = 0.05 * urand(s);
            b[i].lo[k] = c[k] - h;
            b[i].hi[k] = c[k] + h;
        }
    }
}

static void check_queries(const pl_bvh *bvh, const pl_aabb *boxes, int n, unsigned *s)
{
    pl_ivec got = {0};
    int *ref = malloc((size_t)n * sizeof *ref);
    ck_assert_ptr_nonnull(ref);
    for (int qi = 0; qi < 200; ++qi) {
        pl_aabb q;
        random_boxes(s, &q, 1, 1.0);
        for (int k = 0; k < 3; ++k) q.hi[k] += 0.2 * urand(s);
        got.n = 0;
        ck_assert_int_eq(bvh_query(bvh, boxes, &q, &got), PL_OK);
        int nref = 0;
        for (int i = 0; i < n; ++i)
            if (aabb_overlap(&boxes[i], &q)) ref[nref++] = i;
        ck_assert_int_eq(got.n, nref);
        if (got.n > 0) qsort(got.v, (size_t)got.n, sizeof(int), cmp_int);
        for (int i = 0; i < nref; ++i) ck_assert_int_eq(got.v[i], ref[i]);
    }
    ivec_free(&got);
    free(ref);
}

START_TEST(test_bvh_queries_equal_brute_force_lists)
{
    unsigned s = 4242u;
    for (int n = 0; n <= 2000; n = n ? 4 * n : 1) {
        pl_aabb *boxes = malloc((size_t)(n ? n : 1) * sizeof *boxes);
        ck_assert_ptr_nonnull(boxes);
        random_boxes(&s, boxes, n, 1.0);
        pl_bvh bvh;
        bvh_init(&bvh);
        ck_assert_int_eq(bvh_build(&bvh, boxes, n), PL_OK);
        ck_assert_int_le(bvh.nnodes, n > 0 ? 2 * n : 1);
        check_queries(&bvh, boxes, n, &s);
        /* move every box, refit, query again */
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                double d = 0.3 * (2.0 * urand(&s) - 1.0);
                boxes[i].lo[k] += d;
                boxes[i].hi[k] += d;
            }
        bvh_refit(&bvh, boxes);
        check_queries(&bvh, boxes, n, &s);
        bvh_free(&bvh);
        free(boxes);
    }
}
END_TEST

/* A k x k x k grid of cubes, each split into 6 tetrahedra around its main diagonal. */
static void tet_grid(int k, double **verts, int *nv, int **tets, int *nt)
{
    int m = k + 1;
    *nv = m * m * m;
    *nt = 6 * k * k * k;
    *verts = malloc((size_t)*nv * 3 * sizeof **verts);
    *tets = malloc((size_t)*nt * 4 * sizeof **tets);
    ck_assert(*verts && *tets);
    for (int z = 0; z < m; ++z)
        for (int y = 0; y < m; ++y)
            for (int x = 0; x < m; ++x) {
                double *p = &(*verts)[3 * (x + m * (y + m * z))];
                p[0] = (double)x / k;
                p[1] = (double)y / k;
                p[2] = (double)z / k;
            }
    static const int path[6][2] = {{1, 2}, {1, 4}, {2, 1}, {2, 4}, {4, 1}, {4, 2}};
    int t = 0;
    for (int z = 0; z < k; ++z)
        for (int y = 0; y < k; ++y)
            for (int x = 0; x < k; ++x) {
                int c[8];
                for (int b = 0; b < 8; ++b)
                    c[b] = (x + (b & 1)) + m * ((y + ((b >> 1) & 1)) + m * (z + ((b >> 2) & 1)));
                for (int p = 0; p < 6; ++p) {
                    int b1 = path[p][0], b2 = b1 | path[p][1];
                    int *q = &(*tets)[4 * t++];
                    q[0] = c[0];
                    q[1] = c[b1];
                    q[2] = c[b2];
                    q[3] = c[7];
                }
            }
}

START_TEST(test_barycentric_map_reproduces_points)
{
    double *verts;
    int *tets, nv, nt;
    tet_grid(3, &verts, &nv, &tets, &nt);
    unsigned s = 99u;
    enum { NP = 400 };
    double pts[NP * 3], bary[NP * 4];
    int tet_of[NP];
    for (int i = 0; i < NP; ++i)
        for (int k = 0; k < 3; ++k) /* 3/4 inside [0,1]^3, the rest up to 0.3 outside */
            pts[3 * i + k] = i % 4 ? urand(&s) : -0.3 + 1.6 * urand(&s);
    int outside = -1;
    pl_error err;
    ck_assert_int_eq(barycentric_map(verts, nv, tets, nt, pts, NP, tet_of, bary, &outside, &err),
                     PL_OK);
    int nout = 0;
    for (int i = 0; i < NP; ++i) {
        const double *p = &pts[3 * i];
        int in = p[0] >= 0 && p[0] <= 1 && p[1] >= 0 && p[1] <= 1 && p[2] >= 0 && p[2] <= 1;
        nout += !in;
        double q[3] = {0, 0, 0}, sum = 0, mn = INFINITY;
        for (int k = 0; k < 4; ++k) {
            sum += bary[4 * i + k];
            mn = fmin(mn, bary[4 * i + k]);
            for (int j = 0; j < 3; ++j) q[j] += bary[4 * i + k] * verts[3 * tets[4 * tet_of[i] + k] + j];
        }
        ck_assert_double_eq_tol(sum, 1.0, 1e-12);
        ck_assert_double_eq_tol(sqrt(dist2(p, q)), 0.0, 1e-12);
        if (in) {
            ck_assert_msg(mn >= -1e-9, "point %d inside the grid got weight %g", i, mn);
        } else {
            /* the nearest tetrahedron: its distance is the distance to the unit cube */
            double dc = 0, dt = INFINITY, w[3];
            for (int k = 0; k < 3; ++k) {
                double e = fmax(0.0, fmax(-p[k], p[k] - 1.0));
                dc += e * e;
            }
            static const int F[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
            const int *t = &tets[4 * tet_of[i]];
            for (int f = 0; f < 4; ++f)
                dt = fmin(dt, closest_point_triangle(p, &verts[3 * t[F[f][0]]],
                                                        &verts[3 * t[F[f][1]]],
                                                        &verts[3 * t[F[f][2]]], w));
            ck_assert_double_eq_tol(sqrt(dt), sqrt(dc), 1e-12);
        }
    }
    ck_assert_int_eq(outside, nout);
    /* a flat tetrahedron is refused */
    int flat[4] = {0, 1, 2, 3};
    double fv[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    ck_assert_int_eq(barycentric_map(fv, 4, flat, 1, pts, 1, tet_of, bary, NULL, &err),
                     PL_EINPUT);
    free(verts);
    free(tets);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_narrow");
    TCase *tc = tcase_create("narrow");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_closest_point_triangle_matches_dense_sampling);
    tcase_add_test(tc, test_closest_point_triangle_regions);
    tcase_add_test(tc, test_closest_segments_match_dense_sampling);
    tcase_add_test(tc, test_bvh_queries_equal_brute_force_lists);
    tcase_add_test(tc, test_barycentric_map_reproduces_points);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *sr = srunner_create(suite());
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
