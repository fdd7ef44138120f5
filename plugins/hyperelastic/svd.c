/* svd.c - SVD and polar decomposition of 3x3 and 3x2 matrices.
 *
 * One-sided Jacobi (Hestenes): plane rotations applied on the right make the
 * columns of F V mutually orthogonal; their norms are the singular values
 * and, normalised, the columns of U.  Unlike an eigen-decomposition of
 * F^T F it keeps small singular values to full relative accuracy, which
 * matters for flat and nearly inverted elements.  The 3x3 result is
 * "signed" (Irving et al. 2004): U and V are proper rotations and the
 * smallest singular value takes the sign of det F, so the polar factor
 * U V^T is a rotation even for an inverted element. */
#include <math.h>
#include <string.h>

#include "hyperelastic.h"
#include "small_matrix.h"

/* Orthogonalises the n columns of A (3 x n) in place, accumulating the
 * rotations in V (n x n, starts as the identity).  Inlined with a constant
 * n so that the compiler unrolls it; squared column norms are updated
 * incrementally (alpha -= t gamma, beta += t gamma).  Convergence is
 * quadratic: once a sweep rotates by less than 1e-8, the next one would
 * rotate by less than round-off, so it is skipped. */
static inline void hestenes(const int n, double *A, double *V)
{
    double nrm[3];
    for (int i = 0; i < n * n; ++i) V[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;
    for (int j = 0; j < n; ++j) nrm[j] = A[j] * A[j] + A[n + j] * A[n + j] + A[2 * n + j] * A[2 * n + j];
    for (int sweep = 0; sweep < 40; ++sweep) {
        double tmax = 0.0;
        for (int i = 0; i < n - 1; ++i)
            for (int j = i + 1; j < n; ++j) {
                double gamma = A[i] * A[j] + A[n + i] * A[n + j] + A[2 * n + i] * A[2 * n + j];
                /* columns already orthogonal to working precision */
                if (gamma * gamma <= 1e-30 * nrm[i] * nrm[j]) continue;
                double zeta = (nrm[j] - nrm[i]) / (2.0 * gamma);
                double t = fabs(zeta) > 1e150
                               ? 0.5 / zeta
                               : (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
                double c = 1.0 / sqrt(1.0 + t * t), s = c * t;
                for (int r = 0; r < 3; ++r) {
                    double ai = A[r * n + i], aj = A[r * n + j];
                    A[r * n + i] = c * ai - s * aj;
                    A[r * n + j] = s * ai + c * aj;
                }
                for (int r = 0; r < n; ++r) {
                    double vi = V[r * n + i], vj = V[r * n + j];
                    V[r * n + i] = c * vi - s * vj;
                    V[r * n + j] = s * vi + c * vj;
                }
                nrm[i] -= t * gamma;
                nrm[j] += t * gamma;
                tmax = fmax(tmax, fabs(t));
            }
        if (tmax < 1e-8) break;
    }
}

static void swap_columns(int rows, int n, double *A, int i, int j)
{
    for (int r = 0; r < rows; ++r) {
        double t = A[r * n + i];
        A[r * n + i] = A[r * n + j];
        A[r * n + j] = t;
    }
}

/* Sorts columns of A (3 x n) and V (n x n) by decreasing column norm of A;
 * s receives the norms. */
static void sort_columns(int n, double *A, double *V, double *s)
{
    for (int j = 0; j < n; ++j) {
        s[j] = 0.0;
        for (int r = 0; r < 3; ++r) s[j] += A[r * n + j] * A[r * n + j];
        s[j] = sqrt(s[j]);
    }
    for (int i = 0; i < n; ++i) {
        int best = i;
        for (int j = i + 1; j < n; ++j)
            if (s[j] > s[best]) best = j;
        if (best != i) {
            double t = s[i];
            s[i] = s[best];
            s[best] = t;
            swap_columns(3, n, A, i, best);
            swap_columns(n, n, V, i, best);
        }
    }
}

/* A unit vector orthogonal to the unit vector a. */
static void any_orthogonal(const double *a, double *out)
{
    /* cross with the axis least aligned with a */
    double e[3] = {0.0, 0.0, 0.0};
    int k = 0;
    if (fabs(a[1]) < fabs(a[k])) k = 1;
    if (fabs(a[2]) < fabs(a[k])) k = 2;
    e[k] = 1.0;
    hm_cross(a, e, out);
    double l = hm_norm3(out);
    for (int r = 0; r < 3; ++r) out[r] /= l;
}

/* Builds the first two orthonormal left vectors u0, u1 from the columns
 * a0, a1 of A V with norms s0 >= s1.  Degenerate columns get a completion. */
static void left_vectors(const double *a0, double s0, const double *a1, double s1, double *u0,
                         double *u1)
{
    const double tiny = 1e-300;
    if (s0 > tiny) {
        for (int r = 0; r < 3; ++r) u0[r] = a0[r] / s0;
    } else {
        u0[0] = 1.0;
        u0[1] = u0[2] = 0.0;
    }
    if (s1 > 1e-14 * s0 && s1 > tiny) {
        for (int r = 0; r < 3; ++r) u1[r] = a1[r] / s1;
        /* one Gram-Schmidt pass against round-off */
        double c = hm_dot3(u0, u1);
        for (int r = 0; r < 3; ++r) u1[r] -= c * u0[r];
        double l = hm_norm3(u1);
        for (int r = 0; r < 3; ++r) u1[r] /= l;
    } else {
        any_orthogonal(u0, u1);
    }
}

/* A power of two that brings the largest |entry| near 1 (0 for a zero
 * matrix): column norms then neither overflow nor underflow. */
static int scale_exponent(int n, const double *F)
{
    double m = 0.0;
    for (int i = 0; i < n; ++i) m = fmax(m, fabs(F[i]));
    int e = 0;
    if (m > 0.0 && isfinite(m)) frexp(m, &e);
    return e < -1000 ? -1000 : e > 1000 ? 1000 : e; /* 2^+-e stays finite */
}

void pl_hyper_svd3(const double F[9], double U[9], double s[3], double V[9])
{
    double A[9];
    int ex = scale_exponent(9, F);
    const double down = ldexp(1.0, -ex), up = ldexp(1.0, ex); /* exact powers of two */
    for (int i = 0; i < 9; ++i) A[i] = F[i] * down;
    hestenes(3, A, V);
    sort_columns(3, A, V, s);
    /* make V a proper rotation: flipping v2 flips a2 = F v2 */
    if (hm_det3(V) < 0.0)
        for (int r = 0; r < 3; ++r) {
            V[r * 3 + 2] = -V[r * 3 + 2];
            A[r * 3 + 2] = -A[r * 3 + 2];
        }
    double a0[3] = {A[0], A[3], A[6]}, a1[3] = {A[1], A[4], A[7]}, a2[3] = {A[2], A[5], A[8]};
    double u0[3], u1[3], u2[3];
    left_vectors(a0, s[0], a1, s[1], u0, u1);
    hm_cross(u0, u1, u2); /* det U = +1 by construction */
    /* a2 is parallel to u2: its signed length is the signed singular value */
    s[2] = hm_dot3(u2, a2);
    for (int i = 0; i < 3; ++i) s[i] *= up;
    for (int r = 0; r < 3; ++r) {
        U[r * 3 + 0] = u0[r];
        U[r * 3 + 1] = u1[r];
        U[r * 3 + 2] = u2[r];
    }
}

void pl_hyper_svd32(const double F[6], double U[6], double s[2], double V[4])
{
    double A[6], Fs[6];
    int ex = scale_exponent(6, F);
    const double down = ldexp(1.0, -ex), up = ldexp(1.0, ex);
    for (int i = 0; i < 6; ++i) A[i] = Fs[i] = F[i] * down;
    hestenes(2, A, V);
    sort_columns(2, A, V, s);
    if (V[0] * V[3] - V[1] * V[2] < 0.0)
        for (int r = 0; r < 2; ++r) V[r * 2 + 1] = -V[r * 2 + 1];
    for (int r = 0; r < 3; ++r) A[r * 2 + 1] = Fs[r * 2 + 0] * V[1] + Fs[r * 2 + 1] * V[3];
    double a0[3] = {A[0], A[2], A[4]}, a1[3] = {A[1], A[3], A[5]};
    double u0[3], u1[3];
    left_vectors(a0, s[0], a1, s[1], u0, u1);
    s[0] *= up;
    s[1] *= up;
    for (int r = 0; r < 3; ++r) {
        U[r * 2 + 0] = u0[r];
        U[r * 2 + 1] = u1[r];
    }
}

void pl_hyper_polar3(const double F[9], double R[9])
{
    double U[9], s[3], V[9];
    pl_hyper_svd3(F, U, s, V);
    hm_mul_bt(3, 3, 3, U, V, R);
}

void pl_hyper_polar32(const double F[6], double R[6])
{
    double U[6], s[2], V[4];
    pl_hyper_svd32(F, U, s, V);
    hm_mul_bt(3, 2, 2, U, V, R);
}
