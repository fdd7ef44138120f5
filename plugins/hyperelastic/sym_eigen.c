/* sym_eigen.c - eigen-decomposition of small symmetric matrices (cyclic
 * Jacobi, sym_eigen.h: the implementation the GPU's local solve shares)
 * and projection onto the PSD cone. */
#include "sym_eigen.h"

#include "hyperelastic.h"

int hyper_sym_eigen(int n, const double *A, double *lambda, double *Q)
{
    if (n < 1 || n > PL_HYPER_SYM_MAX) return PL_EINPUT;
    double M[PL_HYPER_SYM_MAX * PL_HYPER_SYM_MAX];
    hm_sym_eigen(n, A, M, lambda, Q);
    return PL_OK;
}

int hyper_project_psd(int n, double *A)
{
    double lambda[PL_HYPER_SYM_MAX], Q[PL_HYPER_SYM_MAX * PL_HYPER_SYM_MAX];
    int rc = hyper_sym_eigen(n, A, lambda, Q);
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
