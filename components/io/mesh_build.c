/* mesh_build.c - growing a pl_mesh element by element, and the one warning
 * that lists the cell kinds a loader skipped. */
#include "mesh_io.h"

#include "pliant/checked.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

void pl_io_build_init(pl_mesh_build *b, pl_mesh *m)
{
    b->m = m;
    b->cap_verts = m->nverts;
    b->cap_tets = m->ntets;
    b->cap_tris = m->ntris;
}

/* Makes room for `need` items of `width` ints/doubles; doubles capacity. */
static int grow(void **arr, int *cap, long long need, size_t item)
{
    if (need <= *cap) return PL_OK;
    if (need > INT_MAX / 4) return PL_EINTERNAL;
    long long c = *cap ? *cap : 64;
    while (c < need) c *= 2;
    if (c > INT_MAX / 4) c = INT_MAX / 4;
    size_t bytes;
    void *p = pl_array_bytes((uint64_t)c, item, 0, &bytes) ? NULL : realloc(*arr, bytes);
    if (!p) return PL_EINTERNAL;
    *arr = p;
    *cap = (int)c;
    return PL_OK;
}

int pl_io_reserve(pl_mesh_build *b, long long nverts, long long ntets, long long ntris)
{
    pl_mesh *m = b->m;
    if (grow((void **)&m->verts, &b->cap_verts, m->nverts + nverts, 3 * sizeof(double)))
        return PL_EINTERNAL;
    if (grow((void **)&m->tets, &b->cap_tets, m->ntets + ntets, 4 * sizeof(int)))
        return PL_EINTERNAL;
    if (grow((void **)&m->tris, &b->cap_tris, m->ntris + ntris, 3 * sizeof(int)))
        return PL_EINTERNAL;
    return PL_OK;
}

int pl_io_add_vert(pl_mesh_build *b, double x, double y, double z)
{
    pl_mesh *m = b->m;
    if (grow((void **)&m->verts, &b->cap_verts, m->nverts + 1LL, 3 * sizeof(double)))
        return PL_EINTERNAL;
    double *v = m->verts + 3 * (size_t)m->nverts++;
    v[0] = x;
    v[1] = y;
    v[2] = z;
    return PL_OK;
}

int pl_io_add_tet(pl_mesh_build *b, int a, int c, int d, int e)
{
    pl_mesh *m = b->m;
    if (grow((void **)&m->tets, &b->cap_tets, m->ntets + 1LL, 4 * sizeof(int)))
        return PL_EINTERNAL;
    int *t = m->tets + 4 * (size_t)m->ntets++;
    t[0] = a;
    t[1] = c;
    t[2] = d;
    t[3] = e;
    return PL_OK;
}

int pl_io_add_tri(pl_mesh_build *b, int a, int c, int d)
{
    pl_mesh *m = b->m;
    if (grow((void **)&m->tris, &b->cap_tris, m->ntris + 1LL, 3 * sizeof(int)))
        return PL_EINTERNAL;
    int *t = m->tris + 3 * (size_t)m->ntris++;
    t[0] = a;
    t[1] = c;
    t[2] = d;
    return PL_OK;
}

void pl_io_skip_cell(pl_io_skipped *s, long long kind)
{
    if (kind >= 0 && kind < PL_IO_MAX_KINDS) s->count[kind]++;
    else s->other++;
}

void pl_io_report_skipped(pl_text *t, const pl_io_skipped *s, const char *family,
                          const char *(*name)(int kind), const pl_mesh *kept)
{
    char msg[768];
    size_t n = 0;
    long long total = s->other;
    for (int k = 0; k < PL_IO_MAX_KINDS; ++k) total += s->count[k];
    if (total == 0) return;
    for (int k = 0; k < PL_IO_MAX_KINDS && n < sizeof msg - 96; ++k) {
        if (!s->count[k]) continue;
        n += (size_t)snprintf(msg + n, sizeof msg - n, "%s%lld %s (%s type %d)", n ? ", " : "",
                              s->count[k], name(k), family, k);
    }
    if (s->other && n < sizeof msg - 96)
        n += (size_t)snprintf(msg + n, sizeof msg - n, "%s%lld of unknown %s types",
                              n ? ", " : "", s->other, family);
    pl_diag_warn(t->diag, t->path, 0, NULL,
                 "skipped %lld cells that are neither tetrahedra nor triangles: %s; "
                 "kept %d tetrahedra and %d triangles",
                 total, msg, kept->ntets, kept->ntris);
}

const char *pl_io_vtk_cell_name(int type)
{
    switch (type) {
    case 1: return "vertex";
    case 2: return "poly-vertex";
    case 3: return "line";
    case 4: return "poly-line";
    case 5: return "triangle";
    case 6: return "triangle-strip";
    case 7: return "polygon";
    case 8: return "pixel";
    case 9: return "quad";
    case 10: return "tetra";
    case 11: return "voxel";
    case 12: return "hexahedron";
    case 13: return "wedge";
    case 14: return "pyramid";
    case 21: return "quadratic-edge";
    case 22: return "quadratic-triangle";
    case 23: return "quadratic-quad";
    case 24: return "quadratic-tetra";
    case 25: return "quadratic-hexahedron";
    default: return "cell";
    }
}
