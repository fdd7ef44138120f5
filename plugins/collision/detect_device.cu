/* detect_device.cu - detection's candidate pairs on the GPU: one thread per
 * primitive for the boxes and Morton codes, CUB for the bounds (a box
 * union), the sort (radix, stable: ties keep the primitive order) and the
 * offsets (an exclusive scan), one launch per tree level for the refit, one
 * thread per query to count and then to write its sorted list.  The item
 * bodies are detect_cand.h's, which coll_cand_host runs on the host; this
 * file is compiled with -fmad=false so that the distances round as on the
 * host. */
#include <cub/cub.cuh>
#include <cuda_runtime.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "detect_cand.h"
#include "detect_device.h"

namespace {

struct dbuf {
    void *p;
    size_t cap;
};

int grow(dbuf *b, size_t bytes)
{
    if (bytes <= b->cap && b->p) return 0;
    cudaFree(b->p);
    b->p = NULL;
    b->cap = 0;
    if (cudaMalloc(&b->p, bytes ? bytes : 16) != cudaSuccess) return -1;
    b->cap = bytes ? bytes : 16;
    return 0;
}

struct dmesh {
    dbuf x0, x1, tris, edges;
};

struct box_union {
    __device__ pl_aabb operator()(const pl_aabb &a, const pl_aabb &b) const
    {
        pl_aabb r = a;
        coll_cand_union(&r, &b);
        return r;
    }
};

const int TPB = 128;
int blocks(int n) { return (n + TPB - 1) / TPB; }

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

__global__ void k_refit(coll_cand_tree t, const pl_aabb *prims, int lo, int hi)
{
    int i = lo + blockIdx.x * blockDim.x + threadIdx.x;
    if (i < hi) coll_cand_refit(&t, prims, i);
}

__global__ void k_count(coll_cand_pass ps, coll_cand_tree t, const pl_aabb *prims, int queries,
                        int *count)
{
    int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < queries) count[i] = coll_cand_query(&ps, &t, prims, i, NULL, 0);
}

__global__ void k_write(coll_cand_pass ps, coll_cand_tree t, const pl_aabb *prims, int queries,
                        const int *off, coll_cand_key *key)
{
    int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < queries) coll_cand_query(&ps, &t, prims, i, key + off[i], off[i + 1] - off[i]);
}

/* Candidates per item of A (atomic counts: a histogram, order-free). */
__global__ void k_hist(const coll_cand_key *key, int total, coll_cand_key nb, int *count)
{
    int k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k < total) atomicAdd(&count[key[k] / nb], 1);
}

__global__ void k_idx(const coll_cand_key *key, int total, coll_cand_key nb, int *idx)
{
    int k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k < total) idx[k] = (int)(key[k] % nb);
}

} // namespace

struct coll_dev {
    dmesh m[2];
    dbuf prims, node, code[2], order[2], count, start, key[2], idx, root, temp;
    /* its own stream, not blocking with the legacy default stream: the
     * detection never waits for a solver's queued work */
    cudaStream_t s;
    /* PLIANT_DETECT_PROFILE set: time per stage (synchronising after each),
     * printed by coll_dev_close: uploads, trees, counts, lists */
    int profile, calls;
    double stage_ms[4], last;
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}

static void stage(coll_dev *d, int k)
{
    if (!d->profile) return;
    cudaStreamSynchronize(d->s);
    double t = now_ms();
    if (k >= 0) d->stage_ms[k] += t - d->last;
    d->last = t;
}

static int fail(pl_error *err, cudaError_t e, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "device detection: %s: %s", what,
                        cudaGetErrorString(e));
}

#define CK(call, what)                                                                         \
    do {                                                                                       \
        cudaError_t e_ = (call);                                                               \
        if (e_ != cudaSuccess) return fail(err, e_, what);                                     \
    } while (0)
#define GROW(buf, bytes)                                                                       \
    do {                                                                                       \
        if (grow(&(buf), (bytes))) return fail(err, cudaErrorMemoryAllocation, "allocation"); \
    } while (0)

