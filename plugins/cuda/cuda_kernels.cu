/* cuda_kernels.cu - the device service's vector kernels (see cuda_kernels.h):
 * one thread per row (a vertex's xyz), grid-stride free; launch errors are
 * returned, execution errors surface at the next sync. */
#include "cuda_kernels.h"

#include <cuda_runtime.h>

#include "pliant/cuda_launch.h"

namespace {

constexpr int kThreads = 256;

unsigned blocks(long long n)
{
    return (unsigned)((n + kThreads - 1) / kThreads);
}

/* y[i] = s[i] x[i] for row i (a vertex's xyz). */
__device__ __forceinline__ void scale_row(size_t i, const double *__restrict__ s,
                                          const double *__restrict__ x, double *__restrict__ y)
{
    const double m = s[i];
    y[3 * i] = m * x[3 * i];
    y[3 * i + 1] = m * x[3 * i + 1];
    y[3 * i + 2] = m * x[3 * i + 2];
}

__global__ void k_scale_rows(int n, const double *__restrict__ s, const double *__restrict__ x,
                             double *__restrict__ y)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int i = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (i < n) scale_row((size_t)i, s, x, y);
}

__global__ void k_gather_rows(int m, const int *__restrict__ map, const double *__restrict__ x,
                              double *__restrict__ y)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int f = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (f >= m) return;
    const double *src = x + 3 * (size_t)map[f];
    y[3 * (size_t)f] = src[0];
    y[3 * (size_t)f + 1] = src[1];
    y[3 * (size_t)f + 2] = src[2];
}

/* *out = max(*out, the largest d of the block's threads) (d >= 0).
 * Non-negative doubles order like their bit patterns, so the maximum can be
 * taken with an integer atomicMax: the result does not depend on the order.
 * Every thread of the block calls it. */
__device__ __forceinline__ void block_max_to(double d, double *out)
{
    __shared__ double red[kThreads / 32];
    for (int o = 16; o > 0; o >>= 1) d = fmax(d, __shfl_down_sync(0xffffffffu, d, o));
    if ((threadIdx.x & 31) == 0) red[threadIdx.x >> 5] = d;
    __syncthreads();
    if (threadIdx.x == 0) {
        for (int w = 1; w < kThreads / 32; ++w) d = fmax(d, red[w]);
        if (d > 0.0)
            atomicMax(reinterpret_cast<unsigned long long *>(out),
                      (unsigned long long)__double_as_longlong(d));
    }
}

__global__ void k_scatter_rows(int m, const int *__restrict__ map, const double *__restrict__ y,
                               double *__restrict__ x, double *__restrict__ change)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int f = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    double d = 0.0;
    if (f < m) {
        double *dst = x + 3 * (size_t)map[f];
#pragma unroll
        for (int k = 0; k < 3; ++k) {
            const double nv = y[3 * (size_t)f + k];
            const double dk = fabs(nv - dst[k]);
            d = isfinite(nv) ? fmax(d, dk) : INFINITY;
            dst[k] = nv;
        }
    }
    block_max_to(d, change);
}

/* (y0, y1, y2) -= sum over entries q in [b, e) of a[q] x[j[q]], each
 * entry subtracted in turn in row order (as the CPU loop does), by one
 * warp: its lanes load up to 32 entries (value, column, x's 3-vector) into
 * the warp's buffer w at once, then lane 0 subtracts them in order; only
 * lane 0's y is the result.  One thread walking the row waited for two
 * memory latencies every few entries, and a small system's row is nothing
 * but such latencies (docs/benchmarks.md, "The iteration in fewer, shorter kernels"). */
constexpr int kRowWarps = kThreads / 32;

__device__ __forceinline__ void sub_row_warp(int b, int e, const int *__restrict__ j,
                                             const double *__restrict__ a,
                                             const double *__restrict__ x, double (*w)[4],
                                             int lane, double &y0, double &y1, double &y2)
{
    for (int q = b; q < e; q += 32) {
        const int n = e - q < 32 ? e - q : 32;
        if (lane < n) {
            const double *xs = x + 3 * (size_t)j[q + lane];
            w[lane][0] = a[q + lane], w[lane][1] = xs[0], w[lane][2] = xs[1], w[lane][3] = xs[2];
        }
        __syncwarp();
        if (lane == 0)
            for (int t = 0; t < n; ++t) {
                const double v = w[t][0];
                y0 -= v * w[t][1];
                y1 -= v * w[t][2];
                y2 -= v * w[t][3];
            }
        __syncwarp(); /* w is the next round's */
    }
}

