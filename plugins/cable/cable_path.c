/* cable_path.c - geometry of a cable: its points, length, the gradient of
 * the length and the constraint row; locating points in a tetrahedral mesh. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cable.h"

void cable_path_init(pl_cable_path *c) { memset(c, 0, sizeof *c); }

void cable_path_free(pl_cable_path *c)
{
    free(c->vert);
    free(c->weight);
    c->vert = NULL;
    c->weight = NULL;
    c->npoints = 0;
}

int cable_path_alloc(pl_cable_path *c, int npoints) { return cable_path_alloc_slots(c, npoints, 4); }

int cable_path_alloc_slots(pl_cable_path *c, int npoints, int nslot)
{
    cable_path_free(c);
    if (npoints < 1 || nslot < 1) return PL_EINTERNAL;
    size_t total = (size_t)npoints * (size_t)nslot;
    c->vert = malloc(total * sizeof *c->vert);
    c->weight = calloc(total, sizeof *c->weight);
    if (!c->vert || !c->weight) {
        cable_path_free(c);
        return PL_EINTERNAL;
    }
    for (size_t k = 0; k < total; ++k) c->vert[k] = -1;
    c->npoints = npoints;
    c->nslot = nslot;
    return PL_OK;
}

void cable_point(const pl_cable_path *c, const double *x, int i, double p[3])
{
    p[0] = p[1] = p[2] = 0.0;
    for (int s = 0; s < c->nslot; ++s) {
        int v = c->vert[c->nslot * i + s];
        if (v < 0) continue;
        double w = c->weight[c->nslot * i + s];
        for (int k = 0; k < 3; ++k) p[k] += w * x[3 * v + k];
    }
}

/* |b - a| and the unit vector u = (b - a) / |b - a| (0 for a zero segment). */
static double segment(const double a[3], const double b[3], double u[3])
{
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) u[k] = l > 0.0 ? d[k] / l : 0.0;
    return l;
}

double cable_gradient(const pl_cable_path *c, const double *x, double *g)
{
    double L = 0.0, prev[3], cur[3], u[3];
    if (g) memset(g, 0, (size_t)c->npoints * 3 * sizeof *g);
    cable_point(c, x, 0, cur);
    if (c->has_pull) {
        /* the pull point is fixed: only P_0 moves the first segment */
        L += segment(c->pull, cur, u);
        if (g)
            for (int k = 0; k < 3; ++k) g[k] += u[k];
    }
    for (int i = 1; i < c->npoints; ++i) {
        memcpy(prev, cur, sizeof prev);
        cable_point(c, x, i, cur);
        L += segment(prev, cur, u);
        if (!g) continue;
        for (int k = 0; k < 3; ++k) {
            g[3 * i + k] += u[k];
            g[3 * (i - 1) + k] -= u[k];
        }
    }
    return L;
}

double cable_path_length(const pl_cable_path *c, const double *x)
{
    return cable_gradient(c, x, NULL);
}

typedef struct entry {
    int v;
    double c[3];
} entry;

static int cmp_entry(const void *a, const void *b)
{
    int x = ((const entry *)a)->v, y = ((const entry *)b)->v;
    return (x > y) - (x < y);
}

int cable_row(const pl_cable_path *c, const double *g, int *vert, double *coef)
{
    /* every (point, slot) pair contributes -w g_i to its vertex; sort and
     * merge so that a vertex shared by several points appears once (the
     * contact solver's warm start keys rows by their first entry) */
    int n = 0;
    for (int i = 0; i < c->npoints; ++i)
        for (int s = 0; s < c->nslot; ++s)
            if (c->vert[c->nslot * i + s] >= 0) n++;
    entry *tmp = malloc((size_t)(n ? n : 1) * sizeof *tmp);
    if (!tmp) return -1;
    n = 0;
    for (int i = 0; i < c->npoints; ++i)
        for (int s = 0; s < c->nslot; ++s) {
            int v = c->vert[c->nslot * i + s];
            if (v < 0) continue;
            double w = c->weight[c->nslot * i + s];
            tmp[n].v = v;
            for (int k = 0; k < 3; ++k) tmp[n].c[k] = -w * g[3 * i + k];
            n++;
        }
    qsort(tmp, (size_t)n, sizeof *tmp, cmp_entry);
    int m = 0;
    for (int k = 0; k < n; ++k) {
        if (m > 0 && vert[m - 1] == tmp[k].v) {
            for (int j = 0; j < 3; ++j) coef[3 * (m - 1) + j] += tmp[k].c[j];
            continue;
        }
        vert[m] = tmp[k].v;
        memcpy(coef + 3 * m, tmp[k].c, sizeof tmp[k].c);
        m++;
    }
    free(tmp);
    return m;
}

/* Barycentric coordinates of p in tetrahedron (a, b, c, d) by Cramer's rule;
 * returns 6 x the signed volume (0: degenerate, w untouched). */
static double barycentric(const double *a, const double *b, const double *c, const double *d,
                          const double p[3], double w[4])
{
    double e1[3], e2[3], e3[3], r[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = b[k] - a[k];
        e2[k] = c[k] - a[k];
        e3[k] = d[k] - a[k];
        r[k] = p[k] - a[k];
    }
#define DET(u, v, t)                                                                   \
    ((u)[0] * ((v)[1] * (t)[2] - (v)[2] * (t)[1]) -                                    \
     (u)[1] * ((v)[0] * (t)[2] - (v)[2] * (t)[0]) + (u)[2] * ((v)[0] * (t)[1] - (v)[1] * (t)[0]))
    double det = DET(e1, e2, e3);
    if (det == 0.0 || !isfinite(det)) return 0.0;
    w[1] = DET(r, e2, e3) / det;
    w[2] = DET(e1, r, e3) / det;
    w[3] = DET(e1, e2, r) / det;
#undef DET
    w[0] = 1.0 - w[1] - w[2] - w[3];
    return det;
}

int cable_locate(const double *x, const int *tets, int ntets, const double p[3], int v[4],
                    double w[4], double *outside)
{
    int best = -1;
    double best_min = -INFINITY;
    for (int t = 0; t < ntets; ++t) {
        const int *tv = tets + 4 * t;
        double wt[4];
        if (barycentric(x + 3 * tv[0], x + 3 * tv[1], x + 3 * tv[2], x + 3 * tv[3], p, wt) == 0.0)
            continue;
        double mn = fmin(fmin(wt[0], wt[1]), fmin(wt[2], wt[3]));
        if (mn > best_min) {
            best_min = mn;
            best = t;
            memcpy(w, wt, sizeof wt);
        }
    }
    if (best < 0) return -1;
    memcpy(v, tets + 4 * best, 4 * sizeof *v);
    *outside = best_min < 0.0 ? -best_min : 0.0;
    return best;
}

int cable_nearest(const double *x, int n, const double p[3])
{
    int best = -1;
    double bd = INFINITY;
    for (int i = 0; i < n; ++i) {
        double d = 0.0;
        for (int k = 0; k < 3; ++k) d += (x[3 * i + k] - p[k]) * (x[3 * i + k] - p[k]);
        if (d < bd) bd = d, best = i;
    }
    return best;
}
