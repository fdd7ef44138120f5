/* test_cable_geometry.c - the cable's geometry (plugins/cable/cable_path.c):
 *  - the length of a straight cable from its pull point is the distance;
 *  - dL/dP agrees with central finite differences, also for points mapped
 *    with barycentric weights, and the row is -dL/dx merged per vertex;
 *  - the net force of a unit tension on the body, sum_a H_a, is the unit
 *    vector from the first point towards the pull point (the sliding
 *    points' forces cancel pairwise along the cable);
 *  - a point located in a tetrahedron is reproduced by its weights, which
 *    are >= 0 and sum to 1; a point outside reports how far outside;
 *  - a zero-length segment adds no (NaN) gradient. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cable.h"

/* deterministic pseudo-random numbers in [0, 1) */
static double rnd(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0;
}

START_TEST(straight_cable_length)
{
    double x[] = {1, 0, 0, 2, 0, 0, 4, 0, 0};
    pl_cable_path c;
    cable_path_init(&c);
    ck_assert_int_eq(cable_path_alloc(&c, 3), PL_OK);
    for (int i = 0; i < 3; ++i) {
        c.vert[4 * i] = i;
        c.weight[4 * i] = 1.0;
    }
    c.has_pull = 1; /* pull point at the origin */
    ck_assert_double_eq_tol(cable_path_length(&c, x), 4.0, 1e-15);
    c.has_pull = 0; /* starts at P_0 */
    ck_assert_double_eq_tol(cable_path_length(&c, x), 3.0, 1e-15);
    cable_path_free(&c);
}
END_TEST

/* A random cable of m points, each mapped on 4 of n vertices. */
static void random_cable(pl_cable_path *c, int m, int n, double *x, unsigned *seed)
{
    cable_path_init(c);
    ck_assert_int_eq(cable_path_alloc(c, m), PL_OK);
    for (int i = 0; i < 3 * n; ++i) x[i] = rnd(seed);
    for (int i = 0; i < m; ++i) {
        double sum = 0;
        for (int s = 0; s < 4; ++s) {
            c->vert[4 * i + s] = (int)(rnd(seed) * n);
            c->weight[4 * i + s] = 0.1 + rnd(seed);
            sum += c->weight[4 * i + s];
        }
        for (int s = 0; s < 4; ++s) c->weight[4 * i + s] /= sum;
    }
    c->has_pull = 1;
    c->pull[0] = -1.0;
    c->pull[1] = 0.5;
    c->pull[2] = 0.25;
}

START_TEST(gradient_matches_finite_differences)
{
    enum { N = 12, M = 7 };
    unsigned seed = 12345u;
    double x[3 * N], g[3 * M], coef[12 * M];
    int vert[4 * M];
    pl_cable_path c;
    random_cable(&c, M, N, x, &seed);
    double L = cable_gradient(&c, x, g);
    ck_assert_double_eq_tol(L, cable_path_length(&c, x), 1e-15);
    int ne = cable_row(&c, g, vert, coef);
    ck_assert_int_gt(ne, 0);
    ck_assert_int_le(ne, N);
    for (int k = 1; k < ne; ++k) ck_assert_int_lt(vert[k - 1], vert[k]); /* merged, sorted */
    /* row entry of every vertex = -dL/dx_v by central differences */
    const double h = 1e-6;
    for (int v = 0; v < N; ++v)
        for (int d = 0; d < 3; ++d) {
            double save = x[3 * v + d];
            x[3 * v + d] = save + h;
            double Lp = cable_path_length(&c, x);
            x[3 * v + d] = save - h;
            double Lm = cable_path_length(&c, x);
            x[3 * v + d] = save;
            double fd = -(Lp - Lm) / (2 * h), row = 0.0;
            for (int k = 0; k < ne; ++k)
                if (vert[k] == v) row = coef[3 * k + d];
            ck_assert_double_eq_tol(row, fd, 1e-7);
        }
    cable_path_free(&c);
}
END_TEST

