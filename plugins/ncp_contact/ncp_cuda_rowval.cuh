/* ncp_cuda_rowval.cuh - the row values delta_j = H_j [x; q_p] - offset_j
 * of one row, one definition for the rows' kernels k_delta and k_delta2
 * (ncp_cuda_rows.cu) and the few rows' one-kernel iteration
 * (ncp_cuda_fused.cu), so that both give the same sums, bitwise. */
#ifndef PLIANT_NCP_CUDA_ROWVAL_CUH
#define PLIANT_NCP_CUDA_ROWVAL_CUH

#include "ncp_cuda.h"

#include <cuda_runtime.h>

namespace {

__device__ __forceinline__ double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A row of at most this many entries is summed by one lane in entry order
 * (the host's order: contacts); a longer one (a cable's or a cavity's
 * mapped points: the cable finger's row has 56) by the warp, lane-strided
 * and shuffled, where one lane's chain of dependent loads took 8 us. */
constexpr int kDeltaSerial = 8;

/* Term k of row j (entries p0 .. p0 + np - 1 prescribed, then the free
 * ones e0 ..): its coefficient times q at the prescribed vertex, or times
 * the free unknown (x, or q at free_vertex when that is not NULL). */
__device__ __forceinline__ double row_term(const pl_ncp_cuda_rows *__restrict__ Rp, int p0, int np,
                                           int e0, int k, const double *x, const double *q,
                                           const int *free_vertex)
{
    if (k < np) return dot3(Rp->pcoef + 3 * (size_t)(p0 + k), q + 3 * (size_t)Rp->pvert[p0 + k]);
    const int e = e0 + k - np, f = Rp->fcol[e];
    const double *xe = free_vertex ? q + 3 * (size_t)free_vertex[f] : x + 3 * (size_t)f;
    return dot3(Rp->fcoef + 3 * (size_t)e, xe);
}

/* H_j [x; q_p], the row's sum without its offset, on one thread in entry
 * order (the host's): the prescribed entries, then the free ones. */
__device__ __forceinline__ double row_value(const pl_ncp_cuda_rows *__restrict__ Rp, int j,
                                            const double *x, const double *q,
                                            const int *free_vertex)
{
    const int p0 = Rp->pstart[j], np = Rp->pstart[j + 1] - p0;
    const int e0 = Rp->fstart[j], n = np + Rp->fstart[j + 1] - e0;
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += row_term(Rp, p0, np, e0, k, x, q, free_vertex);
    return s;
}

/* delta_j (x: the free part, read at R.fvert with use_fvert) by the 32
 * lanes of a warp, all of which call it (k_delta's sum: one lane for at
 * most kDeltaSerial entries, else lane-strided and a shuffle tree); lane 0
 * writes it. */
__device__ __forceinline__ void row_delta_warp(const pl_ncp_cuda_rows *__restrict__ Rp, int j,
                                               const double *x, const double *q, int use_fvert,
                                               int lane, double *delta)
{
    const int *free_vertex = use_fvert ? Rp->fvert : NULL;
    const int p0 = Rp->pstart[j], np = Rp->pstart[j + 1] - p0;
    const int e0 = Rp->fstart[j], n = np + Rp->fstart[j + 1] - e0;
    double s = 0.0;
    if (n <= kDeltaSerial) {
        if (lane == 0) s = row_value(Rp, j, x, q, free_vertex);
    } else {
        for (int k = lane; k < n; k += 32) s += row_term(Rp, p0, np, e0, k, x, q, free_vertex);
        for (int o = 16; o > 0; o >>= 1) s += __shfl_down_sync(0xffffffffu, s, o);
    }
    if (lane == 0) delta[j] = s - Rp->offset[j];
}

/* One of a jacobian iteration's two values of row j (k_delta2's): which 0,
 * delta_j at q (free part at R.fvert); 1, delta_free_j at x. */
__device__ __forceinline__ void row_delta2(const pl_ncp_cuda_rows *__restrict__ Rp, int j,
                                           const double *x, const double *q, int which,
                                           double *out)
{
    const double offset = Rp->offset[j];
    out[j] = (which ? row_value(Rp, j, x, q, NULL) : row_value(Rp, j, NULL, q, Rp->fvert)) -
             offset;
}

} // namespace

#endif
