/* mesh_boundary.c - boundary faces of a tetrahedral mesh: every face is
 * keyed by its sorted vertex triple; after sorting the keys, a face seen
 * once is on the boundary.  For a positively oriented tetrahedron (a,b,c,d)
 * the outward faces are (a,c,b), (a,b,d), (a,d,c) and (b,c,d). */
#include "pliant/mesh.h"

#include <stdlib.h>

typedef struct face_key {
    int v[3];   /* sorted vertex indices */
    int tri[3]; /* the face as oriented by its tetrahedron */
} face_key;

static int cmp_face(const void *a, const void *b)
{
    const face_key *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x->v[k] != y->v[k]) return (x->v[k] > y->v[k]) - (x->v[k] < y->v[k]);
    return 0;
}

static void sort3(int v[3])
{
    int t;
    if (v[0] > v[1]) t = v[0], v[0] = v[1], v[1] = t;
    if (v[1] > v[2]) t = v[1], v[1] = v[2], v[2] = t;
    if (v[0] > v[1]) t = v[0], v[0] = v[1], v[1] = t;
}

int pl_mesh_boundary_triangles(const pl_mesh *m, int **tris, int *ntris)
{
    static const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    *tris = NULL;
    *ntris = 0;
    size_t nf = 4 * (size_t)m->ntets;
    if (nf == 0) return PL_OK;
    face_key *f = malloc(nf * sizeof *f);
    if (!f) return PL_EINTERNAL;
    for (int t = 0; t < m->ntets; ++t) {
        const int *e = m->tets + 4 * (size_t)t;
        for (int k = 0; k < 4; ++k) {
            if (e[k] < 0 || e[k] >= m->nverts) {
                free(f);
                return PL_EINPUT;
            }
            face_key *g = &f[4 * (size_t)t + k];
            for (int j = 0; j < 3; ++j) g->v[j] = g->tri[j] = e[faces[k][j]];
            sort3(g->v);
        }
    }
    qsort(f, nf, sizeof *f, cmp_face);
    size_t nb = 0;
    for (size_t i = 0; i < nf;) { /* compact the boundary faces to the front */
        size_t j = i + 1;
        while (j < nf && cmp_face(&f[i], &f[j]) == 0) j++;
        if (j - i > 2) {
            free(f);
            return PL_EINPUT;
        }
        if (j - i == 1) f[nb++] = f[i];
        i = j;
    }
    int *out = malloc(3 * nb * sizeof *out + 1);
    if (!out) {
        free(f);
        return PL_EINTERNAL;
    }
    for (size_t i = 0; i < nb; ++i)
        for (int j = 0; j < 3; ++j) out[3 * i + j] = f[i].tri[j];
    free(f);
    *tris = out;
    *ntris = (int)nb;
    return PL_OK;
}
