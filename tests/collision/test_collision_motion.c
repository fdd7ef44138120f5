/* test_collision_motion.c - prescribed motion of obstacles:
 *  - rotation about an axis through a point: the axis points stay, a point
 *    turns by w t (quarter turn checked exactly), distances are kept;
 *  - keyframes: linear interpolation, held before the first and after the
 *    last key, left derivative at a key; combined with a velocity;
 *  - the velocity of a material point equals the central finite difference
 *    of its posed position, for a random combined motion;
 *  - a spinning cylinder's surface velocity is w x r: tangent to the
 *    surface, of speed w R;
 *  - a posed shape: a sphere carried by keyframes and a plane turned about
 *    an axis answer at their moved places;
 *  - broken motions: keyframe times not increasing, wrong number of
 *    translations, a zero axis with a spin, non-finite values. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"

static void apply(const double R[9], const double tr[3], const double x[3], double y[3])
{
    for (int i = 0; i < 3; ++i)
        y[i] = R[3 * i] * x[0] + R[3 * i + 1] * x[1] + R[3 * i + 2] * x[2] + tr[i];
}

static pl_motion spin(const double axis[3], double w, const double c[3])
{
    pl_motion m;
    memset(&m, 0, sizeof m);
    memcpy(m.axis, axis, sizeof m.axis);
    m.angular_velocity = w;
    memcpy(m.center, c, sizeof m.center);
    return m;
}

START_TEST(test_rotation_about_axis)
{
    const double axis[3] = {0, 0, 2}, c[3] = {1, 1, 0};
    pl_motion m = spin(axis, M_PI / 2, c);
    pl_error err;
    ck_assert_int_eq(motion_prepare(&m, 0, &err), PL_OK);
    ck_assert_double_eq_tol(m.axis[2], 1.0, 1e-15); /* normalised */
    double R[9], tr[3], y[3];
    motion_pose(&m, 1.0, R, tr); /* a quarter turn */
    const double on_axis[3] = {1, 1, 7}, x[3] = {2, 1, 3};
    apply(R, tr, on_axis, y);
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(y[i], on_axis[i], 1e-14);
    apply(R, tr, x, y); /* (1,0) from the axis turns to (0,1) */
    ck_assert_double_eq_tol(y[0], 1.0, 1e-14);
    ck_assert_double_eq_tol(y[1], 2.0, 1e-14);
    ck_assert_double_eq_tol(y[2], 3.0, 1e-14);
    motion_pose(&m, 4.0, R, tr); /* a full turn: back home */
    apply(R, tr, x, y);
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(y[i], x[i], 1e-13);
}
END_TEST

START_TEST(test_keyframes_interpolate)
{
    const double T[3] = {1.0, 2.0, 4.0}, P[9] = {0, 0, 0, 1, 0, 0, 1, 2, 0};
    pl_motion m;
    memset(&m, 0, sizeof m);
    m.times = T;
    m.translations = P;
    m.ntimes = 3;
    m.velocity[2] = 0.5; /* combined with a constant velocity along z */
    pl_error err;
    ck_assert_int_eq(motion_prepare(&m, 9, &err), PL_OK);
    double R[9], tr[3], v[3];
    const double o[3] = {0, 0, 0};
    motion_pose(&m, 0.5, R, tr); /* before the first key: held */
    ck_assert_double_eq_tol(tr[0], 0.0, 1e-15);
    ck_assert_double_eq_tol(tr[2], 0.25, 1e-15);
    motion_pose(&m, 1.5, R, tr);
    ck_assert_double_eq_tol(tr[0], 0.5, 1e-15);
    motion_pose(&m, 3.0, R, tr);
    ck_assert_double_eq_tol(tr[0], 1.0, 1e-15);
    ck_assert_double_eq_tol(tr[1], 1.0, 1e-15);
    ck_assert_double_eq_tol(tr[2], 1.5, 1e-15);
    motion_pose(&m, 9.0, R, tr); /* after the last key: held */
    ck_assert_double_eq_tol(tr[0], 1.0, 1e-15);
    ck_assert_double_eq_tol(tr[1], 2.0, 1e-15);
    ck_assert_double_eq(R[0], 1.0); /* no rotation */
    /* velocities: left derivative, i.e. over the step that ends at t */
    motion_velocity(&m, 0.5, o, v);
    ck_assert_double_eq(v[0], 0.0);
    ck_assert_double_eq(v[2], 0.5);
    motion_velocity(&m, 2.0, o, v); /* at a key: the segment ending there */
    ck_assert_double_eq_tol(v[0], 1.0, 1e-15);
    ck_assert_double_eq_tol(v[1], 0.0, 1e-15);
    motion_velocity(&m, 2.0 + 1e-9, o, v);
    ck_assert_double_eq_tol(v[0], 0.0, 1e-15);
    ck_assert_double_eq_tol(v[1], 1.0, 1e-15);
    motion_velocity(&m, 5.0, o, v);
    ck_assert_double_eq(v[1], 0.0);
    ck_assert(!motion_is_static(&m));
}
END_TEST

