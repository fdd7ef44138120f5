/* ncp_cuda_fused.cu - the whole constraint update of Algorithm 4 in one
 * single-block kernel when W is explicit and rows are few (see ncp_cuda.h):
 * the phases of ncp_cuda_phases.cuh in turn, CR's loop with its scalars in
 * registers, the work vectors and (when it fits) W in shared memory, and
 * reductions with one barrier each. */
#include "ncp_cuda_phases.cuh"

#include <stdlib.h>
#include <string.h>

namespace {

/* W's place and shape: global (m x m), or shared (m x ld, ld >= m); the
 * product by rows (as k_dense), or by chunks (below). */
struct wplan {
    const double *W;
    int shared, chunks, K, ld;
};

/* chunks: thread t takes row i = t / K (K a power of two, K m <= kThreads
 * when m allows) and its columns c, c + K, ... (c = t % K); ld = K
 * (mod 16) puts the 16 doubles a half warp reads in distinct banks. */
__device__ wplan plan_w(int m, const double *W, int chunks)
{
    wplan w = {W, 0, chunks, 1, m};
    int K = 1;
    while (K < 32 && 2 * K * m <= kThreads) K *= 2;
    w.K = K;
    if (chunks && K < 16) w.ld = m + (((K - m) % 16) + 16) % 16;
    return w;
}

/* y = W x by rows: warp w takes rows w, w + kWarps, ..., each row exactly
 * as k_dense (ncp_cuda_rows.cu) does it (lanes over columns, the same
 * shuffle tree), so the sums are the phased path's, bitwise. */
__device__ void dense_rows(int m, int ld, const double *__restrict__ W,
                           const double *__restrict__ x, double *__restrict__ y)
{
    const int lane = threadIdx.x & 31;
#pragma unroll 2
    for (int i = threadIdx.x >> 5; i < m; i += kWarps) {
        const double *row = W + (size_t)i * (size_t)ld;
        double s = 0.0;
        for (int j = lane; j < m; j += 32) s += row[j] * x[j];
        for (int o = 16; o > 0; o >>= 1) s += __shfl_down_sync(0xffffffffu, s, o);
        if (lane == 0) y[i] = s;
    }
}

/* y = W x by chunks (see plan_w): another summation order. */
__device__ void dense_chunks(int m, const wplan &w, const double *__restrict__ x,
                             double *__restrict__ y)
{
    const int t = threadIdx.x, K = w.K, c = t & (K - 1);
    for (int i0 = 0; i0 < m; i0 += kThreads / K) { /* uniform bound: shuffles below */
        const int i = i0 + t / K;
        double s = 0.0;
        if (i < m) {
            const double *row = w.W + (size_t)i * (size_t)w.ld;
#pragma unroll 4
            for (int j = c; j < m; j += K) s += row[j] * x[j];
        }
        for (int o = K / 2; o > 0; o >>= 1) s += __shfl_down_sync(0xffffffffu, s, o, K);
        if (c == 0 && i < m) y[i] = s;
    }
}

__device__ void product(int m, const wplan &w, const double *x, double *y)
{
    if (w.shared && w.chunks)
        dense_chunks(m, w, x, y);
    else
        dense_rows(m, w.ld, w.W, x, y);
}

/* CR's loop after phase D (phases E and F of ncp_cuda.h with the product
 * between them): the scalars stay in registers (the same in every thread),
 * each thread updates its own rows, five barriers an iteration.  The same
 * arithmetic as cr_e and cr_f; sc gets the scalars at the end. */
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
        double ss = 0.0;
        for (int j = threadIdx.x; j < m; j += kThreads) {
            V.dlambda[j] += alpha * V.cr_p[j];
            const double r = V.cr_r[j] - alpha * V.cr_Ap[j];
            V.cr_r[j] = r;
            ss += r * r;
        }
        rnorm = sqrt(block_reduce(ss, 0, rd));
        if (!isfinite(rnorm)) error = 2;
        if (!isfinite(rnorm) || rnorm <= P.cr_rtol * bnorm) {
            done = 1;
            break;
        }
        its += 1; /* the product that follows (counted on the last one too, as cr_e) */
        if (last) break;
        for (int j = threadIdx.x; j < m; j += kThreads) V.tmp[j] = V.op_omega[j] * V.cr_r[j];
        __syncthreads();
        product(m, w, V.tmp, V.tmp2);
        __syncthreads();
        double s = 0.0;
        for (int j = threadIdx.x; j < m; j += kThreads) {
            const double ar = h2 * V.op_omega[j] * V.tmp2[j] + V.op_e[j] * V.cr_r[j];
            V.cr_Ar[j] = ar;
            s += V.cr_r[j] * ar;
        }
        const double rAr_new = block_reduce(s, 0, rd);
        const double beta = rAr_new / rAr;
        for (int j = threadIdx.x; j < m; j += kThreads) {
            V.cr_p[j] = V.cr_r[j] + beta * V.cr_p[j];
            V.cr_Ap[j] = V.cr_Ar[j] + beta * V.cr_Ap[j];
        }
        rAr = rAr_new;
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
 * Without room the vectors stay global (the update is the same). */
__device__ wplan stage_in(int m, pl_ncp_cuda_vecs &V, pl_ncp_cuda_scalars *scs, double *dyn,
                          int smem, const double *W, int chunks)
{
    wplan w = plan_w(m, W, chunks);
    const size_t vec = sizeof(double) * (size_t)m * kStaged + sizeof(int) * (size_t)(m + 1);
    const size_t wbytes = sizeof(double) * (size_t)m * (size_t)w.ld;
    if (vec > (size_t)smem) {
        w.ld = m; /* W global */
        return w;
    }
    const int t = threadIdx.x;
    double *p = dyn;
    if (vec + wbytes <= (size_t)smem) { /* W first: the vectors after it */
        double *Ws = p;
        for (int k = t; k < m * m; k += kThreads) {
            const int i = k / m;
            Ws[(size_t)i * (size_t)w.ld + (k - i * m)] = W[k];
        }
        p += (size_t)m * (size_t)w.ld;
        w.W = Ws, w.shared = 1;
    } else {
        w.ld = m;
    }
#define NCP_IN(f)                                                \
    for (int j = t; j < m; j += kThreads) p[j] = V.f[j];         \
    V.f = p, p += m;
    NCP_STAGED(NCP_IN)
#undef NCP_IN
    int *ic = (int *)p;
    for (int j = t; j < m; j += kThreads) ic[j] = V.is_clamped[j];
    V.is_clamped = ic;
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

/* The whole constraint update in one block, W explicit: the sequence of
 * contact_device.c's constraint_update (phases and W products), each
 * phase as k_phase runs it, with a barrier where the phased path ends a
 * kernel; CR's loop as cr_loop.  The m-row vectors live in shared memory
 * for the update (copied in and out), and W too when it fits (`smem`
 * bytes of dynamic shared memory); otherwise each product reads W from
 * global memory as k_dense does.  CR's loop stops once CR is done (the
 * product after it only writes tmp2, which the next phase after CR
 * overwrites before use). */
__global__ void __launch_bounds__(kThreads)
    k_update(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs G, pl_ncp_cuda_params P,
             const double *__restrict__ W, int jacobian, int smem, int chunks)
{
    extern __shared__ double dyn[];
    __shared__ double sh[2 * kWarps];
    __shared__ pl_ncp_cuda_scalars scs;
    red rd = {sh, 0};
    const pl_ncp_cuda_rows R = *Rp;
    const int m = R.m;
    pl_ncp_cuda_vecs V = G;
    const wplan w = stage_in(m, V, &scs, dyn, smem, W, chunks);
    __syncthreads();
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
    PHASE(PL_NCP_PHASE_A);
    PRODUCT(V.tmp);
    PHASE(PL_NCP_PHASE_B);
    PRODUCT(V.tmp);
    PHASE(PL_NCP_PHASE_C);
    PRODUCT(V.tmp);
    PHASE(PL_NCP_PHASE_D);
    cr_loop(R, V, P, w, rd);
    __syncthreads();
    PHASE(PL_NCP_PHASE_G);
    if (P.line_search) {
        if (jacobian) {
            PHASE(PL_NCP_PHASE_LAMBDA);
            PRODUCT(V.force);
            PHASE(PL_NCP_PHASE_LS0);
        }
        PHASE(PL_NCP_PHASE_DLAMBDA);
        PRODUCT(V.force);
    }
    PHASE(PL_NCP_PHASE_UPDATE);
#undef PHASE
#undef PRODUCT
    stage_out(m, V, G);
}

/* Dynamic shared memory of k_update: the device's opt-in maximum per block
 * less the kernel's static part, set once (-1: not yet; 0: none).
 * PLIANT_NCP_FUSED_STAGE (a diagnostic): 0 keeps the vectors and W in
 * global memory, chunks takes W's product by chunks. */
int fused_smem = -1, fused_chunks = 0;

int fused_setup(void)
{
    if (fused_smem >= 0) return fused_smem;
    const char *env = getenv("PLIANT_NCP_FUSED_STAGE");
    int dev = 0, optin = 0, bytes = 0;
    cudaFuncAttributes fa;
    fused_chunks = env && !strcmp(env, "chunks");
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
    k_update<<<1, kThreads, (size_t)smem, st>>>(R, *V, *P, W, jacobian, smem, fused_chunks);
    return (int)cudaGetLastError();
}
