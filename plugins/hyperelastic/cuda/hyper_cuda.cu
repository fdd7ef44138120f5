/* hyper_cuda.cu - the FEM local step on the GPU (see hyper_cuda.h), for
 * tetrahedra and membrane triangles: one thread per element, then one
 * thread per vertex for the gather. */
#include "hyper_cuda.h"

#include <cuda_runtime.h>
#include "pliant/cuda_launch.h"
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "local_solve.h" /* the local solve the CPU runs too (compiled as CUDA) */

struct pl_hyper_cuda {
    int n, nverts, material;
    double wscale;          /* the ADMM-PD penalty's scale (elements' weight_scale) */
    int k;                  /* corners: 4 (tetrahedra) or 3 (triangles) */
    int *verts;             /* n x k local vertices */
    /* Per-element arrays of several values are stored value-major ("SoA":
     * value k of element i at [k n + i]), so that a warp's loads and stores
     * of one value are contiguous: element-major, each was 32 transactions
     * (the cable finger's k_project, docs/benchmarks.md "The local step's
     * Newton in fewer divisions"). */
    double *D;              /* (k d) x n: k x d shape matrices, SoA */
    double *mu, *lambda, *w;/* n */
    int *vptr, *vinc;       /* nverts + 1, 4n */
    double *slots;          /* n x 3k: corner 3-vectors (GATHER) */
    double *prev;           /* 3d x n, SoA: each element's last p (over-relaxation; ADMM only) */
    /* What a step starts at zero, one allocation (one memset a step, one
     * read-back): acc, stats, then warm. */
    void *block;
    size_t block_bytes;
    unsigned long long *acc;/* since begin_step: solves, Newton, halvings, capped, histogram */
    int *stats;             /* max iterations, missed, INT_MAX - the first non-finite element
                               (0: none; so that zero is the fresh value) */
    double *warm;           /* HM_WARM_LEN(d) x n, SoA: each element's last prox solution, s
                               and V (zeros: cold) */
};

namespace {

constexpr int kThreads = 128;
constexpr int kAcc = 4 + HYPER_PROX_HIST;

int cuda_fail(pl_error *err, cudaError_t e, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "hyperelastic (cuda): %s: %s", what,
                        cudaGetErrorString(e));
}

#define HC_CK(call, what)                                      \
    do {                                                       \
        cudaError_t hc_e_ = (call);                            \
        if (hc_e_ != cudaSuccess) return cuda_fail(err, hc_e_, what); \
    } while (0)

/* acc (kAcc counts), then the stats (3 ints, 16 bytes kept): what the
 * end of a step reads back */
constexpr size_t kCountBytes = kAcc * sizeof(unsigned long long) + 16;

/* Element i's K local vertices (K = 4: one 16-byte load). */
template <int K> __device__ __forceinline__ void load_verts(const int *verts, int i, int *v);
template <> __device__ __forceinline__ void load_verts<4>(const int *verts, int i, int *v)
{
    const int4 v4 = reinterpret_cast<const int4 *>(verts)[i];
    v[0] = v4.x, v[1] = v4.y, v[2] = v4.z, v[3] = v4.w;
}
template <> __device__ __forceinline__ void load_verts<3>(const int *verts, int i, int *v)
{
    v[0] = verts[3 * (size_t)i], v[1] = verts[3 * (size_t)i + 1], v[2] = verts[3 * (size_t)i + 2];
}

/* One element (K corners, F 3 x Dd): F, the local solve, the dual update
 * and the corner contributions h2 w (p - u) D^T, to its slots or
 * atomically to rhs.  K = 4, Dd = 3: tetrahedra; K = 3, Dd = 2: membranes. */
