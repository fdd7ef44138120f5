/* small_matrix.h - tiny dense helpers shared by the hyperelastic core
 * (internal: not part of the public header).  Matrices are row-major.
 * Compiled as C and as CUDA (pliant/hostdevice.h): the device local step
 * uses them too. */
#ifndef PLIANT_HYPER_SMALL_MATRIX_H
#define PLIANT_HYPER_SMALL_MATRIX_H

#include <math.h>

#include "pliant/hostdevice.h"

PL_HD double hm_dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

PL_HD void hm_cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

PL_HD double hm_norm3(const double *a)
{
    return sqrt(hm_dot3(a, a));
}

PL_HD void hm_sub3(const double *a, const double *b, double *c)
{
    c[0] = a[0] - b[0];
    c[1] = a[1] - b[1];
    c[2] = a[2] - b[2];
}

PL_HD double hm_det3(const double *A)
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* C (m x n) = A (m x p) B (p x n); C must not alias A or B. */
PL_HD void hm_mul(int m, int p, int n, const double *A, const double *B, double *C)
{
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < n; ++j) {
            double s = 0.0;
            for (int k = 0; k < p; ++k) s += A[i * p + k] * B[k * n + j];
            C[i * n + j] = s;
        }
}

/* C (m x n) = A (m x p) B^T (B is n x p). */
PL_HD void hm_mul_bt(int m, int p, int n, const double *A, const double *B, double *C)
{
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < n; ++j) {
            double s = 0.0;
            for (int k = 0; k < p; ++k) s += A[i * p + k] * B[j * p + k];
            C[i * n + j] = s;
        }
}

/* Frobenius inner product of two arrays of length n. */
PL_HD double hm_ddot(int n, const double *a, const double *b)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += a[i] * b[i];
    return s;
}

#endif
