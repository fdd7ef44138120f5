/* ncp_cuda_fused.cu - the whole constraint update of Algorithm 4 in one
 * single-block kernel when W is explicit and rows are few (see ncp_cuda.h):
 * the phases of ncp_cuda_phases.cuh in turn, CR's loop with its scalars in
 * registers and two reductions an iteration (one barrier each), the
 * products in ncp_cuda_dense.cuh's order (k_dense's: the phased path's
 * sums, bitwise).  W and the work vectors stay in global memory (read
 * through the SM's L1): copying them into shared memory for the update
 * was measured on the H100 to save 2.4 of 94 us at 108 rows, while its
 * copies in and out took about 7.5 us of it, which a scene of few rows
 * would pay for nothing (docs/benchmarks.md, "The fused constraint
 * update").  At most NCP_CUDA_WARP_MAX_ROWS rows (the cable fingers' one
 * row) are done by the block's first warp alone (NT = 32), one row a lane:
 * no block barrier, the reductions by shuffles, and the rows, W and work
 * vectors copied into shared memory first (a few loads a lane); the other
 * warps leave at once (docs/benchmarks.md, "The constraint update for few
 * rows in one warp"). */
#include "ncp_cuda_phases.cuh"
#include "ncp_cuda_dense.cuh"
#include "ncp_cuda_correct.cuh"
#include "ncp_cuda_rowval.cuh"

#include <stdio.h>
#include <stdlib.h>

