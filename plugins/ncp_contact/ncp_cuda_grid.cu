/* ncp_cuda_grid.cu - the constraint update's phases (ncp_cuda.h) over a
 * grid of blocks, for many rows.  One block's phase kernel walks every row
 * with 512 threads: with 28.6k rows (the sharp corner 10.2k) its launches
 * took 66-90 us each, most of the device's time of a step.  Here the rows
 * and contacts are spread over a grid, and each reduction that a phase
 * needs before it can go on ends a kernel: every block writes its partial
 * (block_reduce's fixed tree) to a slot of V->part, and each block of the
 * next kernel combines the slot's partials by the same fixed tree, so all
 * blocks hold the same bits, without atomics.  So do places where a
 * contact reads rows that other blocks write (the evaluation after LIN,
 * the projection after the update).  The grid (from the rows' capacity)
 * fixes the order of the sums: deterministic, graph or not, but not the
 * single block's bits.  The per-row code is the block's own
 * (ncp_cuda_phases.cuh).
 *
 * Nothing a kernel reads from the scalars (sc) is written by that kernel:
 * they are written by the last kernel of C, of E (e4, which learns from
 * e3's flag whether CR was still running) and of UPDATE. */
#include "ncp_cuda_phases.cuh"

namespace {

constexpr int kMax = NCP_CUDA_GRID_MAX_BLOCKS;
/* slots of partials: CR's r.Ar, Ap.Ap, r.r; A's max |phi|; C's rhs.rhs;
 * the line search's five merits (step 0, 1, 1/2, 1/4, 1/8) */
enum { SLOT_RAR, SLOT_APAP, SLOT_RR, SLOT_PHIN, SLOT_BB, SLOT_M0, NSLOTS = SLOT_M0 + 5 };
static_assert(NCP_CUDA_GRID_PART >= NSLOTS * kMax + 2, "NCP_CUDA_GRID_PART");
static_assert(kMax <= kThreads, "combine: a thread a block's partial");
constexpr int PART_FLAG = NSLOTS * kMax;      /* e3: 0 CR had stopped, 1 running, 2 a zero step */
constexpr int PART_ALPHA = NSLOTS * kMax + 1; /* the update's step length */

__device__ __forceinline__ int first_row() { return blockIdx.x * kThreads + threadIdx.x; }
__device__ __forceinline__ int row_stride() { return gridDim.x * kThreads; }

/* Slot s's combination over the nb blocks that wrote it (max: maximum, else
 * sum); each block gets the same bits. */
__device__ double combine(const double *part, int s, int nb, int max, red &rd)
{
    const double v = threadIdx.x < nb ? part[s * kMax + threadIdx.x] : 0.0;
    return block_reduce<kThreads>(v, max, rd);
}
__device__ double total(const double *part, int s, red &rd) { return combine(part, s, gridDim.x, 0, rd); }

/* Thread 0 writes the block's partial v (already reduced) to slot s. */
__device__ __forceinline__ void put(double *part, int s, double v)
{
    if (threadIdx.x == 0) part[s * kMax + blockIdx.x] = v;
}

/* The one-assignment phases p and then q (q < 0: none): row_assign. */
__global__ void __launch_bounds__(kThreads)
    k_rows(int p, int q, const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V,
           pl_ncp_cuda_params P)
{
    const int m = Rp->m;
    const double h2 = P.h * P.h;
    for (int j = first_row(); j < m; j += row_stride()) {
        row_assign(p, j, V, h2);
        if (q >= 0) row_assign(q, j, V, h2);
    }
}

/* Phase B: one row each (row_b). */
__global__ void __launch_bounds__(kThreads)
    k_b(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    const int m = Rp->m;
    const double h2 = P.h * P.h;
    for (int j = first_row(); j < m; j += row_stride()) row_b(j, V, h2);
}

/* Phase A, first half: phi, omega, e of the rows and of the contacts'
 * friction rows (evaluate). */
__global__ void __launch_bounds__(kThreads)
    k_eval(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    const pl_ncp_cuda_rows R = *Rp;
    for (int j = first_row(); j < R.m; j += row_stride()) eval_row(j, R, V, P);
    for (int c = first_row(); c < R.nc; c += row_stride()) eval_contact(c, R, V, P);
}

/* Phase A, second half: row_a; partials of max |phi| (UPDATE writes phin). */
__global__ void __launch_bounds__(kThreads)
    k_a(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const pl_ncp_cuda_rows R = *Rp;
    double phin = 0.0;
    for (int j = first_row(); j < R.m; j += row_stride()) phin = fmax(phin, row_a(j, R, V, P));
    put(V.part, SLOT_PHIN, block_reduce<kThreads>(phin, 1, rd));
}

/* Phase C: row_c; partials of rhs.rhs. */
__global__ void __launch_bounds__(kThreads)
    k_c(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const pl_ncp_cuda_rows R = *Rp;
    const double h2 = P.h * P.h;
    double ss = 0.0;
    for (int j = first_row(); j < R.m; j += row_stride()) ss += row_c(j, R, V, P, h2);
    put(V.part, SLOT_BB, block_reduce<kThreads>(ss, 0, rd));
}

/* Phase C's scalars (one block): bnorm from the nb partials, CR's start. */
__global__ void __launch_bounds__(kThreads) k_c_scalars(pl_ncp_cuda_vecs V, pl_ncp_cuda_params P, int nb)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const double bnorm = sqrt(combine(V.part, SLOT_BB, nb, 0, rd));
    if (threadIdx.x == 0) {
        pl_ncp_cuda_scalars *sc = V.sc;
        sc->bnorm = sc->rnorm = bnorm;
        sc->its = 0;
        sc->done = !isfinite(bnorm) || bnorm == 0.0 || bnorm <= P.cr_rtol * bnorm;
        if (!isfinite(bnorm)) sc->error = 1;
    }
}

