/* coll_mesh.c - a triangle mesh prepared for detection: edge-triangle
 * adjacency and closedness (once), then every step the unit face normals at
 * the start of the step (outward for closed meshes: the sign of the enclosed
 * volume decides), the swept boxes of vertices, triangles and edges over the
 * step, and the BVHs of triangles and edges (built once, refitted after
 * when detection walks them: coll_mesh_fit); sharp edges when the narrow
 * phase first asks.  The loops are serial below COLL_PAR_MIN elements. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "detect.h"

void coll_mesh_init(pl_coll_mesh *m)
{
    memset(m, 0, sizeof *m);
    bvh_init(&m->tbvh);
    bvh_init(&m->ebvh);
}

void coll_mesh_free(pl_coll_mesh *m)
{
    free(m->fnormal);
    free(m->edge_tris);
    free(m->sharp);
    free(m->border);
    free(m->vbox);
    free(m->tbox);
    free(m->ebox);
    bvh_free(&m->tbvh);
    bvh_free(&m->ebvh);
    m->fnormal = NULL;
    m->edge_tris = NULL;
    m->sharp = NULL;
    m->border = NULL;
    m->vbox = m->tbox = m->ebox = NULL;
    m->built = 0;
}

typedef struct edge_key {
    int a, b, index;
} edge_key;

static int cmp_edge_key(const void *x, const void *y)
{
    const edge_key *p = x, *q = y;
    if (p->a != q->a) return (p->a > q->a) - (p->a < q->a);
    if (p->b != q->b) return (p->b > q->b) - (p->b < q->b);
    return (p->index > q->index) - (p->index < q->index);
}

static int find_edge(const edge_key *keys, int n, int a, int b)
{
    int lo = 0, hi = n - 1;
    if (a > b) {
        int t = a;
        a = b;
        b = t;
    }
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2;
        const edge_key *k = &keys[mid];
        if (k->a == a && k->b == b) return k->index;
        if (k->a < a || (k->a == a && k->b < b))
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return -1;
}

/* Triangles on each side of every edge; returns 1 when every edge has
 * exactly two (a closed surface), 0 otherwise, -1 out of memory. */
static int build_adjacency(pl_coll_mesh *m)
{
    m->edge_tris = malloc((size_t)(m->nedges ? m->nedges : 1) * 2 * sizeof *m->edge_tris);
    edge_key *keys = malloc((size_t)(m->nedges ? m->nedges : 1) * sizeof *keys);
    if (!m->edge_tris || !keys) {
        free(keys);
        return -1;
    }
    for (int e = 0; e < m->nedges; ++e) {
        int a = m->edges[2 * e], b = m->edges[2 * e + 1];
        keys[e].a = a < b ? a : b;
        keys[e].b = a < b ? b : a;
        keys[e].index = e;
        m->edge_tris[2 * e] = m->edge_tris[2 * e + 1] = -1;
    }
    qsort(keys, (size_t)m->nedges, sizeof *keys, cmp_edge_key);
    int closed = m->ntris > 0 && m->nedges > 0;
    for (int t = 0; t < m->ntris; ++t)
        for (int k = 0; k < 3; ++k) {
            int e = find_edge(keys, m->nedges, m->tris[3 * t + k], m->tris[3 * t + (k + 1) % 3]);
            if (e < 0) {
                closed = 0;
                continue;
            }
            if (m->edge_tris[2 * e] < 0)
                m->edge_tris[2 * e] = t;
            else if (m->edge_tris[2 * e + 1] < 0)
                m->edge_tris[2 * e + 1] = t;
            else
                closed = 0; /* non-manifold edge */
        }
    for (int e = 0; e < m->nedges; ++e)
        if (m->edge_tris[2 * e + 1] < 0) closed = 0;
    free(keys);
    return closed;
}

