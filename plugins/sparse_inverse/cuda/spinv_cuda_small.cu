/* spinv_cuda_small.cu - the global step of a small system in ONE launch:
 * a single thread block does a = P b, y = S a and x = P^T S^T y with a and
 * y in shared memory and __syncthreads between the phases, where the
 * multi-kernel solve (spinv_cuda_kernels.cu) needs three dependent
 * launches.  On a 158-vertex finger each launch is a few microseconds of
 * latency for less than a microsecond of work, and the device loop solves
 * twice an iteration with a row (global step and correction).
 *
 * The phases call the multi-kernel path's own item bodies
 * (spinv_cuda_items.cuh): the block's 32 warps take the ROWS and SHORT
 * items of S in turn, its 4 groups of 8 warps the TILE items of S^T (a split
 * tile's parts are summed in slot order at the end), so every row and tile
 * sums in the same order as there and the result is the same, bit for bit.
 *
 * Chosen at create when the system is small (spinv_cuda_small_fits):
 * n <= PL_SPINV_CUDA_SMALL_N, S's padded values <= PL_SPINV_CUDA_SMALL_BYTES
 * (one block reads them twice a solve, from L1/L2), no split row of S, and
 * the shared memory within the device's per-block limit.
 * PLIANT_SPINV_SMALL=0 keeps the three launches (a diagnostic, for
 * comparisons in one run). */
#include "spinv_cuda_items.cuh"
#include "pliant/cuda_launch.h"

#include <stdlib.h>
#include <string.h>

namespace {

using namespace spinv_items;

constexpr int kGroups = 4;                 /* TILE items at once */
constexpr int kSmallThreads = kGroups * kThreads;
constexpr int kSmallWarps = kSmallThreads / 32;

/* Bytes of the reduction arrays (the same for float32 and float64: 3 x 16
 * bytes a lane) and of the block's shared memory. */
constexpr size_t kRedBytes = (size_t)kGroups * kWarps * 32 * 48;
static_assert(kRedBytes == PL_SPINV_CUDA_SMALL_RED_BYTES, "spinv_cuda_layout.h");

template <typename T, typename Ti, typename To, int G>
__global__ void __launch_bounds__(kSmallThreads)
    k_solve_small(int n, int npad, const int *__restrict__ perm, const Ti *b, To *x,
                  const pl_spinv_cuda_item *__restrict__ items_S, int nitems_S,
                  const pl_spinv_cuda_rowmeta *__restrict__ meta,
                  const int *__restrict__ short_rows, const T *__restrict__ val,
                  const pl_spinv_cuda_item *__restrict__ items_ST, int nitems_ST,
                  const pl_spinv_cuda_tilerow *__restrict__ rowlist, T *part_ST)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    constexpr int NV = 3 * 16 / sizeof(T);
    extern __shared__ __align__(16) unsigned char smem[];
    T(*red)[kWarps][32][NV] = reinterpret_cast<T(*)[kWarps][32][NV]>(smem);
    T *a = reinterpret_cast<T *>(smem + kRedBytes); /* npad x 3 */
    T *y4 = a + 3 * (size_t)npad;                   /* n x 4 */
    const int warp = threadIdx.x >> 5, lane = threadIdx.x & 31;
    /* a = P b (k_permute_in); b is read whole before x is written (x may be b) */
    for (int i = threadIdx.x; i < npad; i += kSmallThreads) {
        T v0 = 0, v1 = 0, v2 = 0;
        if (i < n) {
            const size_t r = 3 * (size_t)perm[i];
            v0 = (T)b[r], v1 = (T)b[r + 1], v2 = (T)b[r + 2];
        }
        a[3 * i] = v0, a[3 * i + 1] = v1, a[3 * i + 2] = v2;
    }
    __syncthreads();
    /* y = S a (k_mult_S), no split rows */
    for (int w = warp; w < nitems_S; w += kSmallWarps) {
        const pl_spinv_cuda_item it = items_S[w];
        rows_item<true, T, G>(it, lane, meta, short_rows, val, a, y4, NULL, NULL);
        __syncwarp();
    }
    __syncthreads();
    /* x = P^T S^T y (k_mult_ST): group grp takes items grp, grp + 4, ... */
    const int grp = warp / kWarps, wib = warp % kWarps;
    for (int r0 = 0; r0 < nitems_ST; r0 += kGroups) {
        const int i = r0 + grp;
        pl_spinv_cuda_item it;
        if (i < nitems_ST) {
            it = items_ST[i];
            tile_rows<true>(it, wib, lane, rowlist, val, y4, red[grp]);
        }
        __syncthreads();
        if (i < nitems_ST && wib == 0) {
            T acc[NV];
            tile_sum(lane, red[grp], acc);
            if (it.part >= 0) {
                T *mine = part_ST + ((size_t)it.part * 32 + lane) * NV;
                for (int q = 0; q < NV; q += 16 / (int)sizeof(T)) st16(mine + q, acc + q);
            } else {
                tile_store(it, lane, n, perm, x, acc);
            }
        }
        __syncthreads(); /* red is the next round's */
    }
    /* split tiles: a warp per tile (at its first part) sums the parts in order */
    for (int i = warp; i < nitems_ST; i += kSmallWarps) {
        const pl_spinv_cuda_item it = items_ST[i];
        if (it.part < 0 || it.part != it.part0) continue;
        T acc[NV];
        tile_parts<false>(it, lane, part_ST, acc);
        tile_store(it, lane, n, perm, x, acc);
    }
}

