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
 * dense_row_width(m); 1 for the warp's few rows), NT / K rows a pass.  The
 * block's K m <= kThreads threads take at most NP = kThreads / NT passes
 * (the narrow paths' NT = 128 or 256 up to 4 or 2, the warp's 1), summed
 * side by side so that their chains of multiply-adds overlap; each row's
 * sum is dense_row_dot's, in its order (bitwise k_dense's). */
template <int NT>
__device__ void product(int m, const double *__restrict__ W, const double *x, double *y)
{
    constexpr int NP = NT == 32 ? 1 : kThreads / NT;
    const int K = dense_row_width(m), c = threadIdx.x & (K - 1), per = NT / K;
    if constexpr (NP == 1) {
        for (int i0 = 0; i0 < m; i0 += per) { /* uniform bound: shuffles inside */
            const int i = i0 + threadIdx.x / K, ok = i < m;
            const double s = dense_row_dot(W + (ok ? (size_t)i * (size_t)m : 0), x, ok ? m : 0, c, K);
            if (ok && c == 0) y[i] = s;
        }
    } else {
        const double *row[NP];
        double s[NP];
#pragma unroll
        for (int p = 0; p < NP; ++p) {
            const int i = p * per + threadIdx.x / K;
            row[p] = W + (size_t)(i < m ? i : 0) * (size_t)m; /* a row past m: summed, not kept */
            s[p] = 0.0;
        }
        if (per >= m) { /* one pass */
            for (int j = c; j < m; j += K) s[0] += row[0][j] * x[j];
        } else {
            for (int j = c; j < m; j += K) {
                const double xj = x[j];
#pragma unroll
                for (int p = 0; p < NP; ++p) s[p] += row[p][j] * xj;
            }
        }
#pragma unroll
        for (int p = 0; p < NP; ++p) {
            for (int o = K / 2; o > 0; o >>= 1) s[p] += __shfl_down_sync(0xffffffffu, s[p], o, K);
            const int i = p * per + threadIdx.x / K;
            if (i < m && c == 0) y[i] = s[p];
        }
    }
}

/* CR's loop after phase D (phases E and F of ncp_cuda.h with the product
 * between them): the same arithmetic as cr_e and cr_f, with the scalars in
 * registers (the same in every thread) and, since a fused update has at
 * most one row a thread (m <= NT), each thread's row of dlambda, r, p, Ap,
 * Ar, op_omega and op_e in registers too: an iteration reads no global
 * memory but W.  The product's operand and result go through xs and ys
 * (shared memory, m <= NCP_CUDA_FUSED_MAX_ROWS doubles each), not tmp and
 * tmp2.  The product after an update of r runs before the stop test, so
 * that |r|^2 and r.Ar are summed together (block_reduce2): two reductions
 * and two more barriers an iteration.  The rows' dlambda, r, p, Ap and Ar
 * go back to V at the end; tmp and tmp2 are left as they were, as nothing
 * reads them before it writes them again (phase G on, as after the phased
 * path's CR). */
