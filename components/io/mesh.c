/* mesh.c - pl_mesh utilities: lifetime, copy, validation, orientation,
 * unused-vertex removal and rigid/scaling transforms. */
#include "pliant/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pl_mesh_init(pl_mesh *m)
{
    memset(m, 0, sizeof *m);
}

void pl_mesh_free(pl_mesh *m)
{
    if (!m) return;
    free(m->verts);
    free(m->tets);
    free(m->tris);
    memset(m, 0, sizeof *m);
}

/* malloc+memcpy that treats n == 0 as "no array". */
static void *dup_array(const void *src, size_t n, int *fail)
{
    if (n == 0 || !src) return NULL;
    void *p = malloc(n);
    if (!p) {
        *fail = 1;
        return NULL;
    }
    memcpy(p, src, n);
    return p;
}

int pl_mesh_copy(pl_mesh *dst, const pl_mesh *src)
{
    pl_mesh m;
    int fail = 0;
    pl_mesh_init(&m);
    m.nverts = src->nverts;
    m.ntets = src->ntets;
    m.ntris = src->ntris;
    m.verts = dup_array(src->verts, (size_t)src->nverts * 3 * sizeof(double), &fail);
    m.tets = dup_array(src->tets, (size_t)src->ntets * 4 * sizeof(int), &fail);
    m.tris = dup_array(src->tris, (size_t)src->ntris * 3 * sizeof(int), &fail);
    if (fail) {
        pl_mesh_free(&m);
        return PL_EINTERNAL;
    }
    *dst = m;
    return PL_OK;
}

/* Checks one element's indices: in range and pairwise distinct. */
static int check_element(const int *e, int k, int nverts, int *bad_index)
{
    for (int a = 0; a < k; ++a) {
        if (e[a] < 0 || e[a] >= nverts) {
            *bad_index = e[a];
            return 1;
        }
        for (int b = 0; b < a; ++b)
            if (e[a] == e[b]) return 2;
    }
    return 0;
}

/* Validates one kind of element array; reports the first problem. */
static int validate_elements(const int *el, int n, int k, int nverts, const char *name,
                             const char *file, pl_diag *diag)
{
    if (n > 0 && !el)
        return pl_diag_error(diag, PL_EINPUT, file, 0, NULL, "%d %s but no index array", n,
                             name);
    for (int i = 0; i < n; ++i) {
        int bad = 0;
        int why = check_element(el + (size_t)k * i, k, nverts, &bad);
        if (why == 1)
            return pl_diag_error(diag, PL_EINPUT, file, 0, NULL,
                                 "%s %d uses vertex %d: expected an index in 0..%d", name, i,
                                 bad, nverts - 1);
        if (why == 2)
            return pl_diag_error(diag, PL_EINPUT, file, 0, NULL,
                                 "%s %d repeats a vertex: expected %d distinct vertices", name,
                                 i, k);
    }
    return PL_OK;
}

int pl_mesh_validate(const pl_mesh *m, const char *file, pl_diag *diag)
{
    if (m->nverts < 0 || m->ntets < 0 || m->ntris < 0)
        return pl_diag_error(diag, PL_EINPUT, file, 0, NULL, "negative element counts");
    if (m->nverts > 0 && !m->verts)
        return pl_diag_error(diag, PL_EINPUT, file, 0, NULL, "vertices without coordinates");
    for (int i = 0; i < m->nverts; ++i) {
        const double *v = m->verts + 3 * (size_t)i;
        if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]))
            return pl_diag_error(diag, PL_EINPUT, file, 0, NULL,
                                 "vertex %d has a non-finite coordinate (%g %g %g): expected "
                                 "finite numbers",
                                 i, v[0], v[1], v[2]);
    }
    if (validate_elements(m->tets, m->ntets, 4, m->nverts, "tetrahedron", file, diag))
        return PL_EINPUT;
    if (validate_elements(m->tris, m->ntris, 3, m->nverts, "triangle", file, diag))
        return PL_EINPUT;
    return PL_OK;
}

