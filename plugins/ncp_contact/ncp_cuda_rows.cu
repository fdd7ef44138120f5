/* ncp_cuda_rows.cu - products with a step's rows on the GPU (ncp_cuda.h):
 * H q (contact_rows.c, ncpc_rows_delta / _delta_all), H^T x per unknown
 * over the transposed entries (the CPU's scatter adds rows in increasing
 * order; here each unknown sums its rows in that same order, so no atomics
 * and the same sums), H X, and the dense W x of the explicit Delassus
 * operator (in ncp_cuda_dense.cuh's order). */
#include "ncp_cuda.h"

#include <cuda_runtime.h>
#include "pliant/cuda_launch.h"

#include "ncp_cuda_dense.cuh"
#include "ncp_cuda_rowval.cuh"

namespace {

constexpr int kThreads = 256;

unsigned blocks(long long n, int per = kThreads)
{
    return (unsigned)((n + per - 1) / per);
}

/* The kernels read the step's rows from their device copy Rp (grids sized
 * by a capacity: threads past R.m return), so that a captured graph stays
 * valid when the rows change; the row values' sums are ncp_cuda_rowval.cuh's. */
/* delta = H q - offset (x: the free part, read at R.fvert with use_fvert):
 * a warp a row (grid of 32 mcap threads). */
__global__ void k_delta(const pl_ncp_cuda_rows *__restrict__ Rp, const double *__restrict__ x,
                        const double *__restrict__ q, int use_fvert, double *__restrict__ delta)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int j = (int)((blockIdx.x * (size_t)blockDim.x + threadIdx.x) >> 5);
    const int lane = threadIdx.x & 31;
    if (j >= Rp->m) return; /* whole warps leave together */
    row_delta_warp(Rp, j, x, q, use_fvert, lane, delta);
}

/* Both row values of a jacobian iteration in one launch: delta at q (free
 * part read at R.fvert) and delta_free at x; each sum as k_delta's. */
__global__ void k_delta2(const pl_ncp_cuda_rows *__restrict__ Rp, const double *__restrict__ x,
                         const double *__restrict__ q, double *__restrict__ delta,
                         double *__restrict__ delta_free)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int j = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (j >= Rp->m) return;
    row_delta2(Rp, j, x, q, 0, delta);
    row_delta2(Rp, j, x, q, 1, delta_free);
}

/* Entry k of H_free^T's lists: l = alpha v_r for its row r (v_r = x_r or,
 * SCALED, scale_r x_r, rounded, then times alpha) and its coefficients. */
template <bool SCALED>
__device__ __forceinline__ void scatter_entry(const pl_ncp_cuda_rows *__restrict__ Rp, int k,
                                              const double *scale, const double *x, double alpha,
                                              double &l, double c[3])
{
    const int e = Rp->tent[k];
    const int r = Rp->erow[e];
    const double v = SCALED ? scale[r] * x[r] : x[r];
    const double *fc = Rp->fcoef + 3 * (size_t)e;
    l = alpha * v, c[0] = fc[0], c[1] = fc[1], c[2] = fc[2];
}

/* X_f = alpha H_free^T v for unknown f: f's entries added in increasing
 * order, as the CPU's scatter adds its rows (an entry whose l is 0 skipped,
 * as the CPU skips such rows).  LANES = 1: one thread; LANES = 32: a warp,
 * all of whose lanes call it: each lane loads one entry of a chunk of 32
 * (one memory latency instead of a chain of dependent loads an entry: a
 * soft finger's vertex under many mapped contacts has tens), then every
 * lane adds the chunk's entries in order from the shuffled values, the
 * same operations.  Lane 0 writes. */
template <bool SCALED, int LANES>
__device__ __forceinline__ void scatter_unknown(const pl_ncp_cuda_rows *__restrict__ Rp, int f,
                                                const double *scale, const double *x,
                                                double alpha, double *X, int lane)
{
    const int k0 = Rp->tptr[f], k1 = Rp->tptr[f + 1];
    double a[3] = {0.0, 0.0, 0.0}, l = 0.0, c[3] = {0.0, 0.0, 0.0};
    for (int b = k0; b < k1; b += LANES) {
        const int n = k1 - b < LANES ? k1 - b : LANES;
        if (b + lane < k1) scatter_entry<SCALED>(Rp, b + lane, scale, x, alpha, l, c);
        for (int i = 0; i < n; ++i) {
            double li = l, d[3] = {c[0], c[1], c[2]};
            if constexpr (LANES > 1) {
                li = __shfl_sync(0xffffffffu, l, i);
                for (int t = 0; t < 3; ++t) d[t] = __shfl_sync(0xffffffffu, c[t], i);
            }
            if (li == 0.0) continue;
            a[0] += li * d[0];
            a[1] += li * d[1];
            a[2] += li * d[2];
        }
    }
    if (lane == 0) X[3 * (size_t)f] = a[0], X[3 * (size_t)f + 1] = a[1], X[3 * (size_t)f + 2] = a[2];
}

/* X = alpha H_free^T (scale .* lambda) and force = scale .* lambda: the
 * multipliers phase (force = S lambda, ncp_cuda_step.cu) and k_scatter in
 * one launch, LANES threads an unknown (and a row's force); l = alpha
 * (scale lambda) rounds as force then alpha force. */
