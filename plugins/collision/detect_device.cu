/* detect_device.cu - detection's candidate pairs on the GPU, for a batch of
 * pairs at once (a step's): every mesh of the batch uploaded once (one copy
 * from pinned memory), one kept tree per mesh and kind
 * (detect_device_tree.cu), then two levels so that threads do even work:
 * one thread per query walks a tree and writes its box overlaps (the broad
 * phase), then one thread per overlap applies the narrow filter and writes
 * the key of each candidate.  One read-back of the counts (if the overlaps
 * overflowed their buffer, it grows and the two kernels run again), then
 * the keys of every pass sorted at once (CUB radix sort; a pass's keys
 * after the previous pass's), each item's list start found by a binary
 * search, one download.  The item bodies are detect_cand.h's, which
 * coll_cand_host runs on the host; this file is compiled with -fmad=false
 * so that the distances round as on the host. */
#include <cub/cub.cuh>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "detect_device_int.cuh"

namespace {

/* A pass as the kernels see it. */
struct dpass {
    coll_cand_pass ps;
    coll_cand_tree t;     /* over ps.T's primitives */
    const pl_aabb *prims; /* their boxes */
    coll_cand_key kbase;  /* its first key: the keys of all passes are disjoint */
    int ibase;            /* its first item among all passes' items */
    int qbase;            /* its first query among all passes' queries */
    int nb;
};

/* A box overlap of the broad phase: query i of pass p with primitive j. */
struct overlap {
    int p, i, j;
};

/* The last pass whose base (qbase, ibase, or kbase for keys) is <= v. */
enum { BASE_Q, BASE_I };
__device__ int pass_of(const dpass *P, int np, int g, int which)
{
    int lo = 0, hi = np - 1;
    while (lo < hi) {
        int m = (lo + hi + 1) / 2;
        if ((which == BASE_Q ? P[m].qbase : P[m].ibase) <= g) lo = m; else hi = m - 1;
    }
    return lo;
}

__device__ int pass_of_key(const dpass *P, int np, coll_cand_key k)
{
    int lo = 0, hi = np - 1;
    while (lo < hi) {
        int m = (lo + hi + 1) / 2;
        if (P[m].kbase <= k) lo = m; else hi = m - 1;
    }
    return lo;
}

/* One thread per query of every pass, walking its pass's tree.
 * counters: [0] overlaps found, [1] keys written, [2 + p] overlaps of pass
 * p.  A thread reserves room for 8 overlaps at a time: one atomic on the
 * shared counter per 8 rather than per overlap. */
__global__ void k_broad(const dpass *P, int np, int nq, overlap *over, int cap, int *counters)
{
    int g = blockIdx.x * blockDim.x + threadIdx.x;
    if (g >= nq) return;
    int p = pass_of(P, np, g, BASE_Q), i = g - P[p].qbase;
    coll_cand_pass ps = P[p].ps;
    coll_cand_tree t = P[p].t;
    const pl_aabb *prims = P[p].prims;
    coll_cand_walk w;
    coll_cand_walk_start(&w, &ps, i);
    int found = 0, m = 0, buf[8];
    for (int j;;) {
        j = coll_cand_walk_next(&w, &t, prims);
        if (j >= 0) buf[m++] = j;
        if (m == 8 || (j < 0 && m > 0)) {
            int at = atomicAdd(&counters[0], m);
            for (int k = 0; k < m; ++k)
                if (at + k < cap) over[at + k] = overlap{p, i, buf[k]};
            found += m;
            m = 0;
        }
        if (j < 0) break;
    }
    if (found) atomicAdd(&counters[2 + p], found);
}

/* One thread per overlap (a grid-stride loop); the keys kept by a warp
 * take one atomic. */
__global__ void k_filter(const dpass *P, const overlap *over, int cap, int *counters,
                         coll_cand_key *key)
{
    int n = min(counters[0], cap), lane = threadIdx.x & 31;
    for (int k = blockIdx.x * blockDim.x + threadIdx.x; k < n; k += gridDim.x * blockDim.x) {
        overlap o = over[k];
        coll_cand_key c = 0;
        int keep = coll_cand_keep(&P[o.p].ps, o.i, o.j, &c);
        unsigned mask = __activemask(), kept = __ballot_sync(mask, keep);
        int leader = __ffs(mask) - 1, base = 0;
        if (lane == leader && kept) base = atomicAdd(&counters[1], __popc(kept));
        base = __shfl_sync(mask, base, leader);
        if (keep) key[base + __popc(kept & ((1u << lane) - 1u))] = P[o.p].kbase + c;
    }
}

/* start[g]: the first sorted key of item g (all passes' items), by binary
 * search; start[items] = total. */
__global__ void k_start(const dpass *P, int np, int items, const coll_cand_key *key, int total,
                        int *start)
{
    int g = blockIdx.x * blockDim.x + threadIdx.x;
    if (g > items) return;
    if (g == items) {
        start[g] = total;
        return;
    }
    int p = pass_of(P, np, g, BASE_I);
    coll_cand_key want = P[p].kbase + (coll_cand_key)(g - P[p].ibase) * (coll_cand_key)P[p].nb;
    int lo = 0, hi = total;
    while (lo < hi) {
        int m = lo + (hi - lo) / 2;
        if (key[m] < want) lo = m + 1; else hi = m;
    }
    start[g] = lo;
}

__global__ void k_idx(const dpass *P, int np, const coll_cand_key *key, int total, int *idx)
{
    int k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= total) return;
    int p = pass_of_key(P, np, key[k]);
    idx[k] = (int)((key[k] - P[p].kbase) % (coll_cand_key)P[p].nb);
}

