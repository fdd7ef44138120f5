/* detect_device_int.cuh - what the two .cu files of device detection share
 * (detect_device.cu: the batch of pairs; detect_device_tree.cu: the trees).
 * CUDA C++ only. */
#ifndef PLIANT_COLLISION_DETECT_DEVICE_INT_CUH
#define PLIANT_COLLISION_DETECT_DEVICE_INT_CUH

#include <cuda_runtime.h>

#include "detect_cand.h"
#include "detect_device.h"

/* A device allocation that only grows. */
struct dbuf {
    void *p;
    size_t cap;
};
int dbuf_grow(dbuf *b, size_t bytes);
void dbuf_free(dbuf *b);

/* A tree over one mesh's triangles or edges, kept across batches: the
 * primitive order (the Morton sort) is remade only every few uses, since
 * the candidates do not depend on it (detect_cand.h) and a soft body keeps
 * its neighbourhoods; the boxes are remade and the tree refitted on every
 * use.  Found again by (mesh, kind, count); a different mesh with the same
 * count at the same address would reuse a valid permutation: still right. */
struct dtree {
    const pl_coll_mesh *mesh;
    int edges, n, leaves;
    int uses;          /* batches it served (the order is remade at 0, 8, 16, ...) */
    unsigned stamp;    /* last batch (the least recently used one goes first) */
    dbuf prims, node, order, flag;
};

enum { DEV_TREES = 32, DEV_REORDER_EVERY = 8 };

struct coll_dev {
    cudaStream_t s; /* its own stream, not blocking with the legacy default stream */
    dtree tree[DEV_TREES];
    unsigned batches;
    /* shared scratch of the trees' builds: codes, sorted codes, order input,
     * the bounds, CUB's temporary storage */
    dbuf code[2], order_in, root, temp;
    /* the batch: meshes and pass records (one upload, mesh_mem), broad overlaps,
     * keys, lists */
    dbuf mesh_mem, over, key[2], start, idx, counters;
    void *up, *down; /* pinned host staging: uploads, read-backs */
    size_t up_cap, down_cap;
    size_t over_cap;  /* overlaps the buffers hold (grows on overflow) */
    /* PLIANT_DETECT_PROFILE set: time per stage (synchronising after each),
     * printed by coll_dev_close: uploads, trees, overlaps and filter (with
     * the read-back of the counts), sort and lists (with their download) */
    int profile, calls;
    double stage_ms[4], last;
};

/* A tree to make in this batch, as the tree kernels see it (device
 * pointers): its mesh, its primitives' first index among all trees'
 * (pbase) and its first leaf (lbase). */
struct dtree_rec {
    coll_cand_mesh v;
    int edges, sort; /* sort: its order is remade in this batch */
    coll_cand_tree t;
    pl_aabb *prims;
    int *flag;
    int pbase, lbase;
};

/* The kept tree of T's triangles or edges (n of them) for this batch:
 * buffers grown, *r filled but for v, pbase, lbase; returns 1 when it is to
 * be made (its first pass in the batch), 0 when another pass made it, or
 * -1 with err set. */
int dev_tree_reserve(coll_dev *d, const pl_coll_mesh *T, int edges, int n, dtree_rec *r,
                     pl_error *err);
/* Makes the nt trees of R (device records; host copy H): every box in one
 * launch, the orders due, every refit in one launch; np primitives and nl
 * leaves in all.  PL_OK or PL_EINTERNAL with err set. */
int dev_trees_make(coll_dev *d, const dtree_rec *R, const dtree_rec *H, int nt, int np, int nl,
                   pl_error *err);
void dev_trees_free(coll_dev *d);

int dev_fail(pl_error *err, cudaError_t e, const char *what);

#define DEV_TPB 128
static inline int dev_blocks(long long n) { return (int)((n + DEV_TPB - 1) / DEV_TPB); }

#define CK(call, what)                                                                         \
    do {                                                                                       \
        cudaError_t e_ = (call);                                                               \
        if (e_ != cudaSuccess) return dev_fail(err, e_, what);                                 \
    } while (0)
#define GROW(buf, bytes)                                                                       \
    do {                                                                                       \
        if (dbuf_grow(&(buf), (bytes)))                                                        \
            return dev_fail(err, cudaErrorMemoryAllocation, "allocation");                     \
    } while (0)

#endif
