/* test_collision_shapes.c - the analytic shapes of the collision plugin:
 *  - signed distance of every shape against an independent brute-force
 *    reference (distance to a dense sampling of the surface, sign from an
 *    inside test) on random points inside and outside;
 *  - exact values at chosen points: box faces, edges and corners, capsule
 *    ends and side, cylinder side, caps and rim, sphere, tilted plane;
 *  - invariants of every query: x = closest + phi n, |n| = 1, the closest
 *    point lies on the surface (phi = 0 there);
 *  - a posed (rotated, translated) shape answers like the shape queried in
 *    its own frame;
 *  - the friction tangents are orthonormal and right-handed;
 *  - broken inputs (zero normal or axis, negative or NaN sizes) are refused. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"

static double urand(unsigned *s, double lo, double hi)
{
    *s = *s * 1664525u + 1013904223u;
    return lo + (hi - lo) * ((*s >> 8) / 16777216.0);
}

static double dist3(const double a[3], const double b[3])
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

/* The query's own consistency: x = p + phi n, |n| = 1, phi(p) = 0. */
static void check_invariants(const pl_shape *s, const double x[3])
{
    double p[3], n[3], p2[3], n2[3];
    double phi = shape_query(s, x, p, n);
    ck_assert(isfinite(phi));
    ck_assert_double_eq_tol(sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-12);
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(p[i] + phi * n[i], x[i], 1e-12);
    ck_assert_double_eq_tol(shape_query(s, p, p2, n2), 0.0, 1e-12);
}

/* ---- brute-force references ---------------------------------------------- */

/* Unsigned distance from x to the surface of an axis-aligned box of half
 * extents e at the origin, by sampling each face on a k x k grid. */
static double box_brute(const double e[3], const double x[3], int k)
{
    double best = INFINITY;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = -1; side <= 1; side += 2) {
            int a = (axis + 1) % 3, b = (axis + 2) % 3;
            for (int i = 0; i <= k; ++i)
                for (int j = 0; j <= k; ++j) {
                    double q[3];
                    q[axis] = side * e[axis];
                    q[a] = -e[a] + 2.0 * e[a] * i / k;
                    q[b] = -e[b] + 2.0 * e[b] * j / k;
                    best = fmin(best, dist3(q, x));
                }
        }
    int inside = fabs(x[0]) < e[0] && fabs(x[1]) < e[1] && fabs(x[2]) < e[2];
    return inside ? -best : best;
}

/* Cylinder of radius r, half length hl along z: side and caps sampled. */
static double cylinder_brute(double r, double hl, const double x[3], int k)
{
    double best = INFINITY;
    for (int i = 0; i < 4 * k; ++i) {
        double th = 2.0 * M_PI * i / (4 * k), c = cos(th), s = sin(th);
        for (int j = 0; j <= k; ++j) {
            double side[3] = {r * c, r * s, -hl + 2.0 * hl * j / k};
            best = fmin(best, dist3(side, x));
            for (int z = -1; z <= 1; z += 2) {
                double cap[3] = {r * j / k * c, r * j / k * s, z * hl};
                best = fmin(best, dist3(cap, x));
            }
        }
    }
    int inside = x[0] * x[0] + x[1] * x[1] < r * r && fabs(x[2]) < hl;
    return inside ? -best : best;
}

/* Capsule: distance to the segment by ternary search on the (convex)
 * distance along it, minus the radius. */
static double capsule_brute(const double a[3], const double b[3], double r, const double x[3])
{
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 200; ++it) {
        double t1 = lo + (hi - lo) / 3, t2 = hi - (hi - lo) / 3, q1[3], q2[3];
        for (int k = 0; k < 3; ++k) {
            q1[k] = a[k] + t1 * (b[k] - a[k]);
            q2[k] = a[k] + t2 * (b[k] - a[k]);
        }
        if (dist3(q1, x) < dist3(q2, x)) hi = t2;
        else lo = t1;
    }
    double q[3];
    for (int k = 0; k < 3; ++k) q[k] = a[k] + 0.5 * (lo + hi) * (b[k] - a[k]);
    return dist3(q, x) - r;
}

