/* svd.h - SVD of 3x3 and 3x2 matrices, the one implementation for the CPU
 * (svd.c, material_law.c, local_solve.c) and the GPU (cuda/hyper_cuda.cu);
 * compiled as C and as CUDA (pliant/hostdevice.h).
 *
 * One-sided Jacobi (Hestenes): plane rotations applied on the right make the
 * columns of F V mutually orthogonal; their norms are the singular values
 * and, normalised, the columns of U.  Unlike an eigen-decomposition of
 * F^T F it keeps small singular values to full relative accuracy, which
 * matters for flat and nearly inverted elements.  The 3x3 result is
 * "signed" (Irving et al. 2004): U and V are proper rotations and the
 * smallest singular value takes the sign of det F, so the polar factor
 * U V^T is a rotation even for an inverted element.
 *
 * n (the columns, 2 or 3) is a parameter that every caller passes as a
 * constant, so that on the GPU the small arrays stay in registers. */
#ifndef PLIANT_HYPER_SVD_H
#define PLIANT_HYPER_SVD_H

#include <math.h>
#include <stdbool.h>

#include "pliant/hostdevice.h"
#include "small_matrix.h"

/* One rotation of columns i < j of A (3 x n) and V (n x n) that makes them
 * orthogonal; nrm holds the squared column norms, updated incrementally
 * (alpha -= t gamma, beta += t gamma); tmax the largest |t| of the sweep. */
