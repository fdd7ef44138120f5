/* detect_cand.h - the candidate pairs of detection as the device makes
 * them (detect_device.cu) and the host replays them (detect_cand_host.c):
 * the bodies of the kernels, one per item, PL_HD so that both sides run the
 * same code.
 *
 * Broad phase: the primitives (triangles or edges) of one mesh get their
 * swept boxes (bitwise those of coll_mesh_prepare), are sorted by the Morton
 * code of their centres, and an implicit complete binary tree is laid over
 * the sorted order (node i has children 2i and 2i+1; leaf P + j holds sorted
 * primitives j L .. j L + L - 1): building it is the sort alone, refitting
 * it one pass per level.  Each query (a vertex's or an edge's box of the
 * other mesh) walks the tree.
 *
 * Narrow filter: the early exits of coll_vf_candidate / coll_ee_candidate
 * that only need positions (self adjacency, the boxes, the distance at the
 * start of the step and the look-ahead's reach bound).  What passes is a
 * superset of what detection keeps: the host measures those pairs with the
 * full rules (sides, hints, per-vertex choice) and gets the very contacts
 * of detect_pair, in the same order (detect_pair_given).  Candidates are
 * sort keys (item of A, primitive of B): sorted, they give every item's
 * list in increasing primitive order, like bvh_query's. */
#ifndef PLIANT_COLLISION_DETECT_CAND_H
#define PLIANT_COLLISION_DETECT_CAND_H

#include "detect.h"
#include "geom_hd.h"

#define COLL_CAND_LEAF 4

/* A mesh as the candidate kernels see it (host or device pointers). */
typedef struct coll_cand_mesh {
    int nverts, ntris, nedges;
    const double *x0, *x1; /* nverts x 3 */
    const int *tris, *edges;
    double half;           /* half the box margin of coll_mesh_prepare [m] */
} coll_cand_mesh;

/* One pass: items of P (vertices, or edges when edges) against primitives
 * of T (triangles, or edges).  swap (edges only): P is the pair's second
 * mesh (B), queried against a tree over A's edges.  Edges are queried from
 * the mesh with more of them: a long edge (an obstacle's) overlaps
 * thousands of a cloth's small boxes, and one thread walking them all was
 * the whole time of a step (sharp_corner_10k: 20 ms). */
typedef struct coll_cand_pass {
    coll_cand_mesh P, T;
    int edges, self, swap;
    double alarm, reach; /* alarmDistance; alarm + margin (look-ahead's reach) */
} coll_cand_pass;

/* A candidate as a sort key: item of A (vertex or edge) times the number of
 * B's primitives, plus the primitive.  Sorted keys give the lists of every
 * item of A in increasing primitive order (bvh_query's order). */
typedef unsigned long long coll_cand_key;

/* The edge pass of a pair from its first vertex pass (A's vertices against
 * B's triangles): B's edges query a tree over A's when B has more edges. */
PL_HD coll_cand_pass coll_cand_edge_pass(const coll_cand_pass *vf)
{
    coll_cand_pass e = *vf;
    e.edges = 1;
    if (!vf->self && vf->T.nedges > vf->P.nedges) {
        e.P = vf->T;
        e.T = vf->P;
        e.swap = 1;
    }
    return e;
}

/* The three passes of a pair: [0] A's vertices against B's triangles, [1]
 * B's vertices against A's (not for self pairs), [2] the edges.  use[k]:
 * whether pass k runs (detect_pair's flags; a pass without queries or
 * primitives has no candidates and is not run: detect_run.c's run_pass). */
PL_HD void coll_cand_pair_passes(const coll_cand_mesh *A, const coll_cand_mesh *B, int self,
                                 int vertex_face, int edge_edge, double alarm, double reach,
                                 coll_cand_pass ps[3], int use[3])
{
    coll_cand_pass f = {*A, *B, 0, self, 0, alarm, reach};
    coll_cand_pass r = {*B, *A, 0, 0, 0, alarm, reach};
    ps[0] = f;
    ps[1] = r;
    ps[2] = coll_cand_edge_pass(&f);
    use[0] = vertex_face && A->nverts > 0 && B->ntris > 0;
    use[1] = vertex_face && !self && B->nverts > 0 && A->ntris > 0;
    use[2] = edge_edge && A->nedges > 0 && B->nedges > 0;
}

/* The pass's items of A (the lists' count) and primitives of B. */
PL_HD int coll_cand_na(const coll_cand_pass *ps)
{
    if (!ps->edges) return ps->P.nverts;
    return ps->swap ? ps->T.nedges : ps->P.nedges;
}

PL_HD int coll_cand_nb(const coll_cand_pass *ps)
{
    if (!ps->edges) return ps->T.ntris;
    return ps->swap ? ps->P.nedges : ps->T.nedges;
}

