/* spinv_cuda_kernels.cu - y = S a (rows) and z = S^T y (column tiles) on
 * the padded profile layout, float32 and float64; the permutation in and
 * out.  See spinv_cuda.h and spinv_cuda_layout.h for the layout. */
#include "spinv_cuda_items.cuh"
#include "pliant/cuda_launch.h"

namespace {

using namespace spinv_items; /* kThreads, the item bodies */

/* The rows kernel: one warp per item (ROWS or SHORT, see the layout and
 * rows_item). */
template <typename T, int G>
__global__ void __launch_bounds__(kThreads)
    k_mult_S(const pl_spinv_cuda_item *__restrict__ items, int nitems,
             const pl_spinv_cuda_rowmeta *__restrict__ meta, const int *__restrict__ short_rows,
             const T *__restrict__ val, const T *__restrict__ a, T *__restrict__ y4,
             T *__restrict__ part, int *__restrict__ cnt)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int w = (int)((blockIdx.x * (size_t)blockDim.x + threadIdx.x) >> 5);
    const int lane = threadIdx.x & 31;
    if (w >= nitems) return;
    const pl_spinv_cuda_item it = items[w];
    rows_item<false, T, G>(it, lane, meta, short_rows, val, a, y4, part, cnt);
}

/* The tiles kernel, one block per item: the block's 8 warps take
 * consecutive stretches of the item's rows (tile_rows); warp 0 sums the 8
 * in order.  A split tile's parts are summed by the last block to finish.
 * Output out[perm[j]] (perm NULL: out[j]) in To. */
template <typename T, typename To>
__global__ void __launch_bounds__(kThreads)
    k_mult_ST(const pl_spinv_cuda_item *__restrict__ items,
              const pl_spinv_cuda_tilerow *__restrict__ rowlist, const T *__restrict__ val,
              const T *__restrict__ y4, int n,
              const int *__restrict__ perm, To *__restrict__ out, T *__restrict__ part,
              int *__restrict__ cnt)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    constexpr int VC = 16 / sizeof(T), NV = 3 * VC;
    __shared__ T red[kWarps][32][NV];
    const int wib = threadIdx.x >> 5, lane = threadIdx.x & 31;
    const pl_spinv_cuda_item it = items[blockIdx.x];
    tile_rows<false>(it, wib, lane, rowlist, val, y4, red);
    __syncthreads();
    if (wib != 0) return;
    T acc[NV];
    tile_sum(lane, red, acc);
    if (it.part >= 0) {
        /* split tile: publish, and let the last block sum the parts in order */
        T *mine = part + ((size_t)it.part * 32 + lane) * NV;
        for (int q = 0; q < NV; q += VC) st16(mine + q, acc + q);
        __threadfence();
        __syncwarp();
        int ticket = 0;
        if (lane == 0) ticket = atomicAdd(cnt + it.idx, 1);
        ticket = __shfl_sync(0xffffffffu, ticket, 0);
        if (ticket != it.nparts - 1) return;
        __threadfence();
        tile_parts<true>(it, lane, part, acc);
        if (lane == 0) cnt[it.idx] = 0;
    }
    tile_store(it, lane, n, perm, out, acc);
}

/* a[i] = b[perm[i]] (perm NULL: b[i]) for i < n, zero for n <= i < npad. */
template <typename Ti, typename T>
__global__ void k_permute_in(int n, int npad, const int *__restrict__ perm,
                             const Ti *__restrict__ b, T *__restrict__ a)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int i = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (i >= npad) return;
    T v0 = 0, v1 = 0, v2 = 0;
    if (i < n) {
        const size_t r = 3 * (size_t)(perm ? perm[i] : i);
        v0 = (T)b[r], v1 = (T)b[r + 1], v2 = (T)b[r + 2];
    }
    a[3 * (size_t)i] = v0, a[3 * (size_t)i + 1] = v1, a[3 * (size_t)i + 2] = v2;
}

template <typename T>
__global__ void k_to4(int n, const T *__restrict__ x, T *__restrict__ y4)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int i = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (i >= n) return;
    y4[4 * (size_t)i] = x[3 * (size_t)i];
    y4[4 * (size_t)i + 1] = x[3 * (size_t)i + 1];
    y4[4 * (size_t)i + 2] = x[3 * (size_t)i + 2];
    y4[4 * (size_t)i + 3] = 0;
}

template <typename T>
__global__ void k_from4(int n, const T *__restrict__ y4, T *__restrict__ y)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    const int i = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (i >= n) return;
    y[3 * (size_t)i] = y4[4 * (size_t)i];
    y[3 * (size_t)i + 1] = y4[4 * (size_t)i + 1];
    y[3 * (size_t)i + 2] = y4[4 * (size_t)i + 2];
}

