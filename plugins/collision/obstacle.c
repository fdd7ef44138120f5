/* obstacle.c - the constraint role shared by the analytic obstacles.  Once
 * per step (LocalGlobalSolver, Algorithm 4) every body point of every
 * collision model of the scene is tested against the obstacle posed at the
 * END of the step (t + h: the unknowns q are positions at t + h): a point
 * within alarmDistance at the start of the step, or whose predicted path
 * over the step (x + h v + h^2 g, relative to the obstacle's own motion)
 * comes within it, gets a contact: one normal and two friction rows (see
 * collision.h for the conventions), along the normal at the first point of
 * that path at contactDistance, so that fast bodies are stopped at the
 * surface instead of tunnelling.  Contacts are recorded in the pl_data slot
 * "contacts" and receive their forces after the step. */
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "obstacle.h"

/* The shape at the scene pose and the motion, from the fields as they are
 * now (all are RUNTIME fields, so this is re-checked at every step). */
static int prepare(const coll_obstacle *o, pl_shape *s, pl_motion *m, pl_error *err)
{
    if (o->make_shape(o, s, err) != PL_OK) return PL_EINPUT;
    if (!isfinite(o->mu) || o->mu < 0.0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "mu must be >= 0, got %g", o->mu);
    if (!isfinite(o->alarm_distance) || o->alarm_distance < 0.0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "alarmDistance must be a finite value >= 0 [m], got %g",
                            o->alarm_distance);
    if (!isfinite(o->contact_distance) || o->contact_distance < 0.0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "contactDistance must be a finite value >= 0 [m], got %g",
                            o->contact_distance);
    if (o->contact_distance > o->alarm_distance)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "contactDistance (%g m) exceeds alarmDistance (%g m): a point is "
                            "only detected within alarmDistance, so the kept gap must not be "
                            "larger",
                            o->contact_distance, o->alarm_distance);
    if (o->rotation_center.n != 0 && o->rotation_center.n != 3)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "rotationCenter: expected 3 values (x y z), found %d",
                            o->rotation_center.n);
    memset(m, 0, sizeof *m);
    memcpy(m->velocity, o->velocity, sizeof m->velocity);
    memcpy(m->axis, o->rotation_axis, sizeof m->axis);
    m->angular_velocity = o->angular_velocity;
    memcpy(m->center, o->rotation_center.n == 3 ? o->rotation_center.v : s->center,
           sizeof m->center);
    m->times = o->times.v;
    m->ntimes = o->times.n;
    m->translations = o->translations.v;
    return motion_prepare(m, o->translations.n, err);
}

int coll_obstacle_pose(const coll_obstacle *o, double t, pl_shape *s, pl_error *err)
{
    pl_shape s0;
    pl_motion m;
    if (prepare(o, &s0, &m, err) != PL_OK) return PL_EINPUT;
    double R[9], tr[3];
    motion_pose(&m, t, R, tr);
    shape_transform(&s0, R, tr, s);
    return PL_OK;
}

typedef struct model_list {
    pl_component **items;
    int n;
} model_list;

static int collect_model(pl_component *c, void *user)
{
    model_list *l = user;
    pl_component **items = realloc(l->items, (size_t)(l->n + 1) * sizeof *items);
    if (!items) return 1;
    l->items = items;
    l->items[l->n++] = c;
    return 0;
}

/* Every collision model of the whole scene, in scene order. */
static int find_models(coll_obstacle *o, pl_ctx *ctx)
{
    pl_node *root = o->base.node;
    while (root->parent) root = root->parent;
    free(o->models);
    o->models = NULL;
    o->nmodels = 0;
    model_list l = {NULL, 0};
    if (pl_node_visit_role(root, PL_ROLE_COLLISION_MODEL, collect_model, &l)) {
        free(l.items);
        return pl_component_error(&o->base, ctx, PL_EINTERNAL, "out of memory");
    }
    o->models = l.items;
    o->nmodels = l.n;
    if (o->nmodels == 0)
        pl_component_warn(&o->base, ctx,
                          "the scene has no collision model (e.g. <SurfaceCollisionModel/> next "
                          "to a body's MechanicalObject): nothing can touch this obstacle");
    return PL_OK;
}

