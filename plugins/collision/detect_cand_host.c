/* detect_cand_host.c - the device's candidate pairs made on the host: the
 * kernels' item bodies (detect_cand.h) in plain loops, a qsort where the
 * device sorts with CUB.  Tests replay the device's work with it
 * (test_collision_cand) and compare the device's lists with it (gpu_detect). */
#include <stdlib.h>
#include <string.h>

#include "detect_cand.h"

void coll_cand_list_free(coll_cand_list *l)
{
    free(l->start);
    free(l->idx);
    memset(l, 0, sizeof *l);
}

int coll_cand_list_fit(coll_cand_list *l, int n, int m)
{
    if (n + 1 > l->cap_start) {
        int *s = realloc(l->start, (size_t)(n + 1) * sizeof *s);
        if (!s) return PL_EINTERNAL;
        l->start = s;
        l->cap_start = n + 1;
    }
    if (m > l->cap_idx || !l->idx) {
        int *x = realloc(l->idx, (size_t)(m > 0 ? m : 1) * sizeof *x);
        if (!x) return PL_EINTERNAL;
        l->idx = x;
        l->cap_idx = m > 0 ? m : 1;
    }
    l->n = n;
    return PL_OK;
}

typedef struct code_idx {
    unsigned code;
    int idx;
} code_idx;

static int cmp_code(const void *x, const void *y)
{
    const code_idx *a = x, *b = y;
    if (a->code != b->code) return a->code < b->code ? -1 : 1;
    return (a->idx > b->idx) - (a->idx < b->idx); /* a stable radix sort's order */
}

static coll_cand_mesh view_of(const pl_coll_mesh *m)
{
    coll_cand_mesh v = {m->nverts, m->ntris, m->nedges, m->x0, m->x1, m->tris, m->edges,
                        0.5 * m->margin};
    return v;
}

static int cmp_key(const void *x, const void *y)
{
    coll_cand_key a = *(const coll_cand_key *)x, b = *(const coll_cand_key *)y;
    return (a > b) - (a < b);
}

/* The lists from the keys, sorted: counts per item of A, their offsets, the
 * primitives.  PL_OK or PL_EINTERNAL. */
static int lists_of_keys(const coll_cand_key *key, int total, int na, int nb, coll_cand_list *out)
{
    if (coll_cand_list_fit(out, na, total)) return PL_EINTERNAL;
    memset(out->start, 0, (size_t)(na + 1) * sizeof *out->start);
    for (int k = 0; k < total; ++k) out->start[key[k] / (coll_cand_key)nb + 1]++;
    for (int i = 0; i < na; ++i) out->start[i + 1] += out->start[i];
    for (int k = 0; k < total; ++k) out->idx[k] = (int)(key[k] % (coll_cand_key)nb);
    return PL_OK;
}

/* Appends key to the growable array *key (*n of *cap); PL_OK or
 * PL_EINTERNAL. */
static int push_key(coll_cand_key **key, int *n, int *cap, coll_cand_key k)
{
    if (*n == *cap) {
        int c = *cap ? 2 * *cap : 256;
        coll_cand_key *x = realloc(*key, (size_t)c * sizeof *x);
        if (!x) return PL_EINTERNAL;
        *key = x;
        *cap = c;
    }
    (*key)[(*n)++] = k;
    return PL_OK;
}

/* One pass into out, its box overlaps added to *broad; PL_OK or
 * PL_EINTERNAL.  The device's two levels: the tree walk's overlaps, then
 * the filter on each of them, then the sort. */
static int host_pass(const coll_cand_pass *ps, coll_cand_list *out, long long *broad)
{
    int n = ps->edges ? ps->T.nedges : ps->T.ntris;
    int queries = ps->edges ? ps->P.nedges : ps->P.nverts;
    int leaves = coll_cand_leaves(n);
    pl_aabb *prims = malloc((size_t)(n > 0 ? n : 1) * sizeof *prims);
    pl_aabb *node = malloc((size_t)(2 * leaves) * sizeof *node);
    code_idx *ci = malloc((size_t)(n > 0 ? n : 1) * sizeof *ci);
    int *order = malloc((size_t)(n > 0 ? n : 1) * sizeof *order);
    coll_cand_key *key = NULL;
    int rc = (prims && node && ci && order) ? PL_OK : PL_EINTERNAL, total = 0, cap = 0;
    if (rc == PL_OK) {
        pl_aabb root;
        coll_cand_empty(&root);
        for (int j = 0; j < n; ++j) {
            coll_cand_pbox(&ps->T, ps->edges, j, &prims[j]);
            coll_cand_union(&root, &prims[j]);
        }
        for (int j = 0; j < n; ++j) ci[j].code = coll_cand_morton(&prims[j], &root), ci[j].idx = j;
        qsort(ci, (size_t)n, sizeof *ci, cmp_code);
        for (int j = 0; j < n; ++j) order[j] = ci[j].idx;
        coll_cand_tree t = {n, leaves, order, node};
        for (int i = 2 * leaves - 1; i >= 1; --i) coll_cand_refit(&t, prims, i);
        for (int i = 0; i < queries && rc == PL_OK; ++i) {
            coll_cand_walk w;
            coll_cand_walk_start(&w, ps, i);
            coll_cand_key k;
            for (int j; rc == PL_OK && (j = coll_cand_walk_next(&w, &t, prims)) >= 0;) {
                ++*broad;
                if (coll_cand_keep(ps, i, j, &k)) rc = push_key(&key, &total, &cap, k);
            }
        }
        if (rc == PL_OK && total > 0) qsort(key, (size_t)total, sizeof *key, cmp_key);
    }
    if (rc == PL_OK) rc = lists_of_keys(key, total, coll_cand_na(ps), coll_cand_nb(ps), out);
    free(prims);
    free(node);
    free(ci);
    free(order);
    free(key);
    return rc;
}

int coll_cand_host_counted(const pl_coll_mesh *A, const pl_coll_mesh *B,
                           const pl_detect_params *prm, coll_cand_list out[3], long long *broad)
{
    coll_cand_mesh va = view_of(A), vb = view_of(B);
    coll_cand_pass ps[3];
    int use[3], rc = PL_OK;
    coll_cand_pair_passes(&va, &vb, A == B, prm->vertex_face, prm->edge_edge, prm->alarm,
                          prm->alarm + prm->margin, ps, use);
    *broad = 0;
    for (int k = 0; k < 3 && rc == PL_OK; ++k) {
        if (use[k]) {
            rc = host_pass(&ps[k], &out[k], broad);
            continue;
        }
        int na = k == 1 && A == B ? 0 : coll_cand_na(&ps[k]);
        rc = coll_cand_list_fit(&out[k], na, 0);
        if (rc == PL_OK) memset(out[k].start, 0, (size_t)(na + 1) * sizeof(int));
    }
    return rc;
}

int coll_cand_host(const pl_coll_mesh *A, const pl_coll_mesh *B, const pl_detect_params *prm,
                   coll_cand_list out[3])
{
    long long broad;
    return coll_cand_host_counted(A, B, prm, out, &broad);
}