template <int K, int Dd>
__global__ void __launch_bounds__(kThreads)
    k_project(int n, int material, const int *__restrict__ verts, const double *__restrict__ D,
              const double *__restrict__ mu, const double *__restrict__ lambda,
              const double *__restrict__ w, double wscale, double alpha,
              double *__restrict__ prev, int offset, double h2, const double *__restrict__ q,
              double *__restrict__ dual, double *__restrict__ warm, double *__restrict__ slots,
              double *__restrict__ rhs, int atomic, int *__restrict__ stats,
              unsigned long long *__restrict__ acc)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    constexpr int ND = 3 * Dd, KD = K * Dd;
    const int i = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    int iters = 0, missed = 0, bad = INT_MAX, newton = 0, halvings = 0, bin = -1;
    if (i < n) {
        int v[K];
        load_verts<K>(verts, i, v);
        double Dl[KD], F[ND], z[ND], p[ND];
#pragma unroll
        for (int k = 0; k < KD; ++k) Dl[k] = D[(size_t)k * n + i];
        /* the element's constants and warm start (s, V) in registers: their
         * loads wait with the others, not after the solve */
        const double m = mu[i], la = lambda[i], wi = w[i];
        constexpr int WL = HM_WARM_LEN(Dd);
        double *wg = warm + i, wl[WL]; /* value k at wg[k n] */
#pragma unroll
        for (int k = 0; k < WL; ++k) wl[k] = wg[(size_t)k * n];
#pragma unroll
        for (int k = 0; k < ND; ++k) F[k] = 0.0;
#pragma unroll
        for (int c = 0; c < K; ++c) {
            const double *x = q + 3 * ((size_t)offset + v[c]);
            const double x0 = x[0], x1 = x[1], x2 = x[2];
#pragma unroll
            for (int b = 0; b < Dd; ++b) {
                F[b] += x0 * Dl[c * Dd + b];
                F[Dd + b] += x1 * Dl[c * Dd + b];
                F[2 * Dd + b] += x2 * Dl[c * Dd + b];
            }
        }
        const double what = wscale * (material == 0 ? 2.0 * m : 2.0 * m + la);
        double *u = material != 0 ? dual + ND * (size_t)i : NULL;
        /* over-relaxed ADMM (the host's hyper_elements_project_relaxed) */
        double *pv = u && prev ? prev + i : NULL; /* value k at pv[k n] */
        if (pv && alpha != 1.0) {
#pragma unroll
            for (int k = 0; k < ND; ++k) F[k] = alpha * F[k] + (1.0 - alpha) * pv[(size_t)k * n];
        }
        double ul[ND];
#pragma unroll
        for (int k = 0; k < ND; ++k) {
            ul[k] = u ? u[k] : 0.0;
            z[k] = u ? F[k] + ul[k] : F[k];
        }
        const int it = hm_local_solve(Dd, material, m, la, what, z, p, wl, &halvings);
#pragma unroll
        for (int k = 0; k < WL; ++k) wg[(size_t)k * n] = wl[k];
        bool finite = true;
#pragma unroll
        for (int k = 0; k < ND; ++k) finite &= isfinite(p[k]) != 0;
        if (!finite) {
            bad = i;
#pragma unroll
            for (int k = 0; k < ND; ++k) p[k] = 0.0;
        } else if (it < 0) {
            missed = 1;
        } else {
            iters = it;
            newton = it;
            bin = it < HYPER_PROX_HIST - 1 ? it : HYPER_PROX_HIST - 1;
        }
        if (u && finite) {
#pragma unroll
            for (int k = 0; k < ND; ++k) {
                if (pv) pv[(size_t)k * n] = p[k];
                ul[k] += F[k] - p[k];
                p[k] -= ul[k];
                u[k] = ul[k];
            }
        }
        const double scale = h2 * wi;
#pragma unroll
        for (int c = 0; c < K; ++c)
#pragma unroll
            for (int a = 0; a < 3; ++a) {
                double s = 0.0;
#pragma unroll
                for (int b = 0; b < Dd; ++b) s += p[a * Dd + b] * Dl[c * Dd + b];
                if (atomic)
                    atomicAdd(rhs + 3 * ((size_t)offset + v[c]) + a, scale * s);
                else
                    slots[3 * K * (size_t)i + 3 * c + a] = scale * s;
            }
    }
    /* statistics: one atomic per warp (every lane of the grid gets here) */
    iters = __reduce_max_sync(0xffffffffu, iters);
    missed = __reduce_add_sync(0xffffffffu, missed);
    bad = __reduce_min_sync(0xffffffffu, bad);
    const unsigned solves = __reduce_add_sync(0xffffffffu, i < n ? 1u : 0u);
    const unsigned nsum = __reduce_add_sync(0xffffffffu, (unsigned)newton);
    const unsigned hsum = __reduce_add_sync(0xffffffffu, (unsigned)halvings);
    if ((threadIdx.x & 31) == 0) {
        if (iters > 0) atomicMax(stats, iters);
        if (missed > 0) atomicAdd(stats + 1, missed);
        if (bad != INT_MAX) atomicMax(stats + 2, INT_MAX - bad); /* the lowest bad */
        if (solves) atomicAdd(acc, (unsigned long long)solves);
        if (nsum) atomicAdd(acc + 1, (unsigned long long)nsum);
        if (hsum) atomicAdd(acc + 2, (unsigned long long)hsum);
        if (missed) atomicAdd(acc + 3, (unsigned long long)missed);
    }
    /* the histogram: one atomic per distinct bin of the warp */
    const unsigned same = __match_any_sync(0xffffffffu, bin);
    if (bin >= 0 && (threadIdx.x & 31) == (unsigned)(__ffs(same) - 1))
        atomicAdd(acc + 4 + bin, (unsigned long long)__popc(same));
}

