/* surface_model.c - collision models of deformable bodies, placed in a body's
 * node next to its MechanicalObject:
 *   SurfaceCollisionModel  the vertices of the boundary surface of the node's
 *                          tetrahedral mesh, or every vertex of a triangle
 *                          (cloth) mesh; its triangles and edges are kept for
 *                          mesh-versus-mesh detection later;
 *   PointCollisionModel    every vertex of the state.
 * Each point follows one vertex of the global system with weight 1. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"
#include "collision.h"
#include "models.h"
#include "pliant/pliant.h"

typedef struct surface_model {
    pl_component base;
    /* fields */
    double mu;
    pl_ints group;
    pl_link src;
    /* model */
    int all_vertices;          /* PointCollisionModel */
    pl_component *state;
    int npoints;
    int *local;                /* per point: its vertex in the state */
    int ntris, nedges;
    int *tris, *edges;         /* into the points */
    int solid;                 /* the triangles bound tetrahedra: one-sided */
    double *weight;            /* per point: 1 0 0 0 (one vertex each) */
} surface_model;

static const pl_field SURFACE_FIELDS[] = {
    PL_FIELD(surface_model, mu, "mu", PL_F_DOUBLE, "-1",
             "Coulomb friction coefficient of this body's contacts (-1: the obstacle's)",
             PL_FIELD_RUNTIME),
    PL_FIELD(surface_model, group, "group", PL_F_INTS, "0",
             "collision groups it belongs to, a list (\"1 2\"; 0: none): models that share a "
             "group never collide",
             PL_FIELD_RUNTIME),
    PL_FIELD(surface_model, src, "src", PL_F_LINK, NULL,
             "the mesh (loader or generator; default: the first one in this node)", 0),
};

static const pl_field POINT_FIELDS[] = {
    PL_FIELD(surface_model, mu, "mu", PL_F_DOUBLE, "-1",
             "Coulomb friction coefficient of this body's contacts (-1: the obstacle's)",
             PL_FIELD_RUNTIME),
    PL_FIELD(surface_model, group, "group", PL_F_INTS, "0",
             "collision groups it belongs to, a list (\"1 2\"; 0: none): models that share a "
             "group never collide",
             PL_FIELD_RUNTIME),
};

static int check_fields(const surface_model *m, pl_component *c, pl_ctx *ctx)
{
    if (!isfinite(m->mu) || !(m->mu >= 0.0 || m->mu == -1.0))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "mu must be >= 0, or -1 to use the obstacle's, got %g", m->mu);
    pl_error e;
    unsigned groups;
    if (collision_groups(&m->group, &groups, &e) != PL_OK) /* validates the list */
        return pl_component_error(c, ctx, PL_EINPUT, "%s", e.msg);
    return PL_OK;
}

static int sm_init(pl_component *c, pl_ctx *ctx) { return check_fields((surface_model *)c, c, ctx); }

static int cmp_pair(const void *a, const void *b)
{
    const int *x = a, *y = b;
    if (x[0] != y[0]) return (x[0] > y[0]) - (x[0] < y[0]);
    return (x[1] > y[1]) - (x[1] < y[1]);
}

/* Unique undirected edges of the triangles (sorted: deterministic). */
static int build_edges(surface_model *m)
{
    m->nedges = 0;
    if (m->ntris == 0) return PL_OK;
    int *e = malloc((size_t)m->ntris * 6 * sizeof *e);
    if (!e) return PL_EINTERNAL;
    for (int t = 0; t < m->ntris; ++t)
        for (int k = 0; k < 3; ++k) {
            int a = m->tris[3 * t + k], b = m->tris[3 * t + (k + 1) % 3];
            e[6 * t + 2 * k] = a < b ? a : b;
            e[6 * t + 2 * k + 1] = a < b ? b : a;
        }
    int ne = 3 * m->ntris, w = 0;
    qsort(e, (size_t)ne, 2 * sizeof *e, cmp_pair);
    for (int i = 0; i < ne; ++i)
        if (w == 0 || e[2 * i] != e[2 * (w - 1)] || e[2 * i + 1] != e[2 * (w - 1) + 1]) {
            e[2 * w] = e[2 * i];
            e[2 * w + 1] = e[2 * i + 1];
            w++;
        }
    m->edges = e;
    m->nedges = w;
    return PL_OK;
}