/* D: Ar from tmp2, p = r, Ap = Ar; partials of r.Ar and Ap.Ap. */
__global__ void __launch_bounds__(kThreads)
    k_cr_d(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    if (V.sc->done) return;
    const int m = Rp->m;
    const double h2 = P.h * P.h;
    double s = 0.0, a = 0.0;
    for (int j = first_row(); j < m; j += row_stride()) {
        const double ar = cr_ar(h2, V.op_omega[j], V.tmp2[j], V.op_e[j], V.cr_r[j]);
        V.cr_Ar[j] = V.cr_Ap[j] = ar;
        V.cr_p[j] = V.cr_r[j];
        s += V.cr_r[j] * ar;
        a += ar * ar;
    }
    block_reduce2<kThreads>(s, a, rd);
    put(V.part, SLOT_RAR, s);
    put(V.part, SLOT_APAP, a);
}

/* F, first half: Ar from tmp2; partials of r.Ar (the new rAr). */
__global__ void __launch_bounds__(kThreads)
    k_cr_f(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    if (V.sc->done) return;
    const int m = Rp->m;
    const double h2 = P.h * P.h;
    double s = 0.0;
    for (int j = first_row(); j < m; j += row_stride()) {
        const double ar = cr_ar(h2, V.op_omega[j], V.tmp2[j], V.op_e[j], V.cr_r[j]);
        V.cr_Ar[j] = ar;
        s += V.cr_r[j] * ar;
    }
    put(V.part, SLOT_RAR, block_reduce<kThreads>(s, 0, rd));
}

/* F, second half: beta = new rAr / old (sc->rAr, written by e4 only), p,
 * Ap; partials of Ap.Ap. */
__global__ void __launch_bounds__(kThreads)
    k_cr_f2(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    if (V.sc->done) return;
    const int m = Rp->m;
    const double beta = total(V.part, SLOT_RAR, rd) / V.sc->rAr;
    double a = 0.0;
    for (int j = first_row(); j < m; j += row_stride()) {
        V.cr_p[j] = V.cr_r[j] + beta * V.cr_p[j];
        const double ap = V.cr_Ar[j] + beta * V.cr_Ap[j];
        V.cr_Ap[j] = ap;
        a += ap * ap;
    }
    put(V.part, SLOT_APAP, block_reduce<kThreads>(a, 0, rd));
}

/* E, first half: alpha = rAr / Ap.Ap, x and r; partials of r.r; the flag. */
__global__ void __launch_bounds__(kThreads)
    k_cr_e3(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const int t0 = blockIdx.x == 0 && threadIdx.x == 0;
    if (V.sc->done) {
        if (t0) V.part[PART_FLAG] = 0.0;
        return;
    }
    const double rAr = total(V.part, SLOT_RAR, rd), ApAp = total(V.part, SLOT_APAP, rd);
    if (!(ApAp > 0.0) || rAr == 0.0) {
        if (t0) V.part[PART_FLAG] = 2.0;
        return;
    }
    const int m = Rp->m;
    const double alpha = rAr / ApAp;
    double ss = 0.0;
    for (int j = first_row(); j < m; j += row_stride()) {
        V.dlambda[j] += alpha * V.cr_p[j];
        const double r = V.cr_r[j] - alpha * V.cr_Ap[j];
        V.cr_r[j] = r;
        ss += r * r;
    }
    put(V.part, SLOT_RR, block_reduce<kThreads>(ss, 0, rd));
    if (t0) V.part[PART_FLAG] = 1.0;
}

