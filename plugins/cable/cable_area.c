/* cable_area.c - the pulled area of a surface cable (SoftRobots'
 * CableConstraint with centers, radii and method="sphere"|"geodesic").
 *
 * Instead of one point, the cable's end is an area of a triangle surface:
 * the surface points whose distance d to the center is below the radius R,
 * each weighted by (R - d), the weights normalised to sum 1 (SoftRobots'
 * ratios).  The end point is the weighted centroid of the area.
 *   geodesic: d is the shortest path along the triangles' edges (Dijkstra)
 *             from the center's projection on its nearest triangle: a
 *             corner of that triangle starts at |center - projection| +
 *             |projection - corner|.  Edge paths overestimate the true
 *             surface distance where no edge follows the direction (on a
 *             grid split by one diagonal, up to sqrt(2) times along the
 *             other diagonal).
 *   sphere:   d is the straight distance |point - center| over all surface
 *             points.  (SoftRobots measures from the nearest surface
 *             vertex and only through points connected to it.) */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cable_area.h"

static double dist3(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* q = the point of triangle (a, b, c) nearest to p (by regions of the
 * triangle's plane: corners, edges, interior). */
void cable_closest_on_triangle(const double *p, const double *a, const double *b,
                               const double *c, double q[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k], cp[k] = p[k] - c[k];
    }
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap), d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    double s = 0.0, t = 0.0; /* q = a + s ab + t ac */
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    if (d1 <= 0 && d2 <= 0) {
        s = t = 0.0;
    } else if (d3 >= 0 && d4 <= d3) {
        s = 1.0;
    } else if (d6 >= 0 && d5 <= d6) {
        t = 1.0;
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        s = d1 / (d1 - d3);
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        t = d2 / (d2 - d6);
    } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double u = (d4 - d3) / ((d4 - d3) + (d5 - d6)); /* on bc */
        s = 1.0 - u, t = u;
    } else {
        double den = va + vb + vc;
        s = den != 0.0 ? vb / den : 0.0;
        t = den != 0.0 ? vc / den : 0.0;
    }
    for (int k = 0; k < 3; ++k) q[k] = a[k] + s * ab[k] + t * ac[k];
}

/* The surface's edges as adjacency lists (CSR: start[np + 1], nbr). */
static int adjacency(const int *tris, int ntris, int np, int **start, int **nbr)
{
    *start = calloc((size_t)np + 1, sizeof **start);
    *nbr = malloc((size_t)(ntris ? ntris : 1) * 6 * sizeof **nbr);
    if (!*start || !*nbr) return PL_EINTERNAL;
    for (int t = 0; t < ntris; ++t)
        for (int e = 0; e < 3; ++e) (*start)[tris[3 * t + e] + 1] += 2;
    for (int i = 0; i < np; ++i) (*start)[i + 1] += (*start)[i];
    int *fill = malloc((size_t)(np ? np : 1) * sizeof *fill);
    if (!fill) return PL_EINTERNAL;
    memcpy(fill, *start, (size_t)np * sizeof *fill);
    for (int t = 0; t < ntris; ++t)
        for (int e = 0; e < 3; ++e) {
            int a = tris[3 * t + e];
            (*nbr)[fill[a]++] = tris[3 * t + (e + 1) % 3];
            (*nbr)[fill[a]++] = tris[3 * t + (e + 2) % 3];
        }
    free(fill); /* an edge shared by two triangles appears twice: harmless */
    return PL_OK;
}

/* A binary min-heap of (distance, point), lazy deletion. */
typedef struct heap_item { double d; int v; } heap_item;

static void heap_push(heap_item *h, int *n, double d, int v)
{
    int i = (*n)++;
    while (i > 0 && h[(i - 1) / 2].d > d) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = (heap_item){d, v};
}

static heap_item heap_pop(heap_item *h, int *n)
{
    heap_item top = h[0], last = h[--*n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= *n) break;
        if (c + 1 < *n && h[c + 1].d < h[c].d) ++c;
        if (h[c].d >= last.d) break;
        h[i] = h[c];
        i = c;
    }
    if (*n > 0) h[i] = last;
    return top;
}

/* Geodesic distances (dist[np]) from center; points farther than limit keep
 * limit (the search stops there). */
