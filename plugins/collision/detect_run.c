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

/* Item i of a pass (a vertex of P or an edge of P) against its candidates. */
static int run_item(const pass *ps, work *w, int i)
{
    const pl_coll_mesh *P = ps->P, *T = ps->T;
    pl_proximity p;
    int face = 0;
    double rank = 0.0;
    w->q.n = 0;
    int nt = ps->edges ? T->nedges : T->ntris;
    if (ps->given) {
        const int *g = ps->given->idx + ps->given->start[i];
        w->q.n = 0;
        for (int k = 0; k < ps->given->start[i + 1] - ps->given->start[i]; ++k)
            if (ivec_push(&w->q, g[k])) return PL_EINTERNAL;
    } else if (!ps->brute) {
        const pl_bvh *b = ps->edges ? &T->ebvh : &T->tbvh;
        const pl_aabb *prims = ps->edges ? T->ebox : T->tbox;
        const pl_aabb *q = ps->edges ? &P->ebox[i] : &P->vbox[i];
        if (bvh_query_grown(b, prims, coll_mesh_half(T), q, coll_mesh_half(P), &w->q))
            return PL_EINTERNAL;
    }
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
    int nw = max_threads();
    work *w = calloc((size_t)nw, sizeof *w);
    if (!w) {
        free(todo);
        return PL_EINTERNAL;
    }
    int used = 1;
#pragma omp parallel if (load > (ps->given ? 64 : PASS_PAR_MIN))
    {
        int tid = 0, nth = 1;
#ifdef _OPENMP
        tid = omp_get_thread_num();
        nth = omp_get_num_threads();
#endif
#pragma omp single
        used = nth;
        int chunk = (n + nth - 1) / nth, lo = tid * chunk, hi = lo + chunk < n ? lo + chunk : n;
        for (int k = lo; k < hi && !w[tid].fail; ++k) {
            int i = todo ? todo[k] : k;
            if (ps->given && ps->given->start[i] == ps->given->start[i + 1]) continue;
            if (run_item(ps, &w[tid], i)) w[tid].fail = 1;
        }
    }
    int rc = PL_OK;
    for (int t = 0; t < used; ++t) {
        if (ps->prm->counts) ps->prm->counts->candidates += w[t].candidates;
        if (w[t].fail) rc = PL_EINTERNAL;
        for (int k = 0; k < w[t].out.n && rc == PL_OK; ++k)
            rc = coll_prox_push(out, &w[t].out.items[k]);
    }
    for (int t = 0; t < nw; ++t) {
        proximities_free(&w[t].out);
        ivec_free(&w[t].q);
        free(w[t].c);
    }
    free(w);
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
