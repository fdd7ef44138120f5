/* detect_run.c - the loops of detection: for every vertex (or edge) of one
 * mesh the BVH candidates of the other, measured by detect.c, the closest
 * vertex-face proximities kept per vertex.  Loops are split into one
 * contiguous chunk per thread whose results are concatenated in chunk
 * order: deterministic, whatever the number of threads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "detect_internal.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

pl_detect_params detect_defaults(double alarm)
{
    pl_detect_params p = {.alarm = alarm, .hints = NULL, .vertex_face = 1, .edge_edge = 1,
                          .max_per_vertex = 3, .normal_cos = 0.9};
    return p;
}

void proximities_free(pl_proximities *p)
{
    free(p->items);
    p->items = NULL;
    p->n = p->cap = 0;
}

/* ---- per-thread work ---------------------------------------------------- */

typedef struct cand {
    pl_proximity p;
    double rank;   /* nearest first (coll_vf_candidate) */
    int prim;
    int over_face; /* the vertex projects inside the triangle */
} cand;

typedef struct work {
    pl_proximities out;
    pl_ivec q;
    cand *c;
    int nc, capc;
    int fail;
    long long candidates;
} work;

/* Nearest first: |gap| (an inside point's way out is its nearest face),
 * then what look-ahead found, earliest first. */
static int cand_less(const cand *x, const cand *y)
{
    return x->rank < y->rank || (x->rank == y->rank && x->prim < y->prim);
}

/* Whether triangles (the b of two vertex-face proximities) share a vertex. */
static int share_vertex(const pl_proximity *x, const pl_proximity *y)
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (x->b[i] == y->b[j]) return 1;
    return 0;
}

/* Keeps the nearest proximity of a vertex and, at most max_per_vertex in
 * all, further ones over a face whose normals differ from every kept one (a
 * vertex in a concave corner touches two faces); beside a convex edge the
 * nearest alone holds it, a second row would be nearly dependent.  A vertex
 * with no DOF (a blade's apex or corner) is the exception: its rows act
 * only on the triangles' vertices, so a face sharing none with the kept
 * ones gives an independent row, whatever its normal, and max_per_vertex
 * (which bounds the rows on one vertex's DOFs) does not apply.  They are
 * needed: a cloth (a thin, two-sided sheet) draped over an apex has it
 * next to folds of several triangles at once, and the nearest (an edge of a fold beside it) does not
 * hold the face it is under (cloth_on_knives.xml: the apex came 6 mm through
 * that face); a blade's corner between layers of a cloth wrapped round it
 * has its three nearest in one layer and must keep the other off too.
 * Against a one-sided (closed) mesh the nearest proximity also says whether
 * the vertex is outside (in front of a face) or inside (behind one): further
 * ones must say the same.  Beside a part thinner than alarm (a dragon's
 * spine or claw) a vertex in front of the near face is also behind the far
 * one; that row (gap minus the distance, normal out of the far face) pushed
 * the vertex through the part, and the near one pushed it back: a ball on
 * dragon.obj jittered at 2-7 m/s with hundreds of vertex steps through. */
static int finish_vertex(work *w, const pl_detect_params *prm, int nodof, int one_sided)
{
    for (int i = 1; i < w->nc; ++i) { /* insertion sort: few candidates */
        cand x = w->c[i];
        int j = i - 1;
        while (j >= 0 && cand_less(&x, &w->c[j])) {
            w->c[j + 1] = w->c[j];
            j--;
        }
        w->c[j + 1] = x;
    }
    int first = w->out.n, kept = 0;
    int inside = w->nc > 0 && w->c[0].p.gap < 0.0; /* one-sided: only the inside rule's gaps */
    for (int i = 0; i < w->nc && (nodof || kept < prm->max_per_vertex); ++i) {
        if (kept > 0 && !w->c[i].over_face) continue;
        if (kept > 0 && one_sided && (w->c[i].p.gap < 0.0) != inside) continue;
        int distinct = 1;
        for (int k = first; k < w->out.n && distinct; ++k)
            if (dot3(w->out.items[k].normal, w->c[i].p.normal) >= prm->normal_cos &&
                !(nodof && !share_vertex(&w->out.items[k], &w->c[i].p)))
                distinct = 0;
        if (!distinct) continue;
        if (coll_prox_push(&w->out, &w->c[i].p)) return PL_EINTERNAL;
        kept++;
    }
    w->nc = 0;
    return PL_OK;
}

static int cand_push(work *w, const pl_proximity *p, int prim, int face, double rank)
{
    if (w->nc == w->capc) {
        int cap = w->capc ? 2 * w->capc : 16;
        cand *c = realloc(w->c, (size_t)cap * sizeof *c);
        if (!c) return PL_EINTERNAL;
        w->c = c;
        w->capc = cap;
    }
    w->c[w->nc].p = *p;
    w->c[w->nc].over_face = face;
    w->c[w->nc].rank = rank;
    w->c[w->nc++].prim = prim;
    return PL_OK;
}

