/* bvh.c - a bounding-volume hierarchy of axis-aligned boxes: built once by
 * median splits of the primitive centres (deterministic quickselect with
 * ties broken by index), refitted bottom-up every step (a large tree by
 * the threads, a subtree each), queried with an explicit stack (hits
 * returned in increasing primitive order).  Children are stored after
 * their parent, two by two. */
#include <stdlib.h>
#include <string.h>

#include "detect.h"

void bvh_init(pl_bvh *b) { memset(b, 0, sizeof *b); }

void bvh_free(pl_bvh *b)
{
    free(b->box);
    free(b->left);
    free(b->start);
    free(b->count);
    free(b->order);
    bvh_init(b);
}

void ivec_free(pl_ivec *a)
{
    free(a->v);
    a->v = NULL;
    a->n = a->cap = 0;
}

int ivec_push(pl_ivec *a, int x)
{
    if (a->n == a->cap) {
        int cap = a->cap ? 2 * a->cap : 32;
        int *v = realloc(a->v, (size_t)cap * sizeof *v);
        if (!v) return PL_EINTERNAL;
        a->v = v;
        a->cap = cap;
    }
    a->v[a->n++] = x;
    return PL_OK;
}

typedef struct kv {
    double key;
    int idx;
} kv;

static int kv_less(const kv *a, const kv *b)
{
    return a->key < b->key || (a->key == b->key && a->idx < b->idx);
}

static void kv_swap(kv *a, kv *b)
{
    kv t = *a;
    *a = *b;
    *b = t;
}

/* Reorders a[0..n-1] so that a[k] is the k-th smallest, smaller ones before. */
static void select_kth(kv *a, int n, int k)
{
    int lo = 0, hi = n - 1;
    while (hi > lo) {
        int mid = lo + (hi - lo) / 2;
        /* median of three as pivot, moved to hi */
        if (kv_less(&a[mid], &a[lo])) kv_swap(&a[mid], &a[lo]);
        if (kv_less(&a[hi], &a[lo])) kv_swap(&a[hi], &a[lo]);
        if (kv_less(&a[mid], &a[hi])) kv_swap(&a[mid], &a[hi]);
        kv pivot = a[hi];
        int store = lo;
        for (int i = lo; i < hi; ++i)
            if (kv_less(&a[i], &pivot)) kv_swap(&a[i], &a[store++]);
        kv_swap(&a[store], &a[hi]);
        if (store == k) return;
        if (store < k)
            lo = store + 1;
        else
            hi = store - 1;
    }
}

/* Stores unconditionally (minsd / maxsd, no branch to mispredict: refits
 * ran at 50 ns a node); the same values as `if (a < r) r = a`. */
static void box_union(pl_aabb *r, const pl_aabb *a)
{
    for (int k = 0; k < 3; ++k) {
        r->lo[k] = a->lo[k] < r->lo[k] ? a->lo[k] : r->lo[k];
        r->hi[k] = a->hi[k] > r->hi[k] ? a->hi[k] : r->hi[k];
    }
}

static void box_empty(pl_aabb *r)
{
    for (int k = 0; k < 3; ++k) {
        r->lo[k] = 1e300;
        r->hi[k] = -1e300;
    }
}

typedef struct build_ctx {
    pl_bvh *b;
    const pl_aabb *prims;
    kv *scratch;
} build_ctx;

