/* spinv_cuda_layout.c - padded profile values and the kernels' work lists
 * (see spinv_cuda_layout.h). */
#include "spinv_cuda_layout.h"

#include <stdlib.h>
#include <string.h>

#define BLK PL_SPINV_CUDA_BLOCK

void spinv_cuda_layout_free(pl_spinv_cuda_layout *L)
{
    if (!L) return;
    free(L->meta);
    free(L->items_S);
    free(L->short_rows);
    free(L->items_ST);
    free(L->rowlist);
    memset(L, 0, sizeof *L);
}

static int fail(pl_spinv_cuda_layout *L, pl_error *err, const char *msg)
{
    spinv_cuda_layout_free(L);
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cuda layout): %s", msg);
}

/* Blocks of row i: its padded columns f0 .. e over BLK. */
static int row_blocks(const pl_spinv_cuda_rowmeta *m)
{
    return (m->e - m->f0 + 1) / BLK;
}

/* Rows idx .. idx+k-1 of one group: consecutive, one padded first column,
 * each longer than a SHORT row, at most GROUP. */
static int group_size(const pl_spinv_cuda_layout *L, int i)
{
    int k = 1;
    while (k < L->group && i + k < L->n && L->meta[i + k].f0 == L->meta[i].f0 &&
           row_blocks(&L->meta[i + k]) > PL_SPINV_CUDA_SHORT_BLOCKS)
        ++k;
    return k;
}

/* Row items: groups of rows become ceil(U / item_blocks) warp items of
 * near-equal size (U: the group's blocks); SHORT rows go 32 to a warp.
 * fill = 0 counts into *nitems / *nshort, fill = 1 writes. */
static void walk_row_items(pl_spinv_cuda_layout *L, int fill, int *nitems, int *nshort)
{
    int it = 0, ns = 0, parts = 0;
    for (int i = 0; i < L->n;) {
        if (row_blocks(&L->meta[i]) <= PL_SPINV_CUDA_SHORT_BLOCKS) {
            if (fill) L->short_rows[ns] = i;
            ++ns, ++i;
            continue;
        }
        int k = group_size(L, i);
        int U = (L->meta[i + k - 1].e - L->meta[i].f0 + 1) / BLK, per = L->item_blocks;
        int m = (U + per - 1) / per;
        for (int q = 0; fill && q < m; ++q) {
            pl_spinv_cuda_item *t = &L->items_S[it + q];
            t->kind = PL_SPINV_ITEM_ROWS;
            t->idx = i;
            t->lo = (int)((int64_t)U * q / m);
            t->hi = (int)((int64_t)U * (q + 1) / m);
            t->part = m > 1 ? parts + q : -1;
            t->part0 = m > 1 ? parts : -1;
            t->nparts = m;
            t->pad = k;
        }
        it += m;
        if (m > 1) parts += m;
        i += k;
    }
    for (int b = 0; fill && b < (ns + 31) / 32; ++b) {
        int cnt = ns - 32 * b < 32 ? ns - 32 * b : 32;
        L->items_S[it + b] = (pl_spinv_cuda_item){PL_SPINV_ITEM_SHORT, 32 * b, cnt, 0, -1, -1, 1, 1};
    }
    *nitems = it + (ns + 31) / 32;
    *nshort = ns;
    if (fill) L->nparts_S = parts;
}

static int build_row_items(pl_spinv_cuda_layout *L)
{
    int nitems = 0, nshort = 0;
    walk_row_items(L, 0, &nitems, &nshort);
    L->short_rows = malloc((size_t)(nshort > 0 ? nshort : 1) * sizeof *L->short_rows);
    L->items_S = malloc((size_t)(nitems > 0 ? nitems : 1) * sizeof *L->items_S);
    if (!L->short_rows || !L->items_S) return -1;
    walk_row_items(L, 1, &L->nitems_S, &L->nshort);
    return 0;
}

static void tile_row(pl_spinv_cuda_layout *L, int64_t p, int i)
{
    L->rowlist[p].vbase = L->meta[i].vbase;
    L->rowlist[p].f0 = L->meta[i].f0;
    L->rowlist[p].row = i;
}

/* Tile row lists: own rows j0 .. j1, then the ancestors of j1 (row j1 of
 * S^T without its first entry, which is j1 itself). */
