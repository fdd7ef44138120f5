/* obstacle_draw.c - the visual role of the analytic obstacles: the shape
 * posed at the state's time (a plane as a finite patch under the bodies)
 * and the last step's contacts with the forces on the body.  Also the
 * helpers the other drawing components of the plugin share. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "obstacle.h"
#include "shape_draw.h"

typedef struct extent_walk {
    double lo[3], hi[3];
} extent_walk;

static int grow_box(pl_component *c, void *user)
{
    extent_walk *w = user;
    const pl_state_ops *so = pl_component_role(c, PL_ROLE_STATE);
    if (!so->rest_positions || !so->count) return 0;
    pl_buffer b = so->rest_positions(c);
    const double *x = pl_buffer_f64(&b);
    int n = so->count(c);
    for (int i = 0; x && i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            if (x[3 * i + k] < w->lo[k]) w->lo[k] = x[3 * i + k];
            if (x[3 * i + k] > w->hi[k]) w->hi[k] = x[3 * i + k];
        }
    return 0;
}

void coll_scene_extent(const pl_component *c, double center[3], double *extent)
{
    pl_node *root = c->node;
    while (root->parent) root = root->parent;
    extent_walk w = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    pl_node_visit_role(root, PL_ROLE_STATE, grow_box, &w);
    *extent = 0.0;
    for (int k = 0; k < 3; ++k) {
        int any = w.lo[k] <= w.hi[k];
        center[k] = any ? 0.5 * (w.lo[k] + w.hi[k]) : 0.0;
        if (any && w.hi[k] - w.lo[k] > *extent) *extent = w.hi[k] - w.lo[k];
    }
}

int coll_draw_contacts(const pl_component *c, pl_drawing *dw, const void *items, int n,
                       size_t stride, size_t point_at, size_t force_at)
{
    pl_draw_part *p = pl_drawing_add(dw, c, PL_DRAW_CONTACTS);
    if (!p) return PL_EINTERNAL;
    for (int k = 0; k < n; ++k) {
        const char *r = (const char *)items + (size_t)k * stride;
        if (pl_draw_vertices(p, (const double *)(r + point_at), (const double *)(r + force_at),
                             1) < 0)
            return PL_EINTERNAL;
    }
    return PL_OK;
}

static int ob_draw(const pl_component *c, const pl_data *d, pl_drawing *dw, pl_error *err)
{
    const coll_obstacle *o = (const coll_obstacle *)c;
    pl_shape s;
    pl_error e;
    if (coll_obstacle_pose(o, d->time, &s, &e) != PL_OK)
        return pl_component_fail(c, err, PL_EINPUT, "%s", e.msg);
    double center[3], extent;
    coll_scene_extent(c, center, &extent);
    double half = extent > 0.0 ? 1.5 * extent : 1.0;
    pl_draw_part *p = pl_drawing_add(dw, c, PL_DRAW_OBSTACLE);
    if (!p || coll_shape_draw(&s, center, half, p) != PL_OK)
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    p->unbounded = s.kind == PL_SHAPE_PLANE;
    const pl_obstacle_contact *items;
    int n = coll_obstacle_contacts(c, d, &items);
    if (coll_draw_contacts(c, dw, items, n, sizeof *items, offsetof(pl_obstacle_contact, point),
                           offsetof(pl_obstacle_contact, force)) != PL_OK)
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    return PL_OK;
}

const pl_visual_ops coll_obstacle_visual_ops = {.version = PL_VISUAL_OPS_VERSION,
                                                .draw = ob_draw};