/* Points = the vertices the triangles use (in vertex order); triangles
 * renumbered into the points. */
static int points_of_triangles(surface_model *m, const int *tris, int ntris, int nverts)
{
    int *map = malloc((size_t)(nverts ? nverts : 1) * sizeof *map);
    m->tris = malloc((size_t)(ntris ? ntris : 1) * 3 * sizeof *m->tris);
    if (!map || !m->tris) {
        free(map);
        return PL_EINTERNAL;
    }
    for (int v = 0; v < nverts; ++v) map[v] = -1;
    for (int k = 0; k < 3 * ntris; ++k) map[tris[k]] = 0;
    m->npoints = 0;
    for (int v = 0; v < nverts; ++v)
        if (map[v] == 0) map[v] = m->npoints++;
    m->local = malloc((size_t)(m->npoints ? m->npoints : 1) * sizeof *m->local);
    if (!m->local) {
        free(map);
        return PL_EINTERNAL;
    }
    for (int v = 0; v < nverts; ++v)
        if (map[v] >= 0) m->local[map[v]] = v;
    for (int k = 0; k < 3 * ntris; ++k) m->tris[k] = map[tris[k]];
    m->ntris = ntris;
    free(map);
    return build_edges(m);
}

static int all_points(surface_model *m, int n)
{
    m->npoints = n;
    m->local = malloc((size_t)(n ? n : 1) * sizeof *m->local);
    if (!m->local) return PL_EINTERNAL;
    for (int v = 0; v < n; ++v) m->local[v] = v;
    return PL_OK;
}

static void free_model(surface_model *m)
{
    free(m->local);
    free(m->tris);
    free(m->edges);
    free(m->weight);
    m->local = m->tris = m->edges = NULL;
    m->weight = NULL;
    m->npoints = m->ntris = m->nedges = 0;
}

/* The points from the node's mesh: boundary of the tetrahedra, else the triangles. */
static int surface_points(surface_model *m, pl_component *c, pl_ctx *ctx, int nstate)
{
    const pl_mesh *mesh = pl_util_topology(c, &m->src, ctx, 1);
    if (!mesh) return PL_EINPUT;
    if (mesh->nverts != nstate)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "its mesh has %d vertices but the state '%s' has %d: the "
                                  "surface must be the body's own mesh",
                                  mesh->nverts, m->state->name, nstate);
    m->solid = mesh->ntets > 0;
    if (mesh->ntets > 0) {
        int *tris = NULL, ntris = 0;
        int rc = pl_mesh_boundary_triangles(mesh, &tris, &ntris);
        if (rc != PL_OK) {
            free(tris);
            return pl_component_error(c, ctx, rc,
                                      rc == PL_EINPUT ? "the tetrahedral mesh is not a manifold: "
                                                        "no boundary surface"
                                                      : "out of memory");
        }
        rc = points_of_triangles(m, tris, ntris, mesh->nverts);
        free(tris);
        if (rc) return pl_component_error(c, ctx, rc, "out of memory");
    } else if (mesh->ntris > 0) {
        if (points_of_triangles(m, mesh->tris, mesh->ntris, mesh->nverts))
            return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    } else {
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "its mesh has neither tetrahedra nor triangles (use "
                                  "PointCollisionModel for a point cloud)");
    }
    return PL_OK;
}

static int sm_bind(pl_component *c, pl_ctx *ctx)
{
    surface_model *m = (surface_model *)c;
    free_model(m);
    m->state = pl_util_state(c, ctx, 1);
    if (!m->state) return PL_EINPUT;
    const pl_state_ops *so = pl_component_role(m->state, PL_ROLE_STATE);
    int n = so->count(m->state);
    int rc = m->all_vertices ? (all_points(m, n) ? pl_component_error(c, ctx, PL_EINTERNAL,
                                                                      "out of memory")
                                                 : PL_OK)
                             : surface_points(m, c, ctx, n);
    if (rc) return rc;
    size_t np = m->npoints > 0 ? (size_t)m->npoints : 1;
    m->weight = malloc(np * 4 * sizeof *m->weight);
    if (!m->weight)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    for (int i = 0; i < m->npoints; ++i) {
        m->weight[4 * i] = 1.0;
        m->weight[4 * i + 1] = m->weight[4 * i + 2] = m->weight[4 * i + 3] = 0.0;
    }
    pl_log_debug("%s %s: %d points, %d triangles, %d edges", c->type->name, c->name, m->npoints,
                 m->ntris, m->nedges);
    return PL_OK;
}