/* The host's record of a batch: its distinct meshes and its passes. */
struct hmesh {
    const pl_coll_mesh *m;
    size_t off; /* in the upload [bytes] */
    coll_cand_mesh v;
};

struct hpass {
    int pair, k; /* pass k of pair */
    int na;
};

struct batch {
    hmesh *mesh;
    int nmesh;
    hpass *pass;
    dpass *hdp, *dp;      /* the pass records: in the pinned upload; on the device */
    dtree_rec *htr, *dtr; /* the trees to make, likewise */
    int npass, items, queries, ntree, tprims, tleaves;
    coll_cand_key keys; /* the key space of all passes */
};

} // namespace

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

extern "C" int coll_dev_open(coll_dev **d, pl_error *err)
{
    int n = 0;
    *d = NULL;
    CK(cudaGetDeviceCount(&n), "no device");
    if (n < 1) return dev_fail(err, cudaErrorNoDevice, "no device");
    *d = (coll_dev *)calloc(1, sizeof **d);
    if (!*d) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    cudaError_t e = cudaStreamCreateWithFlags(&(*d)->s, cudaStreamNonBlocking);
    if (e != cudaSuccess) {
        free(*d);
        *d = NULL;
        return dev_fail(err, e, "stream");
    }
    (*d)->profile = getenv("PLIANT_DETECT_PROFILE") != NULL;
    return PL_OK;
}

extern "C" void coll_dev_close(coll_dev *d)
{
    if (!d) return;
    if (d->profile && d->calls)
        fprintf(stderr, "device detection: %d batches, ms per batch: uploads %.3f, trees %.3f, "
                "overlaps+filter %.3f, lists %.3f\n", d->calls, d->stage_ms[0] / d->calls,
                d->stage_ms[1] / d->calls, d->stage_ms[2] / d->calls, d->stage_ms[3] / d->calls);
    cudaStreamSynchronize(d->s);
    dev_trees_free(d);
    dbuf *all[] = {&d->code[0], &d->code[1], &d->order_in, &d->root, &d->temp, &d->mesh_mem,
                   &d->over, &d->key[0], &d->key[1], &d->start, &d->idx,
                   &d->counters};
    for (size_t k = 0; k < sizeof all / sizeof *all; ++k) dbuf_free(all[k]);
    cudaFreeHost(d->up);
    cudaFreeHost(d->down);
    cudaStreamDestroy(d->s);
    free(d);
}

/* Pinned host memory of at least bytes in *p (its capacity *cap). */
static int grow_pinned(void **p, size_t *cap, size_t bytes, pl_error *err)
{
    if (bytes <= *cap && *p) return PL_OK;
    cudaFreeHost(*p);
    *p = NULL;
    *cap = 0;
    bytes += bytes / 2 + 4096;
    CK(cudaMallocHost(p, bytes), "pinned memory");
    *cap = bytes;
    return PL_OK;
}

static size_t align16(size_t x) { return (x + 15) & ~(size_t)15; }

static size_t mesh_bytes(const pl_coll_mesh *m)
{
    return 2 * align16((size_t)m->nverts * 3 * sizeof(double)) +
           align16((size_t)m->ntris * 3 * sizeof(int)) +
           align16((size_t)m->nedges * 2 * sizeof(int));
}

