/* detect_device_tree.cu - the trees of device detection: one thread per
 * primitive for the boxes and Morton codes, CUB for the bounds (a box
 * union) and the sort (radix, stable: ties keep the primitive order), one
 * launch for the refit (bottom up: of a node's two children, the thread
 * that arrives second refits it).  Trees are kept across batches
 * (detect_device_int.cuh, struct dtree). */
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

__global__ void k_pbox(coll_cand_mesh T, int edges, int n, pl_aabb *prims)
{
    int j = blockIdx.x * blockDim.x + threadIdx.x;
    if (j < n) coll_cand_pbox(&T, edges, j, &prims[j]);
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

/* One thread per leaf: the leaf, then up while it is the second of two
 * siblings to arrive (flag: arrivals per internal node, zeroed before).
 * The union is min / max, exact: any order gives coll_cand_refit's boxes. */
__global__ void k_refit(coll_cand_tree t, const pl_aabb *prims, int *flag)
{
    int leaf = blockIdx.x * blockDim.x + threadIdx.x;
    if (leaf >= t.leaves) return;
    int i = t.leaves + leaf;
    coll_cand_refit(&t, prims, i);
    while (i > 1) {
        __threadfence();
        i /= 2;
        if (atomicAdd(&flag[i], 1) == 0) return; /* the sibling is not done yet */
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

/* The Morton order of t's primitives (t->order). */
static int sort_tree(coll_dev *d, dtree *t, pl_error *err)
{
    int n = t->n;
    pl_aabb *prims = (pl_aabb *)t->prims.p, empty;
    coll_cand_empty(&empty);
    for (int k = 0; k < 2; ++k) GROW(d->code[k], (size_t)n * sizeof(unsigned));
    GROW(d->order_in, (size_t)n * sizeof(int));
    GROW(d->root, sizeof(pl_aabb));
    size_t tb = 0, tb2 = 0;
    unsigned *c0 = (unsigned *)d->code[0].p, *c1 = (unsigned *)d->code[1].p;
    int *o0 = (int *)d->order_in.p, *o1 = (int *)t->order.p;
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

int dev_tree(coll_dev *d, const pl_coll_mesh *T, const coll_cand_mesh *v, int edges,
             coll_cand_tree *out, const pl_aabb **prims, pl_error *err)
{
    int n = edges ? v->nedges : v->ntris;
    dtree *t = find_tree(d, T, edges, n);
    if (!t) return dev_fail(err, cudaErrorMemoryAllocation, "more trees than kept");
    coll_cand_tree r = {n, t->leaves, (const int *)t->order.p, (pl_aabb *)t->node.p};
    if (t->stamp == d->batches) { /* made for another pass of this batch */
        *out = r;
        *prims = (const pl_aabb *)t->prims.p;
        return PL_OK;
    }
    t->stamp = d->batches;
    GROW(t->prims, (size_t)n * sizeof(pl_aabb));
    GROW(t->node, (size_t)2 * t->leaves * sizeof(pl_aabb));
    GROW(t->order, (size_t)n * sizeof(int));
    GROW(t->flag, (size_t)t->leaves * sizeof(int));
    k_pbox<<<dev_blocks(n), DEV_TPB, 0, d->s>>>(*v, edges, n, (pl_aabb *)t->prims.p);
    CK(cudaGetLastError(), "box kernel");
    if (t->uses++ % DEV_REORDER_EVERY == 0) {
        int rc = sort_tree(d, t, err);
        if (rc) return rc;
    }
    r.order = (const int *)t->order.p;
    r.node = (pl_aabb *)t->node.p;
    CK(cudaMemsetAsync(t->flag.p, 0, (size_t)t->leaves * sizeof(int), d->s), "memset");
    k_refit<<<dev_blocks(t->leaves), DEV_TPB, 0, d->s>>>(r, (const pl_aabb *)t->prims.p,
                                                         (int *)t->flag.p);
    CK(cudaGetLastError(), "refit kernel");
    *out = r;
    *prims = (const pl_aabb *)t->prims.p;
    return PL_OK;
}