static int first_prepare(pl_coll_mesh *m, pl_error *err)
{
    coll_mesh_free(m); /* what an earlier failed attempt left */
    for (int k = 0; k < 3 * m->ntris; ++k)
        if (m->tris[k] < 0 || m->tris[k] >= m->nverts)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "triangle %d uses vertex %d, outside [0, %d)", k / 3, m->tris[k],
                                m->nverts);
    for (int k = 0; k < 2 * m->nedges; ++k)
        if (m->edges[k] < 0 || m->edges[k] >= m->nverts)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "edge %d uses vertex %d, outside [0, %d)", k / 2, m->edges[k],
                                m->nverts);
    int closed = build_adjacency(m);
    if (closed < 0) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    m->two_sided = m->sides == PL_SIDES_TWO || (m->sides == PL_SIDES_AUTO && !closed);
    size_t nv = (size_t)(m->nverts ? m->nverts : 1), nt = (size_t)(m->ntris ? m->ntris : 1),
           ne = (size_t)(m->nedges ? m->nedges : 1);
    m->fnormal = malloc(nt * 3 * sizeof *m->fnormal);
    m->vbox = malloc(nv * sizeof *m->vbox);
    m->tbox = malloc(nt * sizeof *m->tbox);
    m->ebox = malloc(ne * sizeof *m->ebox);
    m->sharp = malloc(ne);
    m->border = calloc(nv, 1);
    if (!m->fnormal || !m->vbox || !m->tbox || !m->ebox || !m->sharp || !m->border)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    for (int e = 0; e < m->nedges; ++e)
        if (m->edge_tris[2 * e + 1] < 0) m->border[m->edges[2 * e]] = m->border[m->edges[2 * e + 1]] = 1;
    return PL_OK;
}

/* Unit normals (b - a) x (c - a) at x0 and the enclosed volume's sign. */
static void face_normals(pl_coll_mesh *m)
{
    double vol = 0.0;
    for (int t = 0; t < m->ntris; ++t) {
        const double *a = &m->x0[3 * m->tris[3 * t]], *b = &m->x0[3 * m->tris[3 * t + 1]],
                     *c = &m->x0[3 * m->tris[3 * t + 2]];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double *n = &m->fnormal[3 * t];
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        vol += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
               a[2] * (b[0] * c[1] - b[1] * c[0]);
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double inv = len > 0.0 ? 1.0 / len : 0.0;
        for (int k = 0; k < 3; ++k) n[k] *= inv;
    }
    m->orientation = (m->two_sided || vol >= 0.0) ? 1.0 : -1.0;
    if (m->orientation < 0.0)
        for (int k = 0; k < 3 * m->ntris; ++k) m->fnormal[k] = -m->fnormal[k];
}

/* The vertex of triangle t that is not on edge e. */
static int opposite(const pl_coll_mesh *m, int t, int e)
{
    for (int k = 0; k < 3; ++k) {
        int v = m->tris[3 * t + k];
        if (v != m->edges[2 * e] && v != m->edges[2 * e + 1]) return v;
    }
    return m->tris[3 * t];
}

/* Sharp at x0: a boundary edge, or one whose faces turn by more than 30
 * degrees (for a closed mesh only a convex one: a concave crease cannot
 * poke anything). */
static int edge_sharp(const pl_coll_mesh *m, int e)
{
    int t1 = m->edge_tris[2 * e], t2 = m->edge_tris[2 * e + 1];
    if (t1 < 0 || t2 < 0) return 1;
    const double *n1 = &m->fnormal[3 * t1], *n2 = &m->fnormal[3 * t2];
    double c = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
    if (m->two_sided) return fabs(c) < PL_SHARP_COS;
    const double *a = &m->x0[3 * m->edges[2 * e]], *o = &m->x0[3 * opposite(m, t2, e)];
    double behind = (o[0] - a[0]) * n1[0] + (o[1] - a[1]) * n1[1] + (o[2] - a[2]) * n1[2];
    return c < PL_SHARP_COS && behind < 0.0;
}

