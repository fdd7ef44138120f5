/* loader_test_util.h - shared helpers of the loader tests: independent
 * geometry (volumes, areas), temp files and diagnostics lookups. */
#ifndef LOADER_TEST_UTIL_H
#define LOADER_TEST_UTIL_H

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "pliant/error.h"
#include "pliant/mesh.h"
#include "test_tmp.h"

#define MESH_DIR PL_SOURCE_DIR "/scenes/meshes/"

/* Signed volume of tetrahedron t, (b-a).((c-a)x(d-a))/6. */
static inline double tu_tet_volume(const pl_mesh *m, int t)
{
    const int *e = m->tets + 4 * t;
    const double *a = m->verts + 3 * e[0];
    double u[3][3];
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) u[k][c] = m->verts[3 * e[k + 1] + c] - a[c];
    return (u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
            u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
            u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0])) / 6;
}

static inline double tu_total_volume(const pl_mesh *m, double *min_vol)
{
    double sum = 0, lo = INFINITY;
    for (int t = 0; t < m->ntets; ++t) {
        double v = tu_tet_volume(m, t);
        sum += v;
        lo = fmin(lo, v);
    }
    if (min_vol) *min_vol = lo;
    return sum;
}

/* Volume enclosed by a closed, outward triangle surface (divergence theorem). */
static inline double tu_surface_volume(const double *verts, const int *tris, int ntris)
{
    double vol = 0;
    for (int f = 0; f < ntris; ++f) {
        const double *a = verts + 3 * tris[3 * f], *b = verts + 3 * tris[3 * f + 1];
        const double *c = verts + 3 * tris[3 * f + 2];
        vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
    return vol;
}

static inline double tu_surface_area(const double *verts, const int *tris, int ntris)
{
    double area = 0;
    for (int f = 0; f < ntris; ++f) {
        const double *a = verts + 3 * tris[3 * f], *b = verts + 3 * tris[3 * f + 1];
        const double *c = verts + 3 * tris[3 * f + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
        area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return area;
}

/* Every directed edge (a,b) of a closed, consistently oriented surface
 * appears once, and (b,a) once: returns the number of violations. */
static int tu_cmp_edge(const void *x, const void *y)
{
    const long long *a = x, *b = y;
    return (*a > *b) - (*a < *b);
}

static inline int tu_open_edges(const int *tris, int ntris)
{
    long long *e = malloc(3 * (size_t)ntris * sizeof *e + 1);
    ck_assert_ptr_nonnull(e);
    for (int f = 0; f < ntris; ++f)
        for (int k = 0; k < 3; ++k)
            e[3 * f + k] = (long long)tris[3 * f + k] << 32 | (unsigned)tris[3 * f + (k + 1) % 3];
    qsort(e, 3 * (size_t)ntris, sizeof *e, tu_cmp_edge);
    int bad = 0;
    for (size_t i = 0; i < 3 * (size_t)ntris; ++i) {
        long long a = e[i] >> 32, b = e[i] & 0xffffffff, rev = b << 32 | a;
        if (i + 1 < 3 * (size_t)ntris && e[i + 1] == e[i]) bad++; /* duplicated direction */
        if (!bsearch(&rev, e, 3 * (size_t)ntris, sizeof *e, tu_cmp_edge)) bad++;
    }
    free(e);
    return bad;
}

/* Weaker than tu_open_edges for surfaces that touch themselves along an
 * edge (non-manifold, like the raptor's): every directed edge (a,b) must be
 * used as often as (b,a).  Returns the number of unbalanced edges. */
static inline int tu_unbalanced_edges(const int *tris, int ntris)
{
    size_t n = 3 * (size_t)ntris;
    long long *e = malloc(n * sizeof *e + 1);
    ck_assert_ptr_nonnull(e);
    for (int f = 0; f < ntris; ++f)
        for (int k = 0; k < 3; ++k)
            e[3 * f + k] = (long long)tris[3 * f + k] << 32 | (unsigned)tris[3 * f + (k + 1) % 3];
    qsort(e, n, sizeof *e, tu_cmp_edge);
    int bad = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && e[j] == e[i]) j++;
        long long a = e[i] >> 32, b = e[i] & 0xffffffff, rev = b << 32 | a;
        long long *r = bsearch(&rev, e, n, sizeof *e, tu_cmp_edge);
        size_t lo = r ? (size_t)(r - e) : 0, hi = lo;
        while (r && lo > 0 && e[lo - 1] == rev) lo--;
        while (r && hi < n && e[hi] == rev) hi++;
        bad += (hi - lo) != (j - i);
        i = j;
    }
    free(e);
    return bad;
}

/* The first diagnostic item with the given code (PL_OK: a warning) whose
 * message contains `needle` (NULL: any), or NULL. */
static inline const pl_error *tu_find(const pl_diag *d, int code, const char *needle)
{
    for (int i = 0; i < d->count; ++i)
        if ((code == PL_OK) == (d->items[i].code == PL_OK) &&
            (!needle || strstr(d->items[i].msg, needle)))
            return &d->items[i];
    return NULL;
}

/* A private temp folder per process (Check forks one per test). */
static char tu_dir[1024];

static inline const char *tu_path(const char *name)
{
    static char path[1300];
    if (!tu_dir[0]) {
        const char *d = test_tmp_dir();
        ck_assert_ptr_nonnull(d);
        snprintf(tu_dir, sizeof tu_dir, "%s", d);
    }
    snprintf(path, sizeof path, "%s/%s", tu_dir, name);
    return path;
}

/* Writes n bytes to a temp file and returns its path (valid until the next call). */
static inline const char *tu_write(const char *name, const void *data, size_t n)
{
    const char *p = tu_path(name);
    FILE *f = fopen(p, "wb");
    ck_assert_ptr_nonnull(f);
    ck_assert_uint_eq(fwrite(data, 1, n, f), n);
    fclose(f);
    return p;
}

static inline const char *tu_write_str(const char *name, const char *text)
{
    return tu_write(name, text, strlen(text));
}

/* Reads a whole file (NUL-terminated). */
static inline char *tu_slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)len + 1);
    ck_assert_ptr_nonnull(b);
    ck_assert_uint_eq(fread(b, 1, (size_t)len, f), (size_t)len);
    fclose(f);
    b[len] = '\0';
    if (n) *n = (size_t)len;
    return b;
}

/* Removes the temp folder and what is in it. */
static inline void tu_cleanup(void)
{
    if (!tu_dir[0]) return;
    test_tmp_dir_remove();
    tu_dir[0] = '\0';
}

#endif
