/* sym_eigen.c - eigen-decomposition of small symmetric matrices (cyclic
 * Jacobi) and projection onto the PSD cone.  Jacobi is simple, accurate
 * to working precision for the 2x2 .. 12x12 element Hessians it serves,
 * and needs no pivoting decisions. */
#include <math.h>
#include <string.h>

#include "hyperelastic.h"

int pl_hyper_sym_eigen(int n, const double *A, double *lambda, double *Q)
{
    if (n < 1 || n > PL_HYPER_SYM_MAX) return PL_EINPUT;
    double M[PL_HYPER_SYM_MAX * PL_HYPER_SYM_MAX];
    /* symmetrise: callers pass matrices symmetric up to round-off */
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) M[i * n + j] = 0.5 * (A[i * n + j] + A[j * n + i]);
    for (int i = 0; i < n * n; ++i) Q[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = 0.0, diag = 0.0;
        for (int i = 0; i < n; ++i) {
            diag += M[i * n + i] * M[i * n + i];
            for (int j = i + 1; j < n; ++j) off += M[i * n + j] * M[i * n + j];
        }
        if (off <= 1e-32 * diag || off == 0.0) break;
        for (int p = 0; p < n - 1; ++p)
            for (int q = p + 1; q < n; ++q) {
                double apq = M[p * n + q];
                if (apq == 0.0) continue;
                double theta = (M[q * n + q] - M[p * n + p]) / (2.0 * apq);
                double t = fabs(theta) > 1e150
                               ? 0.5 / theta
                               : (theta >= 0.0 ? 1.0 : -1.0) /
                                     (fabs(theta) + sqrt(1.0 + theta * theta));
                double c = 1.0 / sqrt(1.0 + t * t), s = t * c;
                /* M <- J^T M J with J the rotation in the (p, q) plane */
                for (int k = 0; k < n; ++k) {
                    double mkp = M[k * n + p], mkq = M[k * n + q];
                    M[k * n + p] = c * mkp - s * mkq;
                    M[k * n + q] = s * mkp + c * mkq;
                }
                for (int k = 0; k < n; ++k) {
                    double mpk = M[p * n + k], mqk = M[q * n + k];
                    M[p * n + k] = c * mpk - s * mqk;
                    M[q * n + k] = s * mpk + c * mqk;
                }
                M[p * n + q] = M[q * n + p] = 0.0;
                for (int k = 0; k < n; ++k) {
                    double qkp = Q[k * n + p], qkq = Q[k * n + q];
                    Q[k * n + p] = c * qkp - s * qkq;
                    Q[k * n + q] = s * qkp + c * qkq;
                }
            }
    }
    for (int i = 0; i < n; ++i) lambda[i] = M[i * n + i];
    /* ascending order (selection sort on columns) */
    for (int i = 0; i < n; ++i) {
        int best = i;
        for (int j = i + 1; j < n; ++j)
            if (lambda[j] < lambda[best]) best = j;
        if (best != i) {
            double t = lambda[i];
            lambda[i] = lambda[best];
            lambda[best] = t;
            for (int k = 0; k < n; ++k) {
                t = Q[k * n + i];
                Q[k * n + i] = Q[k * n + best];
                Q[k * n + best] = t;
            }
        }
    }
    return PL_OK;
}

int pl_hyper_project_psd(int n, double *A)
{
    double lambda[PL_HYPER_SYM_MAX], Q[PL_HYPER_SYM_MAX * PL_HYPER_SYM_MAX];
    int rc = pl_hyper_sym_eigen(n, A, lambda, Q);
    if (rc != PL_OK) return rc;
    if (lambda[0] >= 0.0) return PL_OK; /* already PSD: leave it bit-for-bit */
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double s = 0.0;
            for (int k = 0; k < n; ++k)
                if (lambda[k] > 0.0) s += Q[i * n + k] * lambda[k] * Q[j * n + k];
            A[i * n + j] = s;
        }
    return PL_OK;
}
