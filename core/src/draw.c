/* draw.c - the drawing that visual components fill (draw.h). */
#include "pliant/draw.h"
#include "pliant/node.h"
#include "pliant/roles.h"

#include <stdlib.h>
#include <string.h>

void pl_drawing_init(pl_drawing *dw)
{
    memset(dw, 0, sizeof *dw);
}

void pl_drawing_free(pl_drawing *dw)
{
    for (int k = 0; k < dw->cap_parts; ++k) {
        free(dw->parts[k].x);
        free(dw->parts[k].vec);
        free(dw->parts[k].tris);
        free(dw->parts[k].lines);
    }
    free(dw->parts);
    pl_drawing_init(dw);
}

void pl_drawing_clear(pl_drawing *dw)
{
    for (int k = 0; k < dw->nparts; ++k) {
        pl_draw_part *p = &dw->parts[k];
        p->nverts = p->ntris = p->nlines = 0;
    }
    dw->nparts = 0;
}

pl_draw_part *pl_drawing_add(pl_drawing *dw, const pl_component *c, pl_draw_kind kind)
{
    if (dw->nparts == dw->cap_parts) {
        int cap = dw->cap_parts ? 2 * dw->cap_parts : 8;
        pl_draw_part *parts = realloc(dw->parts, (size_t)cap * sizeof *parts);
        if (!parts) return NULL;
        memset(parts + dw->cap_parts, 0, (size_t)(cap - dw->cap_parts) * sizeof *parts);
        dw->parts = parts;
        dw->cap_parts = cap;
    }
    pl_draw_part *p = &dw->parts[dw->nparts++];
    p->owner = c;
    p->kind = kind;
    p->unbounded = 0;
    p->nverts = p->ntris = p->nlines = 0;
    return p;
}

/* Makes room for `more` items of `width` values each in *a (capacity *cap). */
static int grow(void **a, int *cap, int count, int more, size_t item)
{
    if (more < 0 || count > (1 << 30) - more) return -1;
    if (count + more <= *cap) return 0;
    int c = *cap ? *cap : 16;
    while (c < count + more) c = c > (1 << 29) ? (1 << 30) : 2 * c;
    void *p = realloc(*a, (size_t)c * item);
    if (!p) return -1;
    *a = p;
    *cap = c;
    return 0;
}

int pl_draw_vertices(pl_draw_part *p, const double *x, const double *vec, int n)
{
    int cap = p->cap_verts;
    if (grow((void **)&p->x, &cap, p->nverts, n, 3 * sizeof(double))) return -1;
    int cap2 = p->cap_verts;
    if (grow((void **)&p->vec, &cap2, p->nverts, n, 3 * sizeof(double))) return -1;
    p->cap_verts = cap < cap2 ? cap : cap2;
    int first = p->nverts;
    memcpy(p->x + 3 * (size_t)first, x, (size_t)n * 3 * sizeof(double));
    if (vec)
        memcpy(p->vec + 3 * (size_t)first, vec, (size_t)n * 3 * sizeof(double));
    else
        memset(p->vec + 3 * (size_t)first, 0, (size_t)n * 3 * sizeof(double));
    p->nverts += n;
    return first;
}

static int append_cells(const pl_draw_part *p, int **cells, int *count, int *cap, const int *src,
                        int n, int width, int base)
{
    for (int k = 0; k < n * width; ++k)
        if (src[k] < 0 || base + src[k] >= p->nverts) return PL_EINPUT;
    if (grow((void **)cells, cap, *count, n, (size_t)width * sizeof(int))) return PL_EINTERNAL;
    int *dst = *cells + (size_t)*count * width;
    for (int k = 0; k < n * width; ++k) dst[k] = base + src[k];
    *count += n;
    return PL_OK;
}

int pl_draw_triangles(pl_draw_part *p, const int *tris, int n, int base)
{
    return append_cells(p, &p->tris, &p->ntris, &p->cap_tris, tris, n, 3, base);
}

int pl_draw_lines(pl_draw_part *p, const int *lines, int n, int base)
{
    return append_cells(p, &p->lines, &p->nlines, &p->cap_lines, lines, n, 2, base);
}

int pl_draw_polyline(pl_draw_part *p, const double *x, int n)
{
    if (n < 1) return PL_OK;
    int first = pl_draw_vertices(p, x, NULL, n);
    if (first < 0) return PL_EINTERNAL;
    for (int k = 0; k + 1 < n; ++k) {
        int seg[2] = {k, k + 1};
        int rc = pl_draw_lines(p, seg, 1, first);
        if (rc) return rc;
    }
    return PL_OK;
}

typedef struct collect_walk {
    const pl_data *d;
    pl_drawing *dw;
    pl_error *err;
    int rc;
} collect_walk;

static int draw_one(pl_component *c, void *user)
{
    collect_walk *w = user;
    const pl_visual_ops *ops = pl_component_role(c, PL_ROLE_VISUAL);
    if (!ops || ops->version < 1 || !ops->draw) return 0;
    w->rc = ops->draw(c, w->d, w->dw, w->err);
    return w->rc;
}

int pl_drawing_collect(pl_node *root, const pl_data *d, pl_drawing *dw, pl_error *err)
{
    collect_walk w = {d, dw, err, PL_OK};
    pl_node_visit_role(root, PL_ROLE_VISUAL, draw_one, &w);
    return w.rc;
}