/* Lets the object's kernels (io float64 and float32) use `bytes` of shared
 * memory. */
template <typename T, int G>
cudaError_t allow_shmem(int bytes)
{
    cudaError_t e = cudaFuncSetAttribute(k_solve_small<T, double, double, G>,
                                         cudaFuncAttributeMaxDynamicSharedMemorySize, bytes);
    if (e == cudaSuccess)
        e = cudaFuncSetAttribute(k_solve_small<T, float, float, G>,
                                 cudaFuncAttributeMaxDynamicSharedMemorySize, bytes);
    return e;
}

template <typename T>
cudaError_t allow_group(int group, int bytes)
{
    switch (group) {
    case 1: return allow_shmem<T, 1>(bytes);
    case 2: return allow_shmem<T, 2>(bytes);
    case 4: return allow_shmem<T, 4>(bytes);
    default: return allow_shmem<T, 8>(bytes);
    }
}

template <typename T, typename Ti, typename To, int G>
void launch(pl_spinv_cuda *g, const void *b, void *x, cudaStream_t st)
{
    pl_cuda_launch(k_solve_small<T, Ti, To, G>, 1, kSmallThreads, g->small_shmem, st,
        g->n, g->npad, g->perm, static_cast<const Ti *>(b), static_cast<To *>(x), g->items_S,
        g->nitems_S, g->meta, g->short_rows, static_cast<const T *>(g->val), g->items_ST,
        g->nitems_ST, g->rowlist, static_cast<T *>(g->part_ST));
}

template <typename T, typename Ti, typename To>
void launch_group(pl_spinv_cuda *g, const void *b, void *x, cudaStream_t st)
{
    switch (g->group) {
    case 1: launch<T, Ti, To, 1>(g, b, x, st); break;
    case 2: launch<T, Ti, To, 2>(g, b, x, st); break;
    case 4: launch<T, Ti, To, 4>(g, b, x, st); break;
    default: launch<T, Ti, To, 8>(g, b, x, st); break;
    }
}

template <typename T>
void launch_io(pl_spinv_cuda *g, const void *b, void *x, pl_precision io, cudaStream_t st)
{
    if (io == PL_F32)
        launch_group<T, float, float>(g, b, x, st);
    else
        launch_group<T, double, double>(g, b, x, st);
}

} // namespace

int spinv_cuda_small_setup(pl_spinv_cuda *g, pl_error *err)
{
    g->small = 0;
    const char *env = getenv("PLIANT_SPINV_SMALL");
    if (env && !strcmp(env, "0")) return PL_OK;
    int dev = 0, optin = 0;
    SPINV_CK(cudaGetDevice(&dev), "cudaGetDevice");
    SPINV_CK(cudaDeviceGetAttribute(&optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, dev),
             "cudaDeviceGetAttribute");
    int rs = g->prec == PL_F32 ? 4 : 8;
    if (!spinv_cuda_small_fits(g->n, g->nval, g->nparts_S, rs, optin)) return PL_OK;
    size_t bytes = spinv_cuda_small_shmem(g->n, rs);
    cudaError_t e = g->prec == PL_F32 ? allow_group<float>(g->group, (int)bytes)
                                      : allow_group<double>(g->group, (int)bytes);
    if (e != cudaSuccess) return spinv_cuda_fail(err, e, "single-block solve setup");
    g->small = 1;
    g->small_shmem = bytes;
    return PL_OK;
}

int spinv_cuda_launch_small(pl_spinv_cuda *g, const void *b, void *x, pl_precision io,
                            cudaStream_t st, pl_error *err)
{
    if (g->prec == PL_F32)
        launch_io<float>(g, b, x, io, st);
    else
        launch_io<double>(g, b, x, io, st);
    cudaError_t e = cudaGetLastError();
    return e == cudaSuccess ? PL_OK : spinv_cuda_fail(err, e, "single-block solve");
}