/* One warp a row (launch with row_blocks). */
__global__ void k_sub_csr(int nrows, const int *__restrict__ p, const int *__restrict__ j,
                          const double *__restrict__ a, const double *__restrict__ x,
                          double *__restrict__ y)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    __shared__ double buf[kRowWarps][32][4];
    const int warp = threadIdx.x >> 5, lane = threadIdx.x & 31;
    const int r = (int)(blockIdx.x * (size_t)kRowWarps + warp);
    if (r >= nrows) return; /* the whole warp */
    const int b = p[r], e = p[r + 1];
    if (b == e) return;
    double y0 = y[3 * (size_t)r], y1 = y[3 * (size_t)r + 1], y2 = y[3 * (size_t)r + 2];
    sub_row_warp(b, e, j, a, x, buf[warp], lane, y0, y1, y2);
    if (lane == 0) y[3 * (size_t)r] = y0, y[3 * (size_t)r + 1] = y1, y[3 * (size_t)r + 2] = y2;
}

/* t = x[map[f]] - (A q)[f] for row f by its warp (p NULL: no A), the
 * entries in k_sub_csr's order; only lane 0's t is the result.  w: the
 * warp's buffer. */
__device__ __forceinline__ void gather_sub_row(int f, const int *__restrict__ map,
                                               const double *__restrict__ x,
                                               const int *__restrict__ p,
                                               const int *__restrict__ j,
                                               const double *__restrict__ a,
                                               const double *__restrict__ q, double (*w)[4],
                                               int lane, double t[3])
{
    const double *src = x + 3 * (size_t)map[f];
    t[0] = src[0], t[1] = src[1], t[2] = src[2];
    if (p) sub_row_warp(p[f], p[f + 1], j, a, q, w, lane, t[0], t[1], t[2]);
}

/* k_gather_rows then k_sub_csr for row f, one warp a row: the same values
 * subtracted in the same order (A NULL: the gather alone). */
__global__ void k_gather_sub_csr(int m, const int *__restrict__ map, const double *__restrict__ x,
                                 const int *__restrict__ p, const int *__restrict__ j,
                                 const double *__restrict__ a, const double *__restrict__ q,
                                 double *__restrict__ y)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    __shared__ double buf[kRowWarps][32][4];
    const int warp = threadIdx.x >> 5, lane = threadIdx.x & 31;
    const int f = (int)(blockIdx.x * (size_t)kRowWarps + warp);
    if (f >= m) return; /* the whole warp */
    double t[3];
    gather_sub_row(f, map, x, p, j, a, q, buf[warp], lane, t);
    if (lane == 0) y[3 * (size_t)f] = t[0], y[3 * (size_t)f + 1] = t[1], y[3 * (size_t)f + 2] = t[2];
}

unsigned row_blocks(long long rows)
{
    return (unsigned)((rows + kRowWarps - 1) / kRowWarps);
}

/* The force residual's 3-vector of unknown f (vertex v = map[f]):
 * r = s[v] (x[v] - y[v]) / h2 + g[v] + t[f] / h2 (t NULL: no last term; in
 * force_residual.c's order of operations), and
 * *out = max(*out, |r|) by the bit-pattern atomicMax of k_scatter_rows;
 * +inf when an r is not finite. */
__device__ __forceinline__ double residual_norm(size_t v, const double *__restrict__ s, double h2,
                                                const double *__restrict__ x,
                                                const double *__restrict__ y,
                                                const double *__restrict__ g, const double *t)
{
    const double sv = s[v];
    double r2 = 0.0;
#pragma unroll
    for (int k = 0; k < 3; ++k) {
        double r = sv * (x[3 * v + k] - y[3 * v + k]) / h2 + g[3 * v + k];
        if (t) r += t[k] / h2;
        r2 += r * r;
    }
    return isfinite(r2) ? sqrt(r2) : INFINITY;
}

