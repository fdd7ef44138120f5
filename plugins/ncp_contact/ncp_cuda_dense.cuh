/* ncp_cuda_dense.cuh - the summation order of the dense product y = W x
 * (W explicit, m x m), one definition for the phased path's k_dense
 * (ncp_cuda_rows.cu) and the fused update (ncp_cuda_fused.cu), so that
 * both give the same sums, bitwise.  Row i is summed by K threads of one
 * warp (K = dense_width(m), a power of two): thread c of them adds the
 * columns c, c + K, ... in order, and the K partial sums meet by a
 * shuffle tree.  At most NCP_CUDA_WARP_MAX_ROWS rows (the fused update's
 * one-warp path) take K = 1: thread i sums row i in column order, no
 * shuffle, so that one warp does the whole product at once; up to
 * NCP_CUDA_FUSED_MAX_ROWS (the fused update's block) the K that lets a
 * 512-thread block do all rows at once, about 2 m K <= 512 (K = 4 for 108
 * rows: 27 products a thread, two shuffle levels); more rows take a warp
 * per row (K = 32: coalesced reads of W in global memory). */
#ifndef PLIANT_NCP_CUDA_DENSE_CUH
#define PLIANT_NCP_CUDA_DENSE_CUH

#include "ncp_cuda.h"

__device__ __forceinline__ int dense_row_width(int m)
{
    if (m > NCP_CUDA_FUSED_MAX_ROWS) return 32;
    if (m <= NCP_CUDA_WARP_MAX_ROWS) return 1;
    int K = 1;
    while (K < 32 && 2 * K * m <= 512) K *= 2;
    return K;
}

/* Row `row` (m entries) times x by the K threads of a group (c = the
 * thread's place in it, groups aligned within the warp); every lane of the
 * warp must call it (m = 0 for a group without a row).  The sum is in the
 * group's c = 0. */
__device__ __forceinline__ double dense_row_dot(const double *__restrict__ row,
                                                const double *__restrict__ x, int m, int c, int K)
{
    double s = 0.0;
#pragma unroll 4
    for (int j = c; j < m; j += K) s += row[j] * x[j];
    for (int o = K / 2; o > 0; o >>= 1) s += __shfl_down_sync(0xffffffffu, s, o, K);
    return s;
}

#endif