/* Six times the signed volume of tetrahedron t. */
static double tet_volume6(const pl_mesh *m, const int *t)
{
    const double *a = m->verts + 3 * (size_t)t[0], *b = m->verts + 3 * (size_t)t[1];
    const double *c = m->verts + 3 * (size_t)t[2], *d = m->verts + 3 * (size_t)t[3];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

int pl_mesh_fix_inverted(pl_mesh *m)
{
    int flipped = 0;
    for (int i = 0; i < m->ntets; ++i) {
        int *t = m->tets + 4 * (size_t)i;
        if (tet_volume6(m, t) < 0) { /* swapping two vertices negates the volume */
            int s = t[2];
            t[2] = t[3];
            t[3] = s;
            flipped++;
        }
    }
    return flipped;
}

/* Marks the vertices an index array uses; 1 when an index is out of range. */
static int mark_used(const int *idx, size_t n, int nverts, int *map)
{
    for (size_t k = 0; k < n; ++k) {
        if (idx[k] < 0 || idx[k] >= nverts) return 1;
        map[idx[k]] = 0;
    }
    return 0;
}

int pl_mesh_drop_unused(pl_mesh *m)
{
    if (m->nverts == 0) return 0;
    int *map = malloc((size_t)m->nverts * sizeof *map);
    if (!map) return -1;
    for (int i = 0; i < m->nverts; ++i) map[i] = -1;
    int bad = mark_used(m->tets, 4 * (size_t)m->ntets, m->nverts, map) ||
              mark_used(m->tris, 3 * (size_t)m->ntris, m->nverts, map);
    if (bad) { /* an invalid mesh: refuse rather than write out of bounds */
        free(map);
        return -1;
    }
    int n = 0;
    for (int i = 0; i < m->nverts; ++i) {
        if (map[i] < 0) continue;
        map[i] = n;
        if (n != i) memcpy(m->verts + 3 * (size_t)n, m->verts + 3 * (size_t)i, 3 * sizeof(double));
        n++;
    }
    for (size_t k = 0; k < 4 * (size_t)m->ntets; ++k) m->tets[k] = map[m->tets[k]];
    for (size_t k = 0; k < 3 * (size_t)m->ntris; ++k) m->tris[k] = map[m->tris[k]];
    free(map);
    int removed = m->nverts - n;
    m->nverts = n;
    if (removed && n > 0) { /* shrinking cannot lose data; keep the old block if it fails */
        double *v = realloc(m->verts, 3 * (size_t)n * sizeof(double));
        if (v) m->verts = v;
    }
    return removed;
}

/* Rotation matrix R = Rz * Ry * Rx (x applied first), angles in degrees. */
static void rotation_matrix(const double deg[3], double R[3][3])
{
    const double k = acos(-1.0) / 180.0;
    double cx = cos(deg[0] * k), sx = sin(deg[0] * k);
    double cy = cos(deg[1] * k), sy = sin(deg[1] * k);
    double cz = cos(deg[2] * k), sz = sin(deg[2] * k);
    R[0][0] = cz * cy;
    R[0][1] = cz * sy * sx - sz * cx;
    R[0][2] = cz * sy * cx + sz * sx;
    R[1][0] = sz * cy;
    R[1][1] = sz * sy * sx + cz * cx;
    R[1][2] = sz * sy * cx - cz * sx;
    R[2][0] = -sy;
    R[2][1] = cy * sx;
    R[2][2] = cy * cx;
}

void pl_mesh_transform(pl_mesh *m, const double scale[3], const double rotation_deg[3],
                       const double translation[3])
{
    static const double one[3] = {1, 1, 1}, zero[3] = {0, 0, 0};
    const double *s = scale ? scale : one;
    const double *t = translation ? translation : zero;
    double R[3][3];
    rotation_matrix(rotation_deg ? rotation_deg : zero, R);
    for (int i = 0; i < m->nverts; ++i) {
        double *v = m->verts + 3 * (size_t)i;
        double p[3] = {v[0] * s[0], v[1] * s[1], v[2] * s[2]};
        for (int r = 0; r < 3; ++r) v[r] = R[r][0] * p[0] + R[r][1] * p[1] + R[r][2] * p[2] + t[r];
    }
    /* A mirroring scale turns every element inside out; swap two vertices so
     * tetrahedra stay positively oriented and triangles keep facing outward. */
    if (s[0] * s[1] * s[2] < 0) {
        for (int i = 0; i < m->ntets; ++i) {
            int *e = m->tets + 4 * (size_t)i, x = e[2];
            e[2] = e[3];
            e[3] = x;
        }
        for (int i = 0; i < m->ntris; ++i) {
            int *e = m->tris + 3 * (size_t)i, x = e[1];
            e[1] = e[2];
            e[2] = x;
        }
    }
}