/* Restored contacts (a saved state is input): models in range, finite values. */
_Static_assert(offsetof(pl_obstacle_contact, point) == 0, "the doubles come first");
static int check_restored(const pl_component *c, const void *data, size_t bytes, pl_error *err)
{
    const coll_obstacle *o = (const coll_obstacle *)c;
    const pl_obstacle_contact *r = data;
    for (size_t k = 0; k < bytes / sizeof *r; ++k) {
        if (r[k].model < 0 || r[k].model >= o->nmodels || r[k].vertex < 0)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "contact %zu names model %d, "
                                "vertex %d: expected a model in 0..%d", k, r[k].model,
                                r[k].vertex, o->nmodels - 1);
        const double *v = (const double *)(const void *)&r[k]; /* point .. force */
        for (size_t i = 0; i < offsetof(pl_obstacle_contact, vertex) / sizeof(double); ++i)
            if (!isfinite(v[i]))
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "contact %zu holds a "
                                    "non-finite value", k);
    }
    return PL_OK;
}

int coll_obstacle_init(pl_component *c, pl_ctx *ctx, coll_shape_fn make_shape)
{
    coll_obstacle *o = (coll_obstacle *)c;
    o->make_shape = make_shape;
    o->slot = pl_model_add_var_slot(ctx->build, c, "contacts", sizeof(pl_obstacle_contact),
                                    INT_MAX);
    if (o->slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->build, o->slot, check_restored);
    pl_shape s;
    pl_motion m;
    pl_error err;
    if (prepare(o, &s, &m, &err) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    return PL_OK;
}

int coll_obstacle_bind(pl_component *c, pl_ctx *ctx)
{
    return find_models((coll_obstacle *)c, ctx);
}

int coll_obstacle_reinit(pl_component *c, pl_ctx *ctx)
{
    coll_obstacle *o = (coll_obstacle *)c;
    pl_shape s;
    pl_motion m;
    pl_error err;
    if (prepare(o, &s, &m, &err) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    return PL_OK;
}

void coll_obstacle_destroy(pl_component *c)
{
    coll_obstacle *o = (coll_obstacle *)c;
    free(o->models);
    o->models = NULL;
}

void coll_obstacle_workspace_free(const pl_component *c, void *ws)
{
    (void)c;
    coll_obstacle_ws *w = ws;
    free(w->work);
    free(w->geo);
    free(w->reach);
}

/* The workspace's per-model arrays, sized for the scene's models. */
static int fit_models(const coll_obstacle *o, coll_obstacle_ws *ws)
{
    if (ws->geo && ws->nmodels == o->nmodels) return PL_OK;
    free(ws->geo);
    free(ws->reach);
    size_t n = (size_t)(o->nmodels ? o->nmodels : 1);
    ws->geo = calloc(n, sizeof *ws->geo);
    ws->reach = calloc(n, sizeof *ws->reach);
    ws->nmodels = o->nmodels;
    return ws->geo && ws->reach ? PL_OK : PL_EINTERNAL;
}

static pl_obstacle_contact *push_record(coll_obstacle_ws *o)
{
    if (o->nwork == o->capwork) {
        int cap = o->capwork ? 2 * o->capwork : 64;
        pl_obstacle_contact *w = realloc(o->work, (size_t)cap * sizeof *w);
        if (!w) return NULL;
        o->work = w;
        o->capwork = cap;
    }
    pl_obstacle_contact *r = &o->work[o->nwork++];
    memset(r, 0, sizeof *r);
    return r;
}

/* The mapped vertices of point i (those >= 0), checked against the system;
 * returns their count, 0 when none of them is free (a contact there could
 * not move anything), or -1 on an index out of range. */
static int point_vertices(const pl_collision_geometry *g, int i, const pl_system *sys,
                          int vert[4], double w[4])
{
    int nv = 0, nfree = 0;
    for (int a = 0; a < 4; ++a) {
        int v = g->map_vertex[4 * i + a];
        if (v < 0) continue;
        if (v >= sys->nverts) return -1;
        vert[nv] = v;
        w[nv++] = g->map_weight[4 * i + a];
        if (!sys->free_index || sys->free_index[v] >= 0) nfree++;
    }
    return nfree ? nv : 0;
}

/* The shape posed at both ends of the step, the motion between them, and
 * what a body point's predicted motion needs. */
typedef struct posed {
    pl_shape s;            /* at t + h (the unknowns are positions at t + h) */
    double R[9], tr[3];    /* the obstacle's own motion from t to t + h */
    double t1, h, g[3];    /* end time [s], step [s], the model's gravity [m/s^2] */
    double margin;         /* how far the model may move beyond its prediction [m] */
} posed;

/* Where point i of g will be in contact, if anywhere: its position at the
 * start of the step when within alarmDistance there (as always), else the
 * first point of its predicted path over the step (x + h v + h^2 g,
 * relative to the moving obstacle) that comes within contactDistance, or
 * within alarmDistance (plus the margin of a body struck by another) when
 * it comes no closer: a fast point is caught before it crosses
 * (look-ahead).  Fills p, n; returns the signed distance at the start of
 * the step along n, or NAN when the point stays clear. */
static double find_contact(const coll_obstacle *o, const posed *ps,
                           const pl_collision_geometry *g, int i, double p[3], double n[3])
{
    const double *x = &g->x[3 * i];
    double phi = shape_query(&ps->s, x, p, n);
    if (phi < o->alarm_distance) return phi;
    double y0[3], y1[3], t;
    for (int k = 0; k < 3; ++k) {
        const double *r = &ps->R[3 * k];
        double v = g->v ? g->v[3 * i + k] : 0.0;
        y0[k] = r[0] * x[0] + r[1] * x[1] + r[2] * x[2] + ps->tr[k]; /* rides with the shape */
        y1[k] = x[k] + ps->h * v + ps->h * ps->h * ps->g[k];
    }
    if (!shape_sweep(&ps->s, y0, y1, o->alarm_distance + ps->margin, o->contact_distance, &t,
                        p, n))
        return NAN;
    return n[0] * (x[0] - p[0]) + n[1] * (x[1] - p[1]) + n[2] * (x[2] - p[2]);
}

/* Whether none of a model's points can come within d of the posed shape in
 * this step, so that its points need no test (a floor far below a cloth:
 * ten thousand shape_query and shape_sweep calls a step for nothing).
 * Every point's position and predicted path lie in its reach box (reach_of:
 * x and x + h v + h^2 g), and the shape stays farther than d from that box:
 * a plane by its exact distance to the box's nearest corner, the other
 * shapes by the distance of the box's centre less its half-diagonal (phi
 * is a distance).  Only for a shape at rest over the step, where a point's
 * path relative to it is its own; d gets a relative 1e-9 of slack so that
 * rounding never culls a point find_contact would keep. */
static int model_clear(const posed *ps, const pl_aabb *box, double d)
{
    static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int k = 0; k < 9; ++k)
        if (ps->R[k] != I[k]) return 0;
    if (ps->tr[0] != 0.0 || ps->tr[1] != 0.0 || ps->tr[2] != 0.0) return 0;
    double c[3], half[3];
    for (int k = 0; k < 3; ++k) {
        if (!isfinite(box->lo[k]) || !isfinite(box->hi[k])) return 0;
        c[k] = 0.5 * (box->lo[k] + box->hi[k]);
        half[k] = 0.5 * (box->hi[k] - box->lo[k]);
    }
    double phi = shape_query(&ps->s, c, NULL, NULL), reach = 0.0;
    if (ps->s.kind == PL_SHAPE_PLANE) /* the normal is the local z axis: R's third column */
        reach = fabs(ps->s.R[2]) * half[0] + fabs(ps->s.R[5]) * half[1] + fabs(ps->s.R[8]) * half[2];
    else
        reach = sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]);
    return phi - reach > d * (1.0 + 1e-9) + 1e-12;
}