extern "C" int coll_dev_open(coll_dev **d, pl_error *err)
{
    int n = 0;
    *d = NULL;
    CK(cudaGetDeviceCount(&n), "no device");
    if (n < 1) return fail(err, cudaErrorNoDevice, "no device");
    *d = (coll_dev *)calloc(1, sizeof **d);
    if (!*d) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    cudaError_t e = cudaStreamCreateWithFlags(&(*d)->s, cudaStreamNonBlocking);
    if (e != cudaSuccess) {
        free(*d);
        *d = NULL;
        return fail(err, e, "stream");
    }
    (*d)->profile = getenv("PLIANT_DETECT_PROFILE") != NULL;
    return PL_OK;
}

extern "C" void coll_dev_close(coll_dev *d)
{
    if (!d) return;
    if (d->profile && d->calls)
        fprintf(stderr, "device detection: %d calls, ms per call: uploads %.3f, trees %.3f, "
                "counts %.3f, lists %.3f\n", d->calls, d->stage_ms[0] / d->calls,
                d->stage_ms[1] / d->calls, d->stage_ms[2] / d->calls, d->stage_ms[3] / d->calls);
    dbuf *all[] = {&d->m[0].x0, &d->m[0].x1, &d->m[0].tris, &d->m[0].edges, &d->m[1].x0,
                   &d->m[1].x1, &d->m[1].tris, &d->m[1].edges, &d->prims, &d->node,
                   &d->code[0], &d->code[1], &d->order[0], &d->order[1], &d->count,
                   &d->start, &d->key[0], &d->key[1], &d->idx, &d->root, &d->temp};
    for (size_t k = 0; k < sizeof all / sizeof *all; ++k) cudaFree(all[k]->p);
    cudaStreamDestroy(d->s);
    free(d);
}

/* Uploads mesh m into slot dm; v = its view with device pointers. */
static int upload(dmesh *dm, const pl_coll_mesh *m, coll_cand_mesh *v, cudaStream_t st,
                  pl_error *err)
{
    size_t nx = (size_t)m->nverts * 3 * sizeof(double);
    GROW(dm->x0, nx);
    GROW(dm->x1, nx);
    GROW(dm->tris, (size_t)m->ntris * 3 * sizeof(int));
    GROW(dm->edges, (size_t)m->nedges * 2 * sizeof(int));
    if (nx) CK(cudaMemcpyAsync(dm->x0.p, m->x0, nx, cudaMemcpyHostToDevice, st), "upload");
    if (nx) CK(cudaMemcpyAsync(dm->x1.p, m->x1, nx, cudaMemcpyHostToDevice, st), "upload");
    if (m->ntris)
        CK(cudaMemcpyAsync(dm->tris.p, m->tris, (size_t)m->ntris * 3 * sizeof(int),
                           cudaMemcpyHostToDevice, st), "upload");
    if (m->nedges)
        CK(cudaMemcpyAsync(dm->edges.p, m->edges, (size_t)m->nedges * 2 * sizeof(int),
                           cudaMemcpyHostToDevice, st), "upload");
    coll_cand_mesh r = {m->nverts, m->ntris, m->nedges, (const double *)dm->x0.p,
                        (const double *)dm->x1.p, (const int *)dm->tris.p,
                        (const int *)dm->edges.p, 0.5 * m->margin};
    *v = r;
    return PL_OK;
}