START_TEST(test_velocity_is_derivative_of_pose)
{
    const double T[2] = {0.0, 3.0}, P[6] = {0, 0, 0, 0.3, -0.6, 0.9};
    pl_motion m;
    memset(&m, 0, sizeof m);
    m.velocity[0] = 0.2, m.velocity[1] = -0.1, m.velocity[2] = 0.05;
    m.axis[0] = 1, m.axis[1] = 2, m.axis[2] = -2;
    m.angular_velocity = 1.7;
    m.center[0] = 0.3, m.center[1] = -0.4, m.center[2] = 1.0;
    m.times = T, m.translations = P, m.ntimes = 2;
    pl_error err;
    ck_assert_int_eq(motion_prepare(&m, 6, &err), PL_OK);
    const double x0[3] = {1.0, 0.5, -0.25}, e = 1e-6;
    for (double t = 0.1; t < 2.9; t += 0.35) {
        double R[9], tr[3], xa[3], xb[3], xt[3], v[3];
        motion_pose(&m, t - e, R, tr);
        apply(R, tr, x0, xa);
        motion_pose(&m, t + e, R, tr);
        apply(R, tr, x0, xb);
        motion_pose(&m, t, R, tr);
        apply(R, tr, x0, xt);
        motion_velocity(&m, t, xt, v);
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(v[i], (xb[i] - xa[i]) / (2 * e), 1e-7);
        /* a rigid motion keeps distances to the (moving) axis point */
        double c0[3], ct[3];
        apply(R, tr, m.center, ct);
        memcpy(c0, m.center, sizeof c0);
        double d0 = 0, dt = 0;
        for (int i = 0; i < 3; ++i) {
            d0 += (x0[i] - c0[i]) * (x0[i] - c0[i]);
            dt += (xt[i] - ct[i]) * (xt[i] - ct[i]);
        }
        ck_assert_double_eq_tol(sqrt(dt), sqrt(d0), 1e-13);
    }
}
END_TEST

