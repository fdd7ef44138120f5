/* ncp_cuda_fused.cu - the whole constraint update of Algorithm 4 in one
 * single-block kernel when W is explicit and rows are few (see ncp_cuda.h):
 * the phases of ncp_cuda_phases.cuh in turn, CR's loop with its scalars in
 * registers, the work vectors and (when it fits) W in shared memory, the
 * products in ncp_cuda_dense.cuh's order (k_dense's: the phased path's sums,
 * bitwise), reductions with one barrier each. */
#include "ncp_cuda_phases.cuh"
#include "ncp_cuda_dense.cuh"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

namespace {

/* W's place for the products: global (m x m), or shared (m x ld, ld >= m);
 * summed in ncp_cuda_dense.cuh's order either way. */
struct wplan {
    const double *W;
    int ld;
};

/* y = W x by the block: row i by the K threads i K ... i K + K - 1 (K =
 * ncp_dense_width(m)), kThreads / K rows at a time.  For W in shared
 * memory, ld = K (mod 16) puts the 16 doubles a half warp reads in
 * distinct banks. */
__device__ void product(int m, const wplan &w, const double *x, double *y)
{
    const int K = ncp_dense_width(m), c = threadIdx.x & (K - 1);
    for (int i0 = 0; i0 < m; i0 += kThreads / K) { /* uniform bound: shuffles inside */
        const int i = i0 + threadIdx.x / K, ok = i < m;
        const double s = ncp_dense_row(w.W + (ok ? (size_t)i * (size_t)w.ld : 0), x, ok ? m : 0,
                                       c, K);
        if (ok && c == 0) y[i] = s;
    }
}

/* CR's loop after phase D (phases E and F of ncp_cuda.h with the product
 * between them): the same arithmetic as cr_e and cr_f, with the scalars in
 * registers (the same in every thread) and each thread on its own rows.
 * The product after an update of r runs before the stop test, so that
 * |r|^2 and r.Ar are summed together (block_reduce2): two reductions and
 * two more barriers an iteration.  When CR stops there, that product only
 * wrote tmp, tmp2 and cr_Ar, which nothing reads before it writes them
 * again (phase A, the next products). */
__device__ void cr_loop(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                        const pl_ncp_cuda_params &P, const wplan &w, red &rd)
{
    pl_ncp_cuda_scalars *sc = V.sc;
    const int m = R.m;
    const double h2 = P.h * P.h, bnorm = sc->bnorm;
    int done = sc->done, its = sc->its, error = 0;
    double rAr = sc->rAr, rnorm = sc->rnorm;
    for (int t = 1; t < P.cr_max_iter && !done; ++t) {
        const int last = t == P.cr_max_iter - 1;
        const double ApAp = dot(m, V.cr_Ap, V.cr_Ap, rd);
        if (!(ApAp > 0.0) || rAr == 0.0) {
            done = 1;
            break;
        }
        const double alpha = rAr / ApAp;
        double ss = 0.0, s = 0.0;
        for (int j = threadIdx.x; j < m; j += kThreads) {
            V.dlambda[j] += alpha * V.cr_p[j];
            const double r = V.cr_r[j] - alpha * V.cr_Ap[j];
            V.cr_r[j] = r;
            ss += r * r;
            if (!last) V.tmp[j] = V.op_omega[j] * r;
        }
        if (last) {
            ss = block_reduce(ss, 0, rd);
        } else {
            __syncthreads();
            product(m, w, V.tmp, V.tmp2);
            __syncthreads();
            for (int j = threadIdx.x; j < m; j += kThreads) {
                const double ar = h2 * V.op_omega[j] * V.tmp2[j] + V.op_e[j] * V.cr_r[j];
                V.cr_Ar[j] = ar;
                s += V.cr_r[j] * ar;
            }
            block_reduce2(ss, s, rd);
        }
        rnorm = sqrt(ss);
        if (!isfinite(rnorm)) error = 2;
        if (!isfinite(rnorm) || rnorm <= P.cr_rtol * bnorm) {
            done = 1;
            break;
        }
        its += 1; /* the product that follows (counted on the last one too, as cr_e) */
        if (last) break;
        const double beta = s / rAr;
        for (int j = threadIdx.x; j < m; j += kThreads) {
            V.cr_p[j] = V.cr_r[j] + beta * V.cr_p[j];
            V.cr_Ap[j] = V.cr_Ar[j] + beta * V.cr_Ap[j];
        }
        rAr = s;
    }
    __syncthreads(); /* every thread has read sc above */
    if (threadIdx.x == 0) {
        sc->done = done, sc->its = its, sc->rAr = rAr, sc->rnorm = rnorm;
        if (error) sc->error = error;
    }
}

/* The work vectors of m rows that the fused update keeps in shared memory. */
#define NCP_STAGED(X)                                                                              \
    X(lambda) X(dlambda) X(delta) X(delta_free) X(omega) X(e) X(phi) X(rhs) X(tmp) X(tmp2)         \
    X(scale) X(clamped) X(op_omega) X(op_e) X(force) X(ls0) X(ls1) X(cr_r) X(cr_p) X(cr_Ar)        \
    X(cr_Ap) X(cr_s)
#define NCP_ONE(f) +1
constexpr int kStaged = 0 NCP_STAGED(NCP_ONE);
#undef NCP_ONE

/* Points V's m-row vectors (and sc) at shared memory `dyn` (smem bytes)
 * and copies them in, W too when it fits after them; returns W's plan.
 * Without room the vectors stay global (the update is the same).  Loads
 * are batched (several in flight a thread) before their stores. */
__device__ wplan stage_in(int m, pl_ncp_cuda_vecs &V, pl_ncp_cuda_scalars *scs, double *dyn,
                          int smem, const double *__restrict__ W)
{
    const int K = ncp_dense_width(m), t = threadIdx.x;
    const int ld = K >= 16 ? m : m + (((K - m) % 16) + 16) % 16;
    const size_t vec = sizeof(double) * (size_t)m * kStaged + sizeof(int) * (size_t)(m + 1);
    const size_t wbytes = sizeof(double) * (size_t)m * (size_t)ld;
    wplan w = {W, m};
    if (vec > (size_t)smem) return w;
    double *p = dyn;
    if (vec + wbytes <= (size_t)smem) { /* W first: the vectors after it */
        constexpr int kBatch = 8;
        const int mm = m * m;
        for (int k0 = 0; k0 < mm; k0 += kBatch * kThreads) {
            double v[kBatch];
#pragma unroll
            for (int u = 0; u < kBatch; ++u) {
                const int k = k0 + u * kThreads + t;
                v[u] = k < mm ? W[k] : 0.0;
            }
#pragma unroll
            for (int u = 0; u < kBatch; ++u) {
                const int k = k0 + u * kThreads + t, i = k / m;
                if (k < mm) p[(size_t)i * (size_t)ld + (k - i * m)] = v[u];
            }
        }
        w.W = p, w.ld = ld;
        p += (size_t)m * (size_t)ld;
    }
    for (int j = t; j < m; j += kThreads) {
        double v[kStaged];
        int k = 0;
#define NCP_LOAD(f) v[k++] = V.f[j];
        NCP_STAGED(NCP_LOAD)
#undef NCP_LOAD
        const int ic = V.is_clamped[j];
#pragma unroll
        for (int u = 0; u < kStaged; ++u) p[(size_t)u * (size_t)m + j] = v[u];
        ((int *)(p + (size_t)kStaged * (size_t)m))[j] = ic;
    }
    int k = 0;
#define NCP_POINT(f) V.f = p + (size_t)(k++) * (size_t)m;
    NCP_STAGED(NCP_POINT)
#undef NCP_POINT
    V.is_clamped = (int *)(p + (size_t)kStaged * (size_t)m);
    if (t == 0) *scs = *V.sc;
    V.sc = scs;
    return w;
}

/* Copies the staged vectors and scalars back to G's (global) arrays. */
__device__ void stage_out(int m, const pl_ncp_cuda_vecs &V, const pl_ncp_cuda_vecs &G)
{
    if (V.sc == G.sc) return; /* nothing was staged */
    const int t = threadIdx.x;
#define NCP_OUT(f) \
    for (int j = t; j < m; j += kThreads) G.f[j] = V.f[j];
    NCP_STAGED(NCP_OUT)
#undef NCP_OUT
    for (int j = t; j < m; j += kThreads) G.is_clamped[j] = V.is_clamped[j];
    if (t == 0) *G.sc = *V.sc;
}

/* Diagnostic (PLIANT_NCP_FUSED_PROFILE=N): thread 0 notes the SM clock
 * after each section and prints the cycles of launches N to N + 19. */
__device__ int prof_launches;

struct prof {
    int on, n;
    long long t[12];
    __device__ void mark()
    {
        if (on && threadIdx.x == 0 && n < 12) t[n++] = clock64();
    }
};

__device__ void prof_print(const prof &pf, int skip, int m, int its)
{
    if (!pf.on || threadIdx.x != 0) return;
    const int k = atomicAdd(&prof_launches, 1);
    if (k < skip || k >= skip + 20 || pf.n < 12) return;
    const long long *t = pf.t;
    printf("fused update %d: m %d, CR products %d; cycles: stage in %lld, linearise %lld, "
           "A %lld, B %lld, C %lld, D %lld, CR loop %lld, G %lld, line search products %lld, "
           "update %lld, stage out %lld, total %lld\n",
           k, m, its, t[1] - t[0], t[2] - t[1], t[3] - t[2], t[4] - t[3], t[5] - t[4],
           t[6] - t[5], t[7] - t[6], t[8] - t[7], t[9] - t[8], t[10] - t[9], t[11] - t[10],
           t[11] - t[0]);
}

/* The whole constraint update in one block, W explicit: the sequence of
 * contact_device.c's constraint_update (phases and W products), each
 * phase as k_phase runs it and each product as k_dense sums it, with a
 * barrier where the phased path ends a kernel; CR's loop as cr_loop.  The
 * m-row vectors live in shared memory for the update (copied in and out),
 * and W too when it fits (`smem` bytes of dynamic shared memory);
 * otherwise the products read W in global memory.  CR's loop stops once
 * CR is done (the product after it only writes tmp2, which the next phase
 * after CR overwrites before use). */
__global__ void __launch_bounds__(kThreads)
    k_update(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs G, pl_ncp_cuda_params P,
             const double *__restrict__ W, int jacobian, int smem, int profile)
{
    extern __shared__ double dyn[];
    __shared__ double sh[kRedShared];
    __shared__ pl_ncp_cuda_scalars scs;
    red rd = {sh, 0};
    prof pf = {profile > 0, 0, {0}};
    pf.mark();
    const pl_ncp_cuda_rows R = *Rp;
    const int m = R.m;
    pl_ncp_cuda_vecs V = G;
    const wplan w = stage_in(m, V, &scs, dyn, smem, W);
    __syncthreads();
    pf.mark();
#define PHASE(p)                             \
    do {                                     \
        run_phase((p), R, V, P, 0, rd);      \
        __syncthreads();                     \
    } while (0)
#define PRODUCT(x)                           \
    do {                                     \
        product(m, w, (x), V.tmp2);          \
        __syncthreads();                     \
    } while (0)
    if (!jacobian) { /* linearise at delta_free + h^2 W lambda */
        PRODUCT(V.lambda);
        PHASE(PL_NCP_PHASE_LIN);
    }
    pf.mark();
    PHASE(PL_NCP_PHASE_A);
    pf.mark();
    PRODUCT(V.tmp);
    PHASE(PL_NCP_PHASE_B);
    pf.mark();
    PRODUCT(V.tmp);
    PHASE(PL_NCP_PHASE_C);
    pf.mark();
    PRODUCT(V.tmp);
    PHASE(PL_NCP_PHASE_D);
    pf.mark();
    cr_loop(R, V, P, w, rd);
    __syncthreads();
    pf.mark();
    PHASE(PL_NCP_PHASE_G);
    pf.mark();
    if (P.line_search) {
        if (jacobian) {
            PHASE(PL_NCP_PHASE_LAMBDA);
            PRODUCT(V.force);
            PHASE(PL_NCP_PHASE_LS0);
        }
        PHASE(PL_NCP_PHASE_DLAMBDA);
        PRODUCT(V.force);
    }
    pf.mark();
    PHASE(PL_NCP_PHASE_UPDATE);
    pf.mark();
#undef PHASE
#undef PRODUCT
    const int its = V.sc->its;
    stage_out(m, V, G);
    __syncthreads();
    pf.mark();
    prof_print(pf, profile - 1, m, its);
}

/* Dynamic shared memory of k_update: the device's opt-in maximum per block
 * less the kernel's static part, set once (-1: not yet; 0: none).
 * Diagnostics: PLIANT_NCP_FUSED_STAGE=0 keeps the vectors and W in global
 * memory; PLIANT_NCP_FUSED_PROFILE=N prints the cycles of each section of
 * launches N to N + 19 (printf, shown when the host next waits). */
int fused_smem = -1, fused_profile = 0;

int fused_setup(void)
{
    if (fused_smem >= 0) return fused_smem;
    const char *env = getenv("PLIANT_NCP_FUSED_STAGE"), *pe = getenv("PLIANT_NCP_FUSED_PROFILE");
    int dev = 0, optin = 0, bytes = 0;
    cudaFuncAttributes fa;
    fused_profile = pe ? 1 + atoi(pe) : 0;
    if (fused_profile < 0) fused_profile = 0;
    if (!(env && !strcmp(env, "0"))) {
        if (cudaGetDevice(&dev) == cudaSuccess &&
            cudaDeviceGetAttribute(&optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, dev) ==
                cudaSuccess &&
            cudaFuncGetAttributes(&fa, k_update) == cudaSuccess &&
            optin > (int)fa.sharedSizeBytes &&
            cudaFuncSetAttribute(k_update, cudaFuncAttributeMaxDynamicSharedMemorySize,
                                 optin - (int)fa.sharedSizeBytes) == cudaSuccess)
            bytes = optin - (int)fa.sharedSizeBytes;
        else
            (void)cudaGetLastError(); /* a refusal only means no staging */
    }
    fused_smem = bytes;
    return bytes;
}

} // namespace

extern "C" int ncp_cuda_update_fused(struct CUstream_st *st, const pl_ncp_cuda_rows *R,
                                     const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P,
                                     const double *W, int jacobian)
{
    const int smem = fused_setup();
    k_update<<<1, kThreads, (size_t)smem, st>>>(R, *V, *P, W, jacobian, smem, fused_profile);
    return (int)cudaGetLastError();
}