static int sm_reinit(pl_component *c, pl_ctx *ctx) { return check_fields((surface_model *)c, c, ctx); }

static void sm_destroy(pl_component *c) { free_model((surface_model *)c); }

static int sm_update(const pl_component *c, pl_ctx *ctx, const pl_buffer *q,
                     pl_collision_geometry *out, pl_error *err)
{
    const surface_model *m = (const surface_model *)c;
    const pl_state_ops *so = pl_component_role(m->state, PL_ROLE_STATE);
    int off = so->offset(m->state);
    coll_geom_ws *w = coll_geom_ws_get(c, ctx->data, m->npoints, 1);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    const double *qx = pl_buffer_f64(q);
    if (off < 0)
        return pl_component_fail(c, err, PL_EINTERNAL,
                                 "its state is not numbered by an animation loop");
    if (!qx || q->cols != 3 || q->rows < (size_t)off + (size_t)so->count(m->state))
        return pl_component_fail(c, err, PL_EINTERNAL,
                                 "positions must be a host float64 block holding its state");
    pl_buffer vb = so->velocities(m->state, ctx->data);
    const double *vs = pl_buffer_f64(&vb);
    for (int i = 0; i < m->npoints; ++i) {
        int l = m->local[i], g = off + l;
        for (int k = 0; k < 3; ++k) {
            w->x[3 * i + k] = qx[3 * g + k];
            w->v[3 * i + k] = vs ? vs[3 * l + k] : 0.0;
        }
        w->vertex[4 * i] = g;
        w->vertex[4 * i + 1] = w->vertex[4 * i + 2] = w->vertex[4 * i + 3] = -1;
    }
    pl_error ge;
    unsigned groups;
    if (collision_groups(&m->group, &groups, &ge) != PL_OK)
        return pl_component_fail(c, err, PL_EINPUT, "%s", ge.msg);
    *out = (pl_collision_geometry){.nverts = m->npoints, .x = w->x, .v = w->v,
                                   .map_vertex = w->vertex, .map_weight = m->weight,
                                   .ntris = m->ntris, .tris = m->tris,
                                   .nedges = m->nedges, .edges = m->edges,
                                   .is_obstacle = 0, .mu = m->mu, .groups = groups};
    return PL_OK;
}

static const pl_collision_model_ops MODEL_OPS = {
    .version = PL_COLLISION_MODEL_OPS_VERSION,
    .update = sm_update,
};

static int point_bind(pl_component *c, pl_ctx *ctx)
{
    ((surface_model *)c)->all_vertices = 1;
    return sm_bind(c, ctx);
}

extern const pl_type coll_surface_model_type;

int coll_surface_model_solid(const pl_component *c)
{
    return c && c->type == &coll_surface_model_type && ((const surface_model *)c)->solid;
}

const pl_type coll_surface_model_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "SurfaceCollisionModel",
    .help = "The collision surface of a deformable body: the boundary vertices of its "
            "tetrahedral mesh (or all vertices of a triangle mesh), which obstacles push back.",
    .size = sizeof(surface_model),
    .workspace_size = sizeof(coll_geom_ws),
    .fields = SURFACE_FIELDS,
    .nfields = sizeof SURFACE_FIELDS / sizeof SURFACE_FIELDS[0],
    .ops = {.init = sm_init, .bind = sm_bind, .reinit = sm_reinit, .destroy = sm_destroy,
            .workspace_free = coll_geom_ws_free},
    .roles = {[PL_ROLE_COLLISION_MODEL] = &MODEL_OPS},
};

const pl_type coll_point_model_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "PointCollisionModel",
    .help = "Every vertex of the node's state collides (point clouds, or bodies whose inner "
            "vertices may touch obstacles).",
    .size = sizeof(surface_model),
    .workspace_size = sizeof(coll_geom_ws),
    .fields = POINT_FIELDS,
    .nfields = sizeof POINT_FIELDS / sizeof POINT_FIELDS[0],
    .ops = {.init = sm_init, .bind = point_bind, .reinit = sm_reinit, .destroy = sm_destroy,
            .workspace_free = coll_geom_ws_free},
    .roles = {[PL_ROLE_COLLISION_MODEL] = &MODEL_OPS},
};