/* Contacts of one collision model's points against the posed shape. */
static int model_contacts(const coll_obstacle *o, coll_obstacle_ws *ws, int k,
                          const pl_collision_geometry *g, const posed *ps, const pl_motion *m,
                          const pl_system *sys, pl_rows *rows, pl_error *err)
{
    double mu = g->mu >= 0.0 ? g->mu : o->mu;
    for (int i = 0; i < g->nverts; ++i) {
        const double *x = &g->x[3 * i];
        double p[3], n[3];
        double phi = find_contact(o, ps, g, i, p, n);
        if (isnan(phi)) continue;
        int vert[4];
        double w[4];
        int nv = point_vertices(g, i, sys, vert, w);
        if (nv < 0)
            return pl_component_fail(&o->base, err, PL_EINTERNAL,
                                     "collision model '%s' maps point %d to a vertex outside "
                                     "the system (%d vertices)",
                                     o->models[k]->name, i, sys->nverts);
        if (nv == 0) continue;
        pl_obstacle_contact *r = push_record(ws);
        if (!r) return pl_component_fail(&o->base, err, PL_EINTERNAL, "out of memory");
        memcpy(r->point, p, sizeof r->point);
        memcpy(r->normal, n, sizeof r->normal);
        memcpy(r->body_point, x, sizeof r->body_point);
        motion_velocity(m, ps->t1, p, r->velocity);
        r->gap = phi;
        r->vertex = vert[0];
        r->model = k;
        if (collision_emit_contact(rows, &o->base, nv, vert, w, p, n, r->velocity, mu,
                                      o->contact_distance, r->t1, r->t2) < 0)
            return pl_component_fail(&o->base, err, PL_EINTERNAL, "out of memory");
    }
    return PL_OK;
}

