/* mesh_subdivide.c - 1-to-8 tetrahedral subdivision (the "red" refinement
 * of Bey 1995): edge midpoints, 4 corner tetrahedra, and the inner
 * octahedron split along its shortest diagonal, which keeps the children's
 * shapes from degrading over several rounds. */
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_subdivide.h"

/* Edges as sorted (lo, hi) pairs packed into one 64-bit key. */
static uint64_t edge_key(int a, int b)
{
    if (a > b) {
        int t = a;
        a = b;
        b = t;
    }
    return ((uint64_t)(uint32_t)a << 32) | (uint32_t)b;
}

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

/* Index of key in the sorted unique array (it is always there). */
static int edge_index(const uint64_t *keys, int n, uint64_t key)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (keys[mid] < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

static const int TET_EDGES[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

static double dist2(const double *a, const double *b)
{
    double d = 0.0;
    for (int k = 0; k < 3; ++k) d += (a[k] - b[k]) * (a[k] - b[k]);
    return d;
}

static double orient(const double *x, const int *t)
{
    const double *a = x + 3 * t[0], *b = x + 3 * t[1], *c = x + 3 * t[2], *d = x + 3 * t[3];
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/* Writes the 8 children of tetrahedron v (midpoints m[6] in TET_EDGES
 * order) into out (8 x 4).  The corner children are translated, halved
 * copies of the parent and keep its orientation; the octahedron's four are
 * ordered around the chosen diagonal and flipped if the parent was. */
static void split_tet(const double *x, const int v[4], const int m[6], int *out)
{
    const int corner[4][4] = {{v[0], m[0], m[1], m[2]},
                              {m[0], v[1], m[3], m[4]},
                              {m[1], m[3], v[2], m[5]},
                              {m[2], m[4], m[5], v[3]}};
    memcpy(out, corner, sizeof corner);
    /* diagonals of the octahedron join the midpoints of opposite edges:
     * (01,23), (02,13), (03,12); the ring lists the other four midpoints
     * so that consecutive ones share a face with the diagonal */
    static const int DIAG[3][2] = {{0, 5}, {1, 4}, {2, 3}};
    static const int RING[3][4] = {{1, 2, 4, 3}, {0, 2, 5, 3}, {0, 1, 5, 4}};
    int best = 0;
    double bd = dist2(x + 3 * m[0], x + 3 * m[5]);
    for (int d = 1; d < 3; ++d) {
        double l = dist2(x + 3 * m[DIAG[d][0]], x + 3 * m[DIAG[d][1]]);
        if (l < bd) bd = l, best = d;
    }
    double parent = orient(x, v);
    for (int i = 0; i < 4; ++i) {
        int *t = out + 16 + 4 * i;
        t[0] = m[DIAG[best][0]];
        t[1] = m[DIAG[best][1]];
        t[2] = m[RING[best][i]];
        t[3] = m[RING[best][(i + 1) % 4]];
        if ((orient(x, t) < 0.0) != (parent < 0.0)) {
            int s = t[2];
            t[2] = t[3];
            t[3] = s;
        }
    }
}

int pl_mesh_subdivide_tets(const pl_mesh *in, pl_mesh *out, pl_error *err)
{
    pl_mesh_free(out);
    long long nkeys = 6LL * in->ntets + 3LL * in->ntris;
    if (8LL * in->ntets > INT_MAX / 4 || 4LL * in->ntris > INT_MAX / 3 ||
        (long long)in->nverts + nkeys > INT_MAX / 3)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "subdivide",
                            "the subdivided mesh would be too large (%d tetrahedra now)",
                            in->ntets);
    uint64_t *keys = malloc((size_t)(nkeys ? nkeys : 1) * sizeof *keys);
    if (!keys) return pl_error_set(err, PL_EINTERNAL, NULL, 0, "subdivide", "out of memory");
    int n = 0;
    for (int t = 0; t < in->ntets; ++t)
        for (int e = 0; e < 6; ++e)
            keys[n++] = edge_key(in->tets[4 * t + TET_EDGES[e][0]], in->tets[4 * t + TET_EDGES[e][1]]);
    for (int t = 0; t < in->ntris; ++t)
        for (int e = 0; e < 3; ++e)
            keys[n++] = edge_key(in->tris[3 * t + e], in->tris[3 * t + (e + 1) % 3]);
    qsort(keys, (size_t)n, sizeof *keys, cmp_u64);
    int nedges = 0;
    for (int k = 0; k < n; ++k)
        if (k == 0 || keys[k] != keys[k - 1]) keys[nedges++] = keys[k];

    out->nverts = in->nverts + nedges;
    out->ntets = 8 * in->ntets;
    out->ntris = 4 * in->ntris;
    out->verts = malloc((size_t)out->nverts * 3 * sizeof *out->verts);
    out->tets = malloc((size_t)(out->ntets ? out->ntets : 1) * 4 * sizeof *out->tets);
    out->tris = malloc((size_t)(out->ntris ? out->ntris : 1) * 3 * sizeof *out->tris);
    if (!out->verts || !out->tets || !out->tris) {
        free(keys);
        pl_mesh_free(out);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "subdivide", "out of memory");
    }
    memcpy(out->verts, in->verts, (size_t)in->nverts * 3 * sizeof *out->verts);
    for (int e = 0; e < nedges; ++e) {
        int a = (int)(keys[e] >> 32), b = (int)(keys[e] & 0xffffffffu);
        for (int k = 0; k < 3; ++k)
            out->verts[3 * (in->nverts + e) + k] = 0.5 * (in->verts[3 * a + k] + in->verts[3 * b + k]);
    }
    for (int t = 0; t < in->ntets; ++t) {
        const int *v = in->tets + 4 * t;
        int m[6];
        for (int e = 0; e < 6; ++e)
            m[e] = in->nverts +
                   edge_index(keys, nedges, edge_key(v[TET_EDGES[e][0]], v[TET_EDGES[e][1]]));
        split_tet(out->verts, v, m, out->tets + 32 * (size_t)t);
    }
    for (int t = 0; t < in->ntris; ++t) {
        const int *v = in->tris + 3 * t;
        int m[3]; /* midpoints of edges 01, 12, 20 */
        for (int e = 0; e < 3; ++e)
            m[e] = in->nverts + edge_index(keys, nedges, edge_key(v[e], v[(e + 1) % 3]));
        const int kids[4][3] = {{v[0], m[0], m[2]}, {m[0], v[1], m[1]}, {m[2], m[1], v[2]},
                                {m[0], m[1], m[2]}};
        memcpy(out->tris + 12 * (size_t)t, kids, sizeof kids);
    }
    free(keys);
    return PL_OK;
}

int pl_mesh_subdivide(pl_mesh *m, int rounds, pl_error *err)
{
    for (int r = 0; r < rounds; ++r) {
        pl_mesh next;
        pl_mesh_init(&next);
        int rc = pl_mesh_subdivide_tets(m, &next, err);
        if (rc) return rc;
        pl_mesh_free(m);
        *m = next;
    }
    return PL_OK;
}
