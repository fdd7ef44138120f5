/* sheet_fixture.c - random wavy sheets for the detection tests (sheet_fixture.h). */
#include "sheet_fixture.h"

#include <stdlib.h>

double sheet_urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / (double)0xffffff;
}

void sheet_free(sheet *s)
{
    free(s->x0);
    free(s->x1);
    free(s->tris);
    free(s->edges);
    s->x0 = s->x1 = NULL;
    s->tris = s->edges = NULL;
}

int sheet_make(sheet *s, int n, double z0, double bump, double dz, double noise, unsigned *seed)
{
    s->nv = n * n;
    s->nt = 2 * (n - 1) * (n - 1);
    s->ne = 0;
    s->edges = NULL;
    s->x0 = malloc((size_t)s->nv * 3 * sizeof(double));
    s->x1 = malloc((size_t)s->nv * 3 * sizeof(double));
    s->tris = malloc((size_t)s->nt * 3 * sizeof(int));
    if (!s->x0 || !s->x1 || !s->tris) {
        sheet_free(s);
        return -1;
    }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double *p = &s->x0[3 * (i + n * j)];
            p[0] = (double)i / (n - 1) + 0.2 * bump * (sheet_urand(seed) - 0.5);
            p[1] = (double)j / (n - 1) + 0.2 * bump * (sheet_urand(seed) - 0.5);
            p[2] = z0 + bump * (sheet_urand(seed) - 0.5);
            for (int k = 0; k < 3; ++k)
                s->x1[3 * (i + n * j) + k] =
                    p[k] + (k == 2 ? dz : 0.0) + noise * (sheet_urand(seed) - 0.5);
        }
    int t = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            int a = i + n * j, b = a + 1, c = a + n, d = c + 1;
            int *q = &s->tris[3 * t++];
            q[0] = a, q[1] = b, q[2] = d;
            q = &s->tris[3 * t++];
            q[0] = a, q[1] = d, q[2] = c;
        }
    if (triangle_edges(s->tris, s->nt, &s->edges, &s->ne) != PL_OK) {
        sheet_free(s);
        return -1;
    }
    return PL_OK;
}

int sheet_mesh(const sheet *s, pl_coll_mesh *m, pl_mesh_sides sides, double margin,
               pl_error *err)
{
    coll_mesh_init(m);
    m->nverts = s->nv;
    m->ntris = s->nt;
    m->nedges = s->ne;
    m->x0 = s->x0;
    m->x1 = s->x1;
    m->tris = s->tris;
    m->edges = s->edges;
    m->sides = sides;
    return coll_mesh_prepare(m, margin, err);
}
