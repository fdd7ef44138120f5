/* detect_device_tree.cu - the trees of device detection: one launch for
 * the boxes of every tree of a batch (one thread per primitive), CUB for
 * the bounds (a box union) and the Morton sort (radix, stable: ties keep
 * the primitive order) of the trees whose order is due, one launch for the
 * refit of every tree (one thread per leaf, bottom up: of a node's two
 * children, the thread that arrives second refits it).  Trees are kept
 * across batches (detect_device_int.cuh, struct dtree). */
#include <cub/cub.cuh>

#include "detect_device_int.cuh"

namespace {

struct box_union {
    __device__ pl_aabb operator()(const pl_aabb &a, const pl_aabb &b) const
    {
        pl_aabb r = a;
        coll_cand_union(&r, &b);
        return r;
    }
};

/* The last record whose base (pbase, or lbase) is <= g. */
__device__ int tree_of(const dtree_rec *R, int nt, int g, int leaves)
{
    int lo = 0, hi = nt - 1;
    while (lo < hi) {
        int m = (lo + hi + 1) / 2;
        if ((leaves ? R[m].lbase : R[m].pbase) <= g) lo = m; else hi = m - 1;
    }
    return lo;
}

/* Every tree's primitive boxes; zeroes its refit flags on the way (a tree
 * has fewer leaves than primitives, or one of each). */
__global__ void k_pbox(const dtree_rec *R, int nt, int np)
{
    int g = blockIdx.x * blockDim.x + threadIdx.x;
    if (g >= np) return;
    const dtree_rec *r = &R[tree_of(R, nt, g, 0)];
    int j = g - r->pbase;
    coll_cand_pbox(&r->v, r->edges, j, &r->prims[j]);
    if (j < r->t.leaves) r->flag[j] = 0;
}

__global__ void k_morton(const pl_aabb *prims, const pl_aabb *root, int n, unsigned *code,
                         int *idx)
{
    int j = blockIdx.x * blockDim.x + threadIdx.x;
    if (j >= n) return;
    code[j] = coll_cand_morton(&prims[j], root);
    idx[j] = j;
}

/* A child's box as another thread wrote it: through L2, not this SM's L1. */
__device__ void load_cg(const pl_aabb *b, pl_aabb *r)
{
    for (int k = 0; k < 3; ++k) {
        r->lo[k] = __ldcg(&b->lo[k]);
        r->hi[k] = __ldcg(&b->hi[k]);
    }
}

/* One thread per leaf of every tree: the leaf, then up while it is the
 * second of two siblings to arrive (flag: arrivals per internal node,
 * zeroed by k_pbox).  The union is min / max, exact: any order gives
 * coll_cand_refit's boxes. */
__global__ void k_refit(const dtree_rec *R, int nt, int nl)
{
    int g = blockIdx.x * blockDim.x + threadIdx.x;
    if (g >= nl) return;
    const dtree_rec *r = &R[tree_of(R, nt, g, 1)];
    coll_cand_tree t = r->t;
    int i = t.leaves + g - r->lbase;
    coll_cand_refit(&t, r->prims, i);
    while (i > 1) {
        __threadfence();
        i /= 2;
        if (atomicAdd(&r->flag[i], 1) == 0) return; /* the sibling is not done yet */
        pl_aabb a, b;
        load_cg(&t.node[2 * i], &a);
        load_cg(&t.node[2 * i + 1], &b);
        coll_cand_union(&a, &b);
        t.node[i] = a;
    }
}

} // namespace

int dbuf_grow(dbuf *b, size_t bytes)
{
    if (bytes <= b->cap && b->p) return 0;
    cudaFree(b->p);
    b->p = NULL;
    b->cap = 0;
    if (cudaMalloc(&b->p, bytes ? bytes : 16) != cudaSuccess) return -1;
    b->cap = bytes ? bytes : 16;
    return 0;
}

void dbuf_free(dbuf *b)
{
    cudaFree(b->p);
    b->p = NULL;
    b->cap = 0;
}

int dev_fail(pl_error *err, cudaError_t e, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "device detection: %s: %s", what,
                        cudaGetErrorString(e));
}

void dev_trees_free(coll_dev *d)
{
    for (int k = 0; k < DEV_TREES; ++k) {
        dtree *t = &d->tree[k];
        dbuf_free(&t->prims), dbuf_free(&t->node), dbuf_free(&t->order), dbuf_free(&t->flag);
        t->mesh = NULL;
    }
}