START_TEST(test_box_against_brute_force)
{
    const double e[3] = {0.3, 0.2, 0.1}, c[3] = {0, 0, 0};
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_box(&s, c, e, NULL, &err), PL_OK);
    unsigned seed = 7;
    const int k = 120;
    double h = 2.0 * 0.3 / k; /* coarsest grid spacing: bounds the sampling error */
    for (int t = 0; t < 150; ++t) {
        double x[3] = {urand(&seed, -0.6, 0.6), urand(&seed, -0.4, 0.4), urand(&seed, -0.3, 0.3)};
        double phi = shape_query(&s, x, NULL, NULL);
        double ref = box_brute(e, x, k);
        ck_assert_msg(fabs(phi - ref) <= h, "box at (%g %g %g): %g vs brute force %g", x[0], x[1],
                      x[2], phi, ref);
        ck_assert(phi <= ref + 1e-15 || ref < 0); /* sampling only over-estimates distance */
        check_invariants(&s, x);
    }
}
END_TEST

START_TEST(test_box_faces_edges_corners)
{
    const double e[3] = {1, 2, 3}, c[3] = {10, 20, 30};
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_box(&s, c, e, NULL, &err), PL_OK);
    double p[3], n[3];
    /* face region: straight out of +y */
    double xf[3] = {10.5, 20 + 2 + 0.25, 30.5};
    ck_assert_double_eq_tol(shape_query(&s, xf, p, n), 0.25, 1e-14);
    ck_assert_double_eq_tol(n[1], 1.0, 1e-15);
    ck_assert_double_eq_tol(p[1], 22.0, 1e-14);
    /* edge region (+x, -z edge): distance to the edge line */
    double xe[3] = {10 + 1 + 0.3, 20.7, 30 - 3 - 0.4};
    ck_assert_double_eq_tol(shape_query(&s, xe, p, n), 0.5, 1e-14);
    ck_assert_double_eq_tol(n[0], 0.6, 1e-14);
    ck_assert_double_eq_tol(n[2], -0.8, 1e-14);
    ck_assert_double_eq_tol(p[0], 11.0, 1e-14);
    ck_assert_double_eq_tol(p[1], 20.7, 1e-14);
    ck_assert_double_eq_tol(p[2], 27.0, 1e-14);
    /* corner region (-x, -y, +z): distance to the corner */
    double xc[3] = {9 - 1, 18 - 2, 33 + 2};
    ck_assert_double_eq_tol(shape_query(&s, xc, p, n), 3.0, 1e-14);
    ck_assert_double_eq_tol(p[0], 9.0, 1e-14);
    ck_assert_double_eq_tol(p[1], 18.0, 1e-14);
    ck_assert_double_eq_tol(p[2], 33.0, 1e-14);
    ck_assert_double_eq_tol(n[2], 2.0 / 3.0, 1e-14);
    /* inside: the nearest face (x is 0.2 from +x, farther from the others) */
    double xi[3] = {10.8, 20.5, 30.0};
    ck_assert_double_eq_tol(shape_query(&s, xi, p, n), -0.2, 1e-14);
    ck_assert_double_eq_tol(n[0], 1.0, 1e-15);
    ck_assert_double_eq_tol(p[0], 11.0, 1e-14);
    /* the centre: the smallest half extent decides (x, -0 -> +x) */
    ck_assert_double_eq_tol(shape_query(&s, c, p, n), -1.0, 1e-15);
    ck_assert_double_eq_tol(n[0], 1.0, 1e-15);
    /* on an edge exactly: distance 0, a valid outward normal */
    double xon[3] = {11, 22, 30};
    ck_assert_double_eq_tol(shape_query(&s, xon, p, n), 0.0, 1e-15);
    ck_assert(n[0] > 0 || n[1] > 0);
}
END_TEST

