/* scene.c - reading what to draw from the simulation (scene.h). */
#include "scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vw_math.h"

static const char *const FIELD_NAMES[] = {"none", "displacement", "velocity", "force"};
static const char *const FIELD_UNITS[] = {"", "m", "m/s", "N"};

const char *vw_field_name(vw_field f)
{
    return f >= 0 && f < VW_FIELD_COUNT ? FIELD_NAMES[f] : "?";
}

const char *vw_field_unit(vw_field f)
{
    return f >= 0 && f < VW_FIELD_COUNT ? FIELD_UNITS[f] : "";
}

int vw_field_parse(const char *s)
{
    for (int k = 0; k < VW_FIELD_COUNT; ++k)
        if (!strcmp(s, FIELD_NAMES[k])) return k;
    return -1;
}

typedef struct body_list {
    vw_body *items;
    int n;
    int failed;
} body_list;

static int add_body(pl_component *c, void *user)
{
    body_list *l = user;
    vw_body *b = realloc(l->items, (size_t)(l->n + 1) * sizeof *b);
    if (!b) return l->failed = 1;
    l->items = b;
    memset(&b[l->n], 0, sizeof b[l->n]);
    b[l->n++].state = c;
    return 0;
}

/* The surface of body b: its topology's tetrahedra boundary or triangles,
 * when the topology describes the state's vertices. */
static int body_surface(vw_body *b, pl_error *err)
{
    pl_component *topo = pl_node_find_role(b->state->node, PL_ROLE_TOPOLOGY);
    const pl_topology_ops *to = topo ? pl_component_role(topo, PL_ROLE_TOPOLOGY) : NULL;
    const pl_mesh *m = to && to->mesh ? to->mesh(topo) : NULL;
    if (!m || m->nverts != b->n) return PL_OK; /* points only */
    if (m->ntets > 0) {
        int rc = pl_mesh_boundary_triangles(m, &b->tris, &b->ntris);
        if (rc) return pl_error_set(err, rc, NULL, 0, topo->name, "no boundary surface");
        return PL_OK;
    }
    if (m->ntris > 0) {
        b->tris = malloc((size_t)m->ntris * 3 * sizeof *b->tris);
        if (!b->tris) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        memcpy(b->tris, m->tris, (size_t)m->ntris * 3 * sizeof *b->tris);
        b->ntris = m->ntris;
    }
    return PL_OK;
}

int vw_scene_init(vw_scene *s, pl_sim *sim, pl_error *err)
{
    memset(s, 0, sizeof *s);
    s->sim = sim;
    pl_drawing_init(&s->drawing);
    body_list l = {NULL, 0, 0};
    pl_node_visit_role(pl_sim_model(sim)->root, PL_ROLE_STATE, add_body, &l);
    s->bodies = l.items;
    s->nbodies = l.n;
    if (l.failed) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    for (int k = 0; k < s->nbodies; ++k) {
        vw_body *b = &s->bodies[k];
        const pl_state_ops *so = pl_component_role(b->state, PL_ROLE_STATE);
        b->n = so->count ? so->count(b->state) : 0;
        b->x = calloc((size_t)(b->n ? b->n : 1) * 3, sizeof *b->x);
        b->value = calloc((size_t)(b->n ? b->n : 1), sizeof *b->value);
        if (!b->x || !b->value) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        int rc = body_surface(b, err);
        if (rc) return rc;
    }
    return PL_OK;
}

void vw_scene_free(vw_scene *s)
{
    for (int k = 0; k < s->nbodies; ++k) {
        free(s->bodies[k].tris);
        free(s->bodies[k].x);
        free(s->bodies[k].value);
    }
    free(s->bodies);
    pl_drawing_free(&s->drawing);
    memset(s, 0, sizeof *s);
}

void vw_scene_reset_scale(vw_scene *s)
{
    s->field_max = 0.0;
}

/* Copies an n x 3 state buffer to the host array out (float64). */
static int copy_block(pl_buffer b, int n, double *out)
{
    if (b.location != PL_HOST || b.rows < (size_t)n || b.cols != 3) return -1;
    for (size_t i = 0; i < (size_t)n * 3; ++i)
        out[i] = b.precision == PL_F64 ? ((const double *)b.data)[i]
               : b.precision == PL_F32 ? ((const float *)b.data)[i]
                                       : 0.0;
    return 0;
}

static int body_update(vw_scene *s, vw_body *b, vw_field field, pl_error *err)
{
    const pl_state_ops *so = pl_component_role(b->state, PL_ROLE_STATE);
    const pl_data *d = pl_sim_data(s->sim);
    if (b->n == 0) return PL_OK;
    if (copy_block(so->positions(b->state, d), b->n, b->x))
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, b->state->name,
                            "the state's positions are not readable on the host");
    pl_buffer f = {0};
    if (field == VW_FIELD_DISPLACEMENT && so->rest_positions) f = so->rest_positions(b->state);
    if (field == VW_FIELD_VELOCITY && so->velocities) f = so->velocities(b->state, d);
    if (field == VW_FIELD_FORCE && so->constraint_forces) f = so->constraint_forces(b->state, d);
    double v[3];
    for (int i = 0; i < b->n; ++i) {
        b->value[i] = 0.0;
        if (!f.data || f.location != PL_HOST || f.precision != PL_F64 || f.rows < (size_t)b->n)
            continue;
        const double *fi = (const double *)f.data + 3 * (size_t)i;
        if (field == VW_FIELD_DISPLACEMENT)
            vw_sub(&b->x[3 * (size_t)i], fi, v);
        else
            memcpy(v, fi, sizeof v);
        b->value[i] = vw_norm(v);
        if (isfinite(b->value[i]) && b->value[i] > s->field_max) s->field_max = b->value[i];
    }
    return PL_OK;
}