/* rhs[offset + v] += the sum of v's slots, in increasing slot order (as
 * hyper_incidence_gather on the CPU), one warp a vertex: the lanes load up
 * to 32 slots at once into shared memory (a slot index, then the slot: two
 * memory latencies for the lot) and lane 0 adds them in order.  One thread
 * a vertex walking its slots waited for those two latencies every few
 * slots, and a tiny scene's gather is nothing but such latencies
 * (docs/benchmarks.md, "The iteration in fewer, shorter kernels"). */
constexpr int kGatherWarps = 4; /* vertices a block */

__global__ void __launch_bounds__(32 * kGatherWarps)
    k_gather(int nverts, const int *__restrict__ vptr, const int *__restrict__ vinc,
             const double *__restrict__ slots, int offset, double *__restrict__ rhs)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    __shared__ double buf[kGatherWarps][32][3];
    const int warp = threadIdx.x >> 5, lane = threadIdx.x & 31;
    const int v = (int)(blockIdx.x * (size_t)kGatherWarps + warp);
    if (v >= nverts) return; /* the whole warp */
    double(*b)[3] = buf[warp];
    double a0 = 0.0, a1 = 0.0, a2 = 0.0;
    for (int k = vptr[v], end = vptr[v + 1]; k < end; k += 32) {
        const int n = end - k < 32 ? end - k : 32;
        if (lane < n) {
            const double *x = slots + 3 * (size_t)vinc[k + lane];
            b[lane][0] = x[0], b[lane][1] = x[1], b[lane][2] = x[2];
        }
        __syncwarp();
        if (lane == 0)
            for (int t = 0; t < n; ++t) {
                a0 += b[t][0];
                a1 += b[t][1];
                a2 += b[t][2];
            }
        __syncwarp(); /* b is the next round's */
    }
    if (lane == 0) {
        double *o = rhs + 3 * ((size_t)offset + v);
        o[0] += a0;
        o[1] += a1;
        o[2] += a2;
    }
}

unsigned gather_blocks(int nverts)
{
    return (unsigned)((nverts + kGatherWarps - 1) / kGatherWarps);
}