static int mesh_index(batch *b, const pl_coll_mesh *m)
{
    for (int k = 0; k < b->nmesh; ++k)
        if (b->mesh[k].m == m) return k;
    b->mesh[b->nmesh].m = m;
    return b->nmesh++;
}

/* Copies the meshes into the pinned upload, their views (device pointers)
 * into b->mesh[].v; the passes' records go after them.  One copy. */
static void upload(coll_dev *d, batch *b)
{
    char *up = (char *)d->up, *dev = (char *)d->mesh_mem.p;
    for (int k = 0; k < b->nmesh; ++k) {
        const pl_coll_mesh *m = b->mesh[k].m;
        size_t o = b->mesh[k].off, nx = (size_t)m->nverts * 3 * sizeof(double);
        size_t nt = (size_t)m->ntris * 3 * sizeof(int), ne = (size_t)m->nedges * 2 * sizeof(int);
        size_t ox1 = o + align16(nx), ot = ox1 + align16(nx), oe = ot + align16(nt);
        if (nx) memcpy(up + o, m->x0, nx), memcpy(up + ox1, m->x1, nx);
        if (nt) memcpy(up + ot, m->tris, nt);
        if (ne) memcpy(up + oe, m->edges, ne);
        coll_cand_mesh v = {m->nverts, m->ntris, m->nedges, (const double *)(dev + o),
                            (const double *)(dev + ox1), (const int *)(dev + ot),
                            (const int *)(dev + oe), 0.5 * m->margin};
        b->mesh[k].v = v;
    }
}

/* Pass k of pair p (its record r filled but for the tree): the tree over
 * its primitives reserved, and listed to be made if it is its first use in
 * the batch.  PL_OK or PL_EINTERNAL. */
static int pass_tree(coll_dev *d, batch *b, int tmesh, dpass *r, pl_error *err)
{
    const coll_cand_pass *ps = &r->ps;
    int n = ps->edges ? ps->T.nedges : ps->T.ntris;
    dtree_rec t;
    memset(&t, 0, sizeof t);
    int make = dev_tree_reserve(d, b->mesh[tmesh].m, ps->edges, n, &t, err);
    if (make < 0) return PL_EINTERNAL;
    r->t = t.t;
    r->prims = t.prims;
    if (make) {
        t.v = ps->T;
        t.pbase = b->tprims;
        t.lbase = b->tleaves;
        b->tprims += n;
        b->tleaves += t.t.leaves;
        b->htr[b->ntree++] = t;
    }
    return PL_OK;
}

/* Pair p's passes: out's lists fitted (skipped passes empty), the records
 * of those that run.  PL_OK or PL_EINTERNAL. */
static int pair_passes(coll_dev *d, batch *b, int p, int ia, int ib, int self,
                       const pl_detect_params *prm, coll_cand_list *out, pl_error *err)
{
    int use[3];
    coll_cand_pass ps[3];
    coll_cand_pair_passes(&b->mesh[ia].v, &b->mesh[ib].v, self, prm->vertex_face,
                          prm->edge_edge, prm->alarm, prm->alarm + prm->margin, ps, use);
    for (int k = 0; k < 3; ++k) {
        coll_cand_list *l = &out[3 * p + k];
        int na = k == 1 && self ? 0 : coll_cand_na(&ps[k]);
        if (coll_cand_list_fit(l, na, 0))
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        memset(l->start, 0, (size_t)(na + 1) * sizeof(int));
        if (!use[k]) continue;
        hpass *h = &b->pass[b->npass];
        h->pair = p, h->k = k, h->na = na;
        dpass *r = &b->hdp[b->npass];
        memset(r, 0, sizeof *r);
        r->ps = ps[k];
        r->kbase = b->keys;
        r->ibase = b->items;
        r->qbase = b->queries;
        r->nb = coll_cand_nb(&ps[k]);
        int rc = pass_tree(d, b, k == 1 || (k == 2 && ps[2].swap) ? ia : ib, r, err);
        if (rc) return rc;
        b->npass++;
        b->keys += (coll_cand_key)na * (coll_cand_key)r->nb;
        b->items += na;
        b->queries += ps[k].edges ? ps[k].P.nedges : ps[k].P.nverts;
    }
    return PL_OK;
}