unsigned blocks_for(long long threads)
{
    return (unsigned)((threads + kThreads - 1) / kThreads);
}

int launched(pl_error *err, const char *what)
{
    cudaError_t e = cudaGetLastError();
    return e == cudaSuccess ? PL_OK : spinv_cuda_fail(err, e, what);
}

template <typename T, typename Ti>
void permute_in(pl_spinv_cuda *g, const void *b, const int *perm, cudaStream_t st)
{
    if (g->npad > 0)
        pl_cuda_launch(k_permute_in<Ti, T>, blocks_for(g->npad), kThreads, 0, st, g->n, g->npad,
                       perm, static_cast<const Ti *>(b), static_cast<T *>(g->a));
}

template <typename T, typename To>
void mult_ST(pl_spinv_cuda *g, void *x, const int *perm, cudaStream_t st)
{
    if (g->nitems_ST > 0)
        pl_cuda_launch(k_mult_ST<T, To>, (unsigned)g->nitems_ST, kThreads, 0, st, g->items_ST,
                       g->rowlist, static_cast<const T *>(g->val),
                       static_cast<const T *>(g->y4), g->n, perm, static_cast<To *>(x),
                       static_cast<T *>(g->part_ST), g->cnt_ST);
}

} // namespace

int spinv_cuda_launch_permute(pl_spinv_cuda *g, const void *b, pl_precision io, const int *perm,
                              cudaStream_t st, pl_error *err)
{
    if (g->prec == PL_F32)
        io == PL_F32 ? permute_in<float, float>(g, b, perm, st)
                     : permute_in<float, double>(g, b, perm, st);
    else
        io == PL_F32 ? permute_in<double, float>(g, b, perm, st)
                     : permute_in<double, double>(g, b, perm, st);
    return launched(err, "permute kernel");
}

template <typename T, int G>
void mult_S(pl_spinv_cuda *g, cudaStream_t st)
{
    pl_cuda_launch(k_mult_S<T, G>, blocks_for(32LL * g->nitems_S), kThreads, 0, st, g->items_S,
                   g->nitems_S, g->meta, g->short_rows, static_cast<const T *>(g->val),
                   static_cast<const T *>(g->a), static_cast<T *>(g->y4),
                   static_cast<T *>(g->part_S), g->cnt_S);
}

template <typename T>
void mult_S_group(pl_spinv_cuda *g, cudaStream_t st)
{
    switch (g->group) {
    case 1: mult_S<T, 1>(g, st); break;
    case 2: mult_S<T, 2>(g, st); break;
    case 4: mult_S<T, 4>(g, st); break;
    default: mult_S<T, 8>(g, st); break;
    }
}

int spinv_cuda_launch_S(pl_spinv_cuda *g, cudaStream_t st, pl_error *err)
{
    if (g->nitems_S == 0) return PL_OK;
    if (g->prec == PL_F32)
        mult_S_group<float>(g, st);
    else
        mult_S_group<double>(g, st);
    return launched(err, "S kernel");
}

int spinv_cuda_launch_ST(pl_spinv_cuda *g, void *x, pl_precision io, const int *perm,
                         cudaStream_t st, pl_error *err)
{
    if (g->prec == PL_F32)
        io == PL_F32 ? mult_ST<float, float>(g, x, perm, st) : mult_ST<float, double>(g, x, perm, st);
    else
        io == PL_F32 ? mult_ST<double, float>(g, x, perm, st)
                     : mult_ST<double, double>(g, x, perm, st);
    return launched(err, "S^T kernel");
}

int spinv_cuda_launch_to4(pl_spinv_cuda *g, const void *x, cudaStream_t st, pl_error *err)
{
    if (g->prec == PL_F32)
        pl_cuda_launch(k_to4<float>, blocks_for(g->n), kThreads, 0, st, g->n,
                       static_cast<const float *>(x), static_cast<float *>(g->y4));
    else
        pl_cuda_launch(k_to4<double>, blocks_for(g->n), kThreads, 0, st, g->n,
                       static_cast<const double *>(x), static_cast<double *>(g->y4));
    return launched(err, "copy kernel");
}

int spinv_cuda_launch_from4(pl_spinv_cuda *g, void *y, cudaStream_t st, pl_error *err)
{
    if (g->prec == PL_F32)
        pl_cuda_launch(k_from4<float>, blocks_for(g->n), kThreads, 0, st, g->n,
                       static_cast<const float *>(g->y4), static_cast<float *>(y));
    else
        pl_cuda_launch(k_from4<double>, blocks_for(g->n), kThreads, 0, st, g->n,
                       static_cast<const double *>(g->y4), static_cast<double *>(y));
    return launched(err, "copy kernel");
}

