/* side_hints.c - the previous step's proximities (normals, sides), looked up
 * by their models and vertices (open addressing, linear probing, the slots
 * holding indices into one copy of the proximities), so that contacts with
 * thin two-sided meshes keep their side while they last. */
#include <stdlib.h>
#include <string.h>

#include "detect.h"

/* A vertex-face proximity's sort key: models, vertex, triangle, then its
 * place among the items given (a total order: the same hints whatever the
 * sort).  Sorting these, not the proximities, moves a few words each. */
struct pl_side_vf {
    int model_a, model_b, vertex, b[3], item;
};

void side_hints_init(pl_side_hints *h) { memset(h, 0, sizeof *h); }

void side_hints_free(pl_side_hints *h)
{
    free(h->key);
    free(h->keyed);
    free(h->items);
    free(h->hash);
    free(h->vf);
    side_hints_init(h);
}

/* What identifies a proximity: kind, models, vertices (b's triangle sorted,
 * it is the same triangle whatever vertex comes first). */
static void ident(const pl_proximity *p, int id[10])
{
    int b[3] = {p->b[0], p->b[1], p->nb == 3 ? p->b[2] : -1};
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
            if (b[j] < b[i]) {
                int t = b[i];
                b[i] = b[j];
                b[j] = t;
            }
    id[0] = p->kind;
    id[1] = p->model_a;
    id[2] = p->model_b;
    id[3] = p->a[0];
    id[4] = p->na > 1 ? p->a[1] : -1;
    id[5] = b[0];
    id[6] = b[1];
    id[7] = b[2];
    id[8] = id[9] = 0;
}

static unsigned long long hash(const int id[10])
{
    unsigned long long x = 1469598103934665603ull;
    for (int k = 0; k < 8; ++k) {
        x ^= (unsigned long long)(unsigned)id[k];
        x *= 1099511628211ull;
        x ^= x >> 29;
    }
    return x | 1ull; /* 0 marks an empty slot */
}

/* Whether p's identity is id (ident's). */
static int same_id(const pl_proximity *p, const int id[10])
{
    int a[10];
    ident(p, a);
    return memcmp(a, id, sizeof a) == 0;
}

/* Keys ordered by (model_a, model_b, vertex); the _vf order adds the
 * triangle and the item (deterministic). */
static int cmp_vertex(const struct pl_side_vf *x, int model_a, int model_b, int vertex)
{
    if (x->model_a != model_a) return x->model_a < model_a ? -1 : 1;
    if (x->model_b != model_b) return x->model_b < model_b ? -1 : 1;
    return (x->vertex > vertex) - (x->vertex < vertex);
}

static int cmp_vf(const void *x, const void *y)
{
    const struct pl_side_vf *p = x, *q = y;
    int c = cmp_vertex(p, q->model_a, q->model_b, q->vertex);
    if (c) return c;
    for (int k = 0; k < 3; ++k)
        if (p->b[k] != q->b[k]) return p->b[k] < q->b[k] ? -1 : 1;
    return (p->item > q->item) - (p->item < q->item);
}

/* Merges the sorted runs src[b[r]] .. src[b[r + 1]] pairwise into dst until
 * one is left; returns the array that holds it (src or dst). */
static struct pl_side_vf *merge_runs(struct pl_side_vf *src, struct pl_side_vf *dst, int *b,
                                     int runs)
{
    while (runs > 1) {
        int out = 0;
        for (int r = 0; r < runs; r += 2) {
            /* runs r and r + 1 (the last one alone when runs is odd) */
            int i = b[r], mid = b[r + 1], end = r + 2 <= runs ? b[r + 2] : mid, o = i, j = mid;
            while (i < mid && j < end) dst[o++] = cmp_vf(&src[j], &src[i]) < 0 ? src[j++] : src[i++];
            while (i < mid) dst[o++] = src[i++];
            while (j < end) dst[o++] = src[j++];
            b[out++] = b[r];
        }
        b[out] = b[runs];
        runs = out;
        struct pl_side_vf *t = src;
        src = dst;
        dst = t;
    }
    return src;
}

/* Sorts h->vf by cmp_vf, a total order (so any sort gives these records in
 * this order).  They come nearly sorted (the previous step's contacts in
 * detection's order: a few runs), so the runs are found and merged
 * pairwise, O(n log runs), instead of a qsort from scratch. */
static int sort_vf(pl_side_hints *h)
{
    int n = h->nvf, runs = 1;
    for (int k = 1; k < n; ++k) runs += cmp_vf(&h->vf[k - 1], &h->vf[k]) > 0;
    if (n < 2 || runs == 1) return PL_OK;
    int *b = malloc(sizeof *b * (size_t)(runs + 1));
    struct pl_side_vf *tmp = malloc(sizeof *tmp * (size_t)n);
    if (!b || !tmp) {
        free(b);
        free(tmp);
        return PL_EINTERNAL;
    }
    b[0] = 0;
    for (int k = 1, r = 1; k < n; ++k)
        if (cmp_vf(&h->vf[k - 1], &h->vf[k]) > 0) b[r++] = k;
    b[runs] = n;
    struct pl_side_vf *sorted = merge_runs(h->vf, tmp, b, runs);
    if (sorted != h->vf) memcpy(h->vf, sorted, sizeof *tmp * (size_t)n);
    free(b);
    free(tmp);
    return PL_OK;
}

