/* spinv_cuda_wdiag.cu - the diagonal of W = H A^-1 H^T alone, on the device:
 * the scaling of a matrix-free W (the contact solver's matrix-free path on
 * the device; before, the host built it from Y = S P H^T, the larger part of
 * the Schur phase of the large contact scenes).
 *
 * With A^-1 = P^T S^T S P, a scalar row h gives W_hh = |S P h^T|^2, and
 * S P h^T = sum_a h_a S(:, c_a) over the row's unknowns a (c_a: the column
 * of S).  Column c of S = L^-1 is nonzero exactly on the etree path from c
 * to its root (row i of S holds the descendants of i: sparse_inverse.h), so
 * one thread walks the union of its row's paths from the bottom, node by
 * node: at node i = the smallest of the walkers' current nodes, the entry
 * is v_i = sum of h_a S(i, c_a) over the walkers standing on i, which then
 * step to parent(i).  Paths that meet walk on together; no search, no
 * sort, n_path reads per unknown.  The row's three coordinates share their
 * unknowns (a contact row's vertices), so one walk over the union of their
 * unknowns makes all three, each S(i, c_a) read once for the three.
 * Deterministic: one thread per row, a fixed order.  Rows with more than
 * MAX_WALK unknowns in all (no contact row: a vertex-face or edge-edge row
 * has 4) get a NaN, and the caller's host path makes those. */
#include "spinv_cuda_internal.h"

#include <math.h>

namespace {

enum { MAX_WALK = 16 };

/* The union of row j's unknowns over its three coordinates into col (their
 * columns of S) and h (coefficients, 3 a walker, 0 where a coordinate lacks
 * it); the walkers' count, or -1 past MAX_WALK. */
__device__ int row_walkers(int m, int j, const int *rp, const int *ru, const double *rx,
                           const int *pos, int *col, double (*h)[3])
{
    int cnt = 0;
    for (int k = 0; k < 3; ++k) {
        const int r = k * m + j;
        for (int e = rp[r]; e < rp[r + 1]; ++e) {
            const int c = pos[ru[e]];
            int t = 0;
            while (t < cnt && col[t] != c) ++t;
            if (t == cnt) {
                if (cnt == MAX_WALK) return -1;
                col[cnt] = c;
                h[cnt][0] = h[cnt][1] = h[cnt][2] = 0.0;
                ++cnt;
            }
            h[t][k] += rx[e];
        }
    }
    return cnt;
}

template <typename T>
__global__ void wdiag(int m, const int *rp, const int *ru, const double *rx, const int *pos,
                      const int *parent, const pl_spinv_cuda_rowmeta *meta, const T *val,
                      double *diag)
{
    for (int j = blockIdx.x * blockDim.x + threadIdx.x; j < m; j += gridDim.x * blockDim.x) {
        int col[MAX_WALK], at[MAX_WALK];
        double h[MAX_WALK][3];
        const int cnt = row_walkers(m, j, rp, ru, rx, pos, col, h);
        if (cnt < 0) {
            diag[j] = NAN;
            continue;
        }
        for (int t = 0; t < cnt; ++t) at[t] = col[t];
        double s[3] = {0.0, 0.0, 0.0};
        for (;;) {
            int i = -1;
            for (int t = 0; t < cnt; ++t)
                if (at[t] >= 0 && (i < 0 || at[t] < i)) i = at[t];
            if (i < 0) break;
            const pl_spinv_cuda_rowmeta mi = meta[i];
            double v[3] = {0.0, 0.0, 0.0};
            for (int t = 0; t < cnt; ++t)
                if (at[t] == i) {
                    const double sv = (double)val[mi.vbase + col[t]];
                    for (int k = 0; k < 3; ++k) v[k] += h[t][k] * sv;
                    at[t] = parent[i];
                }
            for (int k = 0; k < 3; ++k) s[k] += v[k] * v[k];
        }
        diag[j] = s[0] + s[1] + s[2];
    }
}

} // namespace

int spinv_cuda_launch_wdiag(pl_spinv_cuda *g, const pl_spinv_cuda_drows *A, double *diag,
                            cudaStream_t st, pl_error *err)
{
    int m = A->m, threads = 128, blocks = (m + threads - 1) / threads;
    if (blocks < 1) blocks = 1;
    if (g->prec == PL_F32)
        wdiag<float><<<blocks, threads, 0, st>>>(m, A->rp, A->ru, A->rx, A->pos, g->parent, g->meta,
                                                 (const float *)g->val, diag);
    else
        wdiag<double><<<blocks, threads, 0, st>>>(m, A->rp, A->ru, A->rx, A->pos, g->parent, g->meta,
                                                  (const double *)g->val, diag);
    SPINV_CK(cudaGetLastError(), "Delassus: W's diagonal");
    return PL_OK;
}
