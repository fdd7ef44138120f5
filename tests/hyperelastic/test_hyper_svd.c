/* test_hyper_svd.c - signed SVD, polar decompositions and the small
 * symmetric eigen-solver of the hyperelastic core. */
#include <check.h>
#include <math.h>
#include <string.h>

#include "hyper_test_util.h"
#include "hyperelastic.h"

static double det3(const double *A)
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* max |Q^T Q - I| for a 3 x n matrix with orthonormal columns expected. */
static double orth_error(const double *Q, int rows, int n)
{
    double e = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double s = 0.0;
            for (int r = 0; r < rows; ++r) s += Q[r * n + i] * Q[r * n + j];
            e = fmax(e, fabs(s - (i == j)));
        }
    return e;
}

static double fro(const double *A, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += A[i] * A[i];
    return sqrt(s);
}

/* Checks every property of the signed 3x3 SVD of F, its Jacobi sweeps
 * started from V0 (NULL: the identity). */
static void check_svd3_from(const double *F, const double *V0)
{
    double U[9], s[3], V[9], R[9];
    hyper_svd3_from(F, V0, U, s, V);
    double err = 0.0;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            double v = 0.0;
            for (int i = 0; i < 3; ++i) v += U[a * 3 + i] * s[i] * V[b * 3 + i];
            err = fmax(err, fabs(v - F[a * 3 + b]));
        }
    double scale = 0.0; /* max |F_ij|: a 2-norm of 1e-200 entries underflows */
    for (int i = 0; i < 9; ++i) scale = fmax(scale, fabs(F[i]));
    ck_assert_msg(err <= 1e-13 * scale, "reconstruction error %g (|F| %g)", err, scale);
    ck_assert_double_le(orth_error(U, 3, 3), 1e-13);
    ck_assert_double_le(orth_error(V, 3, 3), 1e-13);
    ck_assert_double_eq_tol(det3(U), 1.0, 1e-12);
    ck_assert_double_eq_tol(det3(V), 1.0, 1e-12);
    ck_assert(s[0] >= s[1] && s[1] >= fabs(s[2]) - 1e-15 * scale && s[1] >= 0.0);
    double dF = det3(F);
    if (scale > 1e-100 && fabs(dF) > 1e-10 * scale * scale * scale)
        ck_assert_msg((s[2] < 0) == (dF < 0), "sign");
    hyper_polar3(F, R);
    ck_assert_double_le(orth_error(R, 3, 3), 1e-13);
    ck_assert_double_eq_tol(det3(R), 1.0, 1e-12);
}

static void check_svd3(const double *F)
{
    check_svd3_from(F, NULL);
}

START_TEST(svd3_reconstructs_with_proper_rotations)
{
    unsigned long long st = 42;
    for (int t = 0; t < 2000; ++t) {
        double F[9];
        for (int i = 0; i < 9; ++i) F[i] = ht_rand(&st);
        check_svd3(F);
    }
}
END_TEST

START_TEST(svd3_handles_degenerate_and_repeated_values)
{
    unsigned long long st = 7;
    double R[9], F[9];
    ht_random_rotation(&st, R);
    /* a scaled rotation: all singular values equal */
    for (int i = 0; i < 9; ++i) F[i] = 2.0 * R[i];
    check_svd3(F);
    /* rank 1, rank 2, zero, tiny */
    double u[3] = {0.3, -0.5, 0.8}, v[3] = {-0.2, 0.9, 0.1};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) F[a * 3 + b] = u[a] * v[b];
    check_svd3(F);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) F[a * 3 + b] = u[a] * v[b] + R[a * 3 + 0] * R[b * 3 + 1];
    check_svd3(F);
    memset(F, 0, sizeof F);
    check_svd3(F);
    for (int i = 0; i < 9; ++i) F[i] = 1e-200 * R[i];
    check_svd3(F);
    /* small singular value kept to relative accuracy: diag(1, 1, 1e-12) rotated */
    double S[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1e-12}, T[9], Q[9], s[3], U[9], V[9];
    ht_random_rotation(&st, Q);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            T[a * 3 + b] = 0.0;
            for (int k = 0; k < 3; ++k) T[a * 3 + b] += R[a * 3 + k] * S[k * 3 + b];
        }
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            F[a * 3 + b] = 0.0;
            for (int k = 0; k < 3; ++k) F[a * 3 + b] += T[a * 3 + k] * Q[b * 3 + k];
        }
    hyper_svd3(F, U, s, V);
    ck_assert_double_eq_tol(s[2], 1e-12, 1e-15);
}
END_TEST

/* The warm start of the local step: the sweeps from the V of a nearby
 * matrix (the previous local-global iterate), of a far one, and of the
 * same matrix give the cold SVD's singular values to round-off, with all
 * of its properties (also for inverted and rank-deficient matrices). */
