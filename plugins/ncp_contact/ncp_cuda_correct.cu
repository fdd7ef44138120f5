/* ncp_cuda_correct.cu - the few rows' dense correction (ncp_cuda_correct.h). */
#include "ncp_cuda_correct.h"

#include <cuda_runtime.h>
#include "pliant/cuda_launch.h"

#include "ncp_cuda_correct.cuh"

namespace {

constexpr int kThreads = 256;

unsigned blocks(long long n)
{
    return (unsigned)((n + kThreads - 1) / kThreads);
}

/* U_j = H_j^T, one thread an unknown: its blocks' entries zeroed, then its
 * transposed entries (increasing entry order, so by row) added. */
__global__ void k_rows_blocks(const pl_ncp_cuda_rows *__restrict__ Rp, int nfree,
                              double *__restrict__ U)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int f = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (f >= nfree) return;
    const int m = Rp->m;
    const size_t stride = 3 * (size_t)nfree;
    for (int j = 0; j < m; ++j) {
        double *u = U + j * stride + 3 * (size_t)f;
        u[0] = u[1] = u[2] = 0.0;
    }
    const int *tent = Rp->tent, *erow = Rp->erow;
    const double *fcoef = Rp->fcoef;
    for (int k = Rp->tptr[f]; k < Rp->tptr[f + 1]; ++k) {
        const int e = tent[k];
        double *u = U + erow[e] * stride + 3 * (size_t)f;
        const double *c = fcoef + 3 * (size_t)e;
        u[0] += c[0];
        u[1] += c[1];
        u[2] += c[2];
    }
}

/* One thread a value of q (3 nfree), and the first m threads write force
 * (correct_dense_at). */
__global__ void k_correct_dense(const pl_ncp_cuda_rows *__restrict__ Rp, int nfree,
                                const double *__restrict__ scale,
                                const double *__restrict__ lambda, double h2,
                                const double *__restrict__ U, const double *__restrict__ q_free,
                                double *__restrict__ force, double *__restrict__ q_next)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const long long i = blockIdx.x * (long long)blockDim.x + threadIdx.x;
    correct_dense_at(i, Rp->m, 3LL * nfree, scale, lambda, h2, U, q_free, force, q_next);
}

} // namespace

extern "C" int ncp_cuda_rows_blocks(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int nfree,
                                    double *U)
{
    if (nfree <= 0) return 0;
    pl_cuda_launch(k_rows_blocks, blocks(nfree), kThreads, 0, st, R, nfree, U);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_correct_dense(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                                      int nfree, const double *scale, const double *lambda,
                                      double h2, const double *U, const double *q_free,
                                      double *force, double *q_next)
{
    long long n = 3LL * (nfree > 0 ? nfree : 0);
    if (n < mcap) n = mcap;
    if (n <= 0) return 0;
    pl_cuda_launch(k_correct_dense, blocks(n), kThreads, 0, st, R, nfree, scale, lambda, h2, U,
                   q_free, force, q_next);
    return (int)cudaGetLastError();
}