PL_HD void hm_jacobi_pair(const int n, const int i, const int j, double *A, double *V,
                          double *nrm, double *tmax)
{
    double gamma = A[i] * A[j] + A[n + i] * A[n + j] + A[2 * n + i] * A[2 * n + j];
    /* columns already orthogonal to working precision */
    if (gamma * gamma <= 1e-30 * nrm[i] * nrm[j]) return;
    double zeta = (nrm[j] - nrm[i]) / (2.0 * gamma);
    double t = fabs(zeta) > 1e150 ? 0.5 / zeta
                                  : (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
    double c = 1.0 / sqrt(1.0 + t * t), s = c * t;
    PL_UNROLL
    for (int r = 0; r < 3; ++r) {
        double ai = A[r * n + i], aj = A[r * n + j];
        A[r * n + i] = c * ai - s * aj;
        A[r * n + j] = s * ai + c * aj;
    }
    PL_UNROLL
    for (int r = 0; r < n; ++r) {
        double vi = V[r * n + i], vj = V[r * n + j];
        V[r * n + i] = c * vi - s * vj;
        V[r * n + j] = s * vi + c * vj;
    }
    nrm[i] -= t * gamma;
    nrm[j] += t * gamma;
    *tmax = fmax(*tmax, fabs(t));
}

/* The Jacobi iteration's start: V = V0 (n x n, a rotation: the previous
 * SVD's V of a nearby matrix) when `use`, else the identity, and A = F V
 * scaled by `scale` (F 3 x n).  From a nearby V0 the columns of A are
 * already nearly orthogonal and one or two sweeps finish them.  A flag,
 * not a NULL V0: on the GPU a pointer chosen at run time between an array
 * and NULL puts the array in local memory (measured: a 96-byte stack frame
 * in k_project), a flag keeps it in registers. */
PL_HD void hm_start_columns(const int n, const double *F, double scale, const double *V0,
                            bool use, double *A, double *V)
{
    if (!use) {
        PL_UNROLL
        for (int k = 0; k < n * n; ++k) V[k] = (k % (n + 1) == 0) ? 1.0 : 0.0;
        PL_UNROLL
        for (int k = 0; k < 3 * n; ++k) A[k] = F[k] * scale;
        return;
    }
    PL_UNROLL
    for (int k = 0; k < n * n; ++k) V[k] = V0[k];
    hm_mul(3, n, n, F, V0, A);
    PL_UNROLL
    for (int k = 0; k < 3 * n; ++k) A[k] *= scale;
}

/* Orthogonalises the n columns of A (3 x n) in place, accumulating the
 * rotations into V (n x n, the start: hm_start_columns).  Convergence is quadratic: once a sweep rotates
 * by less than 1e-8, the next one would rotate by less than round-off, so
 * it is skipped. */
PL_HD void hm_hestenes(const int n, double *A, double *V)
{
    double nrm[3];
    PL_UNROLL
    for (int j = 0; j < n; ++j) nrm[j] = A[j] * A[j] + A[n + j] * A[n + j] + A[2 * n + j] * A[2 * n + j];
    for (int sweep = 0; sweep < 40; ++sweep) {
        double tmax = 0.0;
        PL_UNROLL
        for (int i = 0; i < n - 1; ++i)
            PL_UNROLL
            for (int j = i + 1; j < n; ++j) hm_jacobi_pair(n, i, j, A, V, nrm, &tmax);
        if (tmax < 1e-8) break;
    }
}

/* Swaps columns i and j of A (3 x n) and V (n x n), and s[i] with s[j]. */
PL_HD void hm_swap_columns(const int n, const int i, const int j, double *A, double *V, double *s)
{
    double t = s[i];
    s[i] = s[j];
    s[j] = t;
    PL_UNROLL
    for (int r = 0; r < 3; ++r) {
        t = A[r * n + i], A[r * n + i] = A[r * n + j], A[r * n + j] = t;
    }
    PL_UNROLL
    for (int r = 0; r < n; ++r) {
        t = V[r * n + i], V[r * n + i] = V[r * n + j], V[r * n + j] = t;
    }
}

/* Sorts the columns of A (3 x n) and V (n x n) by decreasing column norm of
 * A (selection sort); s receives the norms.  No array is indexed by best
 * (a value known only at run time): the swap is chosen by testing best
 * against each constant j. */
PL_HD void hm_sort_columns(const int n, double *A, double *V, double *s)
{
    PL_UNROLL
    for (int j = 0; j < n; ++j) s[j] = sqrt(A[j] * A[j] + A[n + j] * A[n + j] + A[2 * n + j] * A[2 * n + j]);
    PL_UNROLL
    for (int i = 0; i < n - 1; ++i) {
        int best = i;
        double sbest = s[i]; /* s[best], kept aside: no s[best] */
        PL_UNROLL
        for (int j = i + 1; j < n; ++j)
            if (s[j] > sbest) best = j, sbest = s[j];
        PL_UNROLL
        for (int j = i + 1; j < n; ++j)
            if (best == j) hm_swap_columns(n, i, j, A, V, s);
    }
}

/* A unit vector orthogonal to the unit vector a: a crossed with the axis
 * least aligned with it. */
PL_HD void hm_any_orthogonal(const double *a, double *out)
{
    double e[3], ak = fabs(a[0]); /* ak = |a[k]|, kept aside: no a[k] */
    int k = 0;
    if (fabs(a[1]) < ak) k = 1, ak = fabs(a[1]);
    if (fabs(a[2]) < ak) k = 2;
    e[0] = k == 0, e[1] = k == 1, e[2] = k == 2;
    hm_cross(a, e, out);
    double l = sqrt(hm_dot3(out, out));
    PL_UNROLL
    for (int r = 0; r < 3; ++r) out[r] /= l;
}

/* The first two orthonormal left vectors u0, u1 from the columns a0, a1 of
 * A V with norms s0 >= s1.  Degenerate columns get a completion. */
PL_HD void hm_left_vectors(const double *a0, double s0, const double *a1, double s1, double *u0,
                           double *u1)
{
    const double tiny = 1e-300;
    if (s0 > tiny) {
        PL_UNROLL
        for (int r = 0; r < 3; ++r) u0[r] = a0[r] / s0;
    } else {
        u0[0] = 1.0;
        u0[1] = u0[2] = 0.0;
    }
    if (s1 > 1e-14 * s0 && s1 > tiny) {
        PL_UNROLL
        for (int r = 0; r < 3; ++r) u1[r] = a1[r] / s1;
        /* one Gram-Schmidt pass against round-off */
        double c = hm_dot3(u0, u1);
        PL_UNROLL
        for (int r = 0; r < 3; ++r) u1[r] -= c * u0[r];
        double l = sqrt(hm_dot3(u1, u1));
        PL_UNROLL
        for (int r = 0; r < 3; ++r) u1[r] /= l;
    } else {
        hm_any_orthogonal(u0, u1);
    }
}

/* A power of two that brings the largest |entry| of F (len entries) near 1
 * (0 for a zero matrix): column norms then neither overflow nor underflow. */
PL_HD int hm_scale_exponent(const int len, const double *F)
{
    double m = 0.0;
    PL_UNROLL
    for (int i = 0; i < len; ++i) m = fmax(m, fabs(F[i]));
    int e = 0;
    if (m > 0.0 && isfinite(m)) frexp(m, &e);
    return e < -1000 ? -1000 : e > 1000 ? 1000 : e; /* 2^+-e stays finite */
}

/* Signed SVD of a 3x3 F = U diag(s) V^T, U and V proper rotations,
 * |s0| >= |s1| >= |s2|, s2 < 0 exactly when det F < 0 (hyper_svd3). */
PL_HD void hm_svd3_from(const double *F, const double *V0, bool use, double *U, double *s,
                        double *V)
{
    double A[9];
    int ex = hm_scale_exponent(9, F);
    const double down = ldexp(1.0, -ex), up = ldexp(1.0, ex); /* exact powers of two */
    hm_start_columns(3, F, down, V0, use, A, V);
    hm_hestenes(3, A, V);
    hm_sort_columns(3, A, V, s);
    /* make V a proper rotation: flipping v2 flips a2 = F v2 */
    if (hm_det3(V) < 0.0) {
        PL_UNROLL
        for (int r = 0; r < 3; ++r) {
            V[r * 3 + 2] = -V[r * 3 + 2];
            A[r * 3 + 2] = -A[r * 3 + 2];
        }
    }
    double a0[3] = {A[0], A[3], A[6]}, a1[3] = {A[1], A[4], A[7]}, a2[3] = {A[2], A[5], A[8]};
    double u0[3], u1[3], u2[3];
    hm_left_vectors(a0, s[0], a1, s[1], u0, u1);
    hm_cross(u0, u1, u2); /* det U = +1 by construction */
    /* a2 is parallel to u2: its signed length is the signed singular value */
    s[2] = hm_dot3(u2, a2);
    PL_UNROLL
    for (int i = 0; i < 3; ++i) s[i] *= up;
    PL_UNROLL
    for (int r = 0; r < 3; ++r) {
        U[r * 3 + 0] = u0[r];
        U[r * 3 + 1] = u1[r];
        U[r * 3 + 2] = u2[r];
    }
}

/* SVD of a 3x2 F = U diag(s) V^T: U 3x2 with orthonormal columns,
 * s0 >= s1 >= 0, V a 2x2 rotation (hyper_svd32). */
PL_HD void hm_svd32_from(const double *F, const double *V0, bool use, double *U, double *s,
                         double *V)
{
    double A[6], Fs[6];
    int ex = hm_scale_exponent(6, F);
    const double down = ldexp(1.0, -ex), up = ldexp(1.0, ex);
    PL_UNROLL
    for (int i = 0; i < 6; ++i) Fs[i] = F[i] * down;
    hm_start_columns(2, Fs, 1.0, V0, use, A, V);
    hm_hestenes(2, A, V);
    hm_sort_columns(2, A, V, s);
    if (V[0] * V[3] - V[1] * V[2] < 0.0) V[1] = -V[1], V[3] = -V[3];
    /* the second column of A V again, with the flipped v1 */
    PL_UNROLL
    for (int r = 0; r < 3; ++r) A[r * 2 + 1] = Fs[r * 2] * V[1] + Fs[r * 2 + 1] * V[3];
    double a0[3] = {A[0], A[2], A[4]}, a1[3] = {A[1], A[3], A[5]};
    double u0[3], u1[3];
    hm_left_vectors(a0, s[0], a1, s[1], u0, u1);
    s[0] *= up;
    s[1] *= up;
    PL_UNROLL
    for (int r = 0; r < 3; ++r) U[r * 2] = u0[r], U[r * 2 + 1] = u1[r];
}

PL_HD void hm_svd3(const double *F, double *U, double *s, double *V)
{
    hm_svd3_from(F, NULL, false, U, s, V);
}

PL_HD void hm_svd32(const double *F, double *U, double *s, double *V)
{
    hm_svd32_from(F, NULL, false, U, s, V);
}

/* R (3 x d) = U V^T from an SVD (U 3 x d, V d x d): the closest rotation
 * (d = 3, signed SVD: also for an inverted F) or the closest 3x2 matrix with
 * orthonormal columns (d = 2). */
PL_HD void hm_polar_from_svd(const int d, const double *U, const double *V, double *R)
{
    PL_UNROLL
    for (int a = 0; a < 3; ++a)
        PL_UNROLL
        for (int b = 0; b < d; ++b) {
            double v = U[a * d] * V[b * d];
            PL_UNROLL
            for (int i = 1; i < d; ++i) v += U[a * d + i] * V[b * d + i];
            R[a * d + b] = v;
        }
}

#endif