typedef struct pass {
    const pl_coll_mesh *P, *T; /* vertex-face: points of P, triangles of T; edge-edge: edges */
    int ip, it, self, edges, brute;
    const coll_vv_kept *second; /* the second direction of a pair: what the first kept */
    const coll_cand_list *given; /* candidates from outside (NULL: the BVH's) */
    const pl_detect_params *prm;
} pass;

/* Item i's candidates into w->q (given, or the BVH's box overlaps in
 * increasing order; brute: none, every primitive is one). */
static int item_query(const pass *ps, work *w, int i)
{
    const pl_coll_mesh *P = ps->P, *T = ps->T;
    w->q.n = 0;
    if (ps->given) {
        const int *g = ps->given->idx + ps->given->start[i];
        for (int k = 0; k < ps->given->start[i + 1] - ps->given->start[i]; ++k)
            if (ivec_push(&w->q, g[k])) return PL_EINTERNAL;
    } else if (!ps->brute) {
        const pl_bvh *b = ps->edges ? &T->ebvh : &T->tbvh;
        const pl_aabb *prims = ps->edges ? T->ebox : T->tbox;
        const pl_aabb *q = ps->edges ? &P->ebox[i] : &P->vbox[i];
        if (bvh_query_grown(b, prims, coll_mesh_half(T), q, coll_mesh_half(P), &w->q))
            return PL_EINTERNAL;
    }
    return PL_OK;
}

/* Item i of a pass (a vertex of P or an edge of P) against its candidates. */
static int run_item(const pass *ps, work *w, int i)
{
    const pl_coll_mesh *P = ps->P, *T = ps->T;
    pl_proximity p;
    int face = 0;
    double rank = 0.0;
    int nt = ps->edges ? T->nedges : T->ntris;
    if (item_query(ps, w, i)) return PL_EINTERNAL;
    int count = ps->brute ? nt : w->q.n;
    w->candidates += count;
    for (int k = 0; k < count; ++k) {
        int j = ps->brute ? k : w->q.v[k];
        if (ps->edges) {
            if (coll_ee_candidate(P, ps->ip, i, T, ps->it, j, ps->self, ps->prm, &p) &&
                coll_prox_push(&w->out, &p))
                return PL_EINTERNAL;
        } else if (coll_vf_candidate(P, ps->ip, i, T, ps->it, j, ps->self, ps->second, ps->prm, &p,
                                     &face, &rank) &&
                   cand_push(w, &p, j, face, rank)) {
            return PL_EINTERNAL;
        }
    }
    /* the exception for vertices with no DOF is for thin sheets: a blade's
     * or a plate's corner, or any obstacle vertex over a cloth's layers.
     * Between two closed surfaces the old rule holds (the raptor's grasp
     * failed with it: a fixed finger's vertices kept rows with every face of
     * the body); without it the medium gingerbread's cookie caught on a
     * plate's corner. */
    if (ps->edges) return PL_OK; /* i is an edge: the rest is for vertices */
    int nodof = P->active && !P->active[i] && (P->two_sided || T->two_sided);
    return finish_vertex(w, ps->prm, nodof, !T->two_sided);
}

