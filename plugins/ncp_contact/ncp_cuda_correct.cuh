/* ncp_cuda_correct.cuh - one value of the few rows' dense correction
 * (ncp_cuda_correct.h), one definition for k_correct_dense
 * (ncp_cuda_correct.cu) and the few rows' one-kernel iteration
 * (ncp_cuda_fused.cu), so that both give the same sums, bitwise.  scale
 * and lambda are not __restrict__: the one kernel writes them before it
 * reads them here (no non-coherent loads). */
#ifndef PLIANT_NCP_CUDA_CORRECT_CUH
#define PLIANT_NCP_CUDA_CORRECT_CUH

#include <cuda_runtime.h>

namespace {

/* Value i of the correction: force_i = scale_i lambda_i for i < m, and
 * for i < n = 3 nfree q_next_i = q_free_i + sum_j l_j U_j,i with l_j =
 * h2 (scale_j lambda_j) (rounded as k_scatter_scaled's), rows with l_j = 0
 * skipped as the scatter skips them, j in increasing order. */
__device__ __forceinline__ void correct_dense_at(long long i, int m, long long n,
                                                 const double *scale, const double *lambda,
                                                 double h2, const double *__restrict__ U,
                                                 const double *__restrict__ q_free, double *force,
                                                 double *q_next)
{
    if (i < m) force[i] = scale[i] * lambda[i];
    if (i >= n) return;
    double s = 0.0;
    for (int j = 0; j < m; ++j) {
        const double l = h2 * (scale[j] * lambda[j]);
        if (l == 0.0) continue; /* as the scatter, which skips such rows */
        s += l * U[j * n + i];
    }
    q_next[i] = q_free[i] + s;
}

} // namespace

#endif