/* The tree over ps's primitives in d (d->order[1], d->node). */
static int build_tree(coll_dev *d, const coll_cand_pass *ps, int n, coll_cand_tree *t,
                      pl_error *err)
{
    int leaves = coll_cand_leaves(n);
    pl_aabb *prims = (pl_aabb *)d->prims.p, empty;
    coll_cand_empty(&empty);
    k_pbox<<<blocks(n), TPB, 0, d->s>>>(ps->T, ps->edges, n, prims);
    CK(cudaGetLastError(), "box kernel");
    size_t tb = 0, tb2 = 0;
    CK(cub::DeviceReduce::Reduce(NULL, tb, prims, (pl_aabb *)d->root.p, n, box_union(), empty),
       "bounds");
    unsigned *c0 = (unsigned *)d->code[0].p, *c1 = (unsigned *)d->code[1].p;
    int *o0 = (int *)d->order[0].p, *o1 = (int *)d->order[1].p;
    CK(cub::DeviceRadixSort::SortPairs(NULL, tb2, c0, c1, o0, o1, n, 0, 30), "sort");
    GROW(d->temp, tb > tb2 ? tb : tb2);
    CK(cub::DeviceReduce::Reduce(d->temp.p, tb, prims, (pl_aabb *)d->root.p, n, box_union(),
                                 empty, d->s), "bounds");
    k_morton<<<blocks(n), TPB, 0, d->s>>>(prims, (const pl_aabb *)d->root.p, n, c0, o0);
    CK(cub::DeviceRadixSort::SortPairs(d->temp.p, tb2, c0, c1, o0, o1, n, 0, 30, d->s), "sort");
    coll_cand_tree r = {n, leaves, o1, (pl_aabb *)d->node.p};
    k_refit<<<blocks(leaves), TPB, 0, d->s>>>(r, prims, leaves, 2 * leaves);
    for (int lv = leaves / 2; lv >= 1; lv /= 2)
        k_refit<<<blocks(lv), TPB, 0, d->s>>>(r, prims, lv, 2 * lv);
    CK(cudaGetLastError(), "tree kernels");
    *t = r;
    return PL_OK;
}

/* Offsets of the queries' keys (d->start), *total; the keys (d->key[0]). */
static int write_keys(coll_dev *d, const coll_cand_pass *ps, const coll_cand_tree *t,
                      int queries, int *total, pl_error *err)
{
    int *count = (int *)d->count.p, *off = (int *)d->start.p;
    const pl_aabb *prims = (const pl_aabb *)d->prims.p;
    CK(cudaMemsetAsync(count + queries, 0, sizeof(int), d->s), "memset");
    k_count<<<blocks(queries), TPB, 0, d->s>>>(*ps, *t, prims, queries, count);
    CK(cudaGetLastError(), "count kernel");
    size_t tb = 0;
    CK(cub::DeviceScan::ExclusiveSum(NULL, tb, count, off, queries + 1), "scan");
    GROW(d->temp, tb);
    CK(cub::DeviceScan::ExclusiveSum(d->temp.p, tb, count, off, queries + 1, d->s), "scan");
    CK(cudaMemcpyAsync(total, off + queries, sizeof(int), cudaMemcpyDeviceToHost, d->s),
       "count kernel");
    CK(cudaStreamSynchronize(d->s), "count kernel");
    stage(d, 2);
    size_t kb = (size_t)(*total > 0 ? *total : 1) * sizeof(coll_cand_key);
    for (int k = 0; k < 2; ++k) GROW(d->key[k], kb);
    k_write<<<blocks(queries), TPB, 0, d->s>>>(*ps, *t, prims, queries, off,
                                                (coll_cand_key *)d->key[0].p);
    CK(cudaGetLastError(), "write kernel");
    return PL_OK;
}

/* Sorts the keys, makes the lists (d->start, d->idx) and downloads them. */
static int lists_of_keys(coll_dev *d, int total, int na, int nb, coll_cand_list *out,
                         pl_error *err)
{
    coll_cand_key *k0 = (coll_cand_key *)d->key[0].p, *k1 = (coll_cand_key *)d->key[1].p;
    if (total == 0) { /* no kernel over nothing: a launch of 0 blocks is an error */
        if (coll_cand_list_fit(out, na, 0)) return fail(err, cudaErrorMemoryAllocation, "host");
        memset(out->start, 0, (size_t)(na + 1) * sizeof(int));
        return PL_OK;
    }
    int bits = 1;
    while (bits < 64 && ((coll_cand_key)1 << bits) < (coll_cand_key)na * (coll_cand_key)nb) bits++;
    size_t tb = 0, tb2 = 0;
    CK(cub::DeviceRadixSort::SortKeys(NULL, tb, k0, k1, total, 0, bits), "sort");
    int *count = (int *)d->count.p, *start = (int *)d->start.p;
    CK(cub::DeviceScan::ExclusiveSum(NULL, tb2, count, start, na + 1), "scan");
    GROW(d->temp, tb > tb2 ? tb : tb2);
    CK(cub::DeviceRadixSort::SortKeys(d->temp.p, tb, k0, k1, total, 0, bits, d->s), "sort");
    CK(cudaMemsetAsync(count, 0, (size_t)(na + 1) * sizeof(int), d->s), "memset");
    k_hist<<<blocks(total), TPB, 0, d->s>>>(k1, total, (coll_cand_key)nb, count);
    CK(cub::DeviceScan::ExclusiveSum(d->temp.p, tb2, count, start, na + 1, d->s), "scan");
    k_idx<<<blocks(total), TPB, 0, d->s>>>(k1, total, (coll_cand_key)nb, (int *)d->idx.p);
    CK(cudaGetLastError(), "list kernels");
    if (coll_cand_list_fit(out, na, total)) return fail(err, cudaErrorMemoryAllocation, "host");
    CK(cudaMemcpyAsync(out->start, start, (size_t)(na + 1) * sizeof(int), cudaMemcpyDeviceToHost,
                       d->s), "offsets");
    if (total)
        CK(cudaMemcpyAsync(out->idx, d->idx.p, (size_t)total * sizeof(int),
                           cudaMemcpyDeviceToHost, d->s), "lists");
    CK(cudaStreamSynchronize(d->s), "lists");
    stage(d, 3);
    return PL_OK;
}