namespace {

/* y = W x by the NT threads: row i by the K threads i K ... i K + K - 1 (K =
 * dense_row_width(m); 1 for the warp's few rows), NT / K rows at a time. */
template <int NT>
__device__ void product(int m, const double *__restrict__ W, const double *x, double *y)
{
    const int K = dense_row_width(m), c = threadIdx.x & (K - 1);
    for (int i0 = 0; i0 < m; i0 += NT / K) { /* uniform bound: shuffles inside */
        const int i = i0 + threadIdx.x / K, ok = i < m;
        const double s = dense_row_dot(W + (ok ? (size_t)i * (size_t)m : 0), x, ok ? m : 0, c, K);
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
template <int NT>
__device__ void cr_loop(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                        const pl_ncp_cuda_params &P, const double *__restrict__ W, red &rd)
{
    pl_ncp_cuda_scalars *sc = V.sc;
    const int m = R.m;
    const double h2 = P.h * P.h, bnorm = sc->bnorm;
    int done = sc->done, its = sc->its, error = 0;
    double rAr = sc->rAr, rnorm = sc->rnorm;
    for (int t = 1; t < P.cr_max_iter && !done; ++t) {
        const int last = t == P.cr_max_iter - 1;
        const double ApAp = dot<NT>(m, V.cr_Ap, V.cr_Ap, rd);
        if (!(ApAp > 0.0) || rAr == 0.0) {
            done = 1;
            break;
        }
        const double alpha = rAr / ApAp;
        double ss = 0.0, s = 0.0;
        for (int j = threadIdx.x; j < m; j += NT) {
            V.dlambda[j] += alpha * V.cr_p[j];
            const double r = V.cr_r[j] - alpha * V.cr_Ap[j];
            V.cr_r[j] = r;
            ss += r * r;
            if (!last) V.tmp[j] = V.op_omega[j] * r;
        }
        if (last) {
            ss = block_reduce<NT>(ss, 0, rd);
        } else {
            sync_nt<NT>();
            product<NT>(m, W, V.tmp, V.tmp2);
            sync_nt<NT>();
            for (int j = threadIdx.x; j < m; j += NT) {
                const double ar = h2 * V.op_omega[j] * V.tmp2[j] + V.op_e[j] * V.cr_r[j];
                V.cr_Ar[j] = ar;
                s += V.cr_r[j] * ar;
            }
            block_reduce2<NT>(ss, s, rd);
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
        for (int j = threadIdx.x; j < m; j += NT) {
            V.cr_p[j] = V.cr_r[j] + beta * V.cr_p[j];
            V.cr_Ap[j] = V.cr_Ar[j] + beta * V.cr_Ap[j];
        }
        rAr = s;
    }
    sync_nt<NT>(); /* every thread has read sc above */
    if (threadIdx.x == 0) {
        sc->done = done, sc->its = its, sc->rAr = rAr, sc->rnorm = rnorm;
        if (error) sc->error = error;
    }
}

/* Diagnostic (PLIANT_NCP_FUSED_PROFILE=N): thread 0 notes the SM clock
 * after each section and prints the cycles of launches N to N + 19. */
__device__ int prof_launches;

constexpr int kMarks = 10;

struct prof {
    int on, n;
    long long t[kMarks];
    __device__ void mark()
    {
        if (on && threadIdx.x == 0 && n < kMarks) t[n++] = clock64();
    }
};

__device__ void prof_print(const prof &pf, int skip, int m, int its)
{
    if (!pf.on || threadIdx.x != 0) return;
    const int k = atomicAdd(&prof_launches, 1);
    if (k < skip || k >= skip + 20 || pf.n < kMarks) return;
    const long long *t = pf.t;
    printf("fused update %d: m %d, CR products %d; cycles: linearise %lld, A %lld, B %lld, "
           "C %lld, D %lld, CR loop %lld, G %lld, line search products %lld, update %lld, "
           "total %lld\n",
           k, m, its, t[1] - t[0], t[2] - t[1], t[3] - t[2], t[4] - t[3], t[5] - t[4],
           t[6] - t[5], t[7] - t[6], t[8] - t[7], t[9] - t[8], t[9] - t[0]);
}

/* The whole constraint update by NT threads (the block, or its first warp
 * for few rows), W explicit: the sequence of contact_device.c's
 * constraint_update (phases and W products), each phase as k_phase runs it
 * and each product as k_dense sums it, with a barrier where the phased
 * path ends a kernel; CR's loop as cr_loop.  CR's loop stops once CR is
 * done (the product after it only writes tmp2, which the next phase after
 * CR overwrites before use). */
template <int NT>
__device__ void update_all(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                           const pl_ncp_cuda_params &P, const double *__restrict__ W,
                           int jacobian, red &rd, prof &pf)
{
    const int m = R.m;
#define PHASE(p)                             \
    do {                                     \
        run_phase<NT>((p), R, V, P, 0, rd);  \
        sync_nt<NT>();                       \
    } while (0)
#define PRODUCT(x)                           \
    do {                                     \
        product<NT>(m, W, (x), V.tmp2);      \
        sync_nt<NT>();                       \
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
    cr_loop<NT>(R, V, P, W, rd);
    sync_nt<NT>();
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
}

/* The few rows' copy in shared memory (the warp path): the work vectors of
 * pl_ncp_cuda_vecs in this order, the row arrays the phases read, W and the
 * scalars.  lambda_all and the series stay in global memory. */
constexpr int kWarpRows = NCP_CUDA_WARP_MAX_ROWS;
#define WARP_VECS(X)                                                                        \
    X(0, lambda) X(1, dlambda) X(2, delta) X(3, delta_free) X(4, omega) X(5, e) X(6, phi)   \
    X(7, rhs) X(8, tmp) X(9, tmp2) X(10, scale) X(11, clamped) X(12, op_omega) X(13, op_e)  \
    X(14, force) X(15, ls0) X(16, ls1) X(17, cr_r) X(18, cr_p) X(19, cr_Ar) X(20, cr_Ap)    \
    X(21, cr_s)
#define WARP_ROWD(X) X(0, mu) X(1, compliance) X(2, lo) X(3, hi) X(4, r) X(5, wdiag)
struct warp_stage {
    double vec[22][kWarpRows], rowd[6][kWarpRows], W[kWarpRows * kWarpRows];
    int is_clamped[kWarpRows], kind[kWarpRows], full[kWarpRows], contact[3 * kWarpRows];
    pl_ncp_cuda_scalars sc;
};

/* W (m x m) into shared memory: 8 loads a lane in flight, then their
 * stores (a loop of load-store pairs would wait a memory latency each). */
__device__ __forceinline__ void stage_w(double *sh, const double *__restrict__ W, int mm)
{
    const int lane = threadIdx.x;
    for (int k0 = 0; k0 < mm; k0 += 8 * 32) {
        double w[8];
#pragma unroll
        for (int u = 0; u < 8; ++u) {
            const int k = k0 + 32 * u + lane;
            w[u] = k < mm ? W[k] : 0.0;
        }
#pragma unroll
        for (int u = 0; u < 8; ++u) {
            const int k = k0 + 32 * u + lane;
            if (k < mm) sh[k] = w[u];
        }
    }
}

/* The warp path with its data staged: lane j < m loads row j of every
 * work vector and row array at once (straight code: the loads wait one
 * memory latency together) and stores it into st; update_all<32> on the
 * copies; the work vectors and scalars back (all of them: the same state
 * as the phased path leaves). */
__device__ void update_warp_staged(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                                   const pl_ncp_cuda_params &P, const double *__restrict__ W,
                                   int jacobian, red &rd, prof &pf, warp_stage &st)
{
    const int m = R.m, j = threadIdx.x;
    if (j < m) {
        double v[22], d[6];
        int ic = V.is_clamped[j], kd = R.kind[j], fl = R.full[j], ct[3] = {0, 0, 0};
#define LD_VEC(k, f) v[k] = V.f[j];
#define LD_ROWD(k, f) d[k] = R.f[j];
        WARP_VECS(LD_VEC)
        WARP_ROWD(LD_ROWD)
        if (j < R.nc)
            for (int i = 0; i < 3; ++i) ct[i] = R.contact[3 * j + i];
#define ST_VEC(k, f) st.vec[k][j] = v[k];
#define ST_ROWD(k, f) st.rowd[k][j] = d[k];
        WARP_VECS(ST_VEC)
        WARP_ROWD(ST_ROWD)
        st.is_clamped[j] = ic, st.kind[j] = kd, st.full[j] = fl;
        if (j < R.nc)
            for (int i = 0; i < 3; ++i) st.contact[3 * j + i] = ct[i];
    }
    if (j == 0) st.sc = *V.sc;
    stage_w(st.W, W, m * m);
    pl_ncp_cuda_rows SR = R;
    pl_ncp_cuda_vecs SV = V;
#define SET_VEC(k, f) SV.f = st.vec[k];
#define SET_ROWD(k, f) SR.f = st.rowd[k];
    WARP_VECS(SET_VEC)
    WARP_ROWD(SET_ROWD)
    SV.is_clamped = st.is_clamped, SV.sc = &st.sc;
    SR.kind = st.kind, SR.full = st.full, SR.contact = st.contact;
    __syncwarp();
    update_all<32>(SR, SV, P, st.W, jacobian, rd, pf);
    __syncwarp();
    if (j < m) {
#define OUT_VEC(k, f) V.f[j] = st.vec[k][j];
        WARP_VECS(OUT_VEC)
        V.is_clamped[j] = st.is_clamped[j];
    }
    if (j == 0) *V.sc = st.sc;
#undef LD_VEC
#undef LD_ROWD
#undef ST_VEC
#undef ST_ROWD
#undef SET_VEC
#undef SET_ROWD
#undef OUT_VEC
}

/* The constraint update in one launch of one block.  warp (the
 * PLIANT_NCP_FUSED_WARP switch): 2 = at most kWarpRows rows by the first
 * warp on shared copies, 1 = by the first warp in place, 0 = by the block. */
__global__ void __launch_bounds__(kThreads)
    k_update(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P,
             const double *__restrict__ W, int jacobian, int profile, int warp)
{
    __shared__ double sh[kRedShared];
    __shared__ warp_stage st;
    red rd = {sh, 0, 32};
    prof pf = {profile > 0, 0, {0}};
    pf.mark();
    const pl_ncp_cuda_rows R = *Rp;
    if (warp && R.m <= kWarpRows) {
        if (threadIdx.x >= 32) return; /* the other warps: nothing to do */
        rd.live = R.m;
        if (warp == 2)
            update_warp_staged(R, V, P, W, jacobian, rd, pf, st);
        else
            update_all<32>(R, V, P, W, jacobian, rd, pf);
    } else {
        update_all<kThreads>(R, V, P, W, jacobian, rd, pf);
    }
    prof_print(pf, profile - 1, R.m, V.sc->its);
}

/* A few rows' whole constrained iteration in one launch of one block
 * (ncp_cuda_iterate_few): the row values (ncp_cuda_rowval.cuh, the code
 * of k_delta2 or k_delta, rows over the block's threads or warps), the
 * update as k_update runs it (warp = 2), then the dense correction
 * (ncp_cuda_correct.cuh, k_correct_dense's values over the block's
 * threads), a block barrier between them where the separate kernels end.
 * The values each part writes are the separate kernels', bitwise; x is
 * q_free.  Nothing here is __restrict__ that the kernel writes and reads
 * again (no non-coherent loads of it). */
__global__ void __launch_bounds__(kThreads)
    k_iterate(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P,
              const double *__restrict__ W, int jacobian, int profile, const double *x,
              const double *q, int nfree, double h2, const double *__restrict__ U,
              double *q_next)
{
    __shared__ double sh[kRedShared];
    __shared__ warp_stage st;
    red rd = {sh, 0, 32};
    prof pf = {profile > 0, 0, {0}};
    pf.mark(); /* the profile's first section (linearise) has the row values too */
    const int tid = threadIdx.x, m = Rp->m;
    if (jacobian) /* delta at q, delta_free at x: 2 m values, one a thread */
        for (int t = tid; t < 2 * m; t += kThreads)
            row_delta2(Rp, t % m, x, q, t / m, t < m ? V.delta : V.delta_free);
    else /* delta_free at x, a warp a row (warp-uniform loop) */
        for (int j = tid >> 5; j < m; j += kWarps)
            row_delta_warp(Rp, j, x, q, 0, tid & 31, V.delta_free);
    __syncthreads();
    const pl_ncp_cuda_rows R = *Rp;
    if (R.m <= kWarpRows) {
        if (tid < 32) {
            rd.live = R.m;
            update_warp_staged(R, V, P, W, jacobian, rd, pf, st);
        }
    } else { /* not chosen by the host (dense_max <= kWarpRows); correct all the same */
        update_all<kThreads>(R, V, P, W, jacobian, rd, pf);
    }
    __syncthreads();
    prof_print(pf, profile - 1, R.m, V.sc->its);
    const long long n = 3LL * nfree, end = n > m ? n : m;
    for (long long i = tid; i < end; i += kThreads)
        correct_dense_at(i, m, n, V.scale, V.lambda, h2, U, x, V.force, q_next);
}

/* PLIANT_NCP_FUSED_PROFILE=N (a diagnostic): the cycles of each section of
 * launches N to N + 19, printed by the kernel (shown when the host next
 * waits).  Read once; -1: not yet. */
int fused_profile = -1;

int profile_launches()
{
    if (fused_profile < 0) {
        const char *pe = getenv("PLIANT_NCP_FUSED_PROFILE");
        fused_profile = pe && atoi(pe) >= 0 ? 1 + atoi(pe) : 0;
    }
    return fused_profile;
}

} // namespace

extern "C" int ncp_cuda_update_fused(struct CUstream_st *st, const pl_ncp_cuda_rows *R,
                                     const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P,
                                     const double *W, int jacobian, int warp)
{
    k_update<<<1, kThreads, 0, st>>>(R, *V, *P, W, jacobian, profile_launches(), warp);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_iterate_few(struct CUstream_st *st, const pl_ncp_cuda_rows *R,
                                    const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P,
                                    const double *W, int jacobian, const double *q_free,
                                    const double *q, int nfree, double h2, const double *U,
                                    double *q_next)
{
    k_iterate<<<1, kThreads, 0, st>>>(R, *V, *P, W, jacobian, profile_launches(), q_free, q,
                                      nfree > 0 ? nfree : 0, h2, U, q_next);
    return (int)cudaGetLastError();
}
