/* scene_check.c - see scene_check.h. */
#include "scene_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void sub(const double a[3], const double b[3], double r[3])
{
    for (int k = 0; k < 3; ++k) r[k] = a[k] - b[k];
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double r[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

/* Moller-Trumbore on the segment p + t (q - p), t in [0, 1]. */
int sc_segment_hits_triangle(const double p[3], const double q[3], const double a[3],
                             const double b[3], const double c[3])
{
    double d[3], e1[3], e2[3], h[3], s[3], qv[3];
    sub(q, p, d);
    sub(b, a, e1);
    sub(c, a, e2);
    cross(d, e2, h);
    double det = dot(e1, h);
    if (fabs(det) < 1e-300) return 0;
    double inv = 1.0 / det;
    sub(p, a, s);
    double u = inv * dot(s, h);
    if (u < 0.0 || u > 1.0) return 0;
    cross(s, e1, qv);
    double v = inv * dot(d, qv);
    if (v < 0.0 || u + v > 1.0) return 0;
    double t = inv * dot(e2, qv);
    return t >= 0.0 && t <= 1.0;
}

static double point_segment(const double x[3], const double u[3], const double w[3])
{
    double ed[3], ux[3];
    sub(w, u, ed);
    sub(x, u, ux);
    double l2 = dot(ed, ed), t = l2 > 0.0 ? fmin(1.0, fmax(0.0, dot(ux, ed) / l2)) : 0.0, d2 = 0.0;
    for (int i = 0; i < 3; ++i) d2 += (ux[i] - t * ed[i]) * (ux[i] - t * ed[i]);
    return sqrt(d2);
}

double sc_crossing_depth(const double p[3], const double q[3], const double a[3],
                         const double b[3], const double c[3])
{
    if (!sc_segment_hits_triangle(p, q, a, b, c)) return -1.0;
    double e1[3], e2[3], n[3], ap[3], d[3];
    sub(b, a, e1);
    sub(c, a, e2);
    cross(e1, e2, n);
    sub(p, a, ap);
    sub(q, p, d);
    double dn = dot(d, n), t = fabs(dn) > 0.0 ? -dot(ap, n) / dn : 0.0, x[3];
    for (int k = 0; k < 3; ++k) x[k] = p[k] + t * d[k];
    return fmin(point_segment(x, a, b), fmin(point_segment(x, b, c), point_segment(x, c, a)));
}

double sc_plane_distance(const double x[3], const double a[3], const double b[3],
                         const double c[3])
{
    double e1[3], e2[3], n[3], ax[3];
    sub(b, a, e1);
    sub(c, a, e2);
    cross(e1, e2, n);
    sub(x, a, ax);
    double len = sqrt(dot(n, n));
    return len > 0.0 ? fabs(dot(ax, n)) / len : sqrt(dot(ax, ax));
}

/* Clips the parameter range [t0, t1] of p + t d to f(t) = f0 + t df <= 0. */
static int clip(double f0, double df, double *t0, double *t1)
{
    if (fabs(df) < 1e-300) return f0 <= 0.0;
    double t = -f0 / df;
    if (df > 0.0) {
        if (t < *t1) *t1 = t;
    } else if (t > *t0) {
        *t0 = t;
    }
    return *t0 <= *t1;
}

double sc_edge_depth_beyond(const double p[3], const double q[3], const double a[3],
                            const double b[3], const double c[3], double sign, double band)
{
    double e1[3], e2[3], n[3], d[3];
    sub(b, a, e1);
    sub(c, a, e2);
    cross(e1, e2, n);
    double len = sqrt(dot(n, n));
    if (!(len > 0.0)) return 0.0;
    for (int k = 0; k < 3; ++k) n[k] *= sign / len;
    sub(q, p, d);
    double t0 = 0.0, t1 = 1.0;
    /* inside the prism: on the inner side of the three planes through the
     * edges, perpendicular to the triangle */
    const double *v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
        const double *u = v[k], *w = v[(k + 1) % 3], *o = v[(k + 2) % 3];
        double ed[3], m[3], uo[3], up[3];
        sub(w, u, ed);
        cross(ed, n, m); /* in the triangle's plane, perpendicular to the edge */
        sub(o, u, uo);
        if (dot(m, uo) > 0.0)
            for (int i = 0; i < 3; ++i) m[i] = -m[i]; /* m points out of the triangle */
        sub(p, u, up);
        if (!clip(dot(m, up), dot(m, d), &t0, &t1)) return 0.0;
    }
    /* height h(t) = n . (p + t d - a) within (-inf, band] */
    double ap[3];
    sub(p, a, ap);
    double h0 = dot(n, ap), dh = dot(n, d);
    if (!clip(h0 - band, dh, &t0, &t1)) return 0.0;
    double ha = h0 + t0 * dh, hb = h0 + t1 * dh;
    /* only a segment that goes through the triangle (one part on each side)
     * pierces it; wholly beyond is another part of the scene */
    if (fmin(ha, hb) > 0.0) return 0.0;
    double h = fmax(ha, hb);
    return h > 0.0 ? h : 0.0;
}

static int cmp_face(const void *x, const void *y)
{
    const int *a = x, *b = y;
    for (int k = 0; k < 3; ++k)
        if (a[k] != b[k]) return (a[k] > b[k]) - (a[k] < b[k]);
    return 0;
}

int sc_boundary(const int *tets, int ntets, int **tris)
{
    static const int F[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    int nf = 4 * ntets;
    int *f = malloc((size_t)nf * 6 * sizeof *f); /* sorted key, then oriented face */
    int *out = malloc((size_t)nf * 3 * sizeof *out);
    if (!f || !out) abort();
    for (int t = 0; t < ntets; ++t)
        for (int k = 0; k < 4; ++k) {
            int *r = &f[6 * (4 * t + k)];
            for (int j = 0; j < 3; ++j) r[3 + j] = tets[4 * t + F[k][j]];
            int s[3] = {r[3], r[4], r[5]};
            for (int i = 0; i < 3; ++i)
                for (int j = i + 1; j < 3; ++j)
                    if (s[j] < s[i]) {
                        int tmp = s[i];
                        s[i] = s[j];
                        s[j] = tmp;
                    }
            memcpy(r, s, sizeof s);
        }
    qsort(f, (size_t)nf, 6 * sizeof *f, cmp_face);
    int n = 0;
    for (int i = 0; i < nf;) {
        int j = i + 1;
        while (j < nf && cmp_face(&f[6 * i], &f[6 * j]) == 0) j++;
        if (j - i == 1) memcpy(&out[3 * n++], &f[6 * i + 3], 3 * sizeof *out);
        i = j;
    }
    free(f);
    *tris = out;
    return n;
}

int sc_inside(const double *v, const int *tris, int ntris, const double x[3])
{
    double far[3] = {x[0] + 123.456, x[1] + 71.3, x[2] + 97.1};
    int n = 0;
    for (int t = 0; t < ntris; ++t)
        n += sc_segment_hits_triangle(x, far, &v[3 * tris[3 * t]], &v[3 * tris[3 * t + 1]],
                                      &v[3 * tris[3 * t + 2]]);
    return n & 1;
}

/* Distance from x to triangle a b c by projection or its three edges. */
static double tri_distance(const double x[3], const double a[3], const double b[3],
                           const double c[3])
{
    double e1[3], e2[3], n[3], ax[3];
    sub(b, a, e1);
    sub(c, a, e2);
    cross(e1, e2, n);
    double nn = dot(n, n);
    sub(x, a, ax);
    if (nn > 0.0) {
        double h = dot(ax, n) / nn, f[3];
        for (int k = 0; k < 3; ++k) f[k] = x[k] - h * n[k];
        /* the foot inside (same side of all three edges)? */
        const double *v[3] = {a, b, c};
        int in = 1;
        for (int k = 0; k < 3 && in; ++k) {
            double ed[3], vf[3], cr[3];
            sub(v[(k + 1) % 3], v[k], ed);
            sub(f, v[k], vf);
            cross(ed, vf, cr);
            if (dot(cr, n) < 0.0) in = 0;
        }
        if (in) return fabs(h) * sqrt(nn);
    }
    double best = INFINITY;
    const double *v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
        const double *u = v[k], *w = v[(k + 1) % 3];
        double ed[3], ux[3];
        sub(w, u, ed);
        sub(x, u, ux);
        double l2 = dot(ed, ed), t = l2 > 0.0 ? fmin(1.0, fmax(0.0, dot(ux, ed) / l2)) : 0.0;
        double d2 = 0.0;
        for (int i = 0; i < 3; ++i) d2 += (ux[i] - t * ed[i]) * (ux[i] - t * ed[i]);
        best = fmin(best, sqrt(d2));
    }
    return best;
}

double sc_surface_distance(const double *v, const int *tris, int ntris, const double x[3])
{
    double best = INFINITY;
    for (int t = 0; t < ntris; ++t)
        best = fmin(best, tri_distance(x, &v[3 * tris[3 * t]], &v[3 * tris[3 * t + 1]],
                                       &v[3 * tris[3 * t + 2]]));
    return best;
}

double sc_volume(const double *v, const int *tets, int ntets)
{
    double vol = 0.0;
    for (int t = 0; t < ntets; ++t) {
        const int *q = &tets[4 * t];
        double a[3], b[3], c[3], r[3];
        sub(&v[3 * q[1]], &v[3 * q[0]], a);
        sub(&v[3 * q[2]], &v[3 * q[0]], b);
        sub(&v[3 * q[3]], &v[3 * q[0]], c);
        cross(b, c, r);
        vol += dot(a, r) / 6.0;
    }
    return vol;
}