static void grow_bounds(vw_scene *s, const double *x, int n)
{
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double v = x[3 * (size_t)i + k];
            if (!isfinite(v)) continue;
            if (v < s->lo[k]) s->lo[k] = v;
            if (v > s->hi[k]) s->hi[k] = v;
        }
}

int vw_scene_update(vw_scene *s, vw_field field, pl_error *err)
{
    for (int k = 0; k < 3; ++k) s->lo[k] = INFINITY, s->hi[k] = -INFINITY;
    for (int k = 0; k < s->nbodies; ++k) {
        int rc = body_update(s, &s->bodies[k], field, err);
        if (rc) return rc;
        grow_bounds(s, s->bodies[k].x, s->bodies[k].n);
    }
    pl_drawing_clear(&s->drawing);
    int rc = pl_drawing_collect(pl_sim_model(s->sim)->root, pl_sim_data(s->sim), &s->drawing, err);
    if (rc) return rc;
    s->ncontacts = 0;
    for (int k = 0; k < s->drawing.nparts; ++k) {
        const pl_draw_part *p = &s->drawing.parts[k];
        if (p->kind == PL_DRAW_CONTACTS) s->ncontacts += p->nverts;
        if (p->kind != PL_DRAW_CONTACTS && !p->unbounded) grow_bounds(s, p->x, p->nverts);
    }
    for (int k = 0; k < 3; ++k)
        if (!(s->lo[k] <= s->hi[k])) s->lo[k] = -0.5, s->hi[k] = 0.5;
    return PL_OK;
}

/* Moller-Trumbore: distance along d to triangle (a, b, c), or -1. */
static double ray_triangle(const double o[3], const double d[3], const double *a, const double *b,
                           const double *c)
{
    double e1[3], e2[3], p[3], t[3], q[3];
    vw_sub(b, a, e1);
    vw_sub(c, a, e2);
    vw_cross(d, e2, p);
    double det = vw_dot(e1, p);
    if (fabs(det) < 1e-30) return -1.0;
    vw_sub(o, a, t);
    double u = vw_dot(t, p) / det;
    if (u < 0.0 || u > 1.0) return -1.0;
    vw_cross(t, e1, q);
    double v = vw_dot(d, q) / det;
    if (v < 0.0 || u + v > 1.0) return -1.0;
    double dist = vw_dot(e2, q) / det;
    return dist > 0.0 ? dist : -1.0;
}

int vw_scene_pick(const vw_scene *s, const double o[3], const double d[3], int *body, int *vertex,
                  double hit[3])
{
    double best = INFINITY;
    int found = 0;
    for (int k = 0; k < s->nbodies; ++k) {
        const vw_body *b = &s->bodies[k];
        for (int t = 0; t < b->ntris; ++t) {
            const int *tr = &b->tris[3 * t];
            double dist = ray_triangle(o, d, &b->x[3 * tr[0]], &b->x[3 * tr[1]], &b->x[3 * tr[2]]);
            if (dist < 0.0 || dist >= best) continue;
            best = dist;
            found = 1;
            *body = k;
            for (int i = 0; i < 3; ++i) hit[i] = o[i] + dist * d[i];
            double dmin = INFINITY;
            for (int j = 0; j < 3; ++j) {
                double e[3];
                vw_sub(&b->x[3 * tr[j]], hit, e);
                if (vw_norm(e) < dmin) dmin = vw_norm(e), *vertex = tr[j];
            }
        }
    }
    return found;
}

int vw_scene_global_vertex(const vw_scene *s, int b, int v)
{
    const pl_state_ops *so = pl_component_role(s->bodies[b].state, PL_ROLE_STATE);
    int off = so->offset ? so->offset(s->bodies[b].state) : -1;
    return off < 0 ? -1 : off + v;
}

void vw_scene_centroid(const vw_scene *s, int b, double c[3])
{
    const vw_body *body = &s->bodies[b];
    c[0] = c[1] = c[2] = 0.0;
    for (int i = 0; i < body->n; ++i)
        for (int k = 0; k < 3; ++k) c[k] += body->x[3 * (size_t)i + k] / body->n;
}

void vw_colormap(double s, float rgb[3])
{
    static const float stops[3][3] = {
        {0.230f, 0.299f, 0.754f}, {0.865f, 0.865f, 0.865f}, {0.706f, 0.016f, 0.150f}};
    if (!(s > 0.0)) s = 0.0;
    if (s > 1.0) s = 1.0;
    int i = s < 0.5 ? 0 : 1;
    float t = (float)(s < 0.5 ? 2.0 * s : 2.0 * s - 1.0);
    for (int k = 0; k < 3; ++k) rgb[k] = stops[i][k] + t * (stops[i + 1][k] - stops[i][k]);
}