static int geodesic(const double *p, int np, const int *tris, int ntris, const double *center,
                    double limit, double *dist)
{
    int *start = NULL, *nbr = NULL;
    heap_item *h = NULL;
    int rc = adjacency(tris, ntris, np, &start, &nbr);
    if (rc == PL_OK && !(h = malloc((size_t)(6 * ntris + 3) * sizeof *h))) rc = PL_EINTERNAL;
    if (rc != PL_OK) goto done;
    for (int i = 0; i < np; ++i) dist[i] = limit;
    int best = -1, nh = 0;
    double bestd = DBL_MAX, q[3], bq[3] = {0, 0, 0};
    for (int t = 0; t < ntris; ++t) {
        const int *v = tris + 3 * t;
        cable_closest_on_triangle(center, p + 3 * v[0], p + 3 * v[1], p + 3 * v[2], q);
        double d = dist3(center, q);
        if (d < bestd) bestd = d, best = t, memcpy(bq, q, sizeof bq);
    }
    for (int e = 0; e < 3; ++e) {
        int v = tris[3 * best + e];
        double d = bestd + dist3(bq, p + 3 * v);
        if (d < dist[v]) dist[v] = d, heap_push(h, &nh, d, v);
    }
    while (nh > 0) {
        heap_item it = heap_pop(h, &nh);
        if (it.d > dist[it.v]) continue; /* stale */
        for (int k = start[it.v]; k < start[it.v + 1]; ++k) {
            int u = nbr[k];
            double d = it.d + dist3(p + 3 * it.v, p + 3 * u);
            if (d < dist[u]) dist[u] = d, heap_push(h, &nh, d, u);
        }
    }
done:
    free(start);
    free(nbr);
    free(h);
    return rc;
}

int cable_area(const double *p, int np, const int *tris, int ntris, const double center[3],
               double radius, int method, int *idx, double *w, int *nsel)
{
    *nsel = 0;
    if (np < 1 || !(radius > 0) || (method == CABLE_AREA_GEODESIC && ntris < 1))
        return PL_EINPUT;
    for (int t = 0; t < 3 * ntris; ++t)
        if (tris[t] < 0 || tris[t] >= np) return PL_EINPUT;
    double *dist = malloc((size_t)np * sizeof *dist);
    if (!dist) return PL_EINTERNAL;
    int rc = PL_OK;
    if (method == CABLE_AREA_GEODESIC)
        rc = geodesic(p, np, tris, ntris, center, radius, dist);
    else
        for (int i = 0; i < np; ++i) dist[i] = dist3(p + 3 * i, center);
    double total = 0.0;
    for (int i = 0; rc == PL_OK && i < np; ++i)
        if (dist[i] < radius) {
            idx[*nsel] = i;
            w[*nsel] = radius - dist[i];
            total += w[(*nsel)++];
        }
    free(dist);
    if (rc != PL_OK) return rc;
    if (!*nsel || !(total > 0)) return PL_EINPUT;
    for (int k = 0; k < *nsel; ++k) w[k] /= total;
    return PL_OK;
}

/* Point i of path p: the weighted area points of center i, each spread over
 * the corners of the tetrahedron containing it. */
int cable_area_path(pl_cable_path *p, const cable_surface *s, const double *centers, int ncenters,
                    const double *radii, int nradii, int method, const double *x,
                    const int *tets, int ntets, int *bad_center, int *outside)
{
    int np = s->npoints, rc = PL_OK, maxsel = 0;
    int *idx = malloc((size_t)ncenters * (size_t)np * sizeof *idx), *nsel = calloc((size_t)ncenters, sizeof *nsel);
    double *w = malloc((size_t)ncenters * (size_t)np * sizeof *w);
    *bad_center = -1;
    *outside = 0;
    if (!idx || !w || !nsel) rc = PL_EINTERNAL;
    for (int i = 0; rc == PL_OK && i < ncenters; ++i) {
        double r = nradii == 0 ? 1.0 : radii[nradii == 1 ? 0 : i];
        rc = cable_area(s->points, np, s->tris, s->ntris, centers + 3 * i, r, method,
                        idx + (size_t)i * np, w + (size_t)i * np, nsel + i);
        if (rc == PL_EINPUT) *bad_center = i;
        if (nsel[i] > maxsel) maxsel = nsel[i];
    }
    if (rc == PL_OK) rc = cable_path_alloc_slots(p, ncenters, 4 * maxsel);
    for (int i = 0; rc == PL_OK && i < ncenters; ++i)
        for (int k = 0; k < nsel[i]; ++k) {
            int v[4];
            double bw[4], out;
            int at = idx[(size_t)i * np + k];
            if (cable_locate(x, tets, ntets, s->points + 3 * at, v, bw, &out) < 0) {
                rc = PL_EINPUT;
                break;
            }
            if (out > 1e-6) ++*outside;
            for (int c = 0; c < 4; ++c) {
                p->vert[p->nslot * i + 4 * k + c] = v[c];
                p->weight[p->nslot * i + 4 * k + c] = w[(size_t)i * np + k] * bw[c];
            }
        }
    free(idx);
    free(w);
    free(nsel);
    return rc;
}