template <typename T>
int upload(pl_hyper_cuda *g, T **dst, const T *src, size_t count, pl_error *err)
{
    size_t bytes = (count > 0 ? count : 1) * sizeof(T);
    HC_CK(cudaMalloc((void **)dst, bytes), "cudaMalloc");
    if (src && count) HC_CK(cudaMemcpy(*dst, src, count * sizeof(T), cudaMemcpyHostToDevice), "upload");
    return PL_OK;
}

} // namespace

extern "C" pl_hyper_cuda *hyper_cuda_create(const pl_hyper_elements *e, pl_error *err)
{
    if (!e || !((e->k == 4 && e->d == 3) || (e->k == 3 && e->d == 2))) {
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                     "hyperelastic (cuda): the device local step takes tetrahedra or triangles");
        return NULL;
    }
    pl_hyper_cuda *g = static_cast<pl_hyper_cuda *>(calloc(1, sizeof *g));
    if (!g) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "hyperelastic (cuda): out of memory");
        return NULL;
    }
    g->n = e->n, g->nverts = e->nverts, g->material = (int)e->material, g->k = e->k;
    g->wscale = e->weight_scale;
    size_t n = (size_t)e->n, k = (size_t)e->k;
    const size_t kd = k * (size_t)e->d;
    double *Dt = static_cast<double *>(malloc((kd * n > 0 ? kd * n : 1) * sizeof(double)));
    if (!Dt) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "hyperelastic (cuda): out of memory");
        hyper_cuda_destroy(g);
        return NULL;
    }
    for (size_t i = 0; i < n; ++i) /* element-major to value-major */
        for (size_t c = 0; c < kd; ++c) Dt[c * n + i] = e->D[kd * i + c];
    const int bad_D = upload(g, &g->D, Dt, kd * n, err);
    free(Dt);
    if (bad_D || upload(g, &g->verts, e->verts, k * n, err) || upload(g, &g->mu, e->mu, n, err) ||
        upload(g, &g->lambda, e->lambda, n, err) || upload(g, &g->w, e->w, n, err) ||
        upload(g, &g->vptr, e->vptr, (size_t)e->nverts + 1, err) ||
        upload(g, &g->vinc, e->vinc, k * n, err) ||
        upload(g, &g->slots, static_cast<const double *>(NULL), 3 * k * n, err) ||
        (e->material != PL_HYPER_ARAP &&
         upload(g, &g->prev, static_cast<const double *>(NULL), 3 * (size_t)e->d * n, err))) {
        hyper_cuda_destroy(g);
        return NULL;
    }
    g->block_bytes = kCountBytes + (n > 0 ? n : 1) * HM_WARM_LEN((size_t)e->d) * sizeof(double);
    cudaError_t ce = cudaMalloc(&g->block, g->block_bytes);
    if (ce == cudaSuccess) {
        unsigned char *b = static_cast<unsigned char *>(g->block);
        g->acc = reinterpret_cast<unsigned long long *>(b);
        g->stats = reinterpret_cast<int *>(b + kAcc * sizeof(unsigned long long));
        g->warm = reinterpret_cast<double *>(b + kCountBytes);
        ce = cudaMemset(g->block, 0, g->block_bytes);
    }
    if (ce != cudaSuccess) {
        cuda_fail(err, ce, "upload");
        hyper_cuda_destroy(g);
        return NULL;
    }
    return g;
}

extern "C" void hyper_cuda_destroy(pl_hyper_cuda *g)
{
    if (!g) return;
    void *ptrs[] = {g->verts, g->D,     g->mu,    g->lambda, g->w,
                    g->vptr,  g->vinc,  g->slots, g->block,  g->prev};
    for (void *p : ptrs)
        if (p) cudaFree(p);
    free(g);
}

extern "C" int hyper_cuda_project(pl_hyper_cuda *g, int offset, double h2, const double *q,
                                     double *dual, double *rhs, pl_hyper_cuda_assembly mode,
                                     struct CUstream_st *stream, pl_error *err)
{
    return hyper_cuda_project_relaxed(g, offset, h2, q, dual, 0, 1.0, rhs, mode, stream, err);
}