/* The implicit tree: leaves (a power of two), nodes 1 .. 2 leaves - 1. */
typedef struct coll_cand_tree {
    int n, leaves;
    const int *order; /* sorted primitives */
    pl_aabb *node;    /* 2 leaves */
} coll_cand_tree;

PL_HD int coll_cand_leaves(int n)
{
    int nl = (n + COLL_CAND_LEAF - 1) / COLL_CAND_LEAF, p = 1;
    while (p < nl) p *= 2;
    return p;
}

PL_HD void coll_cand_vbox(const coll_cand_mesh *m, int i, pl_aabb *b)
{
    for (int k = 0; k < 3; ++k) {
        double p = m->x0[3 * i + k], q = m->x1[3 * i + k];
        b->lo[k] = (p < q ? p : q) - m->half;
        b->hi[k] = (p < q ? q : p) + m->half;
    }
}

PL_HD void coll_cand_union(pl_aabb *b, const pl_aabb *v)
{
    for (int k = 0; k < 3; ++k) {
        if (v->lo[k] < b->lo[k]) b->lo[k] = v->lo[k];
        if (v->hi[k] > b->hi[k]) b->hi[k] = v->hi[k];
    }
}

PL_HD int coll_cand_overlap(const pl_aabb *a, const pl_aabb *b)
{
    return a->lo[0] <= b->hi[0] && b->lo[0] <= a->hi[0] && a->lo[1] <= b->hi[1] &&
           b->lo[1] <= a->hi[1] && a->lo[2] <= b->hi[2] && b->lo[2] <= a->hi[2];
}

PL_HD void coll_cand_empty(pl_aabb *b)
{
    for (int k = 0; k < 3; ++k) b->lo[k] = 1e300, b->hi[k] = -1e300;
}

/* Primitive i's box: a triangle's or an edge's vertices' boxes united
 * (coll_mesh.c's order of operations). */
PL_HD void coll_cand_pbox(const coll_cand_mesh *m, int edges, int i, pl_aabb *b)
{
    const int *v = edges ? &m->edges[2 * i] : &m->tris[3 * i];
    pl_aabb o;
    coll_cand_vbox(m, v[0], b);
    for (int j = 1; j < (edges ? 2 : 3); ++j) {
        coll_cand_vbox(m, v[j], &o);
        coll_cand_union(b, &o);
    }
}

/* The query box of item i of P (a vertex's or an edge's). */
PL_HD void coll_cand_qbox(const coll_cand_pass *ps, int i, pl_aabb *b)
{
    if (ps->edges)
        coll_cand_pbox(&ps->P, 1, i, b);
    else
        coll_cand_vbox(&ps->P, i, b);
}

/* 10 bits spread to every third bit. */
PL_HD unsigned coll_cand_spread(unsigned v)
{
    v = (v * 0x00010001u) & 0xFF0000FFu;
    v = (v * 0x00000101u) & 0x0F00F00Fu;
    v = (v * 0x00000011u) & 0xC30C30C3u;
    v = (v * 0x00000005u) & 0x49249249u;
    return v;
}

/* Morton code of a box's centre within the bounds root. */
PL_HD unsigned coll_cand_morton(const pl_aabb *b, const pl_aabb *root)
{
    unsigned c[3];
    for (int k = 0; k < 3; ++k) {
        double ext = root->hi[k] - root->lo[k];
        double u = ext > 0.0 ? (0.5 * (b->lo[k] + b->hi[k]) - root->lo[k]) / ext : 0.0;
        u = u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u);
        c[k] = (unsigned)(u * 1023.0);
    }
    return (coll_cand_spread(c[0]) << 2) | (coll_cand_spread(c[1]) << 1) | coll_cand_spread(c[2]);
}

/* Refits node i from its primitives (a leaf) or its children. */
PL_HD void coll_cand_refit(const coll_cand_tree *t, const pl_aabb *prims, int i)
{
    pl_aabb *b = &t->node[i];
    coll_cand_empty(b);
    if (i >= t->leaves) {
        int lo = (i - t->leaves) * COLL_CAND_LEAF;
        for (int k = lo; k < lo + COLL_CAND_LEAF && k < t->n; ++k)
            coll_cand_union(b, &prims[t->order[k]]);
    } else {
        coll_cand_union(b, &t->node[2 * i]);
        coll_cand_union(b, &t->node[2 * i + 1]);
    }
}

PL_HD double coll_cand_motion(const coll_cand_mesh *m, int v)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double d = m->x1[3 * v + k] - m->x0[3 * v + k];
        d2 += d * d;
    }
    return sqrt(d2);
}

