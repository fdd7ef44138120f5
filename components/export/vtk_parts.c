/* vtk_parts.c - obstacles, cables and contacts in VTKExporter's series
 * (vtk_parts.h). */
#include "export/vtk_parts.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export/export_internal.h"

typedef struct owner_walk {
    pl_vtk_parts *p;
    const pl_component *e;
    int failed;
} owner_walk;

/* Whether node n holds an exporter of e's type (other than e). */
static int has_own_exporter(const pl_node *n, const pl_component *e)
{
    for (int k = 0; k < n->ncomponents; ++k) {
        const pl_component *c = n->components[k];
        if (c != e && c->type->roles[PL_ROLE_EXPORTER] == e->type->roles[PL_ROLE_EXPORTER])
            return 1;
    }
    return 0;
}

static void collect(owner_walk *w, const pl_node *n)
{
    if (n != w->e->node && has_own_exporter(n, w->e)) return;
    for (int k = 0; k < n->ncomponents && !w->failed; ++k) {
        pl_component *c = n->components[k];
        if (!pl_component_role(c, PL_ROLE_VISUAL)) continue;
        pl_component **o = realloc(w->p->owners, (size_t)(w->p->nowners + 1) * sizeof *o);
        if (!o) {
            w->failed = 1;
            return;
        }
        w->p->owners = o;
        o[w->p->nowners++] = c;
    }
    for (int k = 0; k < n->nchildren; ++k) collect(w, n->children[k]);
}

int pl_vtk_parts_find(pl_vtk_parts *p, const pl_component *e)
{
    pl_vtk_parts_free(p);
    owner_walk w = {p, e, 0};
    collect(&w, e->node);
    return w.failed ? PL_EINTERNAL : PL_OK;
}

void pl_vtk_parts_free(pl_vtk_parts *p)
{
    free(p->owners);
    pl_drawing_free(&p->drawing);
    memset(p, 0, sizeof *p);
}

/* One part as a .vtu. */
static int write_part(const pl_draw_part *dp, const char *path, int binary, pl_error *err)
{
    pl_vtu_cells cells = {0, NULL, dp->ntris, dp->tris, dp->nlines, dp->lines};
    pl_vtu_array force = {"force", 3, dp->vec};
    int contacts = dp->kind == PL_DRAW_CONTACTS;
    return pl_vtu_write_cells(path, dp->nverts, dp->x, &cells, contacts ? &force : NULL,
                              contacts, binary, err);
}

int pl_vtk_parts_write(pl_vtk_parts *p, const char *prefix, int frame, const pl_data *d,
                       pl_pvd *pvd, int first_part, int binary, pl_error *err)
{
    pl_drawing_clear(&p->drawing);
    for (int k = 0; k < p->nowners; ++k) {
        const pl_visual_ops *ops = pl_component_role(p->owners[k], PL_ROLE_VISUAL);
        int rc = ops->version >= 1 && ops->draw ? ops->draw(p->owners[k], d, &p->drawing, err)
                                                : PL_OK;
        if (rc) return rc;
    }
    size_t len = strlen(prefix) + 600;
    char *path = malloc(len);
    if (!path) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    int rc = PL_OK;
    for (int k = 0; k < p->drawing.nparts && !rc; ++k) {
        const pl_draw_part *dp = &p->drawing.parts[k];
        snprintf(path, len, "%s_%.200s_%.200s%s_%04d.vtu", prefix, dp->owner->node->name,
                 dp->owner->name, dp->kind == PL_DRAW_CONTACTS ? "_contacts" : "", frame);
        rc = write_part(dp, path, binary, err);
        if (!rc)
            rc = pl_pvd_append_part(pvd, d->time, first_part + k, pl_export_basename(path), err);
    }
    free(path);
    return rc;
}
