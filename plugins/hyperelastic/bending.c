/* bending.c - building the cloth bending stencils and position targets.
 *
 * Isometric bending (Bergou et al. 2006): for an interior edge x0 x1 with
 * triangles T0 = (x0, x1, x2) and T1 = (x0, x1, x3),
 *   K = [c01 + c11, c00 + c10, -(c00 + c01), -(c10 + c11)]
 * with cij the cotangent of triangle Ti's angle at xj.  Within a flat T0,
 * c01 (x0 - x2) + c00 (x1 - x2) = -|e| m0 (m0: unit in-plane normal of the
 * edge towards x2), so K x = |e| (-m0 - m1) vanishes for a flat pair and has
 * norm ~ |e| theta for a dihedral angle theta.
 *
 * Laplace-Beltrami bending (Bouaziz et al. 2014): row i of the cotangent
 * Laplacian (weights (cot a + cot b)/2 per edge) over the barycentric area
 * A_i is the mean-curvature normal 2H n at vertex i. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hyperelastic.h"
#include "small_matrix.h"
#include "stencils_internal.h"

/* Cotangent of the angle between u and v. */
static double cot_angle(const double *u, const double *v)
{
    double c[3];
    hm_cross(u, v, c);
    return hm_dot3(u, v) / hm_norm3(c);
}

/* cot of the angle at vertex a of triangle (a, b, c). */
static double cot_at(const double *rest, int a, int b, int c)
{
    double u[3], v[3];
    hm_sub3(rest + 3 * (size_t)b, rest + 3 * (size_t)a, u);
    hm_sub3(rest + 3 * (size_t)c, rest + 3 * (size_t)a, v);
    return cot_angle(u, v);
}

static double tri_area(const double *rest, int a, int b, int c)
{
    double u[3], v[3], n[3];
    hm_sub3(rest + 3 * (size_t)b, rest + 3 * (size_t)a, u);
    hm_sub3(rest + 3 * (size_t)c, rest + 3 * (size_t)a, v);
    hm_cross(u, v, n);
    return 0.5 * hm_norm3(n);
}

/* A triangle edge (lo, hi) with its triangle and opposite vertex. */
typedef struct edge_ref {
    int lo, hi, tri, opp;
} edge_ref;

static int edge_cmp(const void *pa, const void *pb)
{
    const edge_ref *a = pa, *b = pb;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return (a->tri > b->tri) - (a->tri < b->tri);
}

/* Sorted list of the 3 ntris triangle edges; NULL on allocation failure. */
static edge_ref *sorted_edges(const int *tris, int ntris)
{
    edge_ref *e = malloc((size_t)(ntris > 0 ? 3 * ntris : 1) * sizeof *e);
    if (!e) return NULL;
    for (int t = 0; t < ntris; ++t)
        for (int c = 0; c < 3; ++c) {
            int a = tris[3 * t + (c + 1) % 3], b = tris[3 * t + (c + 2) % 3];
            edge_ref r = {a < b ? a : b, a < b ? b : a, t, tris[3 * t + c]};
            e[3 * t + c] = r;
        }
    qsort(e, (size_t)3 * ntris, sizeof *e, edge_cmp);
    return e;
}

static int check_input(const int *tris, int ntris, const double *rest, int nverts, double stiffness,
                       pl_error *err)
{
    if (!(stiffness >= 0.0) || !isfinite(stiffness))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "stiffness must be a non-negative number [N m], got %g", stiffness);
    for (int t = 0; t < ntris; ++t) {
        for (int c = 0; c < 3; ++c)
            if (tris[3 * t + c] < 0 || tris[3 * t + c] >= nverts)
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "triangle %d: vertex index %d out of range [0, %d)", t,
                                    tris[3 * t + c], nverts);
        if (!(tri_area(rest, tris[3 * t], tris[3 * t + 1], tris[3 * t + 2]) > 0.0))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "triangle %d: degenerate", t);
    }
    return PL_OK;
}