static int build_vf(pl_side_hints *h)
{
    const pl_proximity *items = h->items;
    int n = h->nitems, m = 0;
    for (int k = 0; k < n; ++k) m += items[k].kind == PL_PROX_VERTEX_FACE;
    if (m > h->capvf) {
        struct pl_side_vf *vf = realloc(h->vf, (size_t)m * sizeof *vf);
        if (!vf) return PL_EINTERNAL;
        h->vf = vf;
        h->capvf = m;
    }
    h->nvf = 0;
    for (int k = 0; k < n; ++k)
        if (items[k].kind == PL_PROX_VERTEX_FACE) {
            const pl_proximity *p = &items[k];
            h->vf[h->nvf++] = (struct pl_side_vf){p->model_a, p->model_b, p->a[0],
                                                  {p->b[0], p->b[1], p->b[2]}, k};
        }
    return sort_vf(h);
}

static int shared_vertices(const int a[3], const int b[3])
{
    int n = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) n += a[i] == b[j];
    return n;
}

const pl_proximity *side_hints_find_near(const pl_side_hints *h, const pl_proximity *p)
{
    if (!h || h->nvf == 0 || p->kind != PL_PROX_VERTEX_FACE) return NULL;
    int lo = 0, hi = h->nvf; /* first record not below p's vertex */
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (cmp_vertex(&h->vf[mid], p->model_a, p->model_b, p->a[0]) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    const pl_proximity *best = NULL;
    int shared = 0;
    for (int k = lo; k < h->nvf && cmp_vertex(&h->vf[k], p->model_a, p->model_b, p->a[0]) == 0;
         ++k) {
        const pl_proximity *q = &h->items[h->vf[k].item];
        int s = shared_vertices(q->b, p->b);
        if (s > shared && s < 3 && q->side != 0) best = q, shared = s;
    }
    return best;
}

/* Hashed by the threads from this many proximities on. */
#define HINTS_PAR_MIN 2048

int side_hints_build_strided(pl_side_hints *h, const pl_proximity *first, size_t stride, int n)
{
    int cap = 64;
    while (cap < 2 * n) cap *= 2;
    if (cap != h->cap) {
        free(h->key);
        free(h->keyed);
        h->key = malloc((size_t)cap * sizeof *h->key);
        h->keyed = malloc((size_t)cap * sizeof *h->keyed);
        h->cap = h->key && h->keyed ? cap : 0;
        if (!h->cap) {
            side_hints_free(h);
            return PL_EINTERNAL;
        }
    }
    if (n > h->capitems) {
        pl_proximity *it = realloc(h->items, (size_t)n * sizeof *it);
        unsigned long long *hx = realloc(h->hash, (size_t)n * sizeof *hx);
        if (it) h->items = it;
        if (hx) h->hash = hx;
        if (!it || !hx) return PL_EINTERNAL;
        h->capitems = n;
    }
    const char *src = (const char *)first;
    /* the copies and the hashes by the threads; the inserts in order */
#pragma omp parallel for schedule(static) if (n >= HINTS_PAR_MIN)
    for (int k = 0; k < n; ++k) {
        h->items[k] = *(const pl_proximity *)(src + (size_t)k * stride);
        int id[10];
        ident(&h->items[k], id);
        h->hash[k] = hash(id);
    }
    h->nitems = n;
    memset(h->key, 0, (size_t)cap * sizeof *h->key);
    h->n = 0;
    for (int k = 0; k < n; ++k) {
        unsigned long long x = h->hash[k];
        size_t s = (size_t)x & (size_t)(cap - 1);
        if (h->key[s] != 0) { /* probe: compare identities only where the hashes meet */
            int id[10];
            ident(&h->items[k], id);
            while (h->key[s] != 0 && !(h->key[s] == x && same_id(&h->items[h->keyed[s]], id)))
                s = (s + 1) & (size_t)(cap - 1);
        }
        if (h->key[s] == 0) h->n++;
        h->key[s] = x;
        h->keyed[s] = k; /* a repeated identity: the last one given */
    }
    return build_vf(h);
}

int side_hints_build(pl_side_hints *h, const pl_proximity *items, int n)
{
    return side_hints_build_strided(h, items, sizeof *items, n);
}

const pl_proximity *side_hints_find(const pl_side_hints *h, const pl_proximity *p)
{
    if (!h || h->n == 0) return NULL;
    int id[10];
    ident(p, id);
    unsigned long long x = hash(id);
    size_t s = (size_t)x & (size_t)(h->cap - 1);
    while (h->key[s] != 0) {
        if (h->key[s] == x && same_id(&h->items[h->keyed[s]], id)) return &h->items[h->keyed[s]];
        s = (s + 1) & (size_t)(h->cap - 1);
    }
    return NULL;
}
