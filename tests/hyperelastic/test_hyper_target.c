/* test_hyper_target.c - position targets: motion laws (keyframe
 * interpolation, rotation, velocity), input checks, and the PD term's
 * matrix and right-hand side. */
#include <check.h>
#include <math.h>
#include <string.h>

#include "hyper_test_util.h"
#include "hyperelastic.h"

START_TEST(keyframe_offsets_interpolate_linearly_and_clamp)
{
    const double times[3] = {0.0, 1.0, 3.0};
    const double values[9] = {0, 0, 0, 1, 2, 0, 1, 2, -4}; /* one offset per time */
    pl_hyper_motion m = {.kind = PL_HYPER_MOTION_KEYFRAMES, .times = times, .ntimes = 3,
                         .values = values, .nvalues = 9};
    const double base[6] = {1, 1, 1, -1, 0, 2};
    ck_assert_int_eq(hyper_motion_check(&m, 2, NULL), PL_OK);
    double out[6];
    struct { double t, off[3]; } cases[] = {
        {-1.0, {0, 0, 0}}, {0.0, {0, 0, 0}}, {0.25, {0.25, 0.5, 0}}, {1.0, {1, 2, 0}},
        {2.0, {1, 2, -2}}, {3.0, {1, 2, -4}}, {10.0, {1, 2, -4}}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        hyper_motion_eval(&m, 2, base, cases[c].t, out);
        for (int p = 0; p < 2; ++p)
            for (int a = 0; a < 3; ++a)
                ck_assert_double_eq_tol(out[3 * p + a], base[3 * p + a] + cases[c].off[a], 1e-15);
    }
}
END_TEST

START_TEST(keyframe_positions_per_point)
{
    const double times[2] = {1.0, 2.0};
    /* time 1: points at (0,0,0), (1,0,0); time 2: at (0,2,0), (1,0,4) */
    const double values[12] = {0, 0, 0, 1, 0, 0, 0, 2, 0, 1, 0, 4};
    pl_hyper_motion m = {.kind = PL_HYPER_MOTION_KEYFRAMES, .times = times, .ntimes = 2,
                         .values = values, .nvalues = 12};
    const double base[6] = {9, 9, 9, 9, 9, 9}; /* ignored for positions */
    ck_assert_int_eq(hyper_motion_check(&m, 2, NULL), PL_OK);
    double out[6];
    hyper_motion_eval(&m, 2, base, 1.5, out);
    const double expect[6] = {0, 1, 0, 1, 0, 2};
    for (int i = 0; i < 6; ++i) ck_assert_double_eq_tol(out[i], expect[i], 1e-15);
    hyper_motion_eval(&m, 2, base, 0.0, out);
    for (int i = 0; i < 6; ++i) ck_assert_double_eq_tol(out[i], values[i], 1e-15);
}
END_TEST

START_TEST(rotation_and_velocity_motions)
{
    pl_hyper_motion m = {.kind = PL_HYPER_MOTION_ROTATION, .center = {1, 1, 0},
                         .axis = {0, 0, 2}, .angular_velocity = M_PI / 2};
    const double base[3] = {2, 1, 5};
    double out[3];
    ck_assert_int_eq(hyper_motion_check(&m, 1, NULL), PL_OK);
    hyper_motion_eval(&m, 1, base, 1.0, out); /* quarter turn about z through (1,1) */
    ck_assert_double_eq_tol(out[0], 1.0, 1e-14);
    ck_assert_double_eq_tol(out[1], 2.0, 1e-14);
    ck_assert_double_eq_tol(out[2], 5.0, 1e-14);
    hyper_motion_eval(&m, 1, base, 2.0, out);
    ck_assert_double_eq_tol(out[0], 0.0, 1e-14);
    ck_assert_double_eq_tol(out[1], 1.0, 1e-14);
    pl_hyper_motion v = {.kind = PL_HYPER_MOTION_VELOCITY, .velocity = {1, -2, 0.5}};
    hyper_motion_eval(&v, 1, base, 0.5, out);
    ck_assert_double_eq_tol(out[0], 2.5, 1e-15);
    ck_assert_double_eq_tol(out[1], 0.0, 1e-15);
    ck_assert_double_eq_tol(out[2], 5.25, 1e-15);
    pl_hyper_motion none = {.kind = PL_HYPER_MOTION_NONE};
    hyper_motion_eval(&none, 1, base, 7.0, out);
    for (int a = 0; a < 3; ++a) ck_assert_double_eq(out[a], base[a]);
}
END_TEST

START_TEST(motion_check_rejects_bad_input)
{
    pl_error err;
    const double times[2] = {1.0, 1.0}, values[6] = {0};
    pl_hyper_motion m = {.kind = PL_HYPER_MOTION_KEYFRAMES, .times = times, .ntimes = 2,
                         .values = values, .nvalues = 6};
    ck_assert_int_eq(hyper_motion_check(&m, 4, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "increase"));
    const double t2[2] = {0.0, 1.0};
    m.times = t2;
    m.nvalues = 5;
    ck_assert_int_eq(hyper_motion_check(&m, 4, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "got 5"));
    pl_hyper_motion r = {.kind = PL_HYPER_MOTION_ROTATION};
    ck_assert_int_eq(hyper_motion_check(&r, 1, &err), PL_EINPUT);
}
END_TEST

/* The PD term: A gets h2 k at each target's vertex; rhs gets h2 k t; the
 * global step of a lone target with mass m lands at (m x + h2 k t)/(m + h2 k). */
START_TEST(point_target_matrix_and_rhs)
{
    int idx[2] = {1, 3};
    pl_hyper_stencils s;
    ck_assert_int_eq(hyper_point_targets_build(&s, idx, 2, 4, 100.0, NULL), PL_OK);
    pl_triplets A;
    pl_triplets_init(&A, 6, 6, 4);
    const double h2 = 1e-4;
    ck_assert_int_eq(hyper_stencils_add_matrix(&s, 2, h2, &A, NULL), PL_OK);
    double dense[36] = {0};
    ht_triplets_to_dense(&A, dense, 6);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            ck_assert_double_eq(dense[i * 6 + j], (i == j && (i == 3 || i == 5)) ? h2 * 100.0 : 0.0);
    double q[18] = {0}, rhs[18] = {0}, targets[6] = {1, 2, 3, 4, 5, 6}, work[6];
    ck_assert_uint_eq(hyper_stencils_work_size(&s), 6);
    ck_assert_int_eq(hyper_stencils_project(&s, 2, h2, q, targets, work, rhs, NULL), PL_OK);
    for (int a = 0; a < 3; ++a) {
        ck_assert_double_eq_tol(rhs[3 * 3 + a], h2 * 100.0 * targets[a], 1e-18);
        ck_assert_double_eq_tol(rhs[3 * 5 + a], h2 * 100.0 * targets[3 + a], 1e-18);
        ck_assert_double_eq(rhs[3 * 4 + a], 0.0);
    }
    pl_triplets_free(&A);
    hyper_stencils_free(&s);
    pl_error err;
    ck_assert_int_eq(hyper_point_targets_build(&s, idx, 2, 3, 100.0, &err), PL_EINPUT);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("hyper_target");
    TCase *tc = tcase_create("target");
    tcase_add_test(tc, keyframe_offsets_interpolate_linearly_and_clamp);
    tcase_add_test(tc, keyframe_positions_per_point);
    tcase_add_test(tc, rotation_and_velocity_motions);
    tcase_add_test(tc, motion_check_rejects_bad_input);
    tcase_add_test(tc, point_target_matrix_and_rhs);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
