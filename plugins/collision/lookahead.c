/* lookahead.c - where a pair of primitives that is far apart at the start
 * of the step will be in contact during it (look-ahead detection).  The
 * vertices move straight from x0 to x1 (the prediction of the step), so the
 * distance between a vertex and a triangle, or two edges, changes at most
 * by the largest relative motion of their vertices per unit of the step:
 * conservative advancement (Mirtich) steps the instant forward by the
 * distance left over that bound and never passes the first instant at
 * which they come within the target distance. */
#include <math.h>

#include "detect_internal.h"

/* advancement steps: a head-on approach lands in one or two, a grazing
 * one creeps towards its nearest instant */
#define CA_STEPS 24

void coll_at(const pl_coll_mesh *m, int v, double s, double out[3])
{
    const double *a = &m->x0[3 * v], *b = &m->x1[3 * v];
    for (int k = 0; k < 3; ++k) out[k] = s == 0.0 ? a[k] : a[k] + s * (b[k] - a[k]);
}

static double motion_len(const pl_coll_mesh *m, int v)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double d = m->x1[3 * v + k] - m->x0[3 * v + k];
        d2 += d * d;
    }
    return sqrt(d2);
}

static double vf_distance(const pl_coll_mesh *P, int p, const pl_coll_mesh *T, const int *tri,
                          double s)
{
    double x[3], a[3], b[3], c[3], w[3];
    coll_at(P, p, s, x);
    coll_at(T, tri[0], s, a);
    coll_at(T, tri[1], s, b);
    coll_at(T, tri[2], s, c);
    return sqrt(closest_point_triangle(x, a, b, c, w));
}

static double ee_distance(const pl_coll_mesh *A, const int *ea, const pl_coll_mesh *B,
                          const int *eb, double s)
{
    double p0[3], p1[3], q0[3], q1[3], u, v;
    coll_at(A, ea[0], s, p0);
    coll_at(A, ea[1], s, p1);
    coll_at(B, eb[0], s, q0);
    coll_at(B, eb[1], s, q1);
    return sqrt(closest_segments(p0, p1, q0, q1, &u, &v));
}

/* The advancement over the distance function dist (d0 = dist(0) > reach,
 * Lipschitz bound lip): the first instant within target, or the nearest
 * one reached; 1 and *s when that is within reach, else 0. */
typedef double (*dist_fn)(const void *ctx, double s);

static int advance(dist_fn dist, const void *ctx, double d0, double lip, double target,
                   double reach, double *s)
{
    if (!(lip > 0.0) || !(d0 - lip < reach)) return 0; /* cannot come near */
    double t = 0.0, d = d0;
    for (int k = 0; k < CA_STEPS && d > target && t < 1.0; ++k) {
        t += (d - target) / lip;
        if (t > 1.0) t = 1.0;
        d = dist(ctx, t);
    }
    if (d > target && t < 1.0 && !(d < reach)) {
        /* crept without coming within reach (a grazing path): its end may
         * come nearer.  Not when t is within reach already: a path slanted
         * to a face converges on target geometrically, and whether its last
         * step lands at or 1e-19 m above target is round-off; the end of
         * the step may lie beyond the face, where the pair is no longer on
         * the side it started on and is dropped (cloth_on_knives_small.xml:
         * a cloth vertex at 7.6 mm from a blade, 8.3 mm a step along its
         * normal, went through when the solve's W was explicit) */
        double d1 = dist(ctx, 1.0);
        if (d1 < d) t = 1.0, d = d1;
    }
    if (!(d < reach)) return 0;
    *s = t;
    return 1;
}

typedef struct vf_ctx {
    const pl_coll_mesh *P, *T;
    int p;
    const int *tri;
} vf_ctx;

static double vf_dist(const void *ctx, double s)
{
    const vf_ctx *c = ctx;
    return vf_distance(c->P, c->p, c->T, c->tri, s);
}

typedef struct ee_ctx {
    const pl_coll_mesh *A, *B;
    const int *ea, *eb;
} ee_ctx;

static double ee_dist(const void *ctx, double s)
{
    const ee_ctx *c = ctx;
    return ee_distance(c->A, c->ea, c->B, c->eb, s);
}

static double target_of(const pl_detect_params *prm)
{
    return prm->contact > 0.0 ? prm->contact : 0.5 * prm->alarm;
}

int coll_vf_lookahead(const pl_coll_mesh *P, int p, const pl_coll_mesh *T, const int *tri,
                      double d0, const pl_detect_params *prm, double *s)
{
    double lt = 0.0;
    for (int a = 0; a < 3; ++a) lt = fmax(lt, motion_len(T, tri[a]));
    vf_ctx c = {P, T, p, tri};
    return advance(vf_dist, &c, d0, motion_len(P, p) + lt, target_of(prm),
                   prm->alarm + prm->margin, s);
}

int coll_ee_lookahead(const pl_coll_mesh *A, const int *ea, const pl_coll_mesh *B,
                      const int *eb, double d0, const pl_detect_params *prm, double *s)
{
    double la = fmax(motion_len(A, ea[0]), motion_len(A, ea[1]));
    double lb = fmax(motion_len(B, eb[0]), motion_len(B, eb[1]));
    ee_ctx c = {A, B, ea, eb};
    return advance(ee_dist, &c, d0, la + lb, target_of(prm), prm->alarm + prm->margin, s);
}
