/* ncp_cuda_phases.cuh - the device code of the constraint update's phases
 * (see ncp_cuda.h for the sequence), shared by the phase kernels
 * (ncp_cuda_step.cu) and the fused update (ncp_cuda_fused.cu).  Each
 * phase is run by one block (NT = kThreads) or, for at most
 * NCP_CUDA_WARP_MAX_ROWS rows, by one warp (NT = 32: the fused update's
 * few-rows path): rows and contacts are strided over its NT threads, and
 * sums and maxima go through a fixed reduction order (block_reduce:
 * deterministic, no atomics; a warp's gives the block's value bitwise when
 * all rows are in the first warp).  The NCP functions, residual
 * parts and projections are the CPU's own (ncp_functions.h, ncp_residual.h,
 * ncp_project.h); the rest follows ncp_step.c (evaluate_rows, the clamped
 * rows, the full_force operator), cr.c and ncp_linesearch.c. */
#ifndef PLIANT_NCP_CUDA_PHASES_CUH
#define PLIANT_NCP_CUDA_PHASES_CUH

#include "ncp_cuda.h"

#include <cuda_runtime.h>

/* the row and contact functions the CPU runs too (compiled as CUDA) */
#include "ncp_functions.h"
#include "ncp_project.h"
#include "ncp_residual.h"