int hyper_isometric_bending_build(pl_hyper_stencils *s, const int *tris, int ntris,
                                     const double *rest, int nverts, double stiffness,
                                     int *nskipped, pl_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = check_input(tris, ntris, rest, nverts, stiffness, err);
    if (rc != PL_OK) return rc;
    edge_ref *e = sorted_edges(tris, ntris);
    if (!e) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (edges)");
    int ninterior = 0, skipped = 0, m = 3 * ntris;
    for (int i = 0, j; i < m; i = j) {
        for (j = i; j < m && e[j].lo == e[i].lo && e[j].hi == e[i].hi;) ++j;
        if (j - i == 2) ++ninterior;
        if (j - i > 2) ++skipped;
    }
    if (hyper_stencils_alloc(s, PL_HYPER_STENCIL_FIXED, ninterior, 4 * ninterior, nverts) != 0) {
        free(e);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (bending)");
    }
    int r = 0;
    for (int i = 0, j; i < m; i = j) {
        for (j = i; j < m && e[j].lo == e[i].lo && e[j].hi == e[i].hi;) ++j;
        if (j - i != 2) continue;
        int x0 = e[i].lo, x1 = e[i].hi, x2 = e[i].opp, x3 = e[i + 1].opp;
        double c00 = cot_at(rest, x0, x1, x2), c01 = cot_at(rest, x1, x0, x2);
        double c10 = cot_at(rest, x0, x1, x3), c11 = cot_at(rest, x1, x0, x3);
        int v[4] = {x0, x1, x2, x3};
        double K[4] = {c01 + c11, c00 + c10, -(c00 + c01), -(c10 + c11)};
        s->ptr[r] = 4 * r;
        for (int c = 0; c < 4; ++c) {
            s->vert[4 * r + c] = v[c];
            s->coef[4 * r + c] = K[c];
        }
        double area = tri_area(rest, x0, x1, x2) + tri_area(rest, x0, x1, x3);
        s->w[r] = stiffness * 3.0 / area;
        ++r;
    }
    s->ptr[r] = 4 * r;
    free(e);
    if (nskipped) *nskipped = skipped;
    if (hyper_stencils_finish(s, rest) != 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (bending)");
    return PL_OK;
}

int hyper_laplace_beltrami_build(pl_hyper_stencils *s, const int *tris, int ntris,
                                    const double *rest, int nverts, double stiffness,
                                    pl_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = check_input(tris, ntris, rest, nverts, stiffness, err);
    if (rc != PL_OK) return rc;
    edge_ref *e = sorted_edges(tris, ntris);
    double *area = calloc((size_t)(nverts > 0 ? nverts : 1), sizeof *area);
    int *deg = calloc((size_t)nverts + 1, sizeof *deg);
    unsigned char *boundary = calloc((size_t)(nverts > 0 ? nverts : 1), 1);
    int m = 3 * ntris;
    if (!e || !area || !deg || !boundary) {
        free(e);
        free(area);
        free(deg);
        free(boundary);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (bending)");
    }
    for (int t = 0; t < ntris; ++t) {
        double a = tri_area(rest, tris[3 * t], tris[3 * t + 1], tris[3 * t + 2]) / 3.0;
        for (int c = 0; c < 3; ++c) area[tris[3 * t + c]] += a;
    }
    /* unique edges: each adds a neighbour to both ends */
    int nuniq = 0;
    for (int i = 0, j; i < m; i = j) {
        for (j = i; j < m && e[j].lo == e[i].lo && e[j].hi == e[i].hi;) ++j;
        deg[e[i].lo]++;
        deg[e[i].hi]++;
        ++nuniq;
        if (j - i == 1) boundary[e[i].lo] = boundary[e[i].hi] = 1; /* one triangle */
    }
    int nrows = 0;
    for (int v = 0; v < nverts; ++v) nrows += area[v] > 0.0;
    if (hyper_stencils_alloc(s, PL_HYPER_STENCIL_KEEP_NORM, nrows, nrows + 2 * nuniq, nverts) != 0) {
        free(e);
        free(area);
        free(deg);
        free(boundary);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (bending)");
    }
    /* row layout: the vertex itself, then its neighbours in edge order */
    int *row_of = deg; /* reuse: deg -> first entry of each vertex's row */
    int r = 0, nnz = 0;
    for (int v = 0; v < nverts; ++v) {
        if (!(area[v] > 0.0)) {
            row_of[v] = -1;
            continue;
        }
        int dv = deg[v];
        s->ptr[r] = nnz;
        s->vert[nnz] = v;
        s->coef[nnz] = 0.0;
        s->w[r] = stiffness * area[v];
        row_of[v] = nnz + 1; /* next free neighbour slot */
        nnz += 1 + dv;
        ++r;
    }
    s->ptr[r] = nnz;
    for (int i = 0, j; i < m; i = j) {
        double wij = 0.0; /* (cot a + cot b) / 2 over the edge's triangles */
        for (j = i; j < m && e[j].lo == e[i].lo && e[j].hi == e[i].hi; ++j)
            wij += 0.5 * cot_at(rest, e[j].opp, e[j].lo, e[j].hi);
        int ends[2] = {e[i].lo, e[i].hi};
        for (int c = 0; c < 2; ++c) {
            int v = ends[c], slot = row_of[v]++;
            s->vert[slot] = ends[1 - c];
            s->coef[slot] = wij / area[v];
        }
    }
    /* diagonal: minus the row sum (the Laplacian annihilates constants) */
    for (int q = 0; q < s->n; ++q) {
        double sum = 0.0;
        for (int k = s->ptr[q] + 1; k < s->ptr[q + 1]; ++k) sum += s->coef[k];
        s->coef[s->ptr[q]] = -sum;
    }
    free(e);
    free(area);
    free(deg);
    if (hyper_stencils_finish(s, rest) != 0 || hyper_lb_fix_flat_boundary(s, rest, boundary) != 0) {
        free(boundary);
        hyper_stencils_free(s);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (bending)");
    }
    free(boundary);
    return PL_OK;
}

int hyper_point_targets_build(pl_hyper_stencils *s, const int *idx, int n, int nverts,
                                 double stiffness, pl_error *err)
{
    memset(s, 0, sizeof *s);
    if (!(stiffness >= 0.0) || !isfinite(stiffness))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "stiffness must be a non-negative number [N/m], got %g", stiffness);
    for (int i = 0; i < n; ++i)
        if (idx[i] < 0 || idx[i] >= nverts)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "index %d (entry %d) out of range [0, %d)", idx[i], i, nverts);
    if (hyper_stencils_alloc(s, PL_HYPER_STENCIL_FIXED, n, n, nverts) != 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (targets)");
    for (int i = 0; i < n; ++i) {
        s->ptr[i] = i;
        s->vert[i] = idx[i];
        s->coef[i] = 1.0;
        s->w[i] = stiffness;
    }
    s->ptr[n] = n;
    if (hyper_stencils_finish(s, NULL) != 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (targets)");
    return PL_OK;
}