START_TEST(svd_from_any_start_gives_the_cold_svd)
{
    unsigned long long st = 5;
    for (int t = 0; t < 2000; ++t) {
        double F[9], G[9], U[9], s[3], V0[9], Vf[9], sc[3], Vc[9], Uc[9];
        for (int i = 0; i < 9; ++i) F[i] = ht_rand(&st);
        if (t % 4 == 1) /* rank 2 */
            for (int a = 0; a < 3; ++a) F[a * 3 + 2] = F[a * 3] - 0.5 * F[a * 3 + 1];
        const double step = t % 3 == 0 ? 1e-3 : t % 3 == 1 ? 1e-7 : 0.0;
        for (int i = 0; i < 9; ++i) G[i] = F[i] + step * ht_rand(&st);
        hyper_svd3(G, U, s, V0); /* the nearby matrix's V */
        ht_random_rotation(&st, Vf);
        hyper_svd3(F, Uc, sc, Vc);
        const double *starts[3] = {V0, Vf, Vc};
        for (int k = 0; k < 3; ++k) {
            double Vo[9];
            check_svd3_from(F, starts[k]);
            hyper_svd3_from(F, starts[k], U, s, Vo);
            for (int i = 0; i < 3; ++i)
                ck_assert_msg(fabs(s[i] - sc[i]) <= 1e-14 * sc[0], "sample %d start %d: s%d %.17g "
                              "cold %.17g", t, k, i, s[i], sc[i]);
        }
        double F2[6], U2[6], s2[2], V2[4], W0[4], c2[2], Wc[4];
        for (int i = 0; i < 6; ++i) F2[i] = F[i];
        hyper_svd32(F2, U2, c2, Wc);
        const double a = 0.3 * t; /* a rotation of the plane as the start */
        W0[0] = cos(a), W0[1] = -sin(a), W0[2] = sin(a), W0[3] = cos(a);
        hyper_svd32_from(F2, W0, U2, s2, V2);
        double err = 0.0;
        for (int r = 0; r < 3; ++r)
            for (int b = 0; b < 2; ++b)
                err = fmax(err, fabs(U2[r * 2] * s2[0] * V2[b * 2] +
                                     U2[r * 2 + 1] * s2[1] * V2[b * 2 + 1] - F2[r * 2 + b]));
        ck_assert_double_le(err, 1e-13 * fmax(1.0, fro(F2, 6)));
        ck_assert_double_le(orth_error(U2, 3, 2), 1e-13);
        ck_assert_double_eq_tol(V2[0] * V2[3] - V2[1] * V2[2], 1.0, 1e-12);
        for (int i = 0; i < 2; ++i) ck_assert_double_le(fabs(s2[i] - c2[i]), 1e-14 * c2[0]);
    }
    /* an inverted matrix from the V of its mirror image */
    double F[9], M[9], U[9], s[3], V[9];
    ht_random_rotation(&st, F);
    for (int i = 0; i < 9; ++i) M[i] = F[i];
    for (int a = 0; a < 3; ++a) F[a * 3 + 2] = -0.5 * F[a * 3 + 2];
    hyper_svd3(M, U, s, V);
    check_svd3_from(F, V);
}
END_TEST

START_TEST(polar_of_inverted_matrix_is_a_proper_rotation)
{
    unsigned long long st = 99;
    for (int t = 0; t < 200; ++t) {
        double R[9], F[9], P[9];
        ht_random_rotation(&st, R);
        /* F = R diag(1.2, 0.9, -0.3): an inverted element */
        double d[3] = {1.2, 0.9, -0.3};
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) F[a * 3 + b] = R[a * 3 + b] * d[b];
        ck_assert(det3(F) < 0);
        check_svd3(F);
        hyper_polar3(F, P);
        /* the closest rotation is R itself (flip of the smallest direction) */
        for (int i = 0; i < 9; ++i) ck_assert_double_eq_tol(P[i], R[i], 1e-12);
    }
}
END_TEST

START_TEST(polar_of_rotation_times_spd_is_the_rotation)
{
    unsigned long long st = 5;
    for (int t = 0; t < 200; ++t) {
        double R[9], Q[9], S[9], F[9], P[9];
        ht_random_rotation(&st, R);
        ht_random_rotation(&st, Q);
        double d[3] = {1.5 + ht_rand(&st), 1.0 + 0.5 * ht_rand(&st), 0.6 + 0.3 * ht_rand(&st)};
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                S[a * 3 + b] = 0.0;
                for (int k = 0; k < 3; ++k) S[a * 3 + b] += Q[a * 3 + k] * d[k] * Q[b * 3 + k];
            }
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                F[a * 3 + b] = 0.0;
                for (int k = 0; k < 3; ++k) F[a * 3 + b] += R[a * 3 + k] * S[k * 3 + b];
            }
        hyper_polar3(F, P);
        for (int i = 0; i < 9; ++i) ck_assert_double_eq_tol(P[i], R[i], 1e-12);
    }
}
END_TEST