namespace {

constexpr int kThreads = 512, kWarps = kThreads / 32;

/* A block's reductions: each warp reduces by a fixed shuffle tree, its
 * lane 0 writes the warp's value, one barrier, then every thread combines
 * the kWarps values by a fixed pairwise tree (deterministic, no atomics).  The
 * buffers alternate: a reduction writes the one that the reduction before
 * the previous read, and every reader of that one has passed the previous
 * reduction's barrier since, so one barrier a reduction suffices.  All
 * threads run the same sequence of reductions (uniform control flow). */
struct red {
    double *sh; /* 2 buffers x 2 x kWarps (kRedShared doubles) */
    int k;      /* reductions done: picks the buffer */
    int live;   /* a warp's (NT = 32): lanes at and past it hold no row */
};
constexpr int kRedShared = 4 * kWarps;

/* The kWarps values of b (sum or maximum) by a fixed pairwise tree. */
__device__ __forceinline__ double warps_combine(const double *b, int max)
{
    double r[kWarps];
#pragma unroll
    for (int i = 0; i < kWarps; ++i) r[i] = b[i];
#pragma unroll
    for (int s = 1; s < kWarps; s *= 2)
#pragma unroll
        for (int i = 0; i < kWarps; i += 2 * s) r[i] = max ? fmax(r[i], r[i + s]) : r[i] + r[i + s];
    return r[0];
}

/* The barrier of NT threads: a block's, or a warp's (__syncwarp also
 * orders the warp's memory accesses). */
template <int NT> __device__ __forceinline__ void sync_nt()
{
    if constexpr (NT == 32)
        __syncwarp();
    else
        __syncthreads();
}

/* Sum (max = 0) or maximum (max = 1) over the NT threads; every thread
 * gets it.  A block of NT < kThreads threads (the fused update's narrow
 * blocks: rd.sh's entries of warps NT / 32 and on hold +0.0, written once
 * before) combines by kThreads' tree, whose empty warps give +0.0 too: the
 * bits of a kThreads block for at most NT rows.
 * NT = 32 (one warp, m = rd.live <= 32 rows): the levels of the
 * warp's shuffle tree whose offset o < m (a level with o >= m adds to each
 * lane below o a partial sum of lanes at or past m, all +0.0 or, for the
 * maxima of |.|, 0.0: it changes at most a zero's sign), then what the
 * block's pairwise tree does with the other warps' values, which hold no
 * row either: one v + 0.0 (-0.0 becomes +0.0) or fmax(v, 0.0).  So the
 * warp gives the block's bits for the same rows. */
template <int NT> __device__ double block_reduce(double v, int max, red &rd)
{
    const int lane = threadIdx.x & 31, w = threadIdx.x >> 5;
    if constexpr (NT == 32) {
        for (int o = 16; o > 0; o >>= 1)
            if (o < rd.live) { /* warp-uniform */
                const double u = __shfl_down_sync(0xffffffffu, v, o);
                v = max ? fmax(v, u) : v + u;
            }
        v = __shfl_sync(0xffffffffu, v, 0);
        return max ? fmax(v, 0.0) : v + 0.0;
    } else {
        for (int o = 16; o > 0; o >>= 1) {
            const double u = __shfl_down_sync(0xffffffffu, v, o);
            v = max ? fmax(v, u) : v + u;
        }
        double *b = rd.sh + (rd.k & 1) * 2 * kWarps;
        rd.k += 1;
        if (lane == 0) b[w] = v;
        sync_nt<NT>();
        return warps_combine(b, max);
    }
}

/* Two sums at once (each as block_reduce sums it, bitwise). */
template <int NT> __device__ void block_reduce2(double &a, double &c, red &rd)
{
    const int lane = threadIdx.x & 31, w = threadIdx.x >> 5;
    for (int o = 16; o > 0; o >>= 1)
        if (NT != 32 || o < rd.live) {
            a += __shfl_down_sync(0xffffffffu, a, o);
            c += __shfl_down_sync(0xffffffffu, c, o);
        }
    if constexpr (NT == 32) {
        a = __shfl_sync(0xffffffffu, a, 0) + 0.0;
        c = __shfl_sync(0xffffffffu, c, 0) + 0.0;
    } else {
        double *b = rd.sh + (rd.k & 1) * 2 * kWarps;
        rd.k += 1;
        if (lane == 0) b[w] = a, b[kWarps + w] = c;
        sync_nt<NT>();
        a = warps_combine(b, 0);
        c = warps_combine(b + kWarps, 0);
    }
}

/* CR's A r of one row, h^2 op_omega (W op_omega r) + op_e r, with its one
 * fused multiply-add pinned: nvcc contracts the sum where the operands come
 * from memory as fma(h2 om, y, oe r), and where they are kept in registers
 * across a loop as fma(oe, r, h2 om y); the intrinsics keep phases D and F
 * and the fused update's loop (ncp_cuda_fused.cu) on the same bits. */
__device__ __forceinline__ double cr_ar(double h2, double om, double y, double oe, double r)
{
    return __fma_rn(__dmul_rn(h2, om), y, __dmul_rn(oe, r));
}

template <int NT> __device__ double dot(int m, const double *a, const double *b, red &rd)
{
    double s = 0.0;
    for (int j = threadIdx.x; j < m; j += NT) s += a[j] * b[j];
    return block_reduce<NT>(s, 0, rd);
}

/* The bodies of the phases' loops, one row (or contact) each: the
 * block's loops below and the grid's kernels (ncp_cuda_grid.cu) run the
 * same code. */

/* evaluate_rows (ncp_step.c) for row j: phi, omega, e (not friction rows). */
__device__ __forceinline__ void eval_row(int j, const pl_ncp_cuda_rows &R,
                                         const pl_ncp_cuda_vecs &V, const pl_ncp_cuda_params &P)
{
    const int k = R.kind[j];
    const double d = V.delta[j], l = V.lambda[j];
    if (k == PL_ROW_BILATERAL) {
        ncp_bilateral(d, l, R.compliance[j], &V.phi[j], &V.omega[j], &V.e[j]);
    } else if (k == PL_ROW_NORMAL) {
        ncp_normal(P.fn, d, l, R.r[j], P.fb_eps, &V.phi[j], &V.omega[j], &V.e[j]);
    } else if (k == PL_ROW_BOUNDED) {
        ncp_bounded(d, l, R.lo[j], R.hi[j], R.r[j], &V.phi[j], &V.omega[j], &V.e[j]);
    }
}

/* evaluate_rows for contact c: its friction rows' phi, omega, e. */
__device__ __forceinline__ void eval_contact(int c, const pl_ncp_cuda_rows &R,
                                             const pl_ncp_cuda_vecs &V,
                                             const pl_ncp_cuda_params &P)
{
    const int *ct = R.contact + 3 * c;
    int nt = 0, t[2];
    double y[2], lf[2], phi[2], om, e;
    for (int i = 1; i <= 2; ++i)
        if (ct[i] >= 0) {
            t[nt] = ct[i];
            y[nt] = V.delta[ct[i]];
            lf[nt] = V.lambda[ct[i]];
            ++nt;
        }
    if (nt == 0) return;
    ncp_friction(P.fn, nt, y, lf, V.lambda[ct[0]], R.mu[ct[0]], P.h * R.r[t[0]], phi, &om, &e);
    for (int i = 0; i < nt; ++i) {
        V.phi[t[i]] = phi[i];
        V.omega[t[i]] = om;
        V.e[t[i]] = e;
    }
}

/* Phase A after evaluate, row j: S, the clamped flag, tmp = S lambda;
 * returns |phi_j|. */
__device__ __forceinline__ double row_a(int j, const pl_ncp_cuda_rows &R,
                                        const pl_ncp_cuda_vecs &V, const pl_ncp_cuda_params &P)
{
    int c;
    double s;
    if (P.full_force) {
        s = 1.0;
        c = !(V.omega[j] > PL_NCP_OMEGA_CLAMP);
    } else {
        s = R.kind[j] == PL_ROW_BOUNDED ? 1.0 : V.omega[j];
        c = s != V.omega[j];
    }
    V.scale[j] = s;
    V.is_clamped[j] = c;
    V.tmp[j] = s * V.lambda[j];
    return fabs(V.phi[j]);
}

/* Phase B, row j. */
__device__ __forceinline__ void row_b(int j, const pl_ncp_cuda_vecs &V, double h2)
{
    double p = V.delta[j] - V.delta_free[j] - h2 * V.tmp2[j];
    double rhs = -V.phi[j] + V.omega[j] * p;
    const int c = V.is_clamped[j];
    V.dlambda[j] = 0.0;
    V.clamped[j] = c ? rhs / V.e[j] : 0.0;
    V.tmp[j] = c ? V.scale[j] * V.clamped[j] : 0.0;
    V.rhs[j] = c ? 0.0 : rhs;
}

/* Phase C, row j: CR's operator, scaling and start; returns rhs_j^2. */
__device__ __forceinline__ double row_c(int j, const pl_ncp_cuda_rows &R,
                                        const pl_ncp_cuda_vecs &V, const pl_ncp_cuda_params &P,
                                        double h2)
{
    const int c = V.is_clamped[j];
    double rhs = V.rhs[j];
    if (!c) rhs -= h2 * V.omega[j] * V.tmp2[j];
    if (P.full_force) {
        V.op_omega[j] = c ? 0.0 : 1.0;
        V.op_e[j] = c ? V.e[j] : V.e[j] / V.omega[j];
        if (!c) rhs /= V.omega[j];
    } else {
        V.op_omega[j] = V.omega[j];
        V.op_e[j] = V.e[j];
    }
    /* Jacobi scaling (ncp_step): S A S, rhs S, dlambda = S y */
    const double d = h2 * V.op_omega[j] * V.op_omega[j] * R.wdiag[j] + V.op_e[j];
    const double sj = P.cr_jacobi && d > 0.0 && isfinite(d) ? 1.0 / sqrt(d) : 1.0;
    V.cr_s[j] = sj;
    V.op_omega[j] *= sj;
    V.op_e[j] *= sj * sj;
    rhs *= sj;
    V.rhs[j] = rhs;
    V.cr_r[j] = rhs; /* zero initial guess: r = b */
    V.tmp[j] = V.op_omega[j] * rhs;
    return rhs * rhs;
}

/* The merit's part of a row that is not friction: its residual. */
__device__ __forceinline__ double merit_row(int j, const pl_ncp_cuda_rows &R, const double *d0,
                                            const double *dd, const double *l0, const double *dl,
                                            double a)
{
    return ncp_row_residual(R.kind[j], d0[j] + a * dd[j], l0[j] + a * dl[j], R.compliance[j],
                            R.r[j], R.lo[j], R.hi[j]);
}

/* The merit's part of contact c: its friction residual squared (0 without
 * friction rows: *has = 0). */
__device__ __forceinline__ double merit_contact(int c, const pl_ncp_cuda_rows &R,
                                                const pl_ncp_cuda_params &P, const double *d0,
                                                const double *dd, const double *l0,
                                                const double *dl, double a, int *has)
{
    const int *ct = R.contact + 3 * c;
    int nt = 0;
    double y[2], lf[2];
    for (int i = 1; i <= 2; ++i)
        if (ct[i] >= 0) {
            y[nt] = d0[ct[i]] + a * dd[ct[i]];
            lf[nt] = l0[ct[i]] + a * dl[ct[i]];
            ++nt;
        }
    *has = nt > 0;
    if (nt == 0) return 0.0;
    const double rho = P.h * R.r[ct[1] >= 0 ? ct[1] : ct[2]];
    double cone, fric;
    ncp_friction_residual(nt, y, lf, l0[ct[0]] + a * dl[ct[0]], R.mu[ct[0]], rho, &cone, &fric);
    return ncp_friction_residual2(rho, cone, fric);
}

/* The phases that are one assignment a row (LIN, G, LAMBDA, LS0,
 * DLAMBDA), and UPDATE's ddelta (ls1 = h^2 tmp2: PL_NCP_PHASE_UPDATE). */
__device__ __forceinline__ void row_assign(int phase, int j, const pl_ncp_cuda_vecs &V, double h2)
{
    switch (phase) {
    case PL_NCP_PHASE_LIN: V.delta[j] = V.ls0[j] = V.delta_free[j] + h2 * V.tmp2[j]; break;
    case PL_NCP_PHASE_G: V.dlambda[j] = V.cr_s[j] * V.dlambda[j] + V.clamped[j]; break;
    case PL_NCP_PHASE_LAMBDA: V.force[j] = V.scale[j] * V.lambda[j]; break;
    case PL_NCP_PHASE_LS0: V.ls0[j] = V.delta_free[j] + h2 * V.tmp2[j]; break;
    case PL_NCP_PHASE_DLAMBDA: V.force[j] = V.scale[j] * V.dlambda[j]; break;
    case PL_NCP_PHASE_UPDATE: V.ls1[j] = h2 * V.tmp2[j]; break;
    default: break;
    }
}

/* lambda_j += step dlambda_j, projected as a row. */
__device__ __forceinline__ void update_row(int j, const pl_ncp_cuda_rows &R,
                                           const pl_ncp_cuda_vecs &V, const pl_ncp_cuda_params &P,
                                           double step)
{
    double l = V.lambda[j] + step * V.dlambda[j];
    if (P.project) l = ncp_project_row(R.kind[j], l, R.lo[j], R.hi[j]);
    V.lambda[j] = l;
}

/* evaluate_rows (ncp_step.c): phi, omega, e of every row; friction per contact. */
template <int NT>
__device__ void evaluate(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                         const pl_ncp_cuda_params &P)
{
    for (int j = threadIdx.x; j < R.m; j += NT) eval_row(j, R, V, P);
    for (int c = threadIdx.x; c < R.nc; c += NT) eval_contact(c, R, V, P);
}

/* The residual's 2-norm at (delta0 + a ddelta, lambda + a dlambda). */
template <int NT>
__device__ double merit(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_params &P, const double *d0,
                        const double *dd, const double *l0, const double *dl, double a, red &rd)
{
    double ss = 0.0;
    for (int j = threadIdx.x; j < R.m; j += NT) {
        if (R.kind[j] == PL_ROW_FRICTION) continue;
        const double v = merit_row(j, R, d0, dd, l0, dl, a);
        ss += v * v;
    }
    for (int c = threadIdx.x; c < R.nc; c += NT) {
        int has;
        const double v = merit_contact(c, R, P, d0, dd, l0, dl, a, &has);
        if (has) ss += v;
    }
    return sqrt(block_reduce<NT>(ss, 0, rd));
}

/* lambda += damping alpha dlambda, then ncp_project. */
template <int NT>
__device__ void update(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                       const pl_ncp_cuda_params &P, double alpha)
{
    const double step = P.damping * alpha;
    for (int j = threadIdx.x; j < R.m; j += NT) update_row(j, R, V, P, step);
    sync_nt<NT>();
    if (P.project)
        for (int c = threadIdx.x; c < R.nc; c += NT) {
            const int *ct = R.contact + 3 * c;
            ncp_project_contact(ct, R.mu[ct[0]], V.lambda);
        }
    sync_nt<NT>();
    for (int j = threadIdx.x; j < R.m; j += NT) V.lambda_all[R.full[j]] = V.lambda[j];
}

/* CR phase E: x, r update, stop test; tmp = ox (see ncp_cuda.h). */
template <int NT>
__device__ void cr_e(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                     const pl_ncp_cuda_params &P, int last, red &rd)
{
    pl_ncp_cuda_scalars *sc = V.sc;
    const int m = R.m, t0 = threadIdx.x == 0;
    if (sc->done) return;
    const double ApAp = dot<NT>(m, V.cr_Ap, V.cr_Ap, rd), rAr = sc->rAr;
    if (!(ApAp > 0.0) || rAr == 0.0) {
        if (t0) sc->done = 1;
        return;
    }
    const double alpha = rAr / ApAp;
    double ss = 0.0;
    for (int j = threadIdx.x; j < m; j += NT) {
        V.dlambda[j] += alpha * V.cr_p[j];
        const double r = V.cr_r[j] - alpha * V.cr_Ap[j];
        V.cr_r[j] = r;
        ss += r * r;
    }
    const double rnorm = sqrt(block_reduce<NT>(ss, 0, rd));
    const int stop = !isfinite(rnorm) || rnorm <= P.cr_rtol * sc->bnorm;
    if (!stop && !last)
        for (int j = threadIdx.x; j < m; j += NT) V.tmp[j] = V.op_omega[j] * V.cr_r[j];
    sync_nt<NT>();
    if (t0) {
        sc->rnorm = rnorm;
        if (!isfinite(rnorm)) sc->error = 2;
        if (stop)
            sc->done = 1;
        else
            sc->its += 1; /* the product that follows */
    }
}

/* CR phase F: Ar from tmp2, beta, p, Ap. */
template <int NT>
__device__ void cr_f(const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                     const pl_ncp_cuda_params &P, red &rd)
{
    pl_ncp_cuda_scalars *sc = V.sc;
    const int m = R.m;
    const double h2 = P.h * P.h;
    if (sc->done) return;
    double s = 0.0;
    for (int j = threadIdx.x; j < m; j += NT) {
        const double ar = cr_ar(h2, V.op_omega[j], V.tmp2[j], V.op_e[j], V.cr_r[j]);
        V.cr_Ar[j] = ar;
        s += V.cr_r[j] * ar;
    }
    const double rAr_new = block_reduce<NT>(s, 0, rd);
    const double beta = rAr_new / sc->rAr;
    for (int j = threadIdx.x; j < m; j += NT) {
        V.cr_p[j] = V.cr_r[j] + beta * V.cr_p[j];
        V.cr_Ap[j] = V.cr_Ar[j] + beta * V.cr_Ap[j];
    }
    sync_nt<NT>();
    if (threadIdx.x == 0) sc->rAr = rAr_new;
}

/* One phase by the NT threads (k_phase: a block; the fused update runs
 * them in turn, by its block or its first warp). */
template <int NT>
__device__ void run_phase(int phase, const pl_ncp_cuda_rows &R, const pl_ncp_cuda_vecs &V,
                          const pl_ncp_cuda_params &P, int last, red &rd)
{
    pl_ncp_cuda_scalars *sc = V.sc;
    const int m = R.m, t0 = threadIdx.x == 0;
    const double h2 = P.h * P.h;
    switch (phase) {
    case PL_NCP_PHASE_LIN:
    case PL_NCP_PHASE_G:
    case PL_NCP_PHASE_LAMBDA:
    case PL_NCP_PHASE_LS0:
    case PL_NCP_PHASE_DLAMBDA:
        for (int j = threadIdx.x; j < m; j += NT) row_assign(phase, j, V, h2);
        break;
    case PL_NCP_PHASE_A: {
        evaluate<NT>(R, V, P);
        sync_nt<NT>();
        double phin = 0.0;
        for (int j = threadIdx.x; j < m; j += NT) phin = fmax(phin, row_a(j, R, V, P));
        phin = block_reduce<NT>(phin, 1, rd);
        if (t0) sc->phin = phin;
        break;
    }
    case PL_NCP_PHASE_B:
        for (int j = threadIdx.x; j < m; j += NT) row_b(j, V, h2);
        break;
    case PL_NCP_PHASE_C: {
        double ss = 0.0;
        for (int j = threadIdx.x; j < m; j += NT) ss += row_c(j, R, V, P, h2);
        const double bnorm = sqrt(block_reduce<NT>(ss, 0, rd));
        if (t0) {
            sc->bnorm = sc->rnorm = bnorm;
            sc->its = 0;
            sc->done = !isfinite(bnorm) || bnorm == 0.0 || bnorm <= P.cr_rtol * bnorm;
            if (!isfinite(bnorm)) sc->error = 1;
        }
        break;
    }
    case PL_NCP_PHASE_D: {
        if (sc->done) break;
        double s = 0.0;
        for (int j = threadIdx.x; j < m; j += NT) {
            const double ar = cr_ar(h2, V.op_omega[j], V.tmp2[j], V.op_e[j], V.cr_r[j]);
            V.cr_Ar[j] = V.cr_Ap[j] = ar;
            V.cr_p[j] = V.cr_r[j];
            s += V.cr_r[j] * ar;
        }
        s = block_reduce<NT>(s, 0, rd);
        if (t0) sc->rAr = s, sc->its = 1;
        break;
    }
    case PL_NCP_PHASE_E:
        cr_e<NT>(R, V, P, last, rd);
        break;
    case PL_NCP_PHASE_F:
        cr_f<NT>(R, V, P, rd);
        break;
    case PL_NCP_PHASE_UPDATE: {
        double alpha = 1.0;
        if (P.line_search) {
            /* ncp_line_search: ddelta = h^2 W S dlambda, then halvings */
            for (int j = threadIdx.x; j < m; j += NT) row_assign(PL_NCP_PHASE_UPDATE, j, V, h2);
            sync_nt<NT>();
            const double m0 = merit<NT>(R, P, V.ls0, V.ls1, V.lambda, V.dlambda, 0.0, rd);
            int bad = !isfinite(m0);
            double a = 1.0;
            for (int t = 0; t <= 3 && !bad; ++t, a *= 0.5) {
                const double mt = merit<NT>(R, P, V.ls0, V.ls1, V.lambda, V.dlambda, a, rd);
                if (!isfinite(mt)) {
                    bad = 1;
                    break;
                }
                if (mt <= (1.0 - 1e-4 * a) * m0) {
                    alpha = a;
                    break;
                }
            }
            if (bad && t0) sc->error = 3;
        }
        update<NT>(R, V, P, alpha);
        if (t0) {
            const int k = sc->iter;
            if (k < V.series_cap) {
                double *s = V.series + 4 * (size_t)k;
                s[0] = sc->phin;
                s[1] = sc->its;
                s[2] = sc->bnorm > 0.0 ? sc->rnorm / sc->bnorm : 0.0;
                s[3] = alpha;
            }
            sc->iter = k + 1;
        }
        break;
    }
    default:
        break;
    }
}

} // namespace

#endif