static int ob_build_rows(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                         const pl_buffer *q, pl_rows *rows, pl_error *err)
{
    const coll_obstacle *o = (const coll_obstacle *)c;
    coll_obstacle_ws *ws = pl_data_workspace(ctx->data, c);
    if (!ws || fit_models(o, ws))
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    pl_shape s0;
    pl_motion m;
    pl_error e;
    if (prepare(o, &s0, &m, &e) != PL_OK) return pl_component_fail(c, err, PL_EINPUT, "%s", e.msg);
    if (!pl_buffer_f64(q))
        return pl_component_fail(c, err, PL_EINTERNAL, "positions must be host float64");
    /* posed at the end of the step: q is solved for t + h */
    posed ps;
    double R[9], tr[3];
    ps.h = sys->h;
    ps.t1 = ctx->data->time + sys->h;
    motion_pose(&m, ps.t1, R, tr);
    shape_transform(&s0, R, tr, &ps.s);
    motion_step_map(&m, ctx->data->time, ps.t1, ps.R, ps.tr);
    unsigned groups;
    if (collision_groups(&o->group, &groups, &e) != PL_OK)
        return pl_component_fail(c, err, PL_EINPUT, "%s", e.msg);
    ws->nwork = 0;
    /* every model first: a body struck by another in this step may move
     * beyond its prediction (impact.c) */
    for (int k = 0; k < o->nmodels; ++k) {
        pl_component *mc = o->models[k];
        const pl_collision_model_ops *ops = pl_component_role(mc, PL_ROLE_COLLISION_MODEL);
        pl_collision_geometry *g = &ws->geo[k];
        memset(g, 0, sizeof *g);
        int rc = ops->update(mc, ctx, q, g, err);
        if (rc) return rc;
        double grav[3] = {0.0, 0.0, 0.0};
        if (!g->is_obstacle) pl_node_gravity(mc->node, grav);
        reach_of(g->x, g->v, g->nverts, g->is_obstacle, g->groups, sys->h, grav, &ws->reach[k]);
    }
    for (int k = 0; k < o->nmodels; ++k) {
        const pl_collision_geometry *g = &ws->geo[k];
        /* geometry without DOFs cannot respond; groups opt out */
        if (g->is_obstacle || (groups & g->groups)) continue;
        pl_node_gravity(o->models[k]->node, ps.g);
        ps.margin = sys->h * hit_speed(ws->reach, o->nmodels, k, -1, o->alarm_distance);
        if (model_clear(&ps, &ws->reach[k].box, o->alarm_distance + ps.margin)) continue;
        int rc = model_contacts(o, ws, k, g, &ps, &m, sys, rows, err);
        if (rc) return rc;
    }
    if (pl_data_store(ctx->data, o->slot, ws->work, (size_t)ws->nwork * sizeof *ws->work))
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    return PL_OK;
}