START_TEST(svd32_reconstructs_and_polar_has_orthonormal_columns)
{
    unsigned long long st = 11;
    for (int t = 0; t < 2000; ++t) {
        double F[6], U[6], s[2], V[4], P[6];
        for (int i = 0; i < 6; ++i) F[i] = ht_rand(&st);
        if (t == 0) memset(F, 0, sizeof F);
        hyper_svd32(F, U, s, V);
        double err = 0.0;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 2; ++b) {
                double v = U[a * 2] * s[0] * V[b * 2] + U[a * 2 + 1] * s[1] * V[b * 2 + 1];
                err = fmax(err, fabs(v - F[a * 2 + b]));
            }
        ck_assert_double_le(err, 1e-13 * fmax(1.0, fro(F, 6)));
        ck_assert_double_le(orth_error(U, 3, 2), 1e-13);
        ck_assert_double_le(orth_error(V, 2, 2), 1e-13);
        ck_assert_double_eq_tol(V[0] * V[3] - V[1] * V[2], 1.0, 1e-12);
        ck_assert(s[0] >= s[1] && s[1] >= 0.0);
        hyper_polar32(F, P);
        ck_assert_double_le(orth_error(P, 3, 2), 1e-13);
    }
    /* F = Q[:, 0:2] S (S SPD 2x2): the polar factor is Q[:, 0:2] */
    double Q[9], F[6], P[6], S[4] = {1.3, 0.2, 0.2, 0.7};
    ht_random_rotation(&st, Q);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 2; ++b) F[a * 2 + b] = Q[a * 3] * S[b] + Q[a * 3 + 1] * S[2 + b];
    hyper_polar32(F, P);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 2; ++b) ck_assert_double_eq_tol(P[a * 2 + b], Q[a * 3 + b], 1e-12);
}
END_TEST

START_TEST(sym_eigen_decomposes_and_projects_to_psd)
{
    unsigned long long st = 3;
    for (int n = 1; n <= PL_HYPER_SYM_MAX; ++n) {
        double A[144], B[144], lam[12], Q[144];
        for (int i = 0; i < n; ++i)
            for (int j = 0; j <= i; ++j) A[i * n + j] = A[j * n + i] = ht_rand(&st);
        ck_assert_int_eq(hyper_sym_eigen(n, A, lam, Q), PL_OK);
        for (int i = 0; i < n; ++i) {
            if (i) ck_assert(lam[i] >= lam[i - 1]);
            for (int j = 0; j < n; ++j) {
                double v = 0.0;
                for (int k = 0; k < n; ++k) v += Q[i * n + k] * lam[k] * Q[j * n + k];
                ck_assert_double_eq_tol(v, A[i * n + j], 1e-13);
            }
        }
        ck_assert_double_le(orth_error(Q, n, n), 1e-13);
        memcpy(B, A, sizeof(double) * n * n);
        ck_assert_int_eq(hyper_project_psd(n, B), PL_OK);
        ck_assert_int_eq(hyper_sym_eigen(n, B, lam, Q), PL_OK);
        ck_assert_double_ge(lam[0], -1e-13);
        /* a PSD matrix is left unchanged */
        memcpy(A, B, sizeof(double) * n * n);
        for (int i = 0; i < n; ++i) A[i * n + i] += 1e-3;
        memcpy(B, A, sizeof(double) * n * n);
        hyper_project_psd(n, B);
        for (int i = 0; i < n * n; ++i) ck_assert_double_eq(A[i], B[i]);
    }
    double lam[1], Q[1], A[1] = {0};
    ck_assert_int_eq(hyper_sym_eigen(13, A, lam, Q), PL_EINPUT);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("hyper_svd");
    TCase *tc = tcase_create("svd");
    tcase_add_test(tc, svd3_reconstructs_with_proper_rotations);
    tcase_add_test(tc, svd3_handles_degenerate_and_repeated_values);
    tcase_add_test(tc, svd_from_any_start_gives_the_cold_svd);
    tcase_add_test(tc, polar_of_inverted_matrix_is_a_proper_rotation);
    tcase_add_test(tc, polar_of_rotation_times_spd_is_the_rotation);
    tcase_add_test(tc, svd32_reconstructs_and_polar_has_orthonormal_columns);
    tcase_add_test(tc, sym_eigen_decomposes_and_projects_to_psd);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
