/* sym_eigen.h - eigen-decomposition of a small symmetric matrix by cyclic
 * Jacobi, the one implementation for the CPU (sym_eigen.c: any n up to
 * PL_HYPER_SYM_MAX, for element Hessians) and the GPU (the Newton step of
 * the local solve, n = 2 or 3 as constants: local_solve.h); compiled as C
 * and as CUDA (pliant/hostdevice.h).  Jacobi is simple, accurate to
 * working precision for the matrices it serves, and needs no pivoting
 * decisions. */
#ifndef PLIANT_HYPER_SYM_EIGEN_H
#define PLIANT_HYPER_SYM_EIGEN_H

#include <math.h>

#include "pliant/hostdevice.h"

/* M <- J^T M J and Q <- Q J, J the rotation in the (p, q) plane that zeroes
 * M_pq (M, Q n x n). */
PL_HD void hm_jacobi_sym(const int n, const int p, const int q, double *M, double *Q)
{
    double apq = M[p * n + q];
    if (apq == 0.0) return;
    double theta = (M[q * n + q] - M[p * n + p]) / (2.0 * apq);
    double t = fabs(theta) > 1e150
                   ? 0.5 / theta
                   : (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(1.0 + theta * theta));
    double c = 1.0 / sqrt(1.0 + t * t), s = t * c;
    PL_UNROLL
    for (int k = 0; k < n; ++k) {
        double mkp = M[k * n + p], mkq = M[k * n + q];
        M[k * n + p] = c * mkp - s * mkq;
        M[k * n + q] = s * mkp + c * mkq;
    }
    PL_UNROLL
    for (int k = 0; k < n; ++k) {
        double mpk = M[p * n + k], mqk = M[q * n + k];
        M[p * n + k] = c * mpk - s * mqk;
        M[q * n + k] = s * mpk + c * mqk;
    }
    M[p * n + q] = M[q * n + p] = 0.0;
    PL_UNROLL
    for (int k = 0; k < n; ++k) {
        double qkp = Q[k * n + p], qkq = Q[k * n + q];
        Q[k * n + p] = c * qkp - s * qkq;
        Q[k * n + q] = s * qkp + c * qkq;
    }
}

/* Swaps eigenpairs i and j. */
PL_HD void hm_swap_eigen(const int n, const int i, const int j, double *lam, double *Q)
{
    double t = lam[i];
    lam[i] = lam[j];
    lam[j] = t;
    PL_UNROLL
    for (int k = 0; k < n; ++k) t = Q[k * n + i], Q[k * n + i] = Q[k * n + j], Q[k * n + j] = t;
}

/* A (n x n, symmetric up to round-off) = Q diag(lam) Q^T, Q's columns the
 * eigenvectors, lam ascending.  M: n x n scratch. */
PL_HD void hm_sym_eigen(const int n, const double *A, double *M, double *lam, double *Q)
{
    /* symmetrise: callers pass matrices symmetric up to round-off */
    PL_UNROLL
    for (int i = 0; i < n; ++i)
        PL_UNROLL
        for (int j = 0; j < n; ++j) M[i * n + j] = 0.5 * (A[i * n + j] + A[j * n + i]);
    PL_UNROLL
    for (int k = 0; k < n * n; ++k) Q[k] = (k % (n + 1) == 0) ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = 0.0, diag = 0.0;
        PL_UNROLL
        for (int i = 0; i < n; ++i) {
            diag += M[i * n + i] * M[i * n + i];
            PL_UNROLL
            for (int j = i + 1; j < n; ++j) off += M[i * n + j] * M[i * n + j];
        }
        if (off <= 1e-32 * diag || off == 0.0) break;
        PL_UNROLL
        for (int p = 0; p < n - 1; ++p)
            PL_UNROLL
            for (int q = p + 1; q < n; ++q) hm_jacobi_sym(n, p, q, M, Q);
    }
    PL_UNROLL
    for (int i = 0; i < n; ++i) lam[i] = M[i * n + i];
    /* ascending (selection sort; swaps chosen by testing best == j) */
    PL_UNROLL
    for (int i = 0; i < n - 1; ++i) {
        int best = i;
        double lbest = lam[i]; /* lam[best], kept aside: no lam[best] */
        PL_UNROLL
        for (int j = i + 1; j < n; ++j)
            if (lam[j] < lbest) best = j, lbest = lam[j];
        PL_UNROLL
        for (int j = i + 1; j < n; ++j)
            if (best == j) hm_swap_eigen(n, i, j, lam, Q);
    }
}

#endif
