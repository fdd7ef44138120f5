/* cavity.c - see cavity.h. */
#include "cavity.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void cavity_init(cavity_surface *s) { memset(s, 0, sizeof *s); }

void cavity_free(cavity_surface *s)
{
    free(s->vert);
    free(s->weight);
    free(s->tris);
    cavity_init(s);
}

int cavity_alloc(cavity_surface *s, int npoints, int ntris)
{
    cavity_free(s);
    s->vert = malloc((size_t)npoints * 4 * sizeof *s->vert);
    s->weight = calloc((size_t)npoints * 4, sizeof *s->weight);
    s->tris = malloc((size_t)ntris * 3 * sizeof *s->tris + 1);
    if (!s->vert || !s->weight || !s->tris) {
        cavity_free(s);
        return -1;
    }
    for (int k = 0; k < 4 * npoints; ++k) s->vert[k] = -1;
    s->npoints = npoints;
    s->ntris = ntris;
    return 0;
}

void cavity_point(const cavity_surface *s, const double *x, int i, double p[3])
{
    p[0] = p[1] = p[2] = 0.0;
    for (int k = 0; k < 4; ++k) {
        int v = s->vert[4 * i + k];
        if (v < 0) continue;
        double w = s->weight[4 * i + k];
        for (int c = 0; c < 3; ++c) p[c] += w * x[3 * v + c];
    }
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Corners of triangle t at x, and N = (p1 - p0) x (p2 - p0) / 2. */
static void triangle(const cavity_surface *s, const double *x, int t, double p[3][3], double N[3])
{
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) cavity_point(s, x, s->tris[3 * t + k], p[k]);
    for (int c = 0; c < 3; ++c) e1[c] = p[1][c] - p[0][c], e2[c] = p[2][c] - p[0][c];
    cross(e1, e2, N);
    for (int c = 0; c < 3; ++c) N[c] *= 0.5;
}

double cavity_volume(const cavity_surface *s, const double *x)
{
    double V = 0.0;
    for (int t = 0; t < s->ntris; ++t) {
        double p[3][3], N[3];
        triangle(s, x, t, p, N);
        /* p0 . (p1 x p2) = 2 p0 . N; centred on the centroid for accuracy
         * far from the origin: (p0+p1+p2)/3 . N has the same sum */
        V += (p[0][0] + p[1][0] + p[2][0]) * N[0] + (p[0][1] + p[1][1] + p[2][1]) * N[1] +
             (p[0][2] + p[1][2] + p[2][2]) * N[2];
    }
    return V / 9.0;
}

double cavity_gradient(const cavity_surface *s, const double *x, double *g)
{
    memset(g, 0, (size_t)s->npoints * 3 * sizeof *g);
    double V = 0.0;
    for (int t = 0; t < s->ntris; ++t) {
        double p[3][3], N[3];
        triangle(s, x, t, p, N);
        for (int k = 0; k < 3; ++k) {
            double *gi = g + 3 * s->tris[3 * t + k];
            for (int c = 0; c < 3; ++c) gi[c] += N[c] / 3.0;
        }
        V += (p[0][0] + p[1][0] + p[2][0]) * N[0] + (p[0][1] + p[1][1] + p[2][1]) * N[1] +
             (p[0][2] + p[1][2] + p[2][2]) * N[2];
    }
    return V / 9.0;
}

/* A directed edge a -> b as a sortable key (undirected part first). */
typedef struct dedge {
    int lo, hi, dir; /* dir: 1 when a < b */
} dedge;

static int dedge_cmp(const void *pa, const void *pb)
{
    const dedge *a = pa, *b = pb;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return a->dir - b->dir;
}

int cavity_check_closed(const int *tris, int ntris, int npoints, int *a, int *b)
{
    (void)npoints;
    dedge *e = malloc((size_t)ntris * 3 * sizeof *e + 1);
    if (!e) return -1;
    for (int t = 0; t < ntris; ++t)
        for (int k = 0; k < 3; ++k) {
            int u = tris[3 * t + k], v = tris[3 * t + (k + 1) % 3];
            if (u == v) {
                *a = u, *b = v;
                free(e);
                return 4;
            }
            e[3 * t + k] = (dedge){u < v ? u : v, u < v ? v : u, u < v};
        }
    size_t m = (size_t)ntris * 3;
    qsort(e, m, sizeof *e, dedge_cmp);
    int rc = 0;
    for (size_t i = 0; i < m && !rc;) {
        size_t j = i;
        while (j < m && e[j].lo == e[i].lo && e[j].hi == e[i].hi) ++j;
        *a = e[i].lo, *b = e[i].hi;
        if (j - i == 1) rc = 1;
        else if (j - i > 2) rc = 2;
        else if (e[i].dir == e[i + 1].dir) rc = 3;
        i = j;
    }
    free(e);
    return rc;
}

/* A tetrahedron face as a sortable key, with its cavity-facing order. */
typedef struct tface {
    int key[3]; /* sorted */
    int v[3];   /* facing out of the tetrahedron's complement (into the tetrahedron) */
} tface;

static int tface_cmp(const void *pa, const void *pb)
{
    const tface *a = pa, *b = pb;
    for (int k = 0; k < 3; ++k)
        if (a->key[k] != b->key[k]) return a->key[k] < b->key[k] ? -1 : 1;
    return 0;
}

static int in_box(const double *p, const double *b)
{
    return p[0] >= b[0] && p[0] <= b[3] && p[1] >= b[1] && p[1] <= b[4] && p[2] >= b[2] &&
           p[2] <= b[5];
}

int cavity_faces_in_boxes(const double *x, const int *tets, int ntets, const double *boxes,
                          int nbox, int **out)
{
    /* faces of a positively oriented tetrahedron, turned inward (outward
     * would be {1,2,3}, {0,3,2}, {0,1,3}, {0,2,1}) */
    static const int F[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
    *out = NULL;
    tface *f = malloc((size_t)ntets * 4 * sizeof *f + 1);
    int *tri = malloc((size_t)ntets * 4 * 3 * sizeof *tri + 1);
    if (!f || !tri) {
        free(f);
        free(tri);
        return -1;
    }
    size_t m = 0;
    for (int t = 0; t < ntets; ++t)
        for (int k = 0; k < 4; ++k) {
            tface *g = &f[m++];
            for (int j = 0; j < 3; ++j) g->v[j] = g->key[j] = tets[4 * t + F[k][j]];
            for (int i = 0; i < 2; ++i) /* sort 3 */
                for (int j = 0; j < 2 - i; ++j)
                    if (g->key[j] > g->key[j + 1]) {
                        int s = g->key[j];
                        g->key[j] = g->key[j + 1];
                        g->key[j + 1] = s;
                    }
        }
    qsort(f, m, sizeof *f, tface_cmp);
    int n = 0;
    for (size_t i = 0; i < m;) {
        size_t j = i + 1;
        while (j < m && !tface_cmp(&f[i], &f[j])) ++j;
        if (j - i == 1)
            for (int b = 0; b < nbox; ++b)
                if (in_box(x + 3 * f[i].v[0], boxes + 6 * b) &&
                    in_box(x + 3 * f[i].v[1], boxes + 6 * b) &&
                    in_box(x + 3 * f[i].v[2], boxes + 6 * b)) {
                    memcpy(tri + 3 * n++, f[i].v, sizeof f[i].v);
                    break;
                }
        i = j;
    }
    free(f);
    *out = tri;
    return n;
}