/* The batch's meshes, passes and trees, uploaded in one copy. */
static int plan(coll_dev *d, batch *b, int npairs, const pl_coll_mesh *const *A,
                const pl_coll_mesh *const *B, const pl_detect_params *prm, coll_cand_list *out,
                pl_error *err)
{
    int *pm = (int *)malloc((size_t)npairs * 2 * sizeof(int));
    if (!pm) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    for (int p = 0; p < npairs; ++p)
        pm[2 * p] = mesh_index(b, A[p]), pm[2 * p + 1] = mesh_index(b, B[p]);
    size_t off = 0;
    for (int k = 0; k < b->nmesh; ++k) b->mesh[k].off = off, off += mesh_bytes(b->mesh[k].m);
    size_t pass_off = align16(off), tree_off = pass_off + (size_t)3 * npairs * sizeof(dpass);
    size_t bytes = tree_off + (size_t)3 * npairs * sizeof(dtree_rec);
    int rc = grow_pinned(&d->up, &d->up_cap, bytes, err);
    if (rc == PL_OK && dbuf_grow(&d->mesh_mem, bytes))
        rc = dev_fail(err, cudaErrorMemoryAllocation, "allocation");
    if (rc == PL_OK) {
        upload(d, b);
        b->hdp = (dpass *)((char *)d->up + pass_off);
        b->htr = (dtree_rec *)((char *)d->up + tree_off);
    }
    for (int p = 0; p < npairs && rc == PL_OK; ++p)
        rc = pair_passes(d, b, p, pm[2 * p], pm[2 * p + 1], A[p] == B[p], prm, out, err);
    free(pm);
    if (rc == PL_OK && b->npass)
        CK(cudaMemcpyAsync(d->mesh_mem.p, d->up, tree_off + (size_t)b->ntree * sizeof(dtree_rec),
                           cudaMemcpyHostToDevice, d->s), "upload");
    b->dp = (dpass *)((char *)d->mesh_mem.p + pass_off); /* the kernels' copies */
    b->dtr = (dtree_rec *)((char *)d->mesh_mem.p + tree_off);
    return rc;
}

/* The overlaps and the keys of every pass; counts (2 + npass) read back
 * into *cnt (pinned).  Grows the buffers and runs again on overflow. */
static int overlaps_and_keys(coll_dev *d, const batch *b, int **cnt, pl_error *err)
{
    size_t nc = (size_t)(2 + b->npass) * sizeof(int);
    GROW(d->counters, nc);
    if (!d->over_cap) d->over_cap = 1 << 18;
    for (int attempt = 0; attempt < 2; ++attempt) {
        int cap = (int)d->over_cap;
        GROW(d->over, (size_t)cap * sizeof(overlap));
        for (int k = 0; k < 2; ++k) GROW(d->key[k], (size_t)cap * sizeof(coll_cand_key));
        int *counters = (int *)d->counters.p;
        CK(cudaMemsetAsync(counters, 0, nc, d->s), "memset");
        k_broad<<<dev_blocks(b->queries), DEV_TPB, 0, d->s>>>(
            b->dp, b->npass, b->queries, (overlap *)d->over.p, cap, counters);
        CK(cudaGetLastError(), "overlap kernel");
        int grid = dev_blocks(cap) < 4096 ? dev_blocks(cap) : 4096;
        k_filter<<<grid, DEV_TPB, 0, d->s>>>(b->dp, (const overlap *)d->over.p, cap, counters,
                                              (coll_cand_key *)d->key[0].p);
        CK(cudaGetLastError(), "filter kernel");
        if (grow_pinned(&d->down, &d->down_cap, nc, err)) return PL_EINTERNAL;
        CK(cudaMemcpyAsync(d->down, counters, nc, cudaMemcpyDeviceToHost, d->s), "counts");
        CK(cudaStreamSynchronize(d->s), "overlap kernels");
        *cnt = (int *)d->down;
        if ((*cnt)[0] <= cap) return PL_OK;
        d->over_cap = (size_t)(*cnt)[0] + (size_t)(*cnt)[0] / 2; /* then once more */
    }
    return dev_fail(err, cudaErrorMemoryAllocation, "overlaps grew between two runs");
}

/* Sorts the keys of all passes, finds every item's list and downloads
 * them into out (total keys from the counts). */
