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
 * sort, n_path reads per unknown.  Deterministic: one thread per row, a
 * fixed order.  Rows with more than MAX_WALK unknowns per scalar row (no
 * contact row: a vertex-face or edge-edge row has 4) get a NaN, and the
 * caller's host path makes those. */
#include "spinv_cuda_internal.h"

#include <math.h>

namespace {

enum { MAX_WALK = 16 };

template <typename T>
__global__ void wdiag(int m, const int *rp, const int *ru, const double *rx, const int *pos,
                      const int *parent, const pl_spinv_cuda_rowmeta *meta, const T *val,
                      double *diag)
{
    for (int j = blockIdx.x * blockDim.x + threadIdx.x; j < m; j += gridDim.x * blockDim.x) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k) {
            int r = k * m + j, a0 = rp[r], cnt = rp[r + 1] - a0;
            if (cnt > MAX_WALK) {
                s = NAN;
                break;
            }
            int col[MAX_WALK], at[MAX_WALK];
            double h[MAX_WALK];
            for (int t = 0; t < cnt; ++t) {
                col[t] = at[t] = pos[ru[a0 + t]];
                h[t] = rx[a0 + t];
            }
            for (;;) {
                int i = -1;
                for (int t = 0; t < cnt; ++t)
                    if (at[t] >= 0 && (i < 0 || at[t] < i)) i = at[t];
                if (i < 0) break;
                const pl_spinv_cuda_rowmeta mi = meta[i];
                double v = 0.0;
                for (int t = 0; t < cnt; ++t)
                    if (at[t] == i) {
                        v += h[t] * (double)val[mi.vbase + col[t]];
                        at[t] = parent[i];
                    }
                s += v * v;
            }
        }
        diag[j] = s;
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