__global__ void k_residual_max(int m, const int *__restrict__ map, const double *__restrict__ s,
                               double h2, const double *__restrict__ x, const double *__restrict__ y,
                               const double *__restrict__ g, const double *__restrict__ t,
                               double *__restrict__ out)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int f = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    double d = 0.0;
    if (f < m) d = residual_norm((size_t)map[f], s, h2, x, y, g, t ? t + 3 * (size_t)f : NULL);
    block_max_to(d, out);
}

/* k_gather_sub_csr's t_f = b[map[f]] - (A x)[f] and k_residual_max's r_f
 * with it, one warp a row (launch with row_blocks): the same values as the
 * two kernels, without t's round trip through memory. */
__global__ void k_residual_max_csr(int m, const int *__restrict__ map, const double *__restrict__ s,
                                   double h2, const double *__restrict__ x,
                                   const double *__restrict__ y, const double *__restrict__ g,
                                   const double *__restrict__ b, const int *__restrict__ p,
                                   const int *__restrict__ j, const double *__restrict__ a,
                                   double *__restrict__ out)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    __shared__ double buf[kRowWarps][32][4];
    const int warp = threadIdx.x >> 5, lane = threadIdx.x & 31;
    const int f = (int)(blockIdx.x * (size_t)kRowWarps + warp);
    double d = 0.0;
    if (f < m) { /* the whole warp */
        double t[3];
        gather_sub_row(f, map, b, p, j, a, x, buf[warp], lane, t);
        if (lane == 0) d = residual_norm((size_t)map[f], s, h2, x, y, g, t);
    }
    block_max_to(d, out);
}

/* k_scale_rows and bytes / 8 doubles of z zeroed (a memset's launch less). */
__global__ void k_scale_rows_zero(int n, const double *__restrict__ s,
                                  const double *__restrict__ x, double *__restrict__ y,
                                  double *__restrict__ z, long long nz)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const long long i = (long long)blockIdx.x * blockDim.x + threadIdx.x;
    const long long stride = (long long)gridDim.x * blockDim.x;
    for (long long k = i; k < nz; k += stride) z[k] = 0.0;
    if (i < n) scale_row((size_t)i, s, x, y);
}

/* pl_dynamics_begin's values for coordinate i, each operation rounded as
 * written (__dmul_rn / __dadd_rn: nvcc would otherwise contract x + h v
 * into a fused multiply-add, one rounding less than the host's). */
__global__ void k_step_begin(int n3, double h, int first_order, int guess, double hv,
                             const double *__restrict__ x, const double *__restrict__ v,
                             const double *__restrict__ g, double *__restrict__ q_t,
                             double *__restrict__ sn, double *__restrict__ q)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n3) return;
    const double xi = x[i], vi = v[i], gi = g[i];
    const double m = first_order ? __dadd_rn(xi, __dmul_rn(h, gi))
                                 : __dadd_rn(__dadd_rn(xi, __dmul_rn(h, vi)),
                                             __dmul_rn(__dmul_rn(h, h), gi));
    q_t[i] = xi;
    sn[i] = m;
    q[i] = guess ? __dadd_rn(xi, __dmul_rn(hv, vi)) : m;
}

/* pl_dynamics_scatter's values for coordinate i, rounded as written. */
__global__ void k_step_end(int n3, double h, double scale, const double *__restrict__ q,
                           const double *__restrict__ q_t, double *__restrict__ x,
                           double *__restrict__ v, int *__restrict__ bad)
{
    PL_CUDA_GRID_WAIT();
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n3) return;
    const double qi = q[i];
    if (!isfinite(qi)) *bad = 1;
    v[i] = __ddiv_rn(__dmul_rn(scale, __dsub_rn(qi, q_t[i])), h);
    x[i] = qi;
}

} // namespace