/* E, second half: the stop test, tmp = ox for the next product, and the
 * scalars (rAr, rnorm, its, done) as phases D/F and E leave them. */
__global__ void __launch_bounds__(kThreads)
    k_cr_e4(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P,
            int first, int last)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const double flag = V.part[PART_FLAG];
    if (flag == 0.0) return;
    pl_ncp_cuda_scalars *sc = V.sc;
    const int t0 = blockIdx.x == 0 && threadIdx.x == 0;
    const double rAr = total(V.part, SLOT_RAR, rd);
    if (flag == 2.0) {
        if (t0) {
            sc->rAr = rAr;
            if (first) sc->its = 1;
            sc->done = 1;
        }
        return;
    }
    const double rnorm = sqrt(total(V.part, SLOT_RR, rd));
    const int stop = !isfinite(rnorm) || rnorm <= P.cr_rtol * sc->bnorm;
    const int m = Rp->m;
    if (!stop && !last)
        for (int j = first_row(); j < m; j += row_stride()) V.tmp[j] = V.op_omega[j] * V.cr_r[j];
    if (t0) {
        const int its = first ? 1 : sc->its;
        sc->rAr = rAr;
        sc->rnorm = rnorm;
        if (!isfinite(rnorm)) sc->error = 2;
        if (stop)
            sc->done = 1, sc->its = its;
        else
            sc->its = its + 1; /* the product that follows */
    }
}

/* the line search's trial t: 0, then 1 halved (exact) */
__device__ __forceinline__ double trial(int t) { return t ? 1.0 / (double)(1 << (t - 1)) : 0.0; }

/* UPDATE's line search, first half: partials of the squared merit at the
 * five step lengths it may try (ncp_line_search: 0, then 1 halved up to
 * three times), the block's merit code at each. */
__global__ void __launch_bounds__(kThreads)
    k_merits(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const pl_ncp_cuda_rows R = *Rp;
    for (int t = 0; t < 5; ++t) {
        const double a = trial(t);
        double ss = 0.0;
        for (int j = first_row(); j < R.m; j += row_stride()) {
            if (R.kind[j] == PL_ROW_FRICTION) continue;
            const double v = merit_row(j, R, V.ls0, V.ls1, V.lambda, V.dlambda, a);
            ss += v * v;
        }
        for (int c = first_row(); c < R.nc; c += row_stride()) {
            int has;
            const double v = merit_contact(c, R, P, V.ls0, V.ls1, V.lambda, V.dlambda, a, &has);
            if (has) ss += v;
        }
        put(V.part, SLOT_M0 + t, block_reduce<kThreads>(ss, 0, rd));
    }
}

/* UPDATE, second half: the step length (the first trial that decreases the
 * merit enough, as the block's loop takes it; 1 without line search),
 * lambda += damping alpha dlambda projected row by row, lambda_all. */
__global__ void __launch_bounds__(kThreads)
    k_update_rows(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V,
                  pl_ncp_cuda_params P)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const pl_ncp_cuda_rows R = *Rp;
    const int t0 = blockIdx.x == 0 && threadIdx.x == 0;
    double alpha = 1.0;
    if (P.line_search) {
        double mt[5];
        for (int t = 0; t < 5; ++t) mt[t] = sqrt(total(V.part, SLOT_M0 + t, rd));
        int bad = !isfinite(mt[0]);
        for (int t = 1; t <= 4 && !bad; ++t) {
            if (!isfinite(mt[t])) {
                bad = 1;
                break;
            }
            if (mt[t] <= (1.0 - 1e-4 * trial(t)) * mt[0]) {
                alpha = trial(t);
                break;
            }
        }
        if (bad && t0) V.sc->error = 3;
    }
    if (t0) V.part[PART_ALPHA] = alpha;
    const double step = P.damping * alpha;
    for (int j = first_row(); j < R.m; j += row_stride()) {
        update_row(j, R, V, P, step);
        V.lambda_all[R.full[j]] = V.lambda[j];
    }
}