START_TEST(test_rotated_box_matches_local_query)
{
    /* box turned 30 deg about z: a point along the turned x axis */
    double th = M_PI / 6, R[9] = {cos(th), -sin(th), 0, sin(th), cos(th), 0, 0, 0, 1};
    const double e[3] = {1, 0.5, 0.25}, c[3] = {1, 2, 3};
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_box(&s, c, e, R, &err), PL_OK);
    double x[3] = {1 + 1.5 * cos(th), 2 + 1.5 * sin(th), 3}, p[3], n[3];
    ck_assert_double_eq_tol(shape_query(&s, x, p, n), 0.5, 1e-14);
    ck_assert_double_eq_tol(n[0], cos(th), 1e-14);
    ck_assert_double_eq_tol(n[1], sin(th), 1e-14);
    /* random points: rotated query = local query of R^T (x - c) */
    pl_shape local;
    const double zero[3] = {0, 0, 0};
    ck_assert_int_eq(shape_box(&local, zero, e, NULL, &err), PL_OK);
    unsigned seed = 3;
    for (int t = 0; t < 200; ++t) {
        double y[3] = {urand(&seed, -2, 4), urand(&seed, -1, 5), urand(&seed, 2, 4)}, yl[3];
        for (int j = 0; j < 3; ++j)
            yl[j] = R[j] * (y[0] - c[0]) + R[3 + j] * (y[1] - c[1]) + R[6 + j] * (y[2] - c[2]);
        ck_assert_double_eq_tol(shape_query(&s, y, NULL, NULL),
                                shape_query(&local, yl, NULL, NULL), 1e-13);
        check_invariants(&s, y);
    }
}
END_TEST

START_TEST(test_plane_any_orientation)
{
    const double pt[3] = {0.5, -1, 2}, nn[3] = {1, 2, 2}; /* |nn| = 3 */
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_plane(&s, pt, nn, &err), PL_OK);
    unsigned seed = 11;
    for (int t = 0; t < 100; ++t) {
        double x[3] = {urand(&seed, -3, 3), urand(&seed, -3, 3), urand(&seed, -3, 3)}, p[3], n[3];
        double ref = (nn[0] * (x[0] - pt[0]) + nn[1] * (x[1] - pt[1]) + nn[2] * (x[2] - pt[2])) / 3;
        ck_assert_double_eq_tol(shape_query(&s, x, p, n), ref, 1e-13);
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(n[i], nn[i] / 3.0, 1e-15);
        check_invariants(&s, x);
    }
}
END_TEST

START_TEST(test_sphere_analytic)
{
    const double c[3] = {1, -2, 0.5};
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_sphere(&s, c, 0.75, &err), PL_OK);
    unsigned seed = 5;
    for (int t = 0; t < 100; ++t) {
        double x[3] = {urand(&seed, -1, 3), urand(&seed, -4, 0), urand(&seed, -1.5, 2.5)};
        ck_assert_double_eq_tol(shape_query(&s, x, NULL, NULL), dist3(x, c) - 0.75, 1e-14);
        check_invariants(&s, x);
    }
    double p[3], n[3];
    ck_assert_double_eq_tol(shape_query(&s, c, p, n), -0.75, 1e-15); /* centre: fixed choice */
    ck_assert_double_eq_tol(n[0], 1.0, 1e-15);
}
END_TEST

START_TEST(test_capsule_against_brute_force)
{
    const double a[3] = {0, 0, 0}, b[3] = {1, 1, 0.5};
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_capsule(&s, a, b, 0.2, &err), PL_OK);
    unsigned seed = 13;
    for (int t = 0; t < 150; ++t) {
        double x[3] = {urand(&seed, -0.6, 1.6), urand(&seed, -0.6, 1.6), urand(&seed, -0.5, 1)};
        double ref = capsule_brute(a, b, 0.2, x);
        ck_assert_double_eq_tol(shape_query(&s, x, NULL, NULL), ref, 1e-10);
        check_invariants(&s, x);
    }
    /* beyond an end: the rounded cap, normal along the axis */
    double len = 1.5, u[3] = {1 / len, 1 / len, 0.5 / len}, x[3], p[3], n[3];
    for (int i = 0; i < 3; ++i) x[i] = b[i] + 0.5 * u[i];
    ck_assert_double_eq_tol(shape_query(&s, x, p, n), 0.3, 1e-14);
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(n[i], u[i], 1e-14);
    for (int i = 0; i < 3; ++i) x[i] = a[i] - 0.1 * u[i];
    ck_assert_double_eq_tol(shape_query(&s, x, p, n), -0.1, 1e-14);
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(n[i], -u[i], 1e-14);
    /* on the axis: depth = radius */
    double mid[3] = {0.5, 0.5, 0.25};
    ck_assert_double_eq_tol(shape_query(&s, mid, p, n), -0.2, 1e-14);
    ck_assert_double_eq_tol(n[0] * u[0] + n[1] * u[1] + n[2] * u[2], 0.0, 1e-14);
}
END_TEST