extern "C" int cuda_step_begin(struct CUstream_st *st, int n3, double h, int first_order,
                               int guess, double hv, const double *x, const double *v,
                               const double *g, double *q_t, double *sn, double *q)
{
    if (n3 <= 0) return 0;
    pl_cuda_launch(k_step_begin, blocks(n3), kThreads, 0, st, n3, h, first_order, guess, hv, x, v,
                   g, q_t, sn, q);
    return (int)cudaGetLastError();
}

extern "C" int cuda_step_end(struct CUstream_st *st, int n3, double h, double scale,
                             const double *q, const double *q_t, double *x, double *v, int *bad)
{
    if (n3 <= 0) return 0;
    pl_cuda_launch(k_step_end, blocks(n3), kThreads, 0, st, n3, h, scale, q, q_t, x, v, bad);
    return (int)cudaGetLastError();
}

extern "C" int cuda_residual_max(struct CUstream_st *st, int m, const int *map, const double *s,
                                 double h2, const double *x, const double *y, const double *g,
                                 const double *t, double *out)
{
    if (m <= 0) return 0;
    pl_cuda_launch(k_residual_max, blocks(m), kThreads, 0, st, m, map, s, h2, x, y, g, t, out);
    return (int)cudaGetLastError();
}

extern "C" int cuda_residual_max_csr(struct CUstream_st *st, int m, const int *map,
                                     const double *s, double h2, const double *x, const double *y,
                                     const double *g, const double *b, const int *p, const int *j,
                                     const double *a, double *out)
{
    if (m <= 0) return 0;
    pl_cuda_launch(k_residual_max_csr, row_blocks(m), kThreads, 0, st, m, map, s, h2, x, y, g, b,
                   p, j, a, out);
    return (int)cudaGetLastError();
}

extern "C" int cuda_scale_rows_zero(struct CUstream_st *st, int n, const double *s,
                                    const double *x, double *y, void *z, size_t bytes)
{
    const long long nz = (long long)(bytes / sizeof(double));
    if (bytes % sizeof(double)) return (int)cudaErrorInvalidValue;
    if (n <= 0 && nz <= 0) return 0;
    /* a thread a row; the zeros by grid stride over at least as many
     * threads, up to 32 blocks of them */
    const unsigned rows = blocks(n), zeros = blocks(nz) < 32 ? blocks(nz) : 32;
    const unsigned nb = rows > zeros ? rows : zeros;
    pl_cuda_launch(k_scale_rows_zero, nb, kThreads, 0, st, n, s, x, y,
                   static_cast<double *>(z), nz);
    return (int)cudaGetLastError();
}

extern "C" int cuda_gather_sub_csr(struct CUstream_st *st, int m, const int *map,
                                   const double *x, const int *p, const int *j, const double *a,
                                   const double *q, double *y)
{
    if (m <= 0) return 0;
    pl_cuda_launch(k_gather_sub_csr, row_blocks(m), kThreads, 0, st, m, map, x, p, j, a, q, y);
    return (int)cudaGetLastError();
}

extern "C" int cuda_scale_rows(struct CUstream_st *st, int n, const double *s, const double *x,
                                  double *y)
{
    if (n <= 0) return 0;
    pl_cuda_launch(k_scale_rows, blocks(n), kThreads, 0, st, n, s, x, y);
    return (int)cudaGetLastError();
}

extern "C" int cuda_gather_rows(struct CUstream_st *st, int m, const int *map, const double *x,
                                   double *y)
{
    if (m <= 0) return 0;
    pl_cuda_launch(k_gather_rows, blocks(m), kThreads, 0, st, m, map, x, y);
    return (int)cudaGetLastError();
}

extern "C" int cuda_scatter_rows(struct CUstream_st *st, int m, const int *map, const double *y,
                                    double *x, double *change)
{
    if (m <= 0) return 0;
    pl_cuda_launch(k_scatter_rows, blocks(m), kThreads, 0, st, m, map, y, x, change);
    return (int)cudaGetLastError();
}

extern "C" int cuda_sub_csr(struct CUstream_st *st, int nrows, const int *p, const int *j,
                               const double *a, const double *x, double *y)
{
    if (nrows <= 0) return 0;
    pl_cuda_launch(k_sub_csr, row_blocks(nrows), kThreads, 0, st, nrows, p, j, a, x, y);
    return (int)cudaGetLastError();
}