template <int LANES>
__global__ void k_scatter_scaled(const pl_ncp_cuda_rows *__restrict__ Rp,
                                 const double *__restrict__ scale,
                                 const double *__restrict__ lambda, double alpha,
                                 double *__restrict__ force, double *__restrict__ X)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const long long g = blockIdx.x * (long long)blockDim.x + threadIdx.x;
    const int f = (int)(g / LANES), lane = (int)(g % LANES);
    if (lane == 0 && f < Rp->m) force[f] = scale[f] * lambda[f];
    if (f >= Rp->nfree) return; /* the whole warp where LANES = 32 */
    scatter_unknown<true, LANES>(Rp, f, scale, lambda, alpha, X, lane);
}

template <int LANES>
__global__ void k_scatter(const pl_ncp_cuda_rows *__restrict__ Rp, const double *__restrict__ x,
                          double alpha, double *__restrict__ X)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const long long g = blockIdx.x * (long long)blockDim.x + threadIdx.x;
    const int f = (int)(g / LANES), lane = (int)(g % LANES);
    if (f >= Rp->nfree) return; /* the whole warp where LANES = 32 */
    scatter_unknown<false, LANES>(Rp, f, NULL, x, alpha, X, lane);
}

__global__ void k_gather(const pl_ncp_cuda_rows *__restrict__ Rp, const double *__restrict__ X,
                         double *__restrict__ y)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int j = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (j >= Rp->m) return;
    const int e0 = Rp->fstart[j], e1 = Rp->fstart[j + 1];
    const double *fcoef = Rp->fcoef;
    const int *fcol = Rp->fcol;
    double s = 0.0;
    for (int e = e0; e < e1; ++e) s += dot3(fcoef + 3 * (size_t)e, X + 3 * (size_t)fcol[e]);
    y[j] = s;
}

/* A warp per row; lanes take columns lane, lane + 32, ... and a fixed
 * shuffle tree sums them (deterministic). */
/* y = W x, row i by K threads (ncp_cuda_dense.cuh: the fused update's
 * order); warps wholly past the rows leave, the others shuffle whole. */
__global__ void k_dense(const pl_ncp_cuda_rows *__restrict__ Rp, const double *__restrict__ W,
                        const double *__restrict__ x, double *__restrict__ y)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int m = Rp->m, K = dense_row_width(m);
    const long long g = blockIdx.x * (long long)blockDim.x + threadIdx.x;
    if ((g & ~31LL) / K >= m) return;
    const long long i = g / K;
    const int c = (int)(g % K), ok = i < m;
    const double s = dense_row_dot(W + (ok ? (size_t)i * (size_t)m : 0), x, ok ? m : 0, c, K);
    if (ok && c == 0) y[i] = s;
}

__global__ void k_add(long n, const double *__restrict__ a, const double *__restrict__ b,
                      double *__restrict__ out)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const long i = (long)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (i < n) out[i] = a[i] + b[i];
}

__global__ void k_reset(pl_ncp_cuda_scalars *sc)
{
    sc->error = 0;
    sc->iter = 0;
    sc->done = 0;
    sc->its = 0;
}

} // namespace

extern "C" int ncp_cuda_delta(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                              const double *x, const double *q, int use_fvert, double *delta)
{
    if (mcap <= 0) return 0;
    pl_cuda_launch(k_delta, blocks(32LL * mcap), kThreads, 0, st, R, x, q, use_fvert, delta);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_scatter(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int nfree,
                                const double *x, double alpha, double *X, int warp)
{
    if (nfree <= 0) return 0;
    if (warp)
        pl_cuda_launch(k_scatter<32>, blocks(32LL * nfree), kThreads, 0, st, R, x, alpha, X);
    else
        pl_cuda_launch(k_scatter<1>, blocks(nfree), kThreads, 0, st, R, x, alpha, X);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_delta2(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                               const double *x, const double *q, double *delta,
                               double *delta_free)
{
    if (mcap <= 0) return 0;
    pl_cuda_launch(k_delta2, blocks(mcap), kThreads, 0, st, R, x, q, delta, delta_free);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_scatter_scaled(struct CUstream_st *st, const pl_ncp_cuda_rows *R,
                                       int mcap, int nfree, const double *scale,
                                       const double *lambda, double alpha, double *force,
                                       double *X, int warp)
{
    int n = mcap > nfree ? mcap : nfree;
    if (n <= 0) return 0;
    if (warp)
        pl_cuda_launch(k_scatter_scaled<32>, blocks(32LL * n), kThreads, 0, st, R, scale, lambda,
                       alpha, force, X);
    else
        pl_cuda_launch(k_scatter_scaled<1>, blocks(n), kThreads, 0, st, R, scale, lambda, alpha,
                       force, X);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_gather(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                               const double *X, double *y)
{
    if (mcap <= 0) return 0;
    pl_cuda_launch(k_gather, blocks(mcap), kThreads, 0, st, R, X, y);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_dense(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                              const double *W, const double *x, double *y)
{
    if (mcap <= 0) return 0;
    pl_cuda_launch(k_dense, blocks(32LL * mcap), kThreads, 0, st, R, W, x, y);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_add(struct CUstream_st *st, long n, const double *a, const double *b,
                               double *out)
{
    if (n <= 0) return 0;
    pl_cuda_launch(k_add, blocks(n), kThreads, 0, st, n, a, b, out);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_reset(struct CUstream_st *st, pl_ncp_cuda_scalars *sc)
{
    k_reset<<<1, 1, 0, st>>>(sc);
    return (int)cudaGetLastError();
}