static int dev_pass(coll_dev *d, const coll_cand_pass *ps, coll_cand_list *out, pl_error *err)
{
    int n = ps->edges ? ps->T.nedges : ps->T.ntris;
    int queries = ps->edges ? ps->P.nedges : ps->P.nverts;
    int na = coll_cand_na(ps), nb = coll_cand_nb(ps), leaves = coll_cand_leaves(n);
    int nc = (queries > na ? queries : na) + 1;
    GROW(d->prims, (size_t)(n > 0 ? n : 1) * sizeof(pl_aabb));
    GROW(d->node, (size_t)2 * leaves * sizeof(pl_aabb));
    GROW(d->root, sizeof(pl_aabb));
    for (int k = 0; k < 2; ++k) {
        GROW(d->code[k], (size_t)(n > 0 ? n : 1) * sizeof(unsigned));
        GROW(d->order[k], (size_t)(n > 0 ? n : 1) * sizeof(int));
    }
    GROW(d->count, (size_t)nc * sizeof(int));
    GROW(d->start, (size_t)nc * sizeof(int));
    if (coll_cand_list_fit(out, na, 0)) return fail(err, cudaErrorMemoryAllocation, "host");
    if (n == 0 || queries == 0) {
        memset(out->start, 0, (size_t)(na + 1) * sizeof(int));
        return PL_OK;
    }
    coll_cand_tree t;
    int rc = build_tree(d, ps, n, &t, err), total = 0;
    if (rc) return rc;
    stage(d, 1);
    if ((rc = write_keys(d, ps, &t, queries, &total, err))) return rc;
    GROW(d->idx, (size_t)(total > 0 ? total : 1) * sizeof(int));
    return lists_of_keys(d, total, na, nb, out, err);
}

extern "C" int coll_dev_candidates(coll_dev *d, const pl_coll_mesh *A, const pl_coll_mesh *B,
                                   const pl_detect_params *prm, coll_cand_list out[3],
                                   double *ms, pl_error *err)
{
    double t0 = now_ms();
    d->calls++;
    stage(d, -1);
    coll_cand_mesh va, vb;
    int rc = upload(&d->m[0], A, &va, d->s, err);
    if (rc) return rc;
    if (A == B)
        vb = va;
    else if ((rc = upload(&d->m[1], B, &vb, d->s, err)))
        return rc;
    stage(d, 0);
    coll_cand_pass ps = {va, vb, 0, A == B, 0, prm->alarm, prm->alarm + prm->margin};
    if ((rc = dev_pass(d, &ps, &out[0], err))) return rc;
    if (A != B) {
        coll_cand_pass r = {vb, va, 0, 0, 0, prm->alarm, prm->alarm + prm->margin};
        if ((rc = dev_pass(d, &r, &out[1], err))) return rc;
    } else {
        if (coll_cand_list_fit(&out[1], 0, 0)) return fail(err, cudaErrorMemoryAllocation, "host");
        out[1].start[0] = 0;
    }
    coll_cand_pass e = coll_cand_edge_pass(&ps);
    if ((rc = dev_pass(d, &e, &out[2], err))) return rc;
    if (ms) *ms = now_ms() - t0;
    return PL_OK;
}