START_TEST(net_force_points_to_pull_point)
{
    enum { N = 10, M = 6 };
    unsigned seed = 777u;
    double x[3 * N], g[3 * M], coef[12 * M];
    int vert[4 * M];
    pl_cable_path c;
    random_cable(&c, M, N, x, &seed);
    cable_gradient(&c, x, g);
    int ne = cable_row(&c, g, vert, coef);
    double net[3] = {0, 0, 0}, p0[3], u[3], l = 0;
    for (int k = 0; k < ne; ++k)
        for (int d = 0; d < 3; ++d) net[d] += coef[3 * k + d];
    cable_point(&c, x, 0, p0);
    for (int d = 0; d < 3; ++d) l += (c.pull[d] - p0[d]) * (c.pull[d] - p0[d]);
    for (int d = 0; d < 3; ++d) u[d] = (c.pull[d] - p0[d]) / sqrt(l);
    for (int d = 0; d < 3; ++d) ck_assert_double_eq_tol(net[d], u[d], 1e-13);
    cable_path_free(&c);
}
END_TEST

START_TEST(locate_in_tetrahedra)
{
    /* a cube split into 5 tetrahedra */
    double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1};
    int tets[] = {0, 1, 2, 4, 1, 3, 2, 7, 1, 5, 7, 4, 2, 6, 4, 7, 1, 2, 4, 7};
    unsigned seed = 99u;
    for (int trial = 0; trial < 200; ++trial) {
        double p[3] = {rnd(&seed), rnd(&seed), rnd(&seed)}, w[4], out, q[3] = {0, 0, 0};
        int v[4];
        int t = cable_locate(x, tets, 5, p, v, w, &out);
        ck_assert_int_ge(t, 0);
        ck_assert_double_eq(out, 0.0);
        double sum = 0;
        for (int s = 0; s < 4; ++s) {
            ck_assert_double_ge(w[s], -1e-14);
            sum += w[s];
            for (int d = 0; d < 3; ++d) q[d] += w[s] * x[3 * v[s] + d];
        }
        ck_assert_double_eq_tol(sum, 1.0, 1e-14);
        for (int d = 0; d < 3; ++d) ck_assert_double_eq_tol(q[d], p[d], 1e-14);
    }
    /* outside: still reproduced (extrapolated), reported as outside */
    double p[3] = {1.5, 0.5, 0.5}, w[4], out, q[3] = {0, 0, 0};
    int v[4];
    ck_assert_int_ge(cable_locate(x, tets, 5, p, v, w, &out), 0);
    ck_assert_double_gt(out, 0.1);
    for (int s = 0; s < 4; ++s)
        for (int d = 0; d < 3; ++d) q[d] += w[s] * x[3 * v[s] + d];
    for (int d = 0; d < 3; ++d) ck_assert_double_eq_tol(q[d], p[d], 1e-13);
    ck_assert_int_eq(cable_nearest(x, 8, p), 1); /* (1,0,0) ties broken by the lowest index */
}
END_TEST

START_TEST(zero_length_segment_is_finite)
{
    double x[] = {0, 0, 0, 0, 0, 0, 1, 0, 0};
    double g[9], coef[36];
    int vert[12];
    pl_cable_path c;
    cable_path_init(&c);
    ck_assert_int_eq(cable_path_alloc(&c, 3), PL_OK);
    for (int i = 0; i < 3; ++i) {
        c.vert[4 * i] = i;
        c.weight[4 * i] = 1.0;
    }
    c.has_pull = 1; /* pull point at the origin = P_0: first segment has length 0 */
    ck_assert_double_eq_tol(cable_gradient(&c, x, g), 1.0, 1e-15);
    int ne = cable_row(&c, g, vert, coef);
    for (int k = 0; k < 3 * ne; ++k) ck_assert(isfinite(coef[k]));
    cable_path_free(&c);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cable_geometry");
    TCase *tc = tcase_create("geometry");
    tcase_add_test(tc, straight_cable_length);
    tcase_add_test(tc, gradient_matches_finite_differences);
    tcase_add_test(tc, net_force_points_to_pull_point);
    tcase_add_test(tc, locate_in_tetrahedra);
    tcase_add_test(tc, zero_length_segment_is_finite);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
