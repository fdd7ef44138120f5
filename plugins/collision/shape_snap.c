/* shape_snap.c - smoothing of ImplicitTetrahedra meshes: the kept grid
 * cells make a staircase surface; its vertices are moved onto the shape's
 * zero level (Newton steps along the numerical gradient of a distance-like
 * field), so that the surface is smooth and its edges are not all sharp
 * 90-degree creases (which would make every edge a contact feature).  Moves
 * are bounded and undone where a tetrahedron would get flat or inverted. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "shape_tets.h"

static double box_sdf(const double *b, const double p[3])
{
    double out = 0.0, in = -INFINITY;
    for (int k = 0; k < 3; ++k) {
        double c = 0.5 * (b[k] + b[3 + k]), h = 0.5 * (b[3 + k] - b[k]);
        double d = fabs(p[k] - c) - h;
        if (d > 0) out += d * d;
        if (d > in) in = d;
    }
    return out > 0 ? sqrt(out) : in;
}

double coll_shape_field(const shape_tets *s, const double p[3])
{
    double f = INFINITY;
    for (int i = 0; i + 6 <= s->ellipsoids.n; i += 6) {
        const double *e = &s->ellipsoids.v[i];
        double r = 0, rmin = fmin(e[3], fmin(e[4], e[5]));
        for (int k = 0; k < 3; ++k) r += (p[k] - e[k]) * (p[k] - e[k]) / (e[3 + k] * e[3 + k]);
        f = fmin(f, (sqrt(r) - 1.0) * rmin);
    }
    for (int i = 0; i + 7 <= s->capsules.n; i += 7) {
        const double *c = &s->capsules.v[i];
        double d[3], w[3], dd = 0, t = 0, r2 = 0;
        for (int k = 0; k < 3; ++k) {
            d[k] = c[3 + k] - c[k];
            w[k] = p[k] - c[k];
            dd += d[k] * d[k];
            t += w[k] * d[k];
        }
        t = dd > 0 ? fmin(1.0, fmax(0.0, t / dd)) : 0.0;
        for (int k = 0; k < 3; ++k) r2 += (w[k] - t * d[k]) * (w[k] - t * d[k]);
        f = fmin(f, sqrt(r2) - c[6]);
    }
    for (int i = 0; i + 6 <= s->boxes.n; i += 6) f = fmin(f, box_sdf(&s->boxes.v[i], p));
    if (s->clip.n == 6) f = fmax(f, box_sdf(s->clip.v, p));
    return f;
}

/* A few Newton steps of p towards the zero level, bounded by maxmove. */
static void project(const shape_tets *s, const double p0[3], double maxmove, double out[3])
{
    double p[3] = {p0[0], p0[1], p0[2]}, eps = 1e-3 * s->cell;
    for (int it = 0; it < 4; ++it) {
        double f = coll_shape_field(s, p), g[3], g2 = 0;
        for (int k = 0; k < 3; ++k) {
            double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
            a[k] += eps;
            b[k] -= eps;
            g[k] = (coll_shape_field(s, a) - coll_shape_field(s, b)) / (2 * eps);
            g2 += g[k] * g[k];
        }
        if (!(g2 > 1e-12)) break;
        for (int k = 0; k < 3; ++k) p[k] -= f * g[k] / g2;
    }
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (p[k] - p0[k]) * (p[k] - p0[k]);
    double scale = d2 > maxmove * maxmove ? maxmove / sqrt(d2) : 1.0;
    for (int k = 0; k < 3; ++k) out[k] = p0[k] + scale * (p[k] - p0[k]);
}

int coll_shape_snap(const shape_tets *s, pl_mesh *m, const unsigned char *boundary)
{
    size_t n3 = (size_t)m->nverts * 3;
    double *orig = malloc((n3 ? n3 : 1) * sizeof *orig);
    unsigned char *bad = malloc((size_t)(m->nverts ? m->nverts : 1));
    if (!orig || !bad) {
        free(orig);
        free(bad);
        return PL_EINTERNAL;
    }
    memcpy(orig, m->verts, n3 * sizeof *orig);
    for (int v = 0; v < m->nverts; ++v)
        if (boundary[v]) project(s, &orig[3 * v], 0.45 * s->cell, &m->verts[3 * v]);
    /* tetrahedra must keep a fair share of a grid tetrahedron's volume */
    double vmin = 0.1 * s->cell * s->cell * s->cell / 6.0;
    for (int round = 0; round < 8; ++round) {
        memset(bad, 0, (size_t)m->nverts);
        int nbad = 0;
        for (int t = 0; t < m->ntets; ++t)
            if (coll_tet_volume(m->verts, &m->tets[4 * t]) < vmin) {
                nbad++;
                for (int k = 0; k < 4; ++k) bad[m->tets[4 * t + k]] = 1;
            }
        if (nbad == 0) break;
        for (int v = 0; v < m->nverts; ++v) /* halve the move, or undo it at the end */
            if (bad[v])
                for (int k = 0; k < 3; ++k) {
                    double *x = &m->verts[3 * v + k], o = orig[3 * v + k];
                    *x = round < 7 ? 0.5 * (*x + o) : o;
                }
    }
    free(orig);
    free(bad);
    return PL_OK;
}
