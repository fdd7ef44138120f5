/* tet_map.c - barycentric mapping of points into a tetrahedral mesh (the
 * SoftRobots / SOFA BarycentricMapping of collision and visual meshes):
 * a BVH over the tetrahedra's boxes finds the containing one; points outside
 * take the nearest tetrahedron, found by growing the query box until the
 * best exact distance is inside it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "detect.h"

static void bary_of(const double *v, const int *t, const double p[3], double b[4])
{
    const double *a = &v[3 * t[0]];
    double m[3][3], r[3];
    for (int k = 0; k < 3; ++k) {
        m[k][0] = v[3 * t[1] + k] - a[k];
        m[k][1] = v[3 * t[2] + k] - a[k];
        m[k][2] = v[3 * t[3] + k] - a[k];
        r[k] = p[k] - a[k];
    }
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double x[3];
    for (int c = 0; c < 3; ++c) { /* Cramer: column c replaced by r */
        double q[3][3];
        memcpy(q, m, sizeof q);
        for (int k = 0; k < 3; ++k) q[k][c] = r[k];
        x[c] = (q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) -
                q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
                q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0])) /
               det;
    }
    b[1] = x[0];
    b[2] = x[1];
    b[3] = x[2];
    b[0] = 1.0 - x[0] - x[1] - x[2];
}

static double min4(const double b[4])
{
    double m = b[0];
    for (int k = 1; k < 4; ++k)
        if (b[k] < m) m = b[k];
    return m;
}