template <int NT>
__device__ void cr_loop(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                        const pl_ncp_cuda_params &P, const double *__restrict__ W, red &rd,
                        double *xs, double *ys)
{
    pl_ncp_cuda_scalars *sc = V.sc;
    const int m = R.m, j = threadIdx.x, own = j < m;
    const double h2 = P.h * P.h, bnorm = sc->bnorm;
    int done = sc->done, its = sc->its, error = 0;
    double rAr = sc->rAr, rnorm = sc->rnorm;
    double dl = 0.0, r = 0.0, p = 0.0, Ap = 0.0, Ar = 0.0, om = 0.0, oe = 0.0;
    if (own) {
        dl = V.dlambda[j], r = V.cr_r[j], p = V.cr_p[j], Ap = V.cr_Ap[j], Ar = V.cr_Ar[j];
        om = V.op_omega[j], oe = V.op_e[j];
    }
    for (int t = 1; t < P.cr_max_iter && !done; ++t) {
        const int last = t == P.cr_max_iter - 1;
        double s0 = 0.0; /* dot()'s sum */
        if (own) s0 += Ap * Ap;
        const double ApAp = block_reduce<NT>(s0, 0, rd);
        if (!(ApAp > 0.0) || rAr == 0.0) {
            done = 1;
            break;
        }
        const double alpha = rAr / ApAp;
        double ss = 0.0, s = 0.0;
        if (own) {
            dl += alpha * p;
            r = r - alpha * Ap;
            ss += r * r;
            if (!last) xs[j] = om * r;
        }
        if (last) {
            ss = block_reduce<NT>(ss, 0, rd);
        } else {
            sync_nt<NT>();
            product<NT>(m, W, xs, ys);
            sync_nt<NT>();
            if (own) {
                Ar = cr_ar(h2, om, ys[j], oe, r);
                s += r * Ar;
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
        if (own) {
            p = r + beta * p;
            Ap = Ar + beta * Ap;
        }
        rAr = s;
    }
    if (own) V.dlambda[j] = dl, V.cr_r[j] = r, V.cr_p[j] = p, V.cr_Ap[j] = Ap, V.cr_Ar[j] = Ar;
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
                           int jacobian, red &rd, prof &pf, double *xy)
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
    cr_loop<NT>(R, V, P, W, rd, xy, xy + NCP_CUDA_FUSED_MAX_ROWS);
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
                                   int jacobian, red &rd, prof &pf, warp_stage &st, double *xy)
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
    update_all<32>(SR, SV, P, st.W, jacobian, rd, pf, xy);
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

/* The constraint update in one launch of one block of NT threads.  warp
 * (the PLIANT_NCP_FUSED_WARP switch): 2 = at most kWarpRows rows by the
 * first warp on shared copies, 1 = by the first warp in place, 0 = by the
 * block.  NT = kThreads, or 128 or 256 for a capacity of at most that many
 * rows (one a thread as in kThreads' block: fewer warps meet at each
 * barrier, and up to 255 registers a thread); the reductions' entries of
 * the warps the smaller block lacks hold +0.0, what kThreads' empty warps
 * give, so the sums are kThreads' bitwise. */
template <int NT>
__global__ void __launch_bounds__(NT, 1)
    k_update(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P,
             const double *__restrict__ W, int jacobian, int profile, int warp)
{
    __shared__ double sh[kRedShared];
    __shared__ warp_stage st;
    __shared__ double xy[2 * NCP_CUDA_FUSED_MAX_ROWS]; /* cr_loop's product operands */
    red rd = {sh, 0, 32};
    prof pf = {profile > 0, 0, {0}};
    if constexpr (NT < kThreads) {
        for (int i = threadIdx.x; i < kRedShared; i += NT) sh[i] = 0.0;
        __syncthreads();
    }
    pf.mark();
    const pl_ncp_cuda_rows R = *Rp;
    if (warp && R.m <= kWarpRows) {
        if (threadIdx.x >= 32) return; /* the other warps: nothing to do */
        rd.live = R.m;
        if (warp == 2)
            update_warp_staged(R, V, P, W, jacobian, rd, pf, st, xy);
        else
            update_all<32>(R, V, P, W, jacobian, rd, pf, xy);
    } else {
        update_all<NT>(R, V, P, W, jacobian, rd, pf, xy);
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
    __shared__ double xy[2 * NCP_CUDA_FUSED_MAX_ROWS]; /* cr_loop's product operands */
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
            update_warp_staged(R, V, P, W, jacobian, rd, pf, st, xy);
        }
    } else { /* not chosen by the host (dense_max <= kWarpRows); correct all the same */
        update_all<kThreads>(R, V, P, W, jacobian, rd, pf, xy);
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
                                     const double *W, int jacobian, int warp, int mcap)
{
    const int pr = profile_launches();
    if (mcap > 0 && mcap <= 128)
        k_update<128><<<1, 128, 0, st>>>(R, *V, *P, W, jacobian, pr, warp);
    else if (mcap > 0 && mcap <= 256)
        k_update<256><<<1, 256, 0, st>>>(R, *V, *P, W, jacobian, pr, warp);
    else
        k_update<kThreads><<<1, kThreads, 0, st>>>(R, *V, *P, W, jacobian, pr, warp);
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
