/* spinv_cuda_kernels.cu - y = S a (rows) and z = S^T y (column tiles) on
 * the padded profile layout, float32 and float64; the permutation in and
 * out.  See spinv_cuda.h and spinv_cuda_layout.h for the layout. */
#include "spinv_cuda_internal.h"

namespace {

constexpr int kThreads = 256; /* 8 warps a block */

/* 16-byte vector loads through the read-only path. */
__device__ __forceinline__ void ld16(const float *p, float v[4])
{
    float4 q = __ldg(reinterpret_cast<const float4 *>(p));
    v[0] = q.x, v[1] = q.y, v[2] = q.z, v[3] = q.w;
}
__device__ __forceinline__ void ld16(const double *p, double v[2])
{
    double2 q = __ldg(reinterpret_cast<const double2 *>(p));
    v[0] = q.x, v[1] = q.y;
}
/* The same through L2 only: partial sums written by other warps of this
 * launch (L1 is not coherent). */
__device__ __forceinline__ void ld16_cg(const float *p, float v[4])
{
    float4 q = __ldcg(reinterpret_cast<const float4 *>(p));
    v[0] = q.x, v[1] = q.y, v[2] = q.z, v[3] = q.w;
}
__device__ __forceinline__ void ld16_cg(const double *p, double v[2])
{
    double2 q = __ldcg(reinterpret_cast<const double2 *>(p));
    v[0] = q.x, v[1] = q.y;
}
__device__ __forceinline__ void st16(float *p, const float v[4])
{
    *reinterpret_cast<float4 *>(p) = make_float4(v[0], v[1], v[2], v[3]);
}
__device__ __forceinline__ void st16(double *p, const double v[2])
{
    *reinterpret_cast<double2 *>(p) = make_double2(v[0], v[1]);
}

/* One row of y4 (n x 4): three values and a zero, as 16-byte stores. */
template <typename T>
__device__ __forceinline__ void store_row4(T *y4, int row, T s0, T s1, T s2)
{
    constexpr int VC = 16 / sizeof(T);
    T v[4] = {s0, s1, s2, T(0)};
    for (int q = 0; q < 4; q += VC) st16(y4 + 4 * (size_t)row + q, v + q);
}

/* The S row dot product of one 16-byte group: VC values, columns c .. c+VC-1
 * of a (npad x 3), read as 3 aligned vectors. */
template <typename T>
__device__ __forceinline__ void dot_group(const T *v, const T *x, T &s0, T &s1, T &s2)
{
    constexpr int VC = 16 / sizeof(T);
    T w[VC], p[3 * VC];
    ld16(v, w);
    for (int q = 0; q < 3; ++q) ld16(x + q * VC, p + q * VC);
#pragma unroll
    for (int k = 0; k < VC; ++k) {
        s0 += w[k] * p[3 * k];
        s1 += w[k] * p[3 * k + 1];
        s2 += w[k] * p[3 * k + 2];
    }
}

template <typename T>
__device__ __forceinline__ T warp_sum(T s)
{
#pragma unroll
    for (int o = 16; o > 0; o >>= 1) s += __shfl_xor_sync(0xffffffffu, s, o);
    return s;
}

/* The rows kernel: one warp per item (ROWS or SHORT, see the layout).  A
 * ROWS item's rows share f0; lane l takes the 16-byte groups l, l+32, ...
 * of their union, reads the matching piece of a once and every row's
 * values where the row has them (the rows end at different e). */
template <typename T, int G>
__global__ void __launch_bounds__(kThreads)
    k_mult_S(const pl_spinv_cuda_item *__restrict__ items, int nitems,
             const pl_spinv_cuda_rowmeta *__restrict__ meta, const int *__restrict__ short_rows,
             const T *__restrict__ val, const T *__restrict__ a, T *__restrict__ y4,
             T *__restrict__ part, int *__restrict__ cnt)
{
    constexpr int VC = 16 / sizeof(T), GPB = PL_SPINV_CUDA_BLOCK / VC;
    const int w = (int)((blockIdx.x * (size_t)blockDim.x + threadIdx.x) >> 5);
    const int lane = threadIdx.x & 31;
    if (w >= nitems) return;
    const pl_spinv_cuda_item it = items[w];
    if (it.kind == PL_SPINV_ITEM_SHORT) {
        if (lane >= it.lo) return;
        T s0 = 0, s1 = 0, s2 = 0;
        const int row = short_rows[it.idx + lane];
        const pl_spinv_cuda_rowmeta m = meta[row];
        const T *v = val + m.vbase + m.f0, *x = a + 3 * (size_t)m.f0;
        const int ng = (m.e - m.f0 + 1) / VC;
        for (int g = 0; g < ng; ++g) dot_group(v + g * VC, x + 3 * g * VC, s0, s1, s2);
        store_row4(y4, row, s0, s1, s2);
        return;
    }
    const int row0 = it.idx, nr = it.pad;
    const int f0 = meta[row0].f0;
    int e[G];
    long long vb[G];
#pragma unroll
    for (int r = 0; r < G; ++r) {
        e[r] = -1, vb[r] = 0;
        if (r < nr) {
            const pl_spinv_cuda_rowmeta m = meta[row0 + r];
            e[r] = m.e, vb[r] = m.vbase;
        }
    }
    T acc[G][3];
#pragma unroll
    for (int r = 0; r < G; ++r) acc[r][0] = acc[r][1] = acc[r][2] = 0;
    const int g1 = it.hi * GPB;
#pragma unroll 2
    for (int g = it.lo * GPB + lane; g < g1; g += 32) {
        const int col0 = f0 + g * VC;
        T p[3 * VC];
        for (int q = 0; q < 3; ++q) ld16(a + 3 * (size_t)col0 + q * VC, p + q * VC);
#pragma unroll
        for (int r = 0; r < G; ++r) {
            if (col0 <= e[r]) {
                T v[VC];
                ld16(val + vb[r] + col0, v);
#pragma unroll
                for (int k = 0; k < VC; ++k) {
                    acc[r][0] += v[k] * p[3 * k];
                    acc[r][1] += v[k] * p[3 * k + 1];
                    acc[r][2] += v[k] * p[3 * k + 2];
                }
            }
        }
    }
#pragma unroll
    for (int r = 0; r < G; ++r)
        if (r < nr)
#pragma unroll
            for (int c = 0; c < 3; ++c) acc[r][c] = warp_sum(acc[r][c]);
    if (it.part < 0) {
        if (lane == 0)
#pragma unroll
            for (int r = 0; r < G; ++r)
                if (r < nr) store_row4(y4, row0 + r, acc[r][0], acc[r][1], acc[r][2]);
        return;
    }
    /* split group: publish this part; the last warp to arrive sums all
     * parts in slot order (deterministic whichever warp that is) */
    int ticket = 0;
    if (lane == 0) {
#pragma unroll
        for (int r = 0; r < G; ++r)
            if (r < nr) store_row4(part, it.part * G + r, acc[r][0], acc[r][1], acc[r][2]);
        __threadfence();
        ticket = atomicAdd(cnt + row0, 1);
    }
    ticket = __shfl_sync(0xffffffffu, ticket, 0);
    if (ticket != it.nparts - 1) return;
    __threadfence();
#pragma unroll
    for (int r = 0; r < G; ++r) acc[r][0] = acc[r][1] = acc[r][2] = 0;
    for (int q = lane; q < it.nparts; q += 32)
#pragma unroll
        for (int r = 0; r < G; ++r)
            if (r < nr) {
                T p[4];
                for (int c = 0; c < 4; c += VC)
                    ld16_cg(part + 4 * ((size_t)(it.part0 + q) * G + r) + c, p + c);
                acc[r][0] += p[0], acc[r][1] += p[1], acc[r][2] += p[2];
            }
#pragma unroll
    for (int r = 0; r < G; ++r)
        if (r < nr)
#pragma unroll
            for (int c = 0; c < 3; ++c) acc[r][c] = warp_sum(acc[r][c]);
    if (lane == 0) {
#pragma unroll
        for (int r = 0; r < G; ++r)
            if (r < nr) store_row4(y4, row0 + r, acc[r][0], acc[r][1], acc[r][2]);
        cnt[row0] = 0; /* ready for the next launch */
    }
}

/* The tiles kernel, one block per item: lane l of every warp owns columns
 * col0 .. col0+VC-1 of the tile; the block's 8 warps take consecutive
 * stretches of the item's rows and accumulate S(i, j) y_i; warp 0 sums the
 * 8 in order.  Output out[perm[j]] (perm NULL: out[j]) in To. */
template <typename T, typename To>
__global__ void __launch_bounds__(kThreads)
    k_mult_ST(const pl_spinv_cuda_item *__restrict__ items,
              const pl_spinv_cuda_tilerow *__restrict__ rowlist, const T *__restrict__ val,
              const T *__restrict__ y4, int n,
              const int *__restrict__ perm, To *__restrict__ out, T *__restrict__ part,
              int *__restrict__ cnt)
{
    constexpr int VC = 16 / sizeof(T), NV = 3 * VC, NW = kThreads / 32;
    __shared__ T red[NW][32][NV];
    const int wib = threadIdx.x >> 5, lane = threadIdx.x & 31;
    const pl_spinv_cuda_item it = items[blockIdx.x];
    const int col0 = it.idx * 32 * VC + lane * VC;
    const int per = (it.hi - it.lo + NW - 1) / NW;
    const int p0 = it.lo + wib * per, p1 = min(it.hi, p0 + per);
    T acc[NV];
#pragma unroll
    for (int k = 0; k < NV; ++k) acc[k] = 0;
#pragma unroll 8
    for (int p = p0; p < p1; ++p) {
        const pl_spinv_cuda_tilerow m = rowlist[p];
        T z[4];
        for (int c = 0; c < 4; c += VC) ld16(y4 + 4 * (size_t)m.row + c, z + c);
        if (col0 >= m.f0 && col0 <= (m.row | (PL_SPINV_CUDA_BLOCK - 1))) {
            T v[VC];
            ld16(val + m.vbase + col0, v);
#pragma unroll
            for (int k = 0; k < VC; ++k) {
                acc[3 * k] += v[k] * z[0];
                acc[3 * k + 1] += v[k] * z[1];
                acc[3 * k + 2] += v[k] * z[2];
            }
        }
    }
#pragma unroll
    for (int k = 0; k < NV; ++k) red[wib][lane][k] = acc[k];
    __syncthreads();
    if (wib != 0) return;
#pragma unroll
    for (int k = 0; k < NV; ++k) acc[k] = red[0][lane][k];
    for (int w = 1; w < NW; ++w)
#pragma unroll
        for (int k = 0; k < NV; ++k) acc[k] += red[w][lane][k];
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
#pragma unroll
        for (int k = 0; k < NV; ++k) acc[k] = 0;
        for (int q = 0; q < it.nparts; ++q) {
            const T *src = part + ((size_t)(it.part0 + q) * 32 + lane) * NV;
            T p[NV];
            for (int c = 0; c < NV; c += VC) ld16_cg(src + c, p + c);
#pragma unroll
            for (int k = 0; k < NV; ++k) acc[k] += p[k];
        }
        if (lane == 0) cnt[it.idx] = 0;
    }
#pragma unroll
    for (int k = 0; k < VC; ++k) {
        const int j = col0 + k;
        if (j < n) {
            const size_t r = 3 * (size_t)(perm ? perm[j] : j);
            out[r] = (To)acc[3 * k];
            out[r + 1] = (To)acc[3 * k + 1];
            out[r + 2] = (To)acc[3 * k + 2];
        }
    }
}