/* Asked of the edge pairs the broad phase gives (the narrow phase), not
 * computed for every edge every step, and remembered for the step
 * (m->sharp: 0 not asked yet, 1 no, 2 yes).  Threads of a pass may ask for
 * the same edge at once: relaxed atomic bytes, and the value is a function
 * of x0, so whoever writes it writes the same. */
int coll_edge_sharp(const pl_coll_mesh *m, int e)
{
    unsigned char known = __atomic_load_n(&m->sharp[e], __ATOMIC_RELAXED);
    if (known) return known == 2;
    int sharp = edge_sharp(m, e);
    __atomic_store_n(&m->sharp[e], (unsigned char)(sharp ? 2 : 1), __ATOMIC_RELAXED);
    return sharp;
}

/* The swept boxes, not grown: aabb_overlap_grown adds the margin where
 * they are compared, which gives the bounds of boxes grown first and then
 * united (detect_cand.h's order), bitwise. */
static void boxes(pl_coll_mesh *m)
{
#pragma omp parallel for schedule(static) if (m->nverts > COLL_PAR_MIN)
    for (int i = 0; i < m->nverts; ++i) {
        pl_aabb *b = &m->vbox[i];
        for (int k = 0; k < 3; ++k) {
            double p = m->x0[3 * i + k], q = m->x1[3 * i + k];
            b->lo[k] = p < q ? p : q;
            b->hi[k] = p < q ? q : p;
        }
    }
#pragma omp parallel for schedule(static) if (m->ntris > COLL_PAR_MIN)
    for (int t = 0; t < m->ntris; ++t) {
        pl_aabb *b = &m->tbox[t];
        *b = m->vbox[m->tris[3 * t]];
        for (int j = 1; j < 3; ++j) {
            const pl_aabb *v = &m->vbox[m->tris[3 * t + j]];
            for (int k = 0; k < 3; ++k) {
                b->lo[k] = v->lo[k] < b->lo[k] ? v->lo[k] : b->lo[k];
                b->hi[k] = v->hi[k] > b->hi[k] ? v->hi[k] : b->hi[k];
            }
        }
    }
#pragma omp parallel for schedule(static) if (m->nedges > COLL_PAR_MIN)
    for (int e = 0; e < m->nedges; ++e) {
        pl_aabb *b = &m->ebox[e];
        const pl_aabb *v0 = &m->vbox[m->edges[2 * e]], *v1 = &m->vbox[m->edges[2 * e + 1]];
        for (int k = 0; k < 3; ++k) {
            b->lo[k] = v0->lo[k] < v1->lo[k] ? v0->lo[k] : v1->lo[k];
            b->hi[k] = v0->hi[k] > v1->hi[k] ? v0->hi[k] : v1->hi[k];
        }
    }
}

int coll_mesh_prepare(pl_coll_mesh *m, double margin, pl_error *err)
{
    if (!m->built) {
        int rc = first_prepare(m, err);
        if (rc) return rc;
    }
    face_normals(m);
    memset(m->sharp, 0, (size_t)m->nedges); /* asked anew (coll_edge_sharp) */
    boxes(m);
    m->margin = margin;
    if (!m->built) {
        if (bvh_build(&m->tbvh, m->tbox, m->ntris) || bvh_build(&m->ebvh, m->ebox, m->nedges))
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        m->built = 1;
        m->stale = 0;
    } else {
        m->stale = COLL_TREE_TRIS | COLL_TREE_EDGES; /* coll_mesh_fit, when walked */
    }
    return PL_OK;
}

void coll_mesh_fit(pl_coll_mesh *m, int trees)
{
    int todo = m->stale & trees;
    if (todo & COLL_TREE_TRIS) bvh_refit(&m->tbvh, m->tbox);
    if (todo & COLL_TREE_EDGES) bvh_refit(&m->ebvh, m->ebox);
    m->stale &= ~todo;
}

/* The boxes are compared grown by margin / 2 (aabb_overlap_grown): a new
 * margin changes no box and no tree. */
void coll_mesh_inflate(pl_coll_mesh *m, double margin)
{
    if (m->built) m->margin = margin;
}