START_TEST(test_cylinder_against_brute_force)
{
    /* axis along (0, 1, 0): compare in the cylinder's frame, the brute force along z */
    const double c[3] = {0.2, 0.1, -0.3}, ax[3] = {0, 2, 0};
    const double r = 0.25, len = 0.6;
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_cylinder(&s, c, ax, r, len, &err), PL_OK);
    unsigned seed = 17;
    const int k = 200;
    for (int t = 0; t < 120; ++t) {
        double x[3] = {urand(&seed, -0.3, 0.7), urand(&seed, -0.4, 0.6), urand(&seed, -0.8, 0.2)};
        /* local frame with z along y: (x, y, z) -> (z', x', y') keeps a right-handed swap */
        double xl[3] = {x[2] - c[2], x[0] - c[0], x[1] - c[1]};
        double ref = cylinder_brute(r, len / 2, xl, k);
        double phi = shape_query(&s, x, NULL, NULL);
        ck_assert_msg(fabs(phi - ref) <= 2.0 * M_PI * r / (4 * k) + len / k,
                      "cylinder at (%g %g %g): %g vs %g", x[0], x[1], x[2], phi, ref);
        check_invariants(&s, x);
    }
    double p[3], n[3];
    double side[3] = {0.2 + 0.5, 0.15, -0.3}; /* beside it */
    ck_assert_double_eq_tol(shape_query(&s, side, p, n), 0.25, 1e-14);
    ck_assert_double_eq_tol(n[0], 1.0, 1e-14);
    double cap[3] = {0.3, 0.1 + 0.3 + 0.2, -0.3}; /* above the top cap */
    ck_assert_double_eq_tol(shape_query(&s, cap, p, n), 0.2, 1e-14);
    ck_assert_double_eq_tol(n[1], 1.0, 1e-14);
    double rim[3] = {0.2 + 0.25 + 0.3, 0.1 - 0.3 - 0.4, -0.3}; /* below and beside: the rim */
    ck_assert_double_eq_tol(shape_query(&s, rim, p, n), 0.5, 1e-14);
    ck_assert_double_eq_tol(n[0], 0.6, 1e-14);
    ck_assert_double_eq_tol(n[1], -0.8, 1e-14);
    double in[3] = {0.2, 0.1 + 0.25, -0.3}; /* on the axis, 0.05 below the top cap */
    ck_assert_double_eq_tol(shape_query(&s, in, p, n), -0.05, 1e-14);
    ck_assert_double_eq_tol(n[1], 1.0, 1e-14);
}
END_TEST

START_TEST(test_transform_moves_shape)
{
    /* a capsule turned 90 deg about z and shifted: query at the moved points */
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0};
    pl_shape s, m;
    pl_error err;
    ck_assert_int_eq(shape_capsule(&s, a, b, 0.1, &err), PL_OK);
    const double Rz[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, tr[3] = {5, 0, 0};
    shape_transform(&s, Rz, tr, &m);
    /* the segment is now from (5,0,0) to (5,1,0) */
    double x[3] = {5.3, 0.5, 0}, p[3], n[3];
    ck_assert_double_eq_tol(shape_query(&m, x, p, n), 0.2, 1e-14);
    ck_assert_double_eq_tol(n[0], 1.0, 1e-14);
    double top[3] = {5, 1.4, 0};
    ck_assert_double_eq_tol(shape_query(&m, top, p, n), 0.3, 1e-14);
    ck_assert_double_eq_tol(n[1], 1.0, 1e-14);
}
END_TEST