/* Whether a pair at distance d0 at the start of the step may be kept: near
 * now, or its motion (Lipschitz bound lip) may bring it within reach
 * (lookahead.c's advance refuses the rest before measuring anything). */
PL_HD int coll_cand_reachable(const coll_cand_pass *ps, double d0, double lip)
{
    if (d0 < ps->alarm) return 1;
    return lip > 0.0 && d0 - lip < ps->reach;
}

/* Vertex p of P against triangle j of T. */
PL_HD int coll_cand_vf(const coll_cand_pass *ps, int p, int j)
{
    const coll_cand_mesh *P = &ps->P, *T = &ps->T;
    const int *tri = &T->tris[3 * j];
    if (ps->self && (tri[0] == p || tri[1] == p || tri[2] == p)) return 0;
    double w[3];
    double d0 = sqrt(coll_hd_closest_point_triangle(&P->x0[3 * p], &T->x0[3 * tri[0]],
                                                    &T->x0[3 * tri[1]], &T->x0[3 * tri[2]], w));
    if (d0 < ps->alarm) return 1;
    double lt = 0.0;
    for (int a = 0; a < 3; ++a) lt = fmax(lt, coll_cand_motion(T, tri[a]));
    return coll_cand_reachable(ps, d0, coll_cand_motion(P, p) + lt);
}

/* Edge e of A against edge f of B (A, B: the pair's meshes, whichever is
 * queried). */
PL_HD int coll_cand_ee(const coll_cand_pass *ps, int e, int f)
{
    const coll_cand_mesh *A = ps->swap ? &ps->T : &ps->P, *B = ps->swap ? &ps->P : &ps->T;
    int a0 = A->edges[2 * e], a1 = A->edges[2 * e + 1];
    int b0 = B->edges[2 * f], b1 = B->edges[2 * f + 1];
    if (ps->self && (f <= e || a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1)) return 0;
    double s, t;
    double d0 = sqrt(coll_hd_closest_segments(&A->x0[3 * a0], &A->x0[3 * a1], &B->x0[3 * b0],
                                              &B->x0[3 * b1], &s, &t));
    if (d0 < ps->alarm) return 1;
    double la = fmax(coll_cand_motion(A, a0), coll_cand_motion(A, a1));
    double lb = fmax(coll_cand_motion(B, b0), coll_cand_motion(B, b1));
    return coll_cand_reachable(ps, d0, la + lb);
}

/* The walk of query i over a tree: the primitives whose boxes overlap the
 * query's, one at a time (coll_cand_walk_next), in the tree's order.  The
 * broad phase's pairs are these overlaps; the candidate SET does not depend
 * on the tree's shape or order (box overlap is exact), which lets the
 * device keep a primitive order across steps. */
typedef struct coll_cand_walk {
    pl_aabb q;
    int stack[64], top;
    int k, hi; /* the leaf being read: sorted positions k .. hi - 1 */
} coll_cand_walk;

PL_HD void coll_cand_walk_start(coll_cand_walk *w, const coll_cand_pass *ps, int i)
{
    coll_cand_qbox(ps, i, &w->q);
    w->top = 0;
    w->stack[w->top++] = 1;
    w->k = w->hi = 0;
}

/* The next overlapping primitive, or -1 at the end. */
PL_HD int coll_cand_walk_next(coll_cand_walk *w, const coll_cand_tree *t, const pl_aabb *prims)
{
    if (t->n == 0) return -1;
    for (;;) {
        while (w->k < w->hi) {
            int j = t->order[w->k++];
            if (coll_cand_overlap(&prims[j], &w->q)) return j;
        }
        if (w->top == 0) return -1;
        int node = w->stack[--w->top];
        if (!coll_cand_overlap(&t->node[node], &w->q)) continue;
        if (node < t->leaves) {
            w->stack[w->top++] = 2 * node + 1;
            w->stack[w->top++] = 2 * node;
            continue;
        }
        w->k = (node - t->leaves) * COLL_CAND_LEAF;
        w->hi = w->k + COLL_CAND_LEAF < t->n ? w->k + COLL_CAND_LEAF : t->n;
    }
}

/* Whether the overlap of query i with primitive j is a candidate (the
 * narrow filter), and then its key. */
PL_HD int coll_cand_keep(const coll_cand_pass *ps, int i, int j, coll_cand_key *key)
{
    int a = ps->swap ? j : i, b = ps->swap ? i : j;
    if (!(ps->edges ? coll_cand_ee(ps, a, b) : coll_cand_vf(ps, i, j))) return 0;
    *key = (coll_cand_key)a * (coll_cand_key)coll_cand_nb(ps) + (coll_cand_key)b;
    return 1;
}

#endif