/* a[i] = b[perm[i]] (perm NULL: b[i]) for i < n, zero for n <= i < npad. */
template <typename Ti, typename T>
__global__ void k_permute_in(int n, int npad, const int *__restrict__ perm,
                             const Ti *__restrict__ b, T *__restrict__ a)
{
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
        k_permute_in<Ti, T><<<blocks_for(g->npad), kThreads, 0, st>>>(
            g->n, g->npad, perm, static_cast<const Ti *>(b), static_cast<T *>(g->a));
}

template <typename T, typename To>
void mult_ST(pl_spinv_cuda *g, void *x, const int *perm, cudaStream_t st)
{
    if (g->nitems_ST > 0)
        k_mult_ST<T, To><<<(unsigned)g->nitems_ST, kThreads, 0, st>>>(
            g->items_ST, g->rowlist, static_cast<const T *>(g->val),
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
    k_mult_S<T, G><<<blocks_for(32LL * g->nitems_S), kThreads, 0, st>>>(
        g->items_S, g->nitems_S, g->meta, g->short_rows, static_cast<const T *>(g->val),
        static_cast<const T *>(g->a), static_cast<T *>(g->y4), static_cast<T *>(g->part_S), g->cnt_S);
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
        k_to4<float><<<blocks_for(g->n), kThreads, 0, st>>>(g->n, static_cast<const float *>(x),
                                                           static_cast<float *>(g->y4));
    else
        k_to4<double><<<blocks_for(g->n), kThreads, 0, st>>>(g->n, static_cast<const double *>(x),
                                                            static_cast<double *>(g->y4));
    return launched(err, "copy kernel");
}

int spinv_cuda_launch_from4(pl_spinv_cuda *g, void *y, cudaStream_t st, pl_error *err)
{
    if (g->prec == PL_F32)
        k_from4<float><<<blocks_for(g->n), kThreads, 0, st>>>(
            g->n, static_cast<const float *>(g->y4), static_cast<float *>(y));
    else
        k_from4<double><<<blocks_for(g->n), kThreads, 0, st>>>(
            g->n, static_cast<const double *>(g->y4), static_cast<double *>(y));
    return launched(err, "copy kernel");
}