static int lists(coll_dev *d, const batch *b, int total, coll_cand_list *out, pl_error *err)
{
    int items = b->items;
    size_t need = ((size_t)items + 1 + (size_t)total) * sizeof(int);
    if (grow_pinned(&d->down, &d->down_cap, need, err)) return PL_EINTERNAL;
    GROW(d->start, ((size_t)items + 1) * sizeof(int));
    GROW(d->idx, (size_t)(total > 0 ? total : 1) * sizeof(int));
    int *start = (int *)d->down, *idx = start + items + 1;
    const coll_cand_key *sorted = (const coll_cand_key *)d->key[1].p;
    if (total > 0) {
        int bits = 1;
        while (bits < 64 && ((coll_cand_key)1 << bits) < b->keys) bits++;
        size_t tb = 0;
        coll_cand_key *k0 = (coll_cand_key *)d->key[0].p, *k1 = (coll_cand_key *)d->key[1].p;
        CK(cub::DeviceRadixSort::SortKeys(NULL, tb, k0, k1, total, 0, bits), "sort");
        GROW(d->temp, tb);
        CK(cub::DeviceRadixSort::SortKeys(d->temp.p, tb, k0, k1, total, 0, bits, d->s), "sort");
        k_idx<<<dev_blocks(total), DEV_TPB, 0, d->s>>>(b->dp, b->npass, sorted, total,
                                                       (int *)d->idx.p);
    }
    k_start<<<dev_blocks(items + 1), DEV_TPB, 0, d->s>>>(b->dp, b->npass, items, sorted, total,
                                                         (int *)d->start.p);
    CK(cudaGetLastError(), "list kernels");
    CK(cudaMemcpyAsync(start, d->start.p, ((size_t)items + 1) * sizeof(int),
                       cudaMemcpyDeviceToHost, d->s), "offsets");
    if (total > 0)
        CK(cudaMemcpyAsync(idx, d->idx.p, (size_t)total * sizeof(int), cudaMemcpyDeviceToHost,
                           d->s), "lists");
    CK(cudaStreamSynchronize(d->s), "lists");
    for (int p = 0; p < b->npass; ++p) {
        const hpass *h = &b->pass[p];
        coll_cand_list *l = &out[3 * h->pair + h->k];
        const int *s = start + b->hdp[p].ibase;
        int n = s[h->na] - s[0];
        if (coll_cand_list_fit(l, h->na, n))
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        for (int i = 0; i <= h->na; ++i) l->start[i] = s[i] - s[0];
        if (n) memcpy(l->idx, idx + s[0], (size_t)n * sizeof(int));
    }
    return PL_OK;
}

static int run_batch(coll_dev *d, batch *b, int npairs, const pl_coll_mesh *const *A,
                     const pl_coll_mesh *const *B, const pl_detect_params *prm,
                     coll_cand_list *out, long long *broad, pl_error *err)
{
    int rc = plan(d, b, npairs, A, B, prm, out, err);
    for (int p = 0; p < npairs; ++p) broad[p] = 0;
    if (rc || b->npass == 0) return rc;
    stage(d, 0);
    rc = dev_trees_make(d, b->dtr, b->htr, b->ntree, b->tprims, b->tleaves, err);
    if (rc) return rc;
    stage(d, 1);
    int *cnt = NULL;
    if ((rc = overlaps_and_keys(d, b, &cnt, err))) return rc;
    stage(d, 2);
    for (int p = 0; p < b->npass; ++p) broad[b->pass[p].pair] += cnt[2 + p];
    rc = lists(d, b, cnt[1], out, err);
    stage(d, 3);
    return rc;
}

extern "C" int coll_dev_batch(coll_dev *d, int npairs, const pl_coll_mesh *const *A,
                              const pl_coll_mesh *const *B, const pl_detect_params *prm,
                              coll_cand_list *out, long long *broad, double *ms, pl_error *err)
{
    double t0 = now_ms();
    d->calls++;
    d->batches++;
    stage(d, -1);
    batch b;
    memset(&b, 0, sizeof b);
    b.mesh = (hmesh *)calloc((size_t)(2 * npairs + 1), sizeof *b.mesh);
    b.pass = (hpass *)calloc((size_t)(3 * npairs + 1), sizeof *b.pass);
    int rc = b.mesh && b.pass ? run_batch(d, &b, npairs, A, B, prm, out, broad, err)
                              : pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    free(b.mesh);
    free(b.pass);
    if (rc) cudaStreamSynchronize(d->s); /* nothing left running on the buffers */
    if (ms) *ms = now_ms() - t0;
    return rc;
}

extern "C" int coll_dev_candidates(coll_dev *d, const pl_coll_mesh *A, const pl_coll_mesh *B,
                                   const pl_detect_params *prm, coll_cand_list out[3],
                                   double *ms, pl_error *err)
{
    long long broad;
    return coll_dev_batch(d, 1, &A, &B, prm, out, &broad, ms, err);
}
