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
 * update"). */
#include "ncp_cuda_phases.cuh"
#include "ncp_cuda_dense.cuh"

#include <stdio.h>
#include <stdlib.h>

namespace {

/* y = W x by the block: row i by the K threads i K ... i K + K - 1 (K =
 * ncp_dense_width(m)), kThreads / K rows at a time. */
__device__ void product(int m, const double *__restrict__ W, const double *x, double *y)
{
    const int K = ncp_dense_width(m), c = threadIdx.x & (K - 1);
    for (int i0 = 0; i0 < m; i0 += kThreads / K) { /* uniform bound: shuffles inside */
        const int i = i0 + threadIdx.x / K, ok = i < m;
        const double s = ncp_dense_row(W + (ok ? (size_t)i * (size_t)m : 0), x, ok ? m : 0, c, K);
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
                        const pl_ncp_cuda_params &P, const double *__restrict__ W, red &rd)
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
            product(m, W, V.tmp, V.tmp2);
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

/* The whole constraint update in one block, W explicit: the sequence of
 * contact_device.c's constraint_update (phases and W products), each
 * phase as k_phase runs it and each product as k_dense sums it, with a
 * barrier where the phased path ends a kernel; CR's loop as cr_loop.  CR's
 * loop stops once CR is done (the product after it only writes tmp2, which
 * the next phase after CR overwrites before use). */
__global__ void __launch_bounds__(kThreads)
    k_update(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P,
             const double *__restrict__ W, int jacobian, int profile)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0};
    prof pf = {profile > 0, 0, {0}};
    pf.mark();
    const pl_ncp_cuda_rows R = *Rp;
    const int m = R.m;
#define PHASE(p)                             \
    do {                                     \
        run_phase((p), R, V, P, 0, rd);      \
        __syncthreads();                     \
    } while (0)
#define PRODUCT(x)                           \
    do {                                     \
        product(m, W, (x), V.tmp2);          \
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
    cr_loop(R, V, P, W, rd);
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
    prof_print(pf, profile - 1, m, V.sc->its);
}

/* PLIANT_NCP_FUSED_PROFILE=N (a diagnostic): the cycles of each section of
 * launches N to N + 19, printed by the kernel (shown when the host next
 * waits).  Read once; -1: not yet. */
int fused_profile = -1;

} // namespace

extern "C" int ncp_cuda_update_fused(struct CUstream_st *st, const pl_ncp_cuda_rows *R,
                                     const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P,
                                     const double *W, int jacobian)
{
    if (fused_profile < 0) {
        const char *pe = getenv("PLIANT_NCP_FUSED_PROFILE");
        fused_profile = pe && atoi(pe) >= 0 ? 1 + atoi(pe) : 0;
    }
    k_update<<<1, kThreads, 0, st>>>(R, *V, *P, W, jacobian, fused_profile);
    return (int)cudaGetLastError();
}