/* UPDATE, last: each contact's projection (its rows updated by any block
 * before) and their lambda_all; the series and the scalars (block 0). */
__global__ void __launch_bounds__(kThreads)
    k_update_contacts(const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V,
                      pl_ncp_cuda_params P, int nb)
{
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    const pl_ncp_cuda_rows R = *Rp;
    if (P.project)
        for (int c = first_row(); c < R.nc; c += row_stride()) {
            const int *ct = R.contact + 3 * c;
            ncp_project_contact(ct, R.mu[ct[0]], V.lambda);
            for (int i = 0; i < 3; ++i)
                if (ct[i] >= 0) V.lambda_all[R.full[ct[i]]] = V.lambda[ct[i]];
        }
    if (blockIdx.x != 0) return;
    const double phin = combine(V.part, SLOT_PHIN, nb, 1, rd);
    if (threadIdx.x == 0) {
        pl_ncp_cuda_scalars *sc = V.sc;
        sc->phin = phin;
        const int k = sc->iter;
        if (k < V.series_cap) {
            double *s = V.series + 4 * (size_t)k;
            s[0] = phin;
            s[1] = sc->its;
            s[2] = sc->bnorm > 0.0 ? sc->rnorm / sc->bnorm : 0.0;
            s[3] = V.part[PART_ALPHA];
        }
        sc->iter = k + 1;
    }
}

} // namespace

extern "C" int ncp_cuda_grid_blocks(int mcap)
{
    const int b = (mcap + kThreads - 1) / kThreads;
    return b < 1 ? 1 : b > kMax ? kMax : b;
}

extern "C" int ncp_cuda_cr_grid(struct CUstream_st *st, int first, int last,
                                const pl_ncp_cuda_rows *R, int mcap, const pl_ncp_cuda_vecs *V,
                                const pl_ncp_cuda_params *P)
{
    const int nb = ncp_cuda_grid_blocks(mcap);
    if (first) {
        k_cr_d<<<nb, kThreads, 0, st>>>(R, *V, *P);
    } else {
        k_cr_f<<<nb, kThreads, 0, st>>>(R, *V, *P);
        k_cr_f2<<<nb, kThreads, 0, st>>>(R, *V);
    }
    k_cr_e3<<<nb, kThreads, 0, st>>>(R, *V);
    k_cr_e4<<<nb, kThreads, 0, st>>>(R, *V, *P, first, last);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_grid_rows(struct CUstream_st *st, pl_ncp_cuda_phase p, int q,
                                  const pl_ncp_cuda_rows *R, int mcap, const pl_ncp_cuda_vecs *V,
                                  const pl_ncp_cuda_params *P)
{
    const int nb = ncp_cuda_grid_blocks(mcap);
    if (p == PL_NCP_PHASE_B)
        k_b<<<nb, kThreads, 0, st>>>(R, *V, *P);
    else
        k_rows<<<nb, kThreads, 0, st>>>((int)p, q, R, *V, *P);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_grid_a(struct CUstream_st *st, int lin, const pl_ncp_cuda_rows *R,
                               int mcap, const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P)
{
    const int nb = ncp_cuda_grid_blocks(mcap);
    if (lin) k_rows<<<nb, kThreads, 0, st>>>((int)PL_NCP_PHASE_LIN, -1, R, *V, *P);
    k_eval<<<nb, kThreads, 0, st>>>(R, *V, *P);
    k_a<<<nb, kThreads, 0, st>>>(R, *V, *P);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_grid_c(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                               const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P)
{
    const int nb = ncp_cuda_grid_blocks(mcap);
    k_c<<<nb, kThreads, 0, st>>>(R, *V, *P);
    k_c_scalars<<<1, kThreads, 0, st>>>(*V, *P, nb);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_grid_update(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                                    const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P)
{
    const int nb = ncp_cuda_grid_blocks(mcap);
    if (P->line_search) {
        k_rows<<<nb, kThreads, 0, st>>>((int)PL_NCP_PHASE_UPDATE, -1, R, *V, *P); /* ls1 */
        k_merits<<<nb, kThreads, 0, st>>>(R, *V, *P);
    }
    k_update_rows<<<nb, kThreads, 0, st>>>(R, *V, *P);
    k_update_contacts<<<nb, kThreads, 0, st>>>(R, *V, *P, nb);
    return (int)cudaGetLastError();
}
