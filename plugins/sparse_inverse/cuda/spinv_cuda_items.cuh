/* spinv_cuda_items.cuh - one work item of y = S a (a warp: ROWS, SHORT)
 * and of z = S^T y (a group of 8 warps: TILE) as device functions, shared
 * by the multi-kernel solve (spinv_cuda_kernels.cu: one launch per
 * product) and the single-block solve of small systems (spinv_cuda_small.cu:
 * a and y4 in shared memory).  Both call these same bodies, so a row's and a
 * tile's sums are formed in the same order whichever path runs.  SH: a and
 * y4 are shared memory written by this launch (plain loads; __ldg is for
 * data that no thread of the launch writes).  Internal to the CUDA backend. */
#ifndef PLIANT_SPINV_CUDA_ITEMS_CUH
#define PLIANT_SPINV_CUDA_ITEMS_CUH

#include "spinv_cuda_internal.h"

namespace spinv_items {

constexpr int kThreads = 256; /* 8 warps a block (a TILE item's group) */
constexpr int kWarps = kThreads / 32;

/* 16 bytes of T as one vector (float4: 4 values, double2: 2), split into
 * and packed from an array. */
template <typename T> struct vec16;
template <> struct vec16<float> {
    typedef float4 type;
    static __device__ __forceinline__ void split(float4 q, float v[4])
    {
        v[0] = q.x, v[1] = q.y, v[2] = q.z, v[3] = q.w;
    }
    static __device__ __forceinline__ float4 pack(const float v[4])
    {
        return make_float4(v[0], v[1], v[2], v[3]);
    }
};
template <> struct vec16<double> {
    typedef double2 type;
    static __device__ __forceinline__ void split(double2 q, double v[2]) { v[0] = q.x, v[1] = q.y; }
    static __device__ __forceinline__ double2 pack(const double v[2])
    {
        return make_double2(v[0], v[1]);
    }
};

/* How a 16-byte load goes: through the read-only path (__ldg: data no
 * thread of the launch writes), plain (shared memory, or data written by
 * this launch), or through L2 only (__ldcg: partial sums written by other
 * warps of this launch; L1 is not coherent). */
enum Load { kReadOnly, kPlain, kL2 };

/* One 16-byte vector load of 16 / sizeof(T) values, as L says. */
template <Load L, typename T>
__device__ __forceinline__ void ld16(const T *p, T *v)
{
    typedef typename vec16<T>::type V;
    const V *q = reinterpret_cast<const V *>(p);
    if constexpr (L == kReadOnly)
        vec16<T>::split(__ldg(q), v);
    else if constexpr (L == kL2)
        vec16<T>::split(__ldcg(q), v);
    else
        vec16<T>::split(*q, v);
}
/* a and y4: read-only path in the multi-kernel solve, plain when shared. */
template <bool SH, typename T>
__device__ __forceinline__ void ld16v(const T *p, T *v)
{
    ld16<SH ? kPlain : kReadOnly>(p, v);
}
template <typename T>
__device__ __forceinline__ void st16(T *p, const T *v)
{
    *reinterpret_cast<typename vec16<T>::type *>(p) = vec16<T>::pack(v);
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
template <bool SH, typename T>
__device__ __forceinline__ void dot_group(const T *v, const T *x, T &s0, T &s1, T &s2)
{
    constexpr int VC = 16 / sizeof(T);
    T w[VC], p[3 * VC];
    ld16<kReadOnly>(v, w);
    for (int q = 0; q < 3; ++q) ld16v<SH>(x + q * VC, p + q * VC);
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

/* One ROWS or SHORT item of y = S a, by one whole warp.  A ROWS item's rows
 * share f0; lane l takes the 16-byte groups l, l+32, ... of their union,
 * reads the matching piece of a once and every row's values where the row
 * has them (the rows end at different e).  A split group publishes its part
 * in part; the last warp to arrive sums all parts in slot order
 * (deterministic whichever warp that is). */
template <bool SH, typename T, int G>
__device__ __forceinline__ void rows_item(const pl_spinv_cuda_item &it, int lane,
                                          const pl_spinv_cuda_rowmeta *__restrict__ meta,
                                          const int *__restrict__ short_rows,
                                          const T *__restrict__ val, const T *a, T *y4, T *part,
                                          int *cnt)
{
    constexpr int VC = 16 / sizeof(T), GPB = PL_SPINV_CUDA_BLOCK / VC;
    if (it.kind == PL_SPINV_ITEM_SHORT) {
        if (lane >= it.lo) return;
        T s0 = 0, s1 = 0, s2 = 0;
        const int row = short_rows[it.idx + lane];
        const pl_spinv_cuda_rowmeta m = meta[row];
        const T *v = val + m.vbase + m.f0, *x = a + 3 * (size_t)m.f0;
        const int ng = (m.e - m.f0 + 1) / VC;
        for (int g = 0; g < ng; ++g) dot_group<SH>(v + g * VC, x + 3 * g * VC, s0, s1, s2);
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
        for (int q = 0; q < 3; ++q) ld16v<SH>(a + 3 * (size_t)col0 + q * VC, p + q * VC);
#pragma unroll
        for (int r = 0; r < G; ++r) {
            if (col0 <= e[r]) {
                T v[VC];
                ld16<kReadOnly>(val + vb[r] + col0, v);
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
                    ld16<kL2>(part + 4 * ((size_t)(it.part0 + q) * G + r) + c, p + c);
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

/* The first half of a TILE item of z = S^T y, by a group of 8 warps (wib:
 * the warp in the group): lane l of every warp owns columns col0 .. col0+VC-1
 * of the tile; the warps take consecutive stretches of the item's rows and
 * accumulate S(i, j) y_i into red[wib][lane] (the caller then syncs the
 * group and calls tile_sum). */
template <bool SH, typename T>
__device__ __forceinline__ void tile_rows(const pl_spinv_cuda_item &it, int wib, int lane,
                                          const pl_spinv_cuda_tilerow *__restrict__ rowlist,
                                          const T *__restrict__ val, const T *y4,
                                          T (*red)[32][3 * 16 / sizeof(T)])
{
    constexpr int VC = 16 / sizeof(T), NV = 3 * VC;
    const int col0 = it.idx * 32 * VC + lane * VC;
    const int per = (it.hi - it.lo + kWarps - 1) / kWarps;
    const int p0 = it.lo + wib * per, p1 = min(it.hi, p0 + per);
    T acc[NV];
#pragma unroll
    for (int k = 0; k < NV; ++k) acc[k] = 0;
#pragma unroll 8
    for (int p = p0; p < p1; ++p) {
        const pl_spinv_cuda_tilerow m = rowlist[p];
        T z[4];
        for (int c = 0; c < 4; c += VC) ld16v<SH>(y4 + 4 * (size_t)m.row + c, z + c);
        if (col0 >= m.f0 && col0 <= (m.row | (PL_SPINV_CUDA_BLOCK - 1))) {
            T v[VC];
            ld16<kReadOnly>(val + m.vbase + col0, v);
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
}

/* The group's 8 sums of lane's columns, in warp order. */
template <typename T>
__device__ __forceinline__ void tile_sum(int lane, T (*red)[32][3 * 16 / sizeof(T)],
                                         T acc[3 * 16 / sizeof(T)])
{
    constexpr int NV = 3 * 16 / sizeof(T);
#pragma unroll
    for (int k = 0; k < NV; ++k) acc[k] = red[0][lane][k];
    for (int w = 1; w < kWarps; ++w)
#pragma unroll
        for (int k = 0; k < NV; ++k) acc[k] += red[w][lane][k];
}

/* The parts of a split tile (written by its items' groups), summed in slot
 * order; plain or L2 loads (cg: written by other blocks of this launch). */
template <bool CG, typename T>
__device__ __forceinline__ void tile_parts(const pl_spinv_cuda_item &it, int lane, const T *part,
                                           T acc[3 * 16 / sizeof(T)])
{
    constexpr int VC = 16 / sizeof(T), NV = 3 * VC;
#pragma unroll
    for (int k = 0; k < NV; ++k) acc[k] = 0;
    for (int q = 0; q < it.nparts; ++q) {
        const T *src = part + ((size_t)(it.part0 + q) * 32 + lane) * NV;
        T p[NV];
        for (int c = 0; c < NV; c += VC) ld16<CG ? kL2 : kPlain>(src + c, p + c);
#pragma unroll
        for (int k = 0; k < NV; ++k) acc[k] += p[k];
    }
}

/* Lane's columns of a tile to out[perm[j]] (perm NULL: out[j]) in To. */
template <typename T, typename To>
__device__ __forceinline__ void tile_store(const pl_spinv_cuda_item &it, int lane, int n,
                                           const int *__restrict__ perm, To *out,
                                           const T acc[3 * 16 / sizeof(T)])
{
    constexpr int VC = 16 / sizeof(T);
    const int col0 = it.idx * 32 * VC + lane * VC;
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

} // namespace spinv_items

#endif