START_TEST(test_tangents_orthonormal)
{
    unsigned seed = 19;
    for (int t = 0; t < 500; ++t) {
        double n[3] = {urand(&seed, -1, 1), urand(&seed, -1, 1), urand(&seed, -1, 1)};
        if (t < 6) n[0] = n[1] = n[2] = 0, n[t % 3] = t < 3 ? 1 : -1; /* the axes themselves */
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), t1[3], t2[3];
        for (int i = 0; i < 3; ++i) n[i] /= l;
        contact_tangents(n, t1, t2);
        double d11 = 0, d22 = 0, d12 = 0, d1n = 0, d2n = 0;
        for (int i = 0; i < 3; ++i) {
            d11 += t1[i] * t1[i], d22 += t2[i] * t2[i], d12 += t1[i] * t2[i];
            d1n += t1[i] * n[i], d2n += t2[i] * n[i];
        }
        ck_assert_double_eq_tol(d11, 1, 1e-14);
        ck_assert_double_eq_tol(d22, 1, 1e-14);
        ck_assert_double_eq_tol(d12, 0, 1e-14);
        ck_assert_double_eq_tol(d1n, 0, 1e-14);
        ck_assert_double_eq_tol(d2n, 0, 1e-14);
        /* right-handed: t1 x t2 = n */
        double cz[3] = {t1[1] * t2[2] - t1[2] * t2[1], t1[2] * t2[0] - t1[0] * t2[2],
                        t1[0] * t2[1] - t1[1] * t2[0]};
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(cz[i], n[i], 1e-14);
        /* deterministic: the same normal gives the same tangents */
        double u1[3], u2[3];
        contact_tangents(n, u1, u2);
        ck_assert(memcmp(t1, u1, sizeof t1) == 0 && memcmp(t2, u2, sizeof t2) == 0);
    }
}
END_TEST

START_TEST(test_broken_shapes_refused)
{
    pl_shape s;
    pl_error err;
    const double o[3] = {0, 0, 0}, zero[3] = {0, 0, 0}, x[3] = {1, 0, 0};
    ck_assert_int_eq(shape_plane(&s, o, zero, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "normal"));
    ck_assert_int_eq(shape_sphere(&s, o, -0.1, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "radius"));
    ck_assert_int_eq(shape_sphere(&s, o, NAN, &err), PL_EINPUT);
    const double bad_half[3] = {1, -1, 1};
    ck_assert_int_eq(shape_box(&s, o, bad_half, NULL, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "halfExtents"));
    ck_assert_int_eq(shape_capsule(&s, o, x, -1, &err), PL_EINPUT);
    ck_assert_int_eq(shape_cylinder(&s, o, zero, 1, 1, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "axis"));
    ck_assert_int_eq(shape_cylinder(&s, o, x, 1, -2, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "length"));
    /* a capsule with coinciding ends is a sphere */
    ck_assert_int_eq(shape_capsule(&s, x, x, 0.5, &err), PL_OK);
    double y[3] = {1, 2, 0};
    ck_assert_double_eq_tol(shape_query(&s, y, NULL, NULL), 1.5, 1e-15);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_shapes");
    TCase *tc = tcase_create("shapes");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_box_against_brute_force);
    tcase_add_test(tc, test_box_faces_edges_corners);
    tcase_add_test(tc, test_rotated_box_matches_local_query);
    tcase_add_test(tc, test_plane_any_orientation);
    tcase_add_test(tc, test_sphere_analytic);
    tcase_add_test(tc, test_capsule_against_brute_force);
    tcase_add_test(tc, test_cylinder_against_brute_force);
    tcase_add_test(tc, test_transform_moves_shape);
    tcase_add_test(tc, test_tangents_orthonormal);
    tcase_add_test(tc, test_broken_shapes_refused);
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