static int build_tile_items(pl_spinv_cuda_layout *L, const pl_spinv_runs *ST)
{
    int n = L->n, W = L->tile, nt = (n + W - 1) / W;
    int64_t total = 0, nitems = 0;
    for (int t = 0; t < nt; ++t) {
        int j0 = t * W, j1 = j0 + W - 1 < n - 1 ? j0 + W - 1 : n - 1;
        int64_t len = (j1 - j0 + 1) + (ST->start[j1 + 1] - ST->start[j1]) - 1;
        total += len;
        nitems += (len + PL_SPINV_CUDA_TILE_ROWS - 1) / PL_SPINV_CUDA_TILE_ROWS;
    }
    if (nitems > 0x7fffffff || total > 0x7fffffff) return -1;
    L->rowlist = malloc((size_t)(total > 0 ? total : 1) * sizeof *L->rowlist);
    L->items_ST = malloc((size_t)(nitems > 0 ? nitems : 1) * sizeof *L->items_ST);
    if (!L->rowlist || !L->items_ST) return -1;
    int64_t p = 0;
    int it = 0, parts = 0;
    for (int t = 0; t < nt; ++t) {
        int j0 = t * W, j1 = j0 + W - 1 < n - 1 ? j0 + W - 1 : n - 1;
        int64_t p0 = p;
        for (int i = j0; i <= j1; ++i) tile_row(L, p++, i);
        int64_t r0 = ST->run_ptr[j1], r1 = ST->run_ptr[j1 + 1];
        if (r0 >= r1 || ST->run_col[r0] != j1) return -2;
        for (int64_t r = r0; r < r1; ++r)
            for (int u = (r == r0); u < ST->run_len[r]; ++u) tile_row(L, p++, ST->run_col[r] + u);
        int64_t len = p - p0;
        int k = (int)((len + PL_SPINV_CUDA_TILE_ROWS - 1) / PL_SPINV_CUDA_TILE_ROWS);
        for (int q = 0; q < k; ++q) {
            pl_spinv_cuda_item *x = &L->items_ST[it++];
            x->kind = PL_SPINV_ITEM_TILE;
            x->idx = t;
            x->lo = (int)(p0 + len * q / k);
            x->hi = (int)(p0 + len * (q + 1) / k);
            x->part = k > 1 ? parts + q : -1;
            x->part0 = k > 1 ? parts : -1;
            x->nparts = k;
            x->pad = 0;
        }
        if (k > 1) parts += k;
    }
    L->ntiles = nt;
    L->nitems_ST = it;
    L->nparts_ST = parts;
    L->nrowlist = p;
    return 0;
}

int spinv_cuda_layout_build(const pl_spinv_profile *S, const pl_spinv_runs *ST,
                               int elem_size, int group, int item_blocks,
                               pl_spinv_cuda_layout *L, pl_error *err)
{
    memset(L, 0, sizeof *L);
    if (group == 0) group = PL_SPINV_CUDA_GROUP_DEFAULT;
    if (group != 1 && group != 2 && group != 4 && group != 8)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse (cuda layout): group must be 1, 2, 4 or 8, got %d", group);
    if (!S || !ST || S->n != ST->n || S->n < 1 || (elem_size != 4 && elem_size != 8))
        return fail(L, err, "needs S and S^T of one size and 4- or 8-byte values");
    int n = S->n;
    L->n = n;
    L->npad = (n + BLK - 1) / BLK * BLK;
    L->vc = 16 / elem_size;
    L->tile = 32 * L->vc;
    L->group = group;
    L->item_blocks = item_blocks > 0 ? item_blocks : PL_SPINV_CUDA_ITEM_BYTES / (BLK * elem_size);
    L->meta = malloc((size_t)n * sizeof *L->meta);
    if (!L->meta) return fail(L, err, "out of memory");
    int64_t off = 0;
    for (int i = 0; i < n; ++i) {
        int f0 = S->first[i] / BLK * BLK, e = i / BLK * BLK + BLK - 1;
        L->meta[i].vbase = off - f0;
        L->meta[i].f0 = f0;
        L->meta[i].e = e;
        off += e - f0 + 1;
    }
    L->nval = off;
    if (build_row_items(L) != 0)
        return fail(L, err, "out of memory");
    int rc = build_tile_items(L, ST);
    if (rc == -2) return fail(L, err, "a row of S^T does not start at its diagonal");
    if (rc != 0) return fail(L, err, "out of memory");
    return PL_OK;
}

void spinv_cuda_layout_fill_f64(const pl_spinv_cuda_layout *L, const pl_spinv_profile *S,
                                   double *val)
{
#pragma omp parallel for schedule(dynamic, 64)
    for (int i = 0; i < L->n; ++i) {
        const pl_spinv_cuda_rowmeta *m = &L->meta[i];
        const double *src = S->val + S->start[i];
        int f = S->first[i];
        for (int j = m->f0; j <= m->e; ++j)
            val[m->vbase + j] = (j >= f && j <= i) ? src[j - f] : 0.0;
    }
}

void spinv_cuda_layout_fill_f32(const pl_spinv_cuda_layout *L, const pl_spinv_profile *S,
                                   float *val)
{
#pragma omp parallel for schedule(dynamic, 64)
    for (int i = 0; i < L->n; ++i) {
        const pl_spinv_cuda_rowmeta *m = &L->meta[i];
        const double *src = S->val + S->start[i];
        int f = S->first[i];
        for (int j = m->f0; j <= m->e; ++j)
            val[m->vbase + j] = (j >= f && j <= i) ? (float)src[j - f] : 0.0f;
    }
}

size_t spinv_cuda_small_shmem(int n, int elem_size)
{
    size_t npad = ((size_t)n + BLK - 1) / BLK * BLK;
    return PL_SPINV_CUDA_SMALL_RED_BYTES + (3 * npad + 4 * (size_t)n) * (size_t)elem_size;
}

int spinv_cuda_small_fits(int n, int64_t nval, int nparts_S, int elem_size, int shmem_max)
{
    return n >= 1 && n <= PL_SPINV_CUDA_SMALL_N && nparts_S == 0 &&
           nval * elem_size <= PL_SPINV_CUDA_SMALL_BYTES &&
           spinv_cuda_small_shmem(n, elem_size) <= (size_t)shmem_max;
}
