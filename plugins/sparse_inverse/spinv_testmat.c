/* spinv_testmat.c - test matrices for the sparse inverse (see the header). */
#include "spinv_testmat.h"

#include <stdint.h>
#include <stdlib.h>
#include "pliant/error.h"

int *spinv_grid_tets(int nx, int ny, int nz, int *ntets)
{
    /* the 6 tets of a cube: corner 0 to corner 7 through the corners that
     * add the axes in each of the 6 orders (corner bits: x=1, y=2, z=4) */
    static const int order[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4},
                                    {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
    int nt = 6 * (nx - 1) * (ny - 1) * (nz - 1);
    int *t = malloc((size_t)(nt > 0 ? nt : 1) * 4 * sizeof *t);
    if (!t) return NULL;
    int e = 0;
    for (int k = 0; k + 1 < nz; ++k)
        for (int j = 0; j + 1 < ny; ++j)
            for (int i = 0; i + 1 < nx; ++i)
                for (int o = 0; o < 6; ++o) {
                    int bits = 0;
                    for (int c = 0; c < 4; ++c) {
                        if (c > 0) bits |= order[o][c - 1];
                        t[4 * e + c] = (i + (bits & 1)) + nx * ((j + ((bits >> 1) & 1)) +
                                                               ny * (k + ((bits >> 2) & 1)));
                    }
                    e++;
                }
    *ntets = nt;
    return t;
}

int spinv_grid_matrix(int nx, int ny, int nz, double h2w, pl_csc *A)
{
    if (nx < 2 || ny < 2 || nz < 2) return PL_EINPUT;
    int nt = 0, n = nx * ny * nz;
    int *tets = spinv_grid_tets(nx, ny, nz, &nt);
    if (!tets) return PL_EINTERNAL;
    pl_triplets T;
    if (pl_triplets_init(&T, n, n, 16 * nt + n) != PL_OK) {
        free(tets);
        return PL_EINTERNAL;
    }
    const double vol = 1.0 / 6.0;
    int status = PL_OK;
    for (int e = 0; e < nt && status == PL_OK; ++e) {
        const int *v = tets + 4 * e;
        for (int a = 0; a < 4 && status == PL_OK; ++a) {
            status |= pl_triplets_add(&T, v[a], v[a], vol / 4.0);
            for (int b = 0; b < 4; ++b) {
                if (a == b) continue;
                status |= pl_triplets_add(&T, v[a], v[a], h2w * vol);
                status |= pl_triplets_add(&T, v[a], v[b], -h2w * vol);
            }
        }
    }
    if (status == PL_OK) status = pl_triplets_to_csc(&T, A);
    pl_triplets_free(&T);
    free(tets);
    return status == PL_OK ? PL_OK : PL_EINTERNAL;
}

static uint32_t xorshift(uint32_t *s)
{
    uint32_t x = *s;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return *s = x;
}

int spinv_random_spd(int n, int per_col, unsigned seed, pl_csc *A)
{
    if (n < 1 || per_col < 0) return PL_EINPUT;
    uint32_t st = seed ? seed : 1u;
    double *rowsum = calloc((size_t)n, sizeof *rowsum);
    pl_triplets T;
    if (!rowsum || pl_triplets_init(&T, n, n, 2 * n * per_col + n) != PL_OK) {
        free(rowsum);
        return PL_EINTERNAL;
    }
    int status = PL_OK;
    for (int j = 0; j < n && status == PL_OK; ++j)
        for (int c = 0; c < per_col; ++c) {
            int i = (int)(xorshift(&st) % (uint32_t)n);
            if (i == j) continue;
            double v = 2.0 * (xorshift(&st) / 4294967296.0) - 1.0;
            status |= pl_triplets_add(&T, i, j, v);
            status |= pl_triplets_add(&T, j, i, v);
            rowsum[i] += v < 0 ? -v : v;
            rowsum[j] += v < 0 ? -v : v;
        }
    for (int i = 0; i < n && status == PL_OK; ++i)
        status |= pl_triplets_add(&T, i, i, rowsum[i] + 0.1 + xorshift(&st) / 4294967296.0);
    if (status == PL_OK) status = pl_triplets_to_csc(&T, A);
    pl_triplets_free(&T);
    free(rowsum);
    return status == PL_OK ? PL_OK : PL_EINTERNAL;
}