static void build_node(build_ctx *bc, int node, int s, int n)
{
    pl_bvh *b = bc->b;
    b->start[node] = s;
    b->count[node] = n;
    b->left[node] = -1;
    if (n <= PL_BVH_LEAF) return;
    double clo[3] = {1e300, 1e300, 1e300}, chi[3] = {-1e300, -1e300, -1e300};
    for (int i = s; i < s + n; ++i) {
        const pl_aabb *p = &bc->prims[b->order[i]];
        for (int k = 0; k < 3; ++k) {
            double c = 0.5 * (p->lo[k] + p->hi[k]);
            if (c < clo[k]) clo[k] = c;
            if (c > chi[k]) chi[k] = c;
        }
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    kv *a = bc->scratch + s;
    for (int i = 0; i < n; ++i) {
        const pl_aabb *p = &bc->prims[b->order[s + i]];
        a[i].key = 0.5 * (p->lo[axis] + p->hi[axis]);
        a[i].idx = b->order[s + i];
    }
    int half = n / 2;
    select_kth(a, n, half);
    for (int i = 0; i < n; ++i) b->order[s + i] = a[i].idx;
    int left = b->nnodes;
    b->nnodes += 2;
    b->left[node] = left;
    build_node(bc, left, s, half);
    build_node(bc, left + 1, s + half, n - half);
}

int bvh_build(pl_bvh *b, const pl_aabb *prims, int n)
{
    bvh_free(b);
    size_t cap = (size_t)(n > 0 ? 2 * n : 1);
    b->box = malloc(cap * sizeof *b->box);
    b->left = malloc(cap * sizeof *b->left);
    b->start = malloc(cap * sizeof *b->start);
    b->count = malloc(cap * sizeof *b->count);
    b->order = malloc((size_t)(n > 0 ? n : 1) * sizeof *b->order);
    kv *scratch = malloc((size_t)(n > 0 ? n : 1) * sizeof *scratch);
    if (!b->box || !b->left || !b->start || !b->count || !b->order || !scratch) {
        free(scratch);
        bvh_free(b);
        return PL_EINTERNAL;
    }
    b->nprims = n;
    for (int i = 0; i < n; ++i) b->order[i] = i;
    b->nnodes = 1;
    build_ctx bc = {b, prims, scratch};
    build_node(&bc, 0, 0, n);
    free(scratch);
    bvh_refit(b, prims);
    return PL_OK;
}

/* Node's box from its primitives or its children's boxes. */
static void refit_one(pl_bvh *b, const pl_aabb *prims, int node)
{
    pl_aabb *r = &b->box[node];
    box_empty(r);
    if (b->left[node] < 0) {
        for (int i = b->start[node]; i < b->start[node] + b->count[node]; ++i)
            box_union(r, &prims[b->order[i]]);
    } else {
        box_union(r, &b->box[b->left[node]]);
        box_union(r, &b->box[b->left[node] + 1]);
    }
}

/* The subtree of node, children first. */
static void refit_subtree(pl_bvh *b, const pl_aabb *prims, int node)
{
    if (b->left[node] >= 0) {
        refit_subtree(b, prims, b->left[node]);
        refit_subtree(b, prims, b->left[node] + 1);
    }
    refit_one(b, prims, node);
}

/* The nodes depth levels below node (or leaves above that level) into
 * roots; returns their count. */
static int frontier(const pl_bvh *b, int node, int depth, int *roots, int n)
{
    if (depth == 0 || b->left[node] < 0) {
        roots[n] = node;
        return n + 1;
    }
    n = frontier(b, b->left[node], depth - 1, roots, n);
    return frontier(b, b->left[node] + 1, depth - 1, roots, n);
}

/* The nodes above the frontier, children first. */
static void refit_top(pl_bvh *b, const pl_aabb *prims, int node, int depth)
{
    if (depth == 0 || b->left[node] < 0) return; /* a frontier node: done */
    refit_top(b, prims, b->left[node], depth - 1);
    refit_top(b, prims, b->left[node] + 1, depth - 1);
    refit_one(b, prims, node);
}

/* A tree of more primitives than COLL_PAR_MIN is refitted by the threads,
 * a subtree each (64 of them; smaller trees cost less than waking the
 * team: with 4096 the small raptor's detection lost 0.2 ms a step on the
 * 16-core host); min and max are exact, so the boxes are the serial
 * refit's whatever the order. */
#define BVH_PAR_MIN COLL_PAR_MIN
#define BVH_PAR_DEPTH 6

void bvh_refit(pl_bvh *b, const pl_aabb *prims)
{
    if (b->nprims > BVH_PAR_MIN) {
        int roots[1 << BVH_PAR_DEPTH];
        int n = frontier(b, 0, BVH_PAR_DEPTH, roots, 0);
#pragma omp parallel for schedule(dynamic, 1)
        for (int k = 0; k < n; ++k) refit_subtree(b, prims, roots[k]);
        refit_top(b, prims, 0, BVH_PAR_DEPTH);
        return;
    }
    for (int node = b->nnodes - 1; node >= 0; --node) refit_one(b, prims, node);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* The hits in increasing primitive order: the tree is built from the
 * positions of the first step it sees, so its leaf order depends on the
 * history (a run restored from a saved state builds another tree), and the
 * order of the contacts, which the hits become, must not. */
static void sort_hits(int *v, int n)
{
    if (n > 32) {
        qsort(v, (size_t)n, sizeof *v, cmp_int);
        return;
    }
    for (int i = 1; i < n; ++i) {
        int x = v[i], j = i - 1;
        for (; j >= 0 && v[j] > x; --j) v[j + 1] = v[j];
        v[j + 1] = x;
    }
}

int bvh_query(const pl_bvh *b, const pl_aabb *prims, const pl_aabb *q, pl_ivec *out)
{
    return bvh_query_grown(b, prims, 0.0, q, 0.0, out);
}

int bvh_query_grown(const pl_bvh *b, const pl_aabb *prims, double hp, const pl_aabb *q,
                    double hq, pl_ivec *out)
{
    if (b->nprims == 0) return PL_OK;
    int first = out->n;
    int stack[128], top = 0; /* median splits: depth <= log2(n) + 1 */
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        if (!aabb_overlap_grown(&b->box[node], hp, q, hq)) continue;
        if (b->left[node] < 0) {
            for (int i = b->start[node]; i < b->start[node] + b->count[node]; ++i) {
                int p = b->order[i];
                if (aabb_overlap_grown(&prims[p], hp, q, hq) && ivec_push(out, p))
                    return PL_EINTERNAL;
            }
        } else {
            stack[top++] = b->left[node] + 1; /* left child popped first */
            stack[top++] = b->left[node];
        }
    }
    if (out->n > first) sort_hits(out->v + first, out->n - first); /* v is NULL when empty */
    return PL_OK;
}