START_TEST(test_spinning_cylinder_surface_velocity)
{
    /* a roller of radius 0.1 along x spinning in place at 20 rad/s */
    const double c[3] = {0, 0.1, 0}, ax[3] = {1, 0, 0};
    pl_shape s0, s;
    pl_error err;
    ck_assert_int_eq(shape_cylinder(&s0, c, ax, 0.1, 1.0, &err), PL_OK);
    pl_motion m = spin(ax, 20.0, c);
    ck_assert_int_eq(motion_prepare(&m, 0, &err), PL_OK);
    double R[9], tr[3];
    motion_pose(&m, 0.37, R, tr);
    shape_transform(&s0, R, tr, &s);
    /* spinning about its own axis leaves the shape where it was */
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(s.center[i], c[i], 1e-15);
    const double probes[4][3] = {{0.2, 0.25, 0}, {-0.3, 0.1, 0.3}, {0, -0.05, 0}, {0.1, 0.2, -0.2}};
    for (int k = 0; k < 4; ++k) {
        double p[3], n[3], v[3];
        shape_query(&s, probes[k], p, n);
        motion_velocity(&m, 0.37, p, v);
        double r[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
        double wxr[3] = {0, -20.0 * r[2], 20.0 * r[1]}; /* w = 20 e_x */
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(v[i], wxr[i], 1e-13);
        ck_assert_double_eq_tol(v[0] * n[0] + v[1] * n[1] + v[2] * n[2], 0.0, 1e-13);
        ck_assert_double_eq_tol(sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 2.0, 1e-13);
    }
}
END_TEST

START_TEST(test_posed_shapes)
{
    /* a unit sphere carried by keyframes: at t = 1.5 it is halfway */
    const double T[2] = {1, 2}, P[6] = {0, 0, 0, 0, 0, 2}, o[3] = {0, 0, 0};
    pl_shape s0, s;
    pl_error err;
    ck_assert_int_eq(shape_sphere(&s0, o, 1.0, &err), PL_OK);
    pl_motion m;
    memset(&m, 0, sizeof m);
    m.times = T, m.translations = P, m.ntimes = 2;
    ck_assert_int_eq(motion_prepare(&m, 6, &err), PL_OK);
    double R[9], tr[3];
    motion_pose(&m, 1.5, R, tr);
    shape_transform(&s0, R, tr, &s);
    const double x[3] = {0, 0, 3};
    ck_assert_double_eq_tol(shape_query(&s, x, NULL, NULL), 1.0, 1e-15);
    /* a floor y = 0 tilting about the z axis through the origin at 0.5 rad/s */
    const double n0[3] = {0, 1, 0}, az[3] = {0, 0, 1};
    ck_assert_int_eq(shape_plane(&s0, o, n0, &err), PL_OK);
    pl_motion w = spin(az, 0.5, o);
    ck_assert_int_eq(motion_prepare(&w, 0, &err), PL_OK);
    motion_pose(&w, 1.0, R, tr);
    shape_transform(&s0, R, tr, &s);
    double n[3], p[3];
    const double y[3] = {0, 1, 0};
    ck_assert_double_eq_tol(shape_query(&s, y, p, n), cos(0.5), 1e-15);
    ck_assert_double_eq_tol(n[0], -sin(0.5), 1e-15);
    ck_assert_double_eq_tol(n[1], cos(0.5), 1e-15);
}
END_TEST

START_TEST(test_broken_motions_refused)
{
    pl_motion m;
    pl_error err;
    const double T[3] = {0, 1, 1}, P[9] = {0};
    memset(&m, 0, sizeof m);
    m.times = T, m.translations = P, m.ntimes = 3;
    ck_assert_int_eq(motion_prepare(&m, 9, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "strictly increasing"));
    m.ntimes = 2; /* 0, 1: increasing, but 9 values for 2 times */
    ck_assert_int_eq(motion_prepare(&m, 9, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "translations"));
    ck_assert_int_eq(motion_prepare(&m, 6, &err), PL_OK);
    memset(&m, 0, sizeof m);
    m.angular_velocity = 1.0; /* spin about no axis */
    ck_assert_int_eq(motion_prepare(&m, 0, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "rotationAxis"));
    m.angular_velocity = 0.0;
    ck_assert_int_eq(motion_prepare(&m, 0, &err), PL_OK);
    ck_assert(motion_is_static(&m));
    m.velocity[1] = INFINITY;
    ck_assert_int_eq(motion_prepare(&m, 0, &err), PL_EINPUT);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_motion");
    TCase *tc = tcase_create("motion");
    tcase_add_test(tc, test_rotation_about_axis);
    tcase_add_test(tc, test_keyframes_interpolate);
    tcase_add_test(tc, test_velocity_is_derivative_of_pose);
    tcase_add_test(tc, test_spinning_cylinder_surface_velocity);
    tcase_add_test(tc, test_posed_shapes);
    tcase_add_test(tc, test_broken_motions_refused);
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