int coll_obstacle_contacts(const pl_component *c, const pl_data *d,
                           const pl_obstacle_contact **items)
{
    const coll_obstacle *o = (const coll_obstacle *)c;
    *items = pl_data_slot(d, o->slot);
    return (int)(pl_data_slot_bytes(d, o->slot) / sizeof(pl_obstacle_contact));
}

static void ob_accept_multipliers(const pl_component *c, pl_data *d, const pl_rows *rows,
                                  const double *lambda, int first, int count)
{
    const coll_obstacle *o = (const coll_obstacle *)c;
    pl_obstacle_contact *items = pl_data_slot(d, o->slot);
    int n = (int)(pl_data_slot_bytes(d, o->slot) / sizeof *items);
    /* our rows are 3 per contact in emission order, starting at first */
    if (count != 3 * n || (n && rows->kind[first] != PL_ROW_NORMAL)) return;
    collision_contact_forces(items, n, lambda + first);
}

const pl_constraint_ops coll_obstacle_constraint_ops = {
    .version = PL_CONSTRAINT_OPS_VERSION,
    .build_rows = ob_build_rows,
    .accept_multipliers = ob_accept_multipliers,
};

/* "contactPoints" etc.: one vector of each record, x y z each. */
static int format_vectors(const pl_obstacle_contact *items, int n, size_t member, char *buf,
                          size_t size)
{
    size_t w = 0;
    buf[0] = '\0';
    for (int k = 0; k < n; ++k) {
        const double *v = (const double *)((const char *)&items[k] + member);
        for (int i = 0; i < 3; ++i) {
            int len = snprintf(buf + w, size - w, w ? " %.17g" : "%.17g", v[i]);
            if (len < 0 || (size_t)len >= size - w) return PL_EINTERNAL;
            w += (size_t)len;
        }
    }
    return PL_OK;
}

int coll_obstacle_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                      size_t size)
{
    const pl_obstacle_contact *items;
    int n = coll_obstacle_contacts(c, d, &items);
    if (!strcmp(field, "contactCount")) {
        int len = snprintf(buf, size, "%d", n);
        return (len < 0 || (size_t)len >= size) ? PL_EINTERNAL : PL_OK;
    }
    if (!strcmp(field, "contactPoints"))
        return format_vectors(items, n, offsetof(pl_obstacle_contact, point), buf, size);
    if (!strcmp(field, "contactNormals"))
        return format_vectors(items, n, offsetof(pl_obstacle_contact, normal), buf, size);
    if (!strcmp(field, "contactForces"))
        return format_vectors(items, n, offsetof(pl_obstacle_contact, force), buf, size);
    return PL_EINPUT;
}