/* The cached tree of (T, edges, n), or the least recently used slot made
 * over for it; NULL when every slot serves this batch. */
static dtree *find_tree(coll_dev *d, const pl_coll_mesh *T, int edges, int n)
{
    dtree *old = &d->tree[0];
    for (int k = 0; k < DEV_TREES; ++k) {
        dtree *t = &d->tree[k];
        if (t->mesh == T && t->edges == edges && t->n == n) return t;
        if (t->stamp < old->stamp || !t->mesh) old = t;
        if (!t->mesh) break;
    }
    if (old->mesh && old->stamp == d->batches) return NULL; /* all in use by this batch */
    old->mesh = T;
    old->edges = edges;
    old->n = n;
    old->leaves = coll_cand_leaves(n);
    old->uses = 0;
    return old;
}

/* The Morton order of r's primitives (r->t.order), its boxes made. */
static int sort_tree(coll_dev *d, const dtree_rec *r, pl_error *err)
{
    int n = r->t.n;
    pl_aabb *prims = r->prims, empty;
    coll_cand_empty(&empty);
    for (int k = 0; k < 2; ++k) GROW(d->code[k], (size_t)n * sizeof(unsigned));
    GROW(d->order_in, (size_t)n * sizeof(int));
    GROW(d->root, sizeof(pl_aabb));
    size_t tb = 0, tb2 = 0;
    unsigned *c0 = (unsigned *)d->code[0].p, *c1 = (unsigned *)d->code[1].p;
    int *o0 = (int *)d->order_in.p, *o1 = (int *)r->t.order;
    CK(cub::DeviceReduce::Reduce(NULL, tb, prims, (pl_aabb *)d->root.p, n, box_union(), empty),
       "bounds");
    CK(cub::DeviceRadixSort::SortPairs(NULL, tb2, c0, c1, o0, o1, n, 0, 30), "sort");
    GROW(d->temp, tb > tb2 ? tb : tb2);
    CK(cub::DeviceReduce::Reduce(d->temp.p, tb, prims, (pl_aabb *)d->root.p, n, box_union(),
                                 empty, d->s), "bounds");
    k_morton<<<dev_blocks(n), DEV_TPB, 0, d->s>>>(prims, (const pl_aabb *)d->root.p, n, c0, o0);
    CK(cub::DeviceRadixSort::SortPairs(d->temp.p, tb2, c0, c1, o0, o1, n, 0, 30, d->s), "sort");
    return PL_OK;
}

int dev_tree_reserve(coll_dev *d, const pl_coll_mesh *T, int edges, int n, dtree_rec *r,
                     pl_error *err)
{
    dtree *t = find_tree(d, T, edges, n);
    if (!t) return dev_fail(err, cudaErrorMemoryAllocation, "more trees than kept"), -1;
    int make = t->stamp != d->batches; /* else another pass of this batch made it */
    if (make) {
        t->stamp = d->batches;
        r->sort = t->uses++ % DEV_REORDER_EVERY == 0;
        if (dbuf_grow(&t->prims, (size_t)n * sizeof(pl_aabb)) ||
            dbuf_grow(&t->node, (size_t)2 * t->leaves * sizeof(pl_aabb)) ||
            dbuf_grow(&t->order, (size_t)n * sizeof(int)) ||
            dbuf_grow(&t->flag, (size_t)t->leaves * sizeof(int)))
            return dev_fail(err, cudaErrorMemoryAllocation, "allocation"), -1;
    }
    r->edges = edges;
    coll_cand_tree ct = {n, t->leaves, (const int *)t->order.p, (pl_aabb *)t->node.p};
    r->t = ct;
    r->prims = (pl_aabb *)t->prims.p;
    r->flag = (int *)t->flag.p;
    return make;
}

int dev_trees_make(coll_dev *d, const dtree_rec *R, const dtree_rec *H, int nt, int np, int nl,
                   pl_error *err)
{
    if (nt == 0) return PL_OK;
    k_pbox<<<dev_blocks(np), DEV_TPB, 0, d->s>>>(R, nt, np);
    CK(cudaGetLastError(), "box kernel");
    for (int k = 0; k < nt; ++k) {
        int rc = H[k].sort ? sort_tree(d, &H[k], err) : PL_OK;
        if (rc) return rc;
    }
    k_refit<<<dev_blocks(nl), DEV_TPB, 0, d->s>>>(R, nt, nl);
    CK(cudaGetLastError(), "refit kernel");
    return PL_OK;
}
