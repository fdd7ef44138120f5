/* spinv_cuda_rows.c - the scalar rows of a step renumbered for the device
 * Delassus build (pl_spinv_cuda_rows in spinv_cuda.h): the unknowns they
 * touch, in increasing order, and each one's column of S. */
#include <stdlib.h>
#include <string.h>

#include "spinv_cuda.h"

void spinv_cuda_rows_free(pl_spinv_cuda_rows *R)
{
    free(R->pos);
    free(R->rp);
    free(R->ru);
    free(R->rx);
    memset(R, 0, sizeof *R);
}

int spinv_cuda_rows_build(const pl_csr *H, int m, const int *perm, int n,
                             pl_spinv_cuda_rows *R, pl_error *err)
{
    memset(R, 0, sizeof *R);
    if (H->nrows != 3 * m || H->ncols != n || !perm)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse (cuda): rows of %d x %d for %d constraint rows and %d "
                            "unknowns",
                            H->nrows, H->ncols, m, n);
    size_t nent = (size_t)H->p[3 * m];
    int *ucol = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));   /* unknown -> 0 .. nu-1 */
    int *pinv = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    R->m = m;
    R->rp = malloc(sizeof(int) * (3 * (size_t)m + 1));
    R->ru = malloc(sizeof(int) * (nent > 0 ? nent : 1));
    R->rx = malloc(sizeof(double) * (nent > 0 ? nent : 1));
    R->pos = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    if (!ucol || !pinv || !R->rp || !R->ru || !R->rx || !R->pos) {
        free(ucol), free(pinv);
        spinv_cuda_rows_free(R);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    }
    for (int k = 0; k < n; ++k) pinv[perm[k]] = k, ucol[k] = -1;
    /* unknowns numbered in increasing order: a fixed numbering, whatever
     * the row order (ucol marks the touched ones first) */
    for (size_t e = 0; e < nent; ++e) ucol[H->j[e]] = 0;
    int nu = 0;
    for (int c = 0; c < n; ++c)
        if (ucol[c] >= 0) {
            R->pos[nu] = pinv[c];
            ucol[c] = nu++;
        }
    R->nu = nu;
    memcpy(R->rp, H->p, sizeof(int) * (3 * (size_t)m + 1));
    for (size_t e = 0; e < nent; ++e) {
        R->ru[e] = ucol[H->j[e]];
        R->rx[e] = H->x[e];
    }
    free(ucol), free(pinv);
    return PL_OK;
}