static int max_threads(void)
{
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

/* The items of a BVH pass whose boxes reach the other mesh's root box, in
 * increasing order: the others have no candidate and make nothing
 * (run_item), so the pass runs only these.  *n of them; NULL when out of
 * memory. */
static int *items_near(const pass *ps, int *n)
{
    const pl_coll_mesh *P = ps->P, *T = ps->T;
    const pl_aabb *root = ps->edges ? &T->ebvh.box[0] : &T->tbvh.box[0];
    const pl_aabb *q = ps->edges ? P->ebox : P->vbox;
    double hp = coll_mesh_half(P), ht = coll_mesh_half(T);
    int *v = malloc((size_t)(*n > 0 ? *n : 1) * sizeof *v), m = 0;
    if (!v) return NULL;
    for (int i = 0; i < *n; ++i)
        if (aabb_overlap_grown(root, ht, &q[i], hp)) v[m++] = i;
    *n = m;
    return v;
}

/* A BVH pass runs on one thread below this many items near the other mesh
 * (a query costs about 0.1-1 us; waking a team costs tens). */
#define PASS_PAR_MIN 512
/* Items a thread takes at a time (dynamic scheduling). */
#define PASS_CHUNK 32

/* Candidates of a wide edge pass measured by the threads, a chunk at a
 * time, each chunk's output merged in order. */
#define WIDE_CHUNK 64
/* An edge pass of fewer items than PASS_PAR_MIN with at least this many
 * candidates in all is measured wide (run_wide). */
#define WIDE_MIN 2048

/* Appends the chunks' outputs in chunk order: chunk[3 ch] is the thread
 * that ran chunk ch, chunk[3 ch + 1 .. + 2] its range in that thread's
 * output.  PL_OK or PL_EINTERNAL. */
static int merge_chunks(pl_proximities *out, const work *w, const int *chunk, int nchunks)
{
    int rc = PL_OK;
    for (int ch = 0; ch < nchunks && rc == PL_OK; ++ch) {
        const int *c = &chunk[3 * ch];
        for (int k = c[1]; k < c[2] && rc == PL_OK; ++k)
            rc = coll_prox_push(out, &w[c[0]].out.items[k]);
    }
    return rc;
}

/* An edge pass of few items with many candidates each (an obstacle's
 * edges under a cloth: 18 edges, hundreds of the cloth's each, 1.6 ms a
 * step on one thread for sharp_corner.xml): the items' lists are made
 * first, in order, then the (item, candidate) pairs are measured by the
 * threads in chunks and the chunks' outputs merged in order, which is the
 * serial loop's output (an edge item keeps every candidate's proximity,
 * nothing per item follows).  todo: the n items. */
static int run_wide(const pass *ps, const int *todo, int n, pl_proximities *out)
{
    work q = {0};
    pl_ivec pi = {0}, pj = {0}; /* the pairs: item, candidate */
    int rc = PL_OK;
    for (int k = 0; k < n && rc == PL_OK; ++k) {
        int i = todo ? todo[k] : k;
        rc = item_query(ps, &q, i);
        for (int c = 0; c < q.q.n && rc == PL_OK; ++c)
            rc = ivec_push(&pi, i) || ivec_push(&pj, q.q.v[c]) ? PL_EINTERNAL : PL_OK;
    }
    ivec_free(&q.q);
    int total = pi.n, nchunks = (total + WIDE_CHUNK - 1) / WIDE_CHUNK, nw = max_threads();
    if (ps->prm->counts) ps->prm->counts->candidates += total;
    work *w = rc == PL_OK ? calloc((size_t)nw, sizeof *w) : NULL;
    int *chunk = w ? malloc(3 * (size_t)(nchunks > 0 ? nchunks : 1) * sizeof *chunk) : NULL;
    if (!chunk) rc = PL_EINTERNAL;
#pragma omp parallel if (rc == PL_OK && total >= WIDE_MIN)
    {
        int tid = 0;
#ifdef _OPENMP
        tid = omp_get_thread_num();
#endif
#pragma omp for schedule(dynamic, 1) nowait
        for (int ch = 0; ch < (rc == PL_OK ? nchunks : 0); ++ch) {
            int *c = &chunk[3 * ch], hi = (ch + 1) * WIDE_CHUNK < total ? (ch + 1) * WIDE_CHUNK : total;
            c[0] = tid, c[1] = w[tid].out.n;
            for (int k = ch * WIDE_CHUNK; k < hi && !w[tid].fail; ++k) {
                pl_proximity p;
                if (coll_ee_candidate(ps->P, ps->ip, pi.v[k], ps->T, ps->it, pj.v[k], ps->self,
                                      ps->prm, &p) &&
                    coll_prox_push(&w[tid].out, &p))
                    w[tid].fail = 1;
            }
            c[2] = w[tid].out.n;
        }
    }
    for (int t = 0; w && t < nw; ++t)
        if (w[t].fail) rc = PL_EINTERNAL;
    if (rc == PL_OK) rc = merge_chunks(out, w, chunk, nchunks);
    for (int t = 0; w && t < nw; ++t) proximities_free(&w[t].out);
    free(w);
    free(chunk);
    ivec_free(&pi);
    ivec_free(&pj);
    return rc;
}

static int run_pass(const pass *ps, pl_proximities *out)
{
    int n = ps->edges ? ps->P->nedges : ps->P->nverts;
    if (n == 0 || (ps->edges ? ps->T->nedges : ps->T->ntris) == 0) return PL_OK;
    /* over given candidates, the work is theirs: an item without any makes
     * nothing (run_item), and a pass of a few dozen does not pay for waking
     * the threads (device detection's passes are mostly empty) */
    int load = ps->given ? ps->given->start[n] : n;
    if (load == 0) return PL_OK;
    int *todo = NULL; /* the items to run (NULL: all n) */
    if (!ps->given && !ps->brute) {
        if (!(todo = items_near(ps, &n))) return PL_EINTERNAL;
        load = n;
        if (n == 0) {
            free(todo);
            return PL_OK;
        }
    }
    if (ps->edges && !ps->given && !ps->brute && n < PASS_PAR_MIN && max_threads() > 1) {
        int rc = run_wide(ps, todo, n, out);
        free(todo);
        return rc;
    }
    int nw = max_threads(), nchunks = (n + PASS_CHUNK - 1) / PASS_CHUNK;
    work *w = calloc((size_t)nw, sizeof *w);
    int *chunk = malloc(3 * (size_t)nchunks * sizeof *chunk); /* owner, first, end */
    if (!w || !chunk) {
        free(w);
        free(chunk);
        free(todo);
        return PL_EINTERNAL;
    }
    /* chunks of items go to whichever thread is free (a pass's work sits
     * where the meshes meet: contiguous shares left most threads idle);
     * each chunk's output is merged in chunk order below, so the result is
     * the serial loop's whatever the threads */
#pragma omp parallel if (load > (ps->given ? 64 : PASS_PAR_MIN))
    {
        int tid = 0;
#ifdef _OPENMP
        tid = omp_get_thread_num();
#endif
#pragma omp for schedule(dynamic, 1) nowait
        for (int ch = 0; ch < nchunks; ++ch) {
            int *c = &chunk[3 * ch];
            c[0] = tid, c[1] = c[2] = w[tid].out.n;
            int hi = (ch + 1) * PASS_CHUNK < n ? (ch + 1) * PASS_CHUNK : n;
            for (int k = ch * PASS_CHUNK; k < hi && !w[tid].fail; ++k) {
                int i = todo ? todo[k] : k;
                if (ps->given && ps->given->start[i] == ps->given->start[i + 1]) continue;
                if (run_item(ps, &w[tid], i)) w[tid].fail = 1;
            }
            c[2] = w[tid].out.n;
        }
    }
    int rc = PL_OK;
    for (int t = 0; t < nw; ++t) {
        if (ps->prm->counts) ps->prm->counts->candidates += w[t].candidates;
        if (w[t].fail) rc = PL_EINTERNAL;
    }
    if (rc == PL_OK) rc = merge_chunks(out, w, chunk, nchunks);
    for (int t = 0; t < nw; ++t) {
        proximities_free(&w[t].out);
        ivec_free(&w[t].q);
        free(w[t].c);
    }
    free(w);
    free(chunk);
    free(todo);
    return rc;
}

static int detect(const pl_coll_mesh *A, int ia, const pl_coll_mesh *B, int ib,
                  const pl_detect_params *prm, pl_proximities *out, int brute,
                  const coll_cand_list *given)
{
    int self = A == B;
    pass ps = {.prm = prm, .self = self, .brute = brute};
    ps.given = given ? &given[0] : NULL;
    int rc = PL_OK;
    if (prm->vertex_face) {
        ps.P = A, ps.T = B, ps.ip = ia, ps.it = ib, ps.edges = 0;
        int from = out->n;
        rc = run_pass(&ps, out);
        if (rc == PL_OK && !self) {
            coll_vv_kept kv;
            rc = coll_vv_collect(out, from, B->nverts, &kv);
            ps.P = B, ps.T = A, ps.ip = ib, ps.it = ia, ps.second = &kv;
            ps.given = given ? &given[1] : NULL;
            if (rc == PL_OK) rc = run_pass(&ps, out);
            ps.second = NULL;
            free(kv.key);
        }
    }
    if (rc == PL_OK && prm->edge_edge) {
        ps.P = A, ps.T = B, ps.ip = ia, ps.it = ib, ps.edges = 1;
        ps.given = given ? &given[2] : NULL;
        rc = run_pass(&ps, out);
    }
    return rc;
}

int detect_pair(pl_coll_mesh *A, int ia, pl_coll_mesh *B, int ib, const pl_detect_params *prm,
                pl_proximities *out)
{
    /* the passes walk B's triangles (A's vertices), A's (B's vertices) and
     * B's edges (A's edges) */
    if (prm->vertex_face) {
        coll_mesh_fit(B, COLL_TREE_TRIS);
        coll_mesh_fit(A, COLL_TREE_TRIS);
    }
    if (prm->edge_edge) coll_mesh_fit(B, COLL_TREE_EDGES);
    return detect(A, ia, B, ib, prm, out, 0, NULL);
}

int detect_pair_brute(const pl_coll_mesh *A, int ia, const pl_coll_mesh *B, int ib,
                         const pl_detect_params *prm, pl_proximities *out)
{
    return detect(A, ia, B, ib, prm, out, 1, NULL);
}

int detect_pair_given(const pl_coll_mesh *A, int ia, const pl_coll_mesh *B, int ib,
                      const pl_detect_params *prm, const coll_cand_list given[3],
                      pl_proximities *out)
{
    return detect(A, ia, B, ib, prm, out, 0, given);
}
