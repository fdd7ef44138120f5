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

/* One pass into out; PL_OK or PL_EINTERNAL. */
static int host_pass(const coll_cand_pass *ps, coll_cand_list *out)
{
    int n = ps->edges ? ps->T.nedges : ps->T.ntris, items = ps->edges ? ps->P.nedges : ps->P.nverts;
    int leaves = coll_cand_leaves(n);
    pl_aabb *prims = malloc((size_t)(n > 0 ? n : 1) * sizeof *prims);
    pl_aabb *node = malloc((size_t)(2 * leaves) * sizeof *node);
    code_idx *ci = malloc((size_t)(n > 0 ? n : 1) * sizeof *ci);
    int *order = malloc((size_t)(n > 0 ? n : 1) * sizeof *order);
    int rc = (prims && node && ci && order) ? PL_OK : PL_EINTERNAL;
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
        /* count, then write (the device's two passes) */
        rc = coll_cand_list_fit(out, items, 0);
        int total = 0;
        for (int i = 0; i < items && rc == PL_OK; ++i) {
            out->start[i] = total;
            total += coll_cand_query(ps, &t, prims, i, NULL, 0);
        }
        if (rc == PL_OK) {
            out->start[items] = total;
            rc = coll_cand_list_fit(out, items, total);
        }
        for (int i = 0; i < items && rc == PL_OK; ++i)
            coll_cand_query(ps, &t, prims, i, out->idx + out->start[i],
                            out->start[i + 1] - out->start[i]);
    }
    free(prims);
    free(node);
    free(ci);
    free(order);
    return rc;
}

int coll_cand_host(const pl_coll_mesh *A, const pl_coll_mesh *B, const pl_detect_params *prm,
                   coll_cand_list out[3])
{
    coll_cand_pass ps = {view_of(A), view_of(B), 0, A == B, prm->alarm,
                         prm->alarm + prm->margin};
    int rc = host_pass(&ps, &out[0]);
    if (rc == PL_OK && A != B) {
        coll_cand_pass r = {view_of(B), view_of(A), 0, 0, prm->alarm, prm->alarm + prm->margin};
        rc = host_pass(&r, &out[1]);
    } else if (rc == PL_OK) {
        rc = coll_cand_list_fit(&out[1], 0, 0);
        if (rc == PL_OK) out[1].start[0] = 0;
    }
    ps.edges = 1;
    if (rc == PL_OK) rc = host_pass(&ps, &out[2]);
    return rc;
}
