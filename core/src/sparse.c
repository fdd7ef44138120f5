/* sparse.c - triplets and their compression to CSC (CSparse's cs_compress
 * and cs_dupl, in one pass over a column count). */
#include "pliant/sparse.h"
#include "pliant/error.h"

#include <stdlib.h>
#include <string.h>

int pl_triplets_init(pl_triplets *t, int nrows, int ncols, int cap)
{
    memset(t, 0, sizeof *t);
    t->nrows = nrows;
    t->ncols = ncols;
    if (cap < 16) cap = 16;
    t->i = malloc((size_t)cap * sizeof *t->i);
    t->j = malloc((size_t)cap * sizeof *t->j);
    t->x = malloc((size_t)cap * sizeof *t->x);
    if (!t->i || !t->j || !t->x) {
        pl_triplets_free(t);
        return PL_EINTERNAL;
    }
    t->cap = cap;
    return PL_OK;
}

void pl_triplets_free(pl_triplets *t)
{
    free(t->i);
    free(t->j);
    free(t->x);
    memset(t, 0, sizeof *t);
}

int pl_triplets_add(pl_triplets *t, int i, int j, double x)
{
    if (t->nnz == t->cap) {
        int cap = t->cap ? 2 * t->cap : 16;
        int *ni = realloc(t->i, (size_t)cap * sizeof *ni);
        if (!ni) return PL_EINTERNAL;
        t->i = ni;
        int *nj = realloc(t->j, (size_t)cap * sizeof *nj);
        if (!nj) return PL_EINTERNAL;
        t->j = nj;
        double *nx = realloc(t->x, (size_t)cap * sizeof *nx);
        if (!nx) return PL_EINTERNAL;
        t->x = nx;
        t->cap = cap;
    }
    t->i[t->nnz] = i;
    t->j[t->nnz] = j;
    t->x[t->nnz] = x;
    t->nnz++;
    return PL_OK;
}

/* Counting sort by column, then by row inside each column, then summing
 * duplicates: the result has sorted, unique row indices per column. */
int pl_triplets_to_csc(const pl_triplets *t, pl_csc *out)
{
    int n = t->ncols, nnz = t->nnz;
    memset(out, 0, sizeof *out);
    int *cp = calloc((size_t)n + 1, sizeof *cp);
    int *rp = calloc((size_t)t->nrows + 1, sizeof *rp);
    int *tmp_j = malloc((size_t)(nnz ? nnz : 1) * sizeof *tmp_j);
    int *tmp_i = malloc((size_t)(nnz ? nnz : 1) * sizeof *tmp_i);
    double *tmp_x = malloc((size_t)(nnz ? nnz : 1) * sizeof *tmp_x);
    int *ai = malloc((size_t)(nnz ? nnz : 1) * sizeof *ai);
    double *ax = malloc((size_t)(nnz ? nnz : 1) * sizeof *ax);
    if (!cp || !rp || !tmp_j || !tmp_i || !tmp_x || !ai || !ax) goto fail;
    /* sort by row first (stable), then by column: rows end up sorted in columns */
    for (int k = 0; k < nnz; ++k) rp[t->i[k] + 1]++;
    for (int r = 0; r < t->nrows; ++r) rp[r + 1] += rp[r];
    for (int k = 0; k < nnz; ++k) {
        int q = rp[t->i[k]]++;
        tmp_i[q] = t->i[k];
        tmp_j[q] = t->j[k];
        tmp_x[q] = t->x[k];
    }
    for (int k = 0; k < nnz; ++k) cp[tmp_j[k] + 1]++;
    for (int c = 0; c < n; ++c) cp[c + 1] += cp[c];
    int *next = rp; /* reuse as column cursor (n <= nrows not assumed: realloc) */
    if (n > t->nrows) {
        next = realloc(rp, ((size_t)n + 1) * sizeof *next);
        if (!next) goto fail;
        rp = next;
    }
    for (int c = 0; c <= n; ++c) next[c] = cp[c];
    for (int k = 0; k < nnz; ++k) {
        int q = next[tmp_j[k]]++;
        ai[q] = tmp_i[k];
        ax[q] = tmp_x[k];
    }
    /* sum duplicates in place */
    int w = 0;
    for (int c = 0; c < n; ++c) {
        int start = w;
        for (int q = cp[c]; q < cp[c + 1]; ++q) {
            if (w > start && ai[w - 1] == ai[q])
                ax[w - 1] += ax[q];
            else {
                ai[w] = ai[q];
                ax[w] = ax[q];
                w++;
            }
        }
        cp[c] = start;
    }
    cp[n] = w;
    free(rp);
    free(tmp_i);
    free(tmp_j);
    free(tmp_x);
    out->nrows = t->nrows;
    out->ncols = n;
    out->p = cp;
    out->i = ai;
    out->x = ax;
    return PL_OK;
fail:
    free(cp);
    free(rp);
    free(tmp_i);
    free(tmp_j);
    free(tmp_x);
    free(ai);
    free(ax);
    return PL_EINTERNAL;
}

void pl_csc_free(pl_csc *a)
{
    free(a->p);
    free(a->i);
    free(a->x);
    memset(a, 0, sizeof *a);
}

void pl_csr_free(pl_csr *a)
{
    free(a->p);
    free(a->j);
    free(a->x);
    memset(a, 0, sizeof *a);
}