/* Distance from p to tetrahedron t (0 inside). */
static double tet_distance(const double *v, const int *t, const double p[3])
{
    double b[4];
    bary_of(v, t, p, b);
    if (min4(b) >= 0.0) return 0.0;
    static const int F[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    double best = INFINITY, w[3];
    for (int f = 0; f < 4; ++f) {
        double d2 = closest_point_triangle(p, &v[3 * t[F[f][0]]], &v[3 * t[F[f][1]]],
                                              &v[3 * t[F[f][2]]], w);
        if (d2 < best) best = d2;
    }
    return sqrt(best);
}

static void point_box(const double p[3], double r, pl_aabb *q)
{
    for (int k = 0; k < 3; ++k) {
        q->lo[k] = p[k] - r;
        q->hi[k] = p[k] + r;
    }
}

static int check_mesh(const double *verts, int nverts, const int *tets, int ntets, pl_error *err)
{
    if (ntets <= 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "the volume mesh has no tetrahedra");
    for (int k = 0; k < 4 * ntets; ++k)
        if (tets[k] < 0 || tets[k] >= nverts)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "tetrahedron %d uses vertex %d, outside [0, %d)", k / 4, tets[k],
                                nverts);
    for (int t = 0; t < ntets; ++t) {
        double b[4];
        bary_of(verts, &tets[4 * t], &verts[3 * tets[4 * t]], b);
        if (!isfinite(b[0]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "tetrahedron %d is flat (zero volume): no barycentric "
                                "coordinates",
                                t);
    }
    return PL_OK;
}

/* The nearest tetrahedron of an outside point. */
static int nearest_tet(const pl_bvh *bvh, const pl_aabb *boxes, const double *verts,
                       const int *tets, const double p[3], double r, pl_ivec *cand, int *best)
{
    double bestd = INFINITY;
    for (int round = 0; round < 200; ++round) {
        pl_aabb q;
        point_box(p, r, &q);
        cand->n = 0;
        if (bvh_query(bvh, boxes, &q, cand)) return PL_EINTERNAL;
        for (int k = 0; k < cand->n; ++k) {
            int t = cand->v[k];
            double d = tet_distance(verts, &tets[4 * t], p);
            if (d < bestd || (d == bestd && t < *best)) {
                bestd = d;
                *best = t;
            }
        }
        /* every tetrahedron closer than bestd has its box within bestd of p */
        if (*best >= 0 && bestd <= r) return PL_OK;
        r = *best >= 0 ? bestd : 2.0 * r;
    }
    return PL_OK;
}

int barycentric_map(const double *verts, int nverts, const int *tets, int ntets,
                       const double *pts, int npts, int *tet_of, double *bary, int *outside,
                       pl_error *err)
{
    int rc = check_mesh(verts, nverts, tets, ntets, err);
    if (rc) return rc;
    pl_aabb *boxes = malloc((size_t)ntets * sizeof *boxes);
    if (!boxes) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    double size = 0.0;
    for (int t = 0; t < ntets; ++t) {
        for (int k = 0; k < 3; ++k) boxes[t].lo[k] = boxes[t].hi[k] = verts[3 * tets[4 * t] + k];
        for (int j = 1; j < 4; ++j)
            for (int k = 0; k < 3; ++k) {
                double x = verts[3 * tets[4 * t + j] + k];
                if (x < boxes[t].lo[k]) boxes[t].lo[k] = x;
                if (x > boxes[t].hi[k]) boxes[t].hi[k] = x;
            }
        size += boxes[t].hi[0] - boxes[t].lo[0];
    }
    size /= ntets;
    pl_bvh bvh;
    bvh_init(&bvh);
    pl_ivec cand = {0};
    rc = bvh_build(&bvh, boxes, ntets);
    int nout = 0;
    for (int i = 0; i < npts && rc == PL_OK; ++i) {
        const double *p = &pts[3 * i];
        pl_aabb q;
        point_box(p, 1e-12 * (size + 1.0), &q);
        cand.n = 0;
        if (bvh_query(&bvh, boxes, &q, &cand)) {
            rc = PL_EINTERNAL;
            break;
        }
        int best = -1;
        double bestmin = -INFINITY, b[4];
        for (int k = 0; k < cand.n; ++k) {
            int t = cand.v[k];
            bary_of(verts, &tets[4 * t], p, b);
            double m = min4(b);
            if (m > bestmin || (m == bestmin && t < best)) {
                bestmin = m;
                best = t;
            }
        }
        if (best < 0 || bestmin < -1e-9) {
            nout++;
            best = -1;
            rc = nearest_tet(&bvh, boxes, verts, tets, p, size > 0 ? size : 1.0, &cand, &best);
            if (rc == PL_OK && best < 0) rc = PL_EINTERNAL;
        }
        if (rc != PL_OK) break;
        tet_of[i] = best;
        bary_of(verts, &tets[4 * best], p, &bary[4 * i]);
    }
    ivec_free(&cand);
    bvh_free(&bvh);
    free(boxes);
    if (outside) *outside = nout;
    if (rc == PL_EINTERNAL)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    return rc;
}

static int cmp_pair(const void *a, const void *b)
{
    const int *x = a, *y = b;
    if (x[0] != y[0]) return (x[0] > y[0]) - (x[0] < y[0]);
    return (x[1] > y[1]) - (x[1] < y[1]);
}

int triangle_edges(const int *tris, int ntris, int **edges, int *nedges)
{
    *edges = NULL;
    *nedges = 0;
    if (ntris <= 0) return PL_OK;
    int *e = malloc((size_t)ntris * 6 * sizeof *e);
    if (!e) return PL_EINTERNAL;
    for (int t = 0; t < ntris; ++t)
        for (int k = 0; k < 3; ++k) {
            int a = tris[3 * t + k], b = tris[3 * t + (k + 1) % 3];
            e[6 * t + 2 * k] = a < b ? a : b;
            e[6 * t + 2 * k + 1] = a < b ? b : a;
        }
    int ne = 3 * ntris, w = 0;
    qsort(e, (size_t)ne, 2 * sizeof *e, cmp_pair);
    for (int i = 0; i < ne; ++i)
        if (w == 0 || e[2 * i] != e[2 * (w - 1)] || e[2 * i + 1] != e[2 * (w - 1) + 1]) {
            e[2 * w] = e[2 * i];
            e[2 * w + 1] = e[2 * i + 1];
            w++;
        }
    *edges = e;
    *nedges = w;
    return PL_OK;
}
