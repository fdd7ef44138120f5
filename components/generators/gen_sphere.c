/* gen_sphere.c - sphere surface (icosphere) and solid ball of tetrahedra. */
#include "gen_util.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static int check_sphere(const double c[3], double radius, const char *what, pl_error *err)
{
    if (!(radius > 0) || !isfinite(radius) || !isfinite(c[0]) || !isfinite(c[1]) ||
        !isfinite(c[2]))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "%s: radius %g and centre must be finite, radius > 0", what, radius);
    return PL_OK;
}

/* Midpoint vertices of the current level, keyed by their edge. */
typedef struct edge_map {
    uint64_t *key;
    int *val;
    size_t cap;
} edge_map;

/* The vertex halfway along edge (a, b), created on first use. */
static int midpoint(edge_map *e, pl_mesh *m, int a, int b)
{
    uint64_t lo = (uint64_t)(a < b ? a : b), hi = (uint64_t)(a < b ? b : a);
    uint64_t k = lo << 32 | hi;
    size_t h = (size_t)((k * 0x9E3779B97F4A7C15ULL) >> 17) & (e->cap - 1);
    while (e->val[h] >= 0 && e->key[h] != k) h = (h + 1) & (e->cap - 1);
    if (e->val[h] >= 0) return e->val[h];
    double *v = m->verts + 3 * (size_t)m->nverts;
    const double *p = m->verts + 3 * (size_t)a, *q = m->verts + 3 * (size_t)b;
    double n = 0;
    for (int c = 0; c < 3; ++c) {
        v[c] = 0.5 * (p[c] + q[c]);
        n += v[c] * v[c];
    }
    for (int c = 0; c < 3; ++c) v[c] /= sqrt(n); /* back onto the unit sphere */
    e->key[h] = k;
    e->val[h] = m->nverts;
    return m->nverts++;
}

int pl_generate_sphere_surface(const double center[3], double radius, int level, pl_mesh *out,
                               pl_error *err)
{
    static const int ico[20][3] = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    pl_mesh_init(out);
    if (check_sphere(center, radius, "sphere surface", err)) return PL_EINPUT;
    if (level < 0 || level > 8)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sphere surface: level %d: expected 0..8", level);
    long long nf = 20LL << (2 * level), nv = 10LL * (1LL << (2 * level)) + 2;
    int rc = pl_gen_alloc(out, nv, 0, nf, err);
    if (rc) return rc;
    const double g = (1 + sqrt(5.0)) / 2, s = 1 / sqrt(1 + g * g);
    const double base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (int i = 0; i < 12; ++i)
        for (int c = 0; c < 3; ++c) out->verts[3 * i + c] = base[i][c] * s;
    out->nverts = 12;
    memcpy(out->tris, ico, sizeof ico);
    out->ntris = 20;
    edge_map e = {0};
    int *next = malloc((size_t)nf * 3 * sizeof *next);
    e.cap = 1;
    while (e.cap < (size_t)nf) e.cap *= 2; /* > 1.5 F/4 edges of the previous level */
    e.key = malloc(e.cap * sizeof *e.key);
    e.val = malloc(e.cap * sizeof *e.val);
    if (!next || !e.key || !e.val) rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    for (int l = 0; rc == PL_OK && l < level; ++l) {
        memset(e.val, 0xff, e.cap * sizeof *e.val);
        for (int f = 0; f < out->ntris; ++f) {
            const int *t = out->tris + 3 * f;
            int ab = midpoint(&e, out, t[0], t[1]), bc = midpoint(&e, out, t[1], t[2]);
            int ca = midpoint(&e, out, t[2], t[0]);
            int sub[4][3] = {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}};
            memcpy(next + 12 * f, sub, sizeof sub);
        }
        out->ntris *= 4;
        memcpy(out->tris, next, (size_t)out->ntris * 3 * sizeof *next);
    }
    free(next);
    free(e.key);
    free(e.val);
    if (rc) {
        pl_mesh_free(out);
        return rc;
    }
    for (int i = 0; i < out->nverts; ++i)
        for (int c = 0; c < 3; ++c) out->verts[3 * i + c] = center[c] + radius * out->verts[3 * i + c];
    return PL_OK;
}

/* Position of grid node (i, j, k) of a (2K+1)^3 grid on the ball: its cubic
 * shell r = max|s| goes to the sphere of radius r, with equal-angle
 * (gnomonic) spacing on the shell. */
static void ball_point(const int idx[3], int K, const double c[3], double radius, double *v)
{
    double s[3], r = 0;
    for (int a = 0; a < 3; ++a) {
        s[a] = (double)(idx[a] - K) / K;
        r = fmax(r, fabs(s[a]));
    }
    if (r == 0) {
        memcpy(v, c, 3 * sizeof *v);
        return;
    }
    const double quarter_pi = atan(1.0);
    double d[3], n = 0;
    for (int a = 0; a < 3; ++a) {
        d[a] = tan(quarter_pi * s[a] / r);
        n += d[a] * d[a];
    }
    n = sqrt(n);
    for (int a = 0; a < 3; ++a) v[a] = c[a] + radius * r * d[a] / n;
}

int pl_generate_sphere_tets(const double center[3], double radius, int target_verts,
                            pl_mesh *out, pl_error *err)
{
    pl_mesh_init(out);
    if (check_sphere(center, radius, "sphere volume", err)) return PL_EINPUT;
    if (target_verts < 1 || target_verts > 50000000)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sphere volume: %d vertices requested: expected 1..50000000",
                            target_verts);
    int K = (int)lround((cbrt((double)target_verts) - 1) / 2);
    if (K < 1) K = 1;
    int n = 2 * K + 1;
    int rc = pl_gen_alloc(out, (long long)n * n * n, 6LL * (n - 1) * (n - 1) * (n - 1), 0, err);
    if (rc) return rc;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                int idx[3] = {i, j, k};
                ball_point(idx, K, center, radius, out->verts + 3 * ((size_t)i + n * (j + (size_t)n * k)));
            }
    int *t = out->tets;
    for (int k = 0; k + 1 < n; ++k)
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                int c[8];
                for (int b = 0; b < 8; ++b)
                    c[b] = (i + (b & 1)) + n * ((j + ((b >> 1) & 1)) + n * (k + (b >> 2)));
                /* the diagonal starts at the corner nearest the centre */
                int mirror = (i < K ? 1 : 0) | (j < K ? 2 : 0) | (k < K ? 4 : 0);
                pl_gen_kuhn_cell(c, mirror, t);
                t += 24;
            }
    /* the shell map keeps every tetrahedron positive (checked by the tests);
     * this only guards against rounding in extreme cases */
    pl_mesh_fix_inverted(out);
    return PL_OK;
}