extern "C" int hyper_cuda_project_relaxed(pl_hyper_cuda *g, int offset, double h2,
                                          const double *q, double *dual, int relax, double alpha,
                                          double *rhs, pl_hyper_cuda_assembly mode,
                                          struct CUstream_st *stream, pl_error *err)
{
    if (!g || !q || !rhs || offset < 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "hyperelastic (cuda): bad arguments");
    if (g->material != PL_HYPER_ARAP && !dual)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "hyperelastic (cuda): the ADMM-PD local step needs its dual variables");
    cudaStream_t st = stream;
    /* stats are reset once a step (hyper_cuda_begin_step), not here: one
     * launch less in every iteration */
    if (g->n > 0) {
        unsigned nb = (unsigned)((g->n + kThreads - 1) / kThreads);
        int atomic = mode == PL_HYPER_CUDA_ATOMIC;
        if (g->k == 4)
            pl_cuda_launch(k_project<4, 3>, nb, kThreads, 0, st, g->n, g->material, g->verts, g->D,
                           g->mu, g->lambda, g->w, g->wscale, alpha, relax ? g->prev : NULL,
                           offset, h2, q,
                           dual, g->warm,
                           g->slots, rhs, atomic, g->stats, g->acc);
        else
            pl_cuda_launch(k_project<3, 2>, nb, kThreads, 0, st, g->n, g->material, g->verts, g->D,
                           g->mu, g->lambda, g->w, g->wscale, alpha, relax ? g->prev : NULL,
                           offset, h2, q,
                           dual, g->warm,
                           g->slots, rhs, atomic, g->stats, g->acc);
        if (!atomic && g->nverts > 0)
            pl_cuda_launch(k_gather, gather_blocks(g->nverts), 32 * kGatherWarps, 0, st, g->nverts,
                           g->vptr, g->vinc, g->slots, offset, rhs);
    }
    HC_CK(cudaGetLastError(), "local step kernels");
    return PL_OK;
}

extern "C" int hyper_cuda_step_stats(pl_hyper_cuda *g, struct CUstream_st *stream, int stats[2],
                                     hyper_prox_stats *out, pl_error *err)
{
    unsigned long long h[kCountBytes / sizeof(unsigned long long)];
    HC_CK(cudaMemcpyAsync(h, g->acc, kCountBytes, cudaMemcpyDeviceToHost, stream), "counts");
    HC_CK(cudaStreamSynchronize(stream), "local step");
    int s[3];
    memcpy(s, h + kAcc, sizeof s);
    stats[0] = s[0], stats[1] = s[1];
    if (s[2] != 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "element %d: non-finite deformation gradient in the local step",
                            INT_MAX - s[2]);
    if (out) {
        out->solves += (long long)h[0];
        out->newton += (long long)h[1];
        out->halvings += (long long)h[2];
        out->capped += (long long)h[3];
        for (int b = 0; b < HYPER_PROX_HIST; ++b) out->hist[b] += (long long)h[4 + b];
    }
    return PL_OK;
}

extern "C" int hyper_cuda_gather(int nverts, const int *vptr, const int *vinc, const double *slots,
                                 int offset, double *out, struct CUstream_st *stream, pl_error *err)
{
    if (nverts > 0)
        pl_cuda_launch(k_gather, gather_blocks(nverts), 32 * kGatherWarps, 0, (cudaStream_t)stream,
                       nverts, vptr, vinc, slots, offset, out);
    HC_CK(cudaGetLastError(), "gather");
    return PL_OK;
}

extern "C" int hyper_cuda_begin_step(pl_hyper_cuda *g, struct CUstream_st *stream, pl_error *err)
{
    /* counts, stats and warm starts: one memset */
    HC_CK(cudaMemsetAsync(g->block, 0, g->block_bytes, stream), "step reset");
    return PL_OK;
}
