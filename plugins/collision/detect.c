/* detect.c - proximities between two prepared meshes (or a mesh and
 * itself): every vertex of one against the triangles of the other, both
 * ways, and edge against edge.  Each candidate pair from the BVH is
 * measured at the start of the step (x0); its normal is the direction from
 * the closest point of B to that of A, which is the side A is on at the
 * start of the step, or, for a closed (one-sided) mesh whose face A is
 * behind, the outward face normal (A has penetrated: push it out).  The
 * plane through the closest point along that normal separates the two
 * convex primitives, so its half-space is a safe linearised constraint.
 * A pair is kept when the gap minus the predicted approach over the step
 * is below alarm.  The loops over candidates are in detect_run.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "detect_internal.h"

/* closest points this close to an edge's end are vertex cases [fraction] */
#define EDGE_END 1e-3
/* edges crossing at less than ~12 degrees are nearly parallel: their closest
 * points slide along them and their ends' contacts hold them [sin^2] */
#define EDGE_SIN2 0.04
/* an edge-edge normal this close to a face normal beside either edge [cos] */
#define EDGE_FLAT 0.9396926207859084 /* cos 20 degrees */

int coll_prox_push(pl_proximities *p, const pl_proximity *x)
{
    if (p->n == p->cap) {
        int cap = p->cap ? 2 * p->cap : 64;
        pl_proximity *items = realloc(p->items, (size_t)cap * sizeof *items);
        if (!items) return PL_EINTERNAL;
        p->items = items;
        p->cap = cap;
    }
    p->items[p->n++] = *x;
    return PL_OK;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static int is_active(const pl_coll_mesh *m, int v) { return !m->active || m->active[v]; }

static double tiny_of(const pl_detect_params *prm) { return 1e-12 + 1e-9 * prm->alarm; }

/* Whether a point at distance dist from a triangle, height above its plane,
 * is over the face (edges included): its closest point is the foot of the
 * perpendicular, up to round-off. */
static int foot_inside(double height, double dist) { return fabs(height) >= (1.0 - 1e-9) * dist; }

/* n = +-c / |c| pointing against the relative motion d of A (A came from that side). */
static int oppose_motion(const double c[3], const double d[3], double n[3])
{
    double len = sqrt(dot3(c, c));
    if (!(len > 0.0)) return 0;
    double s = dot3(c, d) > 0.0 ? -1.0 / len : 1.0 / len;
    for (int k = 0; k < 3; ++k) n[k] = s * c[k];
    return 1;
}

/* diff = x_p - (the point of triangle tri at weights w), at the instant s
 * of the step (0: its start); motion = their relative motion over the step
 * (predicted, x1). */
static void offset_and_motion(const pl_coll_mesh *P, int p, const pl_coll_mesh *T, const int *tri,
                              const double w[3], double s, double diff[3], double motion[3])
{
    double x[3], t[3][3];
    coll_at(P, p, s, x);
    for (int a = 0; a < 3; ++a) coll_at(T, tri[a], s, t[a]);
    for (int k = 0; k < 3; ++k) {
        double c = 0.0;
        motion[k] = P->x1[3 * p + k] - P->x0[3 * p + k];
        for (int a = 0; a < 3; ++a) {
            c += w[a] * t[a][k];
            motion[k] -= w[a] * (T->x1[3 * tri[a] + k] - T->x0[3 * tri[a] + k]);
        }
        diff[k] = x[k] - c;
    }
}

/* The unit normal of triangle j of T at the instant s (outward for a
 * one-sided mesh): the one prepared at the start of the step when s = 0. */
static void face_normal_at(const pl_coll_mesh *T, int j, double s, double nf[3])
{
    if (s == 0.0) {
        memcpy(nf, &T->fnormal[3 * j], 3 * sizeof *nf);
        return;
    }
    double a[3], b[3], c[3], u[3], v[3];
    coll_at(T, T->tris[3 * j], s, a);
    coll_at(T, T->tris[3 * j + 1], s, b);
    coll_at(T, T->tris[3 * j + 2], s, c);
    for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
    nf[0] = u[1] * v[2] - u[2] * v[1];
    nf[1] = u[2] * v[0] - u[0] * v[2];
    nf[2] = u[0] * v[1] - u[1] * v[0];
    double len = sqrt(dot3(nf, nf)), f = len > 0.0 ? T->orientation / len : 0.0;
    for (int k = 0; k < 3; ++k) nf[k] *= f;
}

/* Whether vertex p is predicted (x1) to be over the inside of triangle tri
 * at the end of the step, farther inside than now; w then holds the
 * weights of its foot there. */
static int slides_over(const pl_coll_mesh *P, int p, const pl_coll_mesh *T, const int *tri, double *w)
{
    const double *a = &T->x1[3 * tri[0]], *b = &T->x1[3 * tri[1]], *c = &T->x1[3 * tri[2]];
    double w1[3], e1[3], e2[3], nf[3], d[3];
    double d1 = sqrt(closest_point_triangle(&P->x1[3 * p], a, b, c, w1));
    for (int k = 0; k < 3; ++k) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
    nf[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nf[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nf[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(dot3(nf, nf)), h = 0.0;
    if (!(len > 0.0)) return 0;
    for (int k = 0; k < 3; ++k) d[k] = P->x1[3 * p + k] - (w1[0] * a[k] + w1[1] * b[k] + w1[2] * c[k]);
    h = dot3(d, nf) / len;
    double inside1 = fmin(w1[0], fmin(w1[1], w1[2])), inside0 = fmin(w[0], fmin(w[1], w[2]));
    if (!foot_inside(h, d1) || !(inside1 > 0.0) || !(inside1 > inside0)) return 0;
    memcpy(w, w1, sizeof w1);
    return 1;
}

static int cmp_key(const void *x, const void *y)
{
    long long a = *(const long long *)x, b = *(const long long *)y;
    return (a > b) - (a < b);
}

int coll_vv_collect(const pl_proximities *items, int from, int nb, coll_vv_kept *kv)
{
    kv->key = NULL;
    kv->n = 0;
    kv->nb = nb;
    int m = 0;
    for (int k = from; k < items->n; ++k) m += items->items[k].kind == PL_PROX_VERTEX_FACE;
    if (m == 0) return PL_OK;
    kv->key = malloc((size_t)m * sizeof *kv->key);
    if (!kv->key) return PL_EINTERNAL;
    for (int k = from; k < items->n; ++k) {
        const pl_proximity *x = &items->items[k];
        if (x->kind != PL_PROX_VERTEX_FACE) continue;
        for (int a = 0; a < 3; ++a)
            if (x->wb[a] > 1.0 - EDGE_END) kv->key[kv->n++] = (long long)x->a[0] * nb + x->b[a];
    }
    qsort(kv->key, (size_t)kv->n, sizeof *kv->key, cmp_key);
    return PL_OK;
}

/* Whether the first direction kept the proximity of its vertex v with
 * vertex p of the second direction's points. */
static int vv_kept(const coll_vv_kept *kv, int v, int p)
{
    long long k = (long long)v * kv->nb + p;
    return kv->n > 0 && bsearch(&k, kv->key, (size_t)kv->n, sizeof k, cmp_key) != NULL;
}

/* Vertex p of P against triangle j of T; fills out and returns 1 when kept.
 * A closest point at a triangle's vertex is a vertex-vertex proximity that
 * the other direction finds too: identical rows would make W singular, so
 * the second pass drops those the first kept (in self-collision the lower
 * vertex index keeps it).  The first keeps only its vertex's nearest
 * proximity beside the faces: a cloth vertex next to a cube's corner, not
 * the nearest to it, has no other contact there (it is over none of the
 * faces), so the second pass keeps it. */
int coll_vf_candidate(const pl_coll_mesh *P, int ip, int p, const pl_coll_mesh *T, int it,
                        int j, int self, const coll_vv_kept *second, const pl_detect_params *prm,
                        pl_proximity *out, int *face, double *rank)
{
    const int *tri = &T->tris[3 * j];
    if (self && (tri[0] == p || tri[1] == p || tri[2] == p)) return 0;
    if (!aabb_overlap_grown(&P->vbox[p], coll_mesh_half(P), &T->tbox[j], coll_mesh_half(T)))
        return 0; /* the broad phase's test */
    if (!is_active(P, p) && !is_active(T, tri[0]) && !is_active(T, tri[1]) &&
        !is_active(T, tri[2]))
        return 0;
    double w[3], s = 0.0, x[3], ta[3], tb[3], tc[3];
    double d0 = sqrt(closest_point_triangle(&P->x0[3 * p], &T->x0[3 * tri[0]],
                                               &T->x0[3 * tri[1]], &T->x0[3 * tri[2]], w));
    if (d0 >= prm->alarm) {
        /* far now: measured where the predicted motion brings it into
         * contact (look-ahead), or dropped when it never comes near */
        if (!coll_vf_lookahead(P, p, T, tri, d0, prm, &s)) return 0;
        coll_at(P, p, s, x);
        coll_at(T, tri[0], s, ta);
        coll_at(T, tri[1], s, tb);
        coll_at(T, tri[2], s, tc);
        d0 = sqrt(closest_point_triangle(x, ta, tb, tc, w));
    }
    for (int a = 0; a < 3; ++a)
        if (w[a] > 1.0 - EDGE_END &&
            ((second && vv_kept(second, tri[a], p)) || (self && p > tri[a])))
            return 0;
    double diff[3], motion[3], nf[3];
    offset_and_motion(P, p, T, tri, w, s, diff, motion);
    face_normal_at(T, j, s, nf);
    double n[3], gap, tiny = tiny_of(prm), height = dot3(diff, nf);
    if (s > 0.0) {
        /* only a point coming from outside a closed mesh, and still on the
         * side it starts on: a path that has passed the face's plane beside
         * the triangle by then (into a closed mesh through another face),
         * or that runs inside it towards the face from behind (a vertex of
         * a body far across the mesh), is not this face's contact */
        double d[3], m[3], nf0[3];
        offset_and_motion(P, p, T, tri, w, 0.0, d, m);
        face_normal_at(T, j, 0.0, nf0);
        double h0 = dot3(d, nf0);
        if (h0 * height <= 0.0 || (!T->two_sided && h0 < 0.0)) return 0;
    }
    int over_face = foot_inside(height, d0); /* over the face, not beside it */
    memset(out, 0, sizeof *out);
    out->kind = PL_PROX_VERTEX_FACE;
    out->model_a = ip;
    out->model_b = it;
    out->na = 1;
    out->nb = 3;
    out->a[0] = p;
    out->wa[0] = 1.0;
    for (int a = 0; a < 3; ++a) {
        out->b[a] = tri[a];
        out->wb[a] = w[a];
    }
    /* a thin mesh: the side of its oriented face the vertex was on last step
     * (this triangle, else a neighbour it touched) */
    const pl_proximity *hint = T->two_sided ? side_hints_find(prm->hints, out) : NULL;
    if (!(hint && hint->side) && T->two_sided) hint = side_hints_find_near(prm->hints, out);
    int side = hint ? hint->side : 0;
    if (side && slides_over(P, p, T, tri, w)) {
        /* the row holds the point of the face the vertex will be over at the
         * predicted end of the step (a blade's apex under a cloth that slides
         * over it: near the vertex it touches now the cloth moves away, and
         * the apex meets the face's inside); the plane, and so the gap along
         * the face normal, is the same */
        over_face = 1;
        offset_and_motion(P, p, T, tri, w, s, diff, motion);
        height = dot3(diff, nf);
        for (int a = 0; a < 3; ++a) out->wb[a] = w[a];
    }
    /* beside the face, near none of the sheet's rim: a point on the wrong
     * side of the face's plane went through near an inner edge (around the
     * rim, a point passes from one side to the other legitimately) */
    int inner = !over_face;
    for (int a = 0; a < 3 && inner; ++a)
        if (w[a] > 0.0 && T->border[tri[a]]) inner = 0;
    if (side && (over_face || (inner && side * height < 0.0))) {
        /* in contact last step: keep that side, even if a little through */
        for (int k = 0; k < 3; ++k) n[k] = side * nf[k];
        gap = side * height;
        if (gap < -prm->alarm) return 0; /* through by more than alarm: lost */
    } else if (!T->two_sided && height < 0.0) {
        /* behind an outward face: inside, pushed out by the face it is
         * under; deep points belong to another part of the surface */
        if (!over_face || d0 > prm->alarm) return 0;
        memcpy(n, nf, sizeof n);
        gap = -d0;
    } else if (d0 > tiny) {
        /* over the face the direction is the face normal: take it exact (no
         * round-off noise that would turn the friction tangents) */
        double s = height >= 0.0 ? 1.0 : -1.0;
        for (int k = 0; k < 3; ++k) n[k] = over_face ? s * nf[k] : diff[k] / d0;
        gap = d0;
    } else {
        if (!T->two_sided)
            memcpy(n, nf, sizeof n);
        else if (!oppose_motion(nf, motion, n))
            return 0;
        gap = 0.0;
    }
    if (s > 0.0) {
        /* the gap the row has at the start of the step: a contact found
         * later in the step is a plane the point must not cross on its way
         * there, so the point starts in front of it (else it is measured
         * where the point has already passed another face: no contact) */
        offset_and_motion(P, p, T, tri, out->wb, 0.0, diff, motion);
        gap = dot3(n, diff);
        if (!(gap > 0.0)) return 0;
    }
    double approach = -dot3(n, motion);
    if (!(gap - (approach > 0.0 ? approach : 0.0) - prm->margin < prm->alarm)) return 0;
    *face = over_face;
    /* nearest first; pairs in contact only later in the step come after
     * those in contact now, earliest first */
    *rank = s > 0.0 ? prm->alarm * (1.0 + s) + d0 : fabs(gap);
    memcpy(out->normal, n, sizeof n);
    out->gap = gap;
    if (T->two_sided) out->side = dot3(n, nf) >= 0.0 ? 1 : -1;
    return 1;
}

/* One-sided meshes: whether the direction d from edge e points outside the
 * mesh there: beyond at least one of the planes of its faces (a convex
 * edge's outside is the union of the two half-spaces). */
static int outside_of(const pl_coll_mesh *m, int e, const double d[3])
{
    int any = 0;
    for (int k = 0; k < 2; ++k) {
        int t = m->edge_tris[2 * e + k];
        if (t < 0) continue;
        any = 1;
        if (dot3(d, &m->fnormal[3 * t]) > 0.0) return 1;
    }
    return !any;
}

/* One-sided meshes: mo = the outward bisector of the faces beside edge e
 * (unit); returns 1 when the edge-edge direction cr (length len) has a clear
 * component along it and only one of +-cr points outside (then the sign of
 * mo . cr says which side is outside).  When both do (cr nearly along a
 * face: one side beyond each face's plane, a cloth edge hanging beside a
 * cube's side just below its top edge), the bisector does not decide: it
 * pushed such an edge up through the cube's edge (17 mm on sharp_corner.xml
 * at step 198). */
static int outward(const pl_coll_mesh *m, int e, const double *cr, double len, double mo[3])
{
    mo[0] = mo[1] = mo[2] = 0.0;
    for (int k = 0; k < 2; ++k) {
        int t = m->edge_tris[2 * e + k];
        if (t < 0) continue;
        for (int i = 0; i < 3; ++i) mo[i] += m->fnormal[3 * t + i];
    }
    double l = sqrt(dot3(mo, mo));
    if (!(l > 0.0)) return 0;
    for (int i = 0; i < 3; ++i) mo[i] /= l;
    double neg[3] = {-cr[0], -cr[1], -cr[2]};
    return fabs(dot3(mo, cr)) > 0.2 * len && !(outside_of(m, e, cr) && outside_of(m, e, neg));
}

/* The height of q over face t of m (along its normal); *over = its foot is
 * inside the triangle. */
static double height_over(const pl_coll_mesh *m, int t, const double q[3], int *over)
{
    const int *tri = &m->tris[3 * t];
    const double *a = &m->x0[3 * tri[0]], *nf = &m->fnormal[3 * t];
    double w[3], h = 0.0;
    double d = sqrt(closest_point_triangle(q, a, &m->x0[3 * tri[1]], &m->x0[3 * tri[2]], w));
    for (int i = 0; i < 3; ++i) h += (q[i] - a[i]) * nf[i];
    *over = foot_inside(h, d);
    return h;
}

/* Whether n is (anti)parallel to a face beside edge e, within EDGE_FLAT,
 * and the other edge q0 q1 lies over that face: both its ends over the
 * triangle, on one side of it.  Their contacts are then along the face
 * normal too.  Otherwise the contacts of its ends do not hold the edge: an
 * end beyond the border (a cloth edge wrapping round a blade's edge) is
 * held off the border along another normal and lets the segment swing
 * through the sheet past it, and ends on both sides of the plane are each
 * held on their side, not the segment between them off the sheet
 * (cloth_on_knives.xml: such edges went 3.5 to 6.8 mm through a blade). */
static int along_face(const pl_coll_mesh *m, int e, const double n[3], const double q0[3],
                      const double q1[3])
{
    for (int k = 0; k < 2; ++k) {
        int t = m->edge_tris[2 * e + k], o0, o1;
        if (t < 0 || !(fabs(dot3(n, &m->fnormal[3 * t])) > EDGE_FLAT)) continue;
        /* a closed surface's edge: the other edge cannot wrap round it to
         * its inside, the ends' contacts hold it (as before the knives) */
        if (!m->two_sided) return 1;
        double s0 = height_over(m, t, q0, &o0), s1 = height_over(m, t, q1, &o1);
        if (o0 && o1 && s0 * s1 > 0.0) return 1;
    }
    return 0;
}

/* For a border edge of a thin rigid mesh (one triangle beside it): the unit
 * direction in the triangle's plane, perpendicular to the edge, pointing out
 * of the triangle.  Returns 0 for other edges. */
static int border_out(const pl_coll_mesh *m, int e, double mo[3])
{
    /* only rigid sheets (no DOFs): a cloth's border may lie over a blade */
    if (!m->two_sided || !m->active || m->active[m->edges[2 * e]] ||
        m->active[m->edges[2 * e + 1]] || m->edge_tris[2 * e] < 0 || m->edge_tris[2 * e + 1] >= 0)
        return 0;
    int t = m->edge_tris[2 * e], a = m->edges[2 * e], b = m->edges[2 * e + 1], o = a;
    for (int k = 0; k < 3; ++k)
        if (m->tris[3 * t + k] != a && m->tris[3 * t + k] != b) o = m->tris[3 * t + k];
    const double *nf = &m->fnormal[3 * t], *xa = &m->x0[3 * a], *xb = &m->x0[3 * b];
    double ed[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]}, ao[3];
    mo[0] = ed[1] * nf[2] - ed[2] * nf[1];
    mo[1] = ed[2] * nf[0] - ed[0] * nf[2];
    mo[2] = ed[0] * nf[1] - ed[1] * nf[0];
    for (int k = 0; k < 3; ++k) ao[k] = m->x0[3 * o + k] - xa[k];
    double len = sqrt(dot3(mo, mo)), sg = dot3(mo, ao) > 0.0 ? -1.0 : 1.0;
    if (!(len > 0.0)) return 0;
    for (int k = 0; k < 3; ++k) mo[k] *= sg / len;
    return 1;
}

/* The side of the other edge q0 q1 at the border edge e of a thin rigid
 * sheet (mo from border_out), as the sign of cr . n for n pointing from the
 * sheet's edge to the other edge; 0 when cr does not decide it.  An edge
 * that crosses the sheet's plane passes beyond the border (a cloth over a
 * blade's apex edge): it belongs outside, along mo.  An edge on one side of
 * the plane (a cloth hanging along the blade's face past its border) belongs
 * on that side, along the face normal: the border rule would pull it through
 * the sheet. */
static double border_side(const pl_coll_mesh *m, int e, const double mo[3], const double q0[3],
                          const double q1[3], const double cr[3], double len)
{
    const double *nf = &m->fnormal[3 * m->edge_tris[2 * e]], *p = &m->x0[3 * m->edges[2 * e]];
    double s0 = 0.0, s1 = 0.0;
    for (int k = 0; k < 3; ++k) {
        s0 += (q0[k] - p[k]) * nf[k];
        s1 += (q1[k] - p[k]) * nf[k];
    }
    if (s0 * s1 < 0.0) { /* crosses the plane */
        /* where: through the sheet or beyond this border, it belongs
         * outside along mo; beside the sheet past another border (a cloth
         * edge wrapped around a blade's corner, near this edge's end) this
         * border does not decide its side */
        double X[3], f = s0 / (s0 - s1), w[3];
        for (int k = 0; k < 3; ++k) X[k] = q0[k] + f * (q1[k] - q0[k]);
        const int *tri = &m->tris[3 * m->edge_tris[2 * e]];
        double d2 = closest_point_triangle(X, &m->x0[3 * tri[0]], &m->x0[3 * tri[1]],
                                              &m->x0[3 * tri[2]], w);
        double beyond = (X[0] - p[0]) * mo[0] + (X[1] - p[1]) * mo[1] + (X[2] - p[2]) * mo[2];
        int inside = d2 <= 1e-16; /* X is in the plane: inside up to round-off */
        if (!inside && beyond <= 0.0) return 0.0;
        /* through the sheet: it must come out beyond the border even when
         * the edges are nearly perpendicular to it (a cloth edge almost in
         * the blade's plane); only a sign lost in round-off is no answer */
        double lim = inside ? 0.02 : 0.2;
        return fabs(dot3(mo, cr)) > lim * len ? (dot3(mo, cr) > 0.0 ? 1.0 : -1.0) : 0.0;
    }
    double side = s0 + s1 > 0.0 ? 1.0 : -1.0, c = side * dot3(nf, cr);
    return fabs(c) > 0.2 * len ? (c > 0.0 ? 1.0 : -1.0) : 0.0;
}

/* Whether both ends of segment p0 p1 are within dist of segment q0 q1. */
static int ends_near(const double p0[3], const double p1[3], const double q0[3],
                     const double q1[3], double dist)
{
    double s, t;
    return closest_segments(p0, p0, q0, q1, &s, &t) < dist * dist &&
           closest_segments(p1, p1, q0, q1, &s, &t) < dist * dist;
}

/* Edge e of A against edge f of B (interior points of both). */
int coll_ee_candidate(const pl_coll_mesh *A, int ia, int e, const pl_coll_mesh *B, int ib,
                        int f, int self, const pl_detect_params *prm, pl_proximity *out)
{
    int a0 = A->edges[2 * e], a1 = A->edges[2 * e + 1];
    int b0 = B->edges[2 * f], b1 = B->edges[2 * f + 1];
    if (self && (f <= e || a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1)) return 0;
    if (!aabb_overlap_grown(&A->ebox[e], coll_mesh_half(A), &B->ebox[f], coll_mesh_half(B)))
        return 0;
    if (!coll_edge_sharp(A, e) && !coll_edge_sharp(B, f)) return 0;
    if (!is_active(A, a0) && !is_active(A, a1) && !is_active(B, b0) && !is_active(B, b1))
        return 0;
    const double *pa0 = &A->x0[3 * a0], *pa1 = &A->x0[3 * a1];
    const double *pb0 = &B->x0[3 * b0], *pb1 = &B->x0[3 * b1];
    double s, t, when = 0.0, xa0[3], xa1[3], xb0[3], xb1[3];
    double d0 = sqrt(closest_segments(pa0, pa1, pb0, pb1, &s, &t));
    if (d0 >= prm->alarm) {
        /* far now: measured where the predicted motion brings them into
         * contact (look-ahead), or dropped when they never come near */
        if (!coll_ee_lookahead(A, &A->edges[2 * e], B, &B->edges[2 * f], d0, prm, &when))
            return 0;
        coll_at(A, a0, when, xa0);
        coll_at(A, a1, when, xa1);
        coll_at(B, b0, when, xb0);
        coll_at(B, b1, when, xb1);
        pa0 = xa0, pa1 = xa1, pb0 = xb0, pb1 = xb1;
        d0 = sqrt(closest_segments(pa0, pa1, pb0, pb1, &s, &t));
    }
    if (s < EDGE_END || s > 1.0 - EDGE_END || t < EDGE_END || t > 1.0 - EDGE_END) {
        /* closest at an end now (a cloth edge from a vertex that sits on a
         * blade's apex): the ends' vertex contacts hold the distance, but
         * not the edges' crossing when the edge turns about that vertex.
         * Between thin meshes, where they will be closest at the predicted
         * end of the step, if interior, is the pair of points to keep
         * apart (a closed mesh's edges lie on faces whose vertex contacts
         * hold them). */
        if (!A->two_sided || !B->two_sided) return 0;
        double s1, t1;
        closest_segments(&A->x1[3 * a0], &A->x1[3 * a1], &B->x1[3 * b0], &B->x1[3 * b1], &s1, &t1);
        if (s1 < EDGE_END || s1 > 1.0 - EDGE_END || t1 < EDGE_END || t1 > 1.0 - EDGE_END) return 0;
        s = s1, t = t1;
        double q[3];
        for (int k = 0; k < 3; ++k)
            q[k] = (pa0[k] + s * (pa1[k] - pa0[k])) - (pb0[k] + t * (pb1[k] - pb0[k]));
        d0 = sqrt(dot3(q, q));
    }
    double ea[3], eb[3], cr[3], diff[3], motion[3];
    for (int k = 0; k < 3; ++k) {
        ea[k] = pa1[k] - pa0[k];
        eb[k] = pb1[k] - pb0[k];
        diff[k] = (pa0[k] + s * ea[k]) - (pb0[k] + t * eb[k]);
        motion[k] = (1.0 - s) * (A->x1[3 * a0 + k] - A->x0[3 * a0 + k]) +
                    s * (A->x1[3 * a1 + k] - A->x0[3 * a1 + k]) -
                    (1.0 - t) * (B->x1[3 * b0 + k] - B->x0[3 * b0 + k]) -
                    t * (B->x1[3 * b1 + k] - B->x0[3 * b1 + k]);
    }
    cr[0] = ea[1] * eb[2] - ea[2] * eb[1];
    cr[1] = ea[2] * eb[0] - ea[0] * eb[2];
    cr[2] = ea[0] * eb[1] - ea[1] * eb[0];
    /* (nearly) parallel edges: their end vertices carry the contact */
    if (!(dot3(cr, cr) > EDGE_SIN2 * dot3(ea, ea) * dot3(eb, eb))) return 0;
    memset(out, 0, sizeof *out);
    out->kind = PL_PROX_EDGE_EDGE;
    out->model_a = ia;
    out->model_b = ib;
    out->na = out->nb = 2;
    out->a[0] = a0;
    out->a[1] = a1;
    out->wa[0] = 1.0 - s;
    out->wa[1] = s;
    out->b[0] = b0;
    out->b[1] = b1;
    out->wb[0] = 1.0 - t;
    out->wb[1] = t;
    double n[3], gap = d0, mo[3], len = sqrt(dot3(cr, cr));
    /* The side is chosen, in this order, by: the border of a thin rigid
     * sheet (a blade's edge: the other edge belongs outside it, beyond the
     * border in the sheet's plane); the outside of a closed mesh (the other
     * edge belongs on the outer side of the edge's two faces); the side of
     * the last step (thin against thin); the side now.  The first two hold
     * whatever side the edge is on now, so that an edge pushed a little
     * through (an unconverged step) comes back out. */
    double sg = 0.0;
    if (border_out(A, e, mo))
        sg = -border_side(A, e, mo, pb0, pb1, cr, len); /* n . mo < 0: B outside A */
    if (sg == 0.0 && border_out(B, f, mo))
        sg = border_side(B, f, mo, pa0, pa1, cr, len); /* n . mo > 0: A outside B */
    if (sg != 0.0)
        ;
    else if (!A->two_sided && outward(A, e, cr, len, mo))
        sg = dot3(mo, cr) > 0.0 ? -1.0 : 1.0;
    else if (!B->two_sided && outward(B, f, cr, len, mo))
        sg = dot3(mo, cr) > 0.0 ? 1.0 : -1.0;
    const pl_proximity *hp = sg == 0.0 && A->two_sided && B->two_sided
                                 ? side_hints_find(prm->hints, out)
                                 : NULL;
    const double *hint = hp ? hp->normal : NULL;
    if (hint && dot3(hint, cr) != 0.0) sg = dot3(hint, cr) > 0.0 ? 1.0 : -1.0;
    if (sg != 0.0) {
        for (int k = 0; k < 3; ++k) n[k] = sg * cr[k] / len;
        gap = dot3(diff, n);
        if (gap < -prm->alarm) return 0; /* through by more than alarm: lost */
    } else if (d0 > tiny_of(prm)) {
        for (int k = 0; k < 3; ++k) n[k] = diff[k] / d0;
    } else if (!oppose_motion(cr, motion, n)) {
        return 0;
    }
    /* a closed mesh repels only towards its outside */
    if (!B->two_sided && !outside_of(B, f, n)) return 0;
    if (!A->two_sided) {
        double m[3] = {-n[0], -n[1], -n[2]};
        if (!outside_of(A, e, m)) return 0;
    }
    /* an edge lying (nearly) flat over a face beside the other edge, with
     * both its ends near that edge, is held by the contacts of its ends: the
     * edge-edge row would be (close to) their linear combination, an
     * ill-conditioned W.  A blade edge under a flat cloth is not: its ends
     * are far from the cloth edge it crosses; nor is a cloth edge wrapped
     * round a blade's border (along_face). */
    if ((along_face(B, f, n, pa0, pa1) && ends_near(pa0, pa1, pb0, pb1, prm->alarm)) ||
        (along_face(A, e, n, pb0, pb1) && ends_near(pb0, pb1, pa0, pa1, prm->alarm)))
        return 0;
    if (when > 0.0) { /* the gap the row has at the start of the step (as for vertices) */
        gap = 0.0;
        for (int k = 0; k < 3; ++k)
            gap += n[k] * ((1.0 - s) * A->x0[3 * a0 + k] + s * A->x0[3 * a1 + k] -
                           (1.0 - t) * B->x0[3 * b0 + k] - t * B->x0[3 * b1 + k]);
        if (!(gap > 0.0)) return 0;
    }
    double approach = -dot3(n, motion);
    if (!(gap - (approach > 0.0 ? approach : 0.0) - prm->margin < prm->alarm)) return 0;
    memcpy(out->normal, n, sizeof n);
    out->gap = gap;
    return 1;
}
