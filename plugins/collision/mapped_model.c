/* mapped_model.c - MappedSurfaceCollisionModel: a separate surface mesh
 * (SoftRobots-style collision mesh: OBJ, STL, VTK...) that follows a
 * deformable body through a barycentric mapping into its tetrahedra.  At
 * bind every surface vertex is located in the rest configuration (the
 * containing tetrahedron, or the nearest one with extrapolated weights);
 * from then on it is sum_k w_k q_k over that tetrahedron's 4 vertices, and
 * its contact rows spread over those vertices with the same weights. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "models.h"

typedef struct mapped_model {
    pl_component base;
    coll_mesh_source source;
    pl_link volume;
    double mu;
    pl_ints group;
    /* model */
    pl_component *state;
    pl_mesh surface;
    int *edges, nedges;
    int *local;          /* npoints x 4 local vertices of the state */
    double *weight;      /* npoints x 4 barycentric weights */
} mapped_model;

static const pl_field FIELDS[] = {
    COLL_MESH_SOURCE_FIELDS(mapped_model, source, "collision surface"),
    PL_FIELD(mapped_model, volume, "tetrahedra", PL_F_LINK, NULL,
             "the body's tetrahedral mesh the surface is mapped into (default: the mesh of the "
             "state's node)",
             0),
    PL_FIELD(mapped_model, mu, "mu", PL_F_DOUBLE, "-1",
             "Coulomb friction coefficient of this body's contacts (-1: unset)", PL_FIELD_RUNTIME),
    PL_FIELD(mapped_model, group, "group", PL_F_INTS, "0",
             "collision groups it belongs to, a list (\"1 2\"; 0: none): models that share a "
             "group never collide",
             PL_FIELD_RUNTIME),
};

static int check_fields(const mapped_model *m, pl_component *c, pl_ctx *ctx)
{
    if (!isfinite(m->mu) || !(m->mu >= 0.0 || m->mu == -1.0))
        return pl_component_error(c, ctx, PL_EINPUT, "mu must be >= 0, or -1 (unset), got %g",
                                  m->mu);
    pl_error e;
    unsigned groups;
    if (collision_groups(&m->group, &groups, &e) != PL_OK) /* validates the list */
        return pl_component_error(c, ctx, PL_EINPUT, "%s", e.msg);
    return PL_OK;
}

static void free_model(mapped_model *m)
{
    pl_mesh_free(&m->surface);
    pl_mesh_init(&m->surface);
    free(m->edges);
    free(m->local);
    free(m->weight);
    m->edges = m->local = NULL;
    m->weight = NULL;
    m->nedges = 0;
}

static int mm_init(pl_component *c, pl_ctx *ctx)
{
    pl_mesh_init(&((mapped_model *)c)->surface);
    return check_fields((mapped_model *)c, c, ctx);
}

/* The tetrahedral mesh: the link, else the first topology of the state's node. */
static const pl_mesh *volume_mesh(mapped_model *m, pl_component *c, pl_ctx *ctx)
{
    pl_component *t = m->volume.target;
    if (!t) t = pl_node_find_role(m->state->node, PL_ROLE_TOPOLOGY);
    const pl_topology_ops *ops = t ? pl_component_role(t, PL_ROLE_TOPOLOGY) : NULL;
    if (!ops) {
        pl_component_error(c, ctx, PL_EINPUT,
                           m->volume.target ? "tetrahedra: '%s' provides no mesh"
                                            : "tetrahedra: the node of state '%s' has no mesh "
                                              "(link one with tetrahedra=\"@...\")",
                           m->volume.target ? m->volume.target->name : m->state->name);
        return NULL;
    }
    return ops->mesh(t);
}

static int mm_bind(pl_component *c, pl_ctx *ctx)
{
    mapped_model *m = (mapped_model *)c;
    free_model(m);
    m->state = pl_node_find_role_up(c->node, PL_ROLE_STATE);
    if (!m->state)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "no state (MechanicalObject) in this node or above it to map "
                                  "the surface to");
    int n;
    const double *rest = pl_util_rest(m->state, &n);
    const pl_mesh *vol = volume_mesh(m, c, ctx);
    if (!vol) return PL_EINPUT;
    if (vol->ntets == 0 || vol->nverts != n || !rest)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "tetrahedra: the mesh has %d tetrahedra and %d vertices; the "
                                  "state '%s' has %d: map into the body's own tetrahedra",
                                  vol->ntets, vol->nverts, m->state->name, n);
    int rc = coll_mesh_source_load(c, ctx, &m->source, &m->surface);
    if (rc) return rc;
    int np = m->surface.nverts;
    size_t cnt = (size_t)(np ? np : 1);
    int *tet_of = malloc(cnt * sizeof *tet_of);
    m->local = malloc(cnt * 4 * sizeof *m->local);
    m->weight = malloc(cnt * 4 * sizeof *m->weight);
    if (!tet_of || !m->local || !m->weight ||
        triangle_edges(m->surface.tris, m->surface.ntris, &m->edges, &m->nedges)) {
        free(tet_of);
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    }
    pl_error err;
    int outside = 0;
    rc = barycentric_map(rest, n, vol->tets, vol->ntets, m->surface.verts, np, tet_of,
                            m->weight, &outside, &err);
    if (rc == PL_OK)
        for (int i = 0; i < np; ++i)
            for (int k = 0; k < 4; ++k) m->local[4 * i + k] = vol->tets[4 * tet_of[i] + k];
    free(tet_of);
    if (rc) return pl_component_error(c, ctx, rc, "%s", err.msg);
    pl_log_info("%s: %d surface points mapped into %d tetrahedra (%d outside, extrapolated from "
                "the nearest), %d triangles, %d edges",
                c->name, np, vol->ntets, outside, m->surface.ntris, m->nedges);
    return PL_OK;
}

static int mm_reinit(pl_component *c, pl_ctx *ctx) { return check_fields((mapped_model *)c, c, ctx); }

static void mm_destroy(pl_component *c) { free_model((mapped_model *)c); }

static int mm_update(const pl_component *c, pl_ctx *ctx, const pl_buffer *q,
                     pl_collision_geometry *out, pl_error *err)
{
    const mapped_model *m = (const mapped_model *)c;
    const pl_state_ops *so = pl_component_role(m->state, PL_ROLE_STATE);
    int off = so->offset(m->state), n = so->count(m->state);
    coll_geom_ws *ws = coll_geom_ws_get(c, ctx->data, m->surface.nverts, 1);
    if (!ws) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    const double *qx = pl_buffer_f64(q);
    if (off < 0)
        return pl_component_fail(c, err, PL_EINTERNAL,
                                 "its state is not numbered by an animation loop");
    if (!qx || q->cols != 3 || q->rows < (size_t)off + (size_t)n)
        return pl_component_fail(c, err, PL_EINTERNAL,
                                 "positions must be a host float64 block holding its state");
    pl_buffer vb = so->velocities(m->state, ctx->data);
    const double *vs = pl_buffer_f64(&vb);
    for (int i = 0; i < m->surface.nverts; ++i) {
        double x[3] = {0, 0, 0}, v[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k) {
            int l = m->local[4 * i + k];
            double w = m->weight[4 * i + k];
            ws->vertex[4 * i + k] = off + l;
            for (int j = 0; j < 3; ++j) {
                x[j] += w * qx[3 * (off + l) + j];
                if (vs) v[j] += w * vs[3 * l + j];
            }
        }
        memcpy(&ws->x[3 * i], x, sizeof x);
        memcpy(&ws->v[3 * i], v, sizeof v);
    }
    pl_error ge;
    unsigned groups;
    if (collision_groups(&m->group, &groups, &ge) != PL_OK)
        return pl_component_fail(c, err, PL_EINPUT, "%s", ge.msg);
    *out = (pl_collision_geometry){.nverts = m->surface.nverts, .x = ws->x, .v = ws->v,
                                   .map_vertex = ws->vertex, .map_weight = m->weight,
                                   .ntris = m->surface.ntris, .tris = m->surface.tris,
                                   .nedges = m->nedges, .edges = m->edges,
                                   .is_obstacle = 0, .mu = m->mu, .groups = groups};
    return PL_OK;
}

static const pl_collision_model_ops MODEL_OPS = {
    .version = PL_COLLISION_MODEL_OPS_VERSION,
    .update = mm_update,
};

const pl_type coll_mapped_model_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "MappedSurfaceCollisionModel",
    .help = "A separate collision surface (file, loader, or triangles in the scene) that follows "
            "a deformable body through a barycentric mapping into its tetrahedra.",
    .size = sizeof(mapped_model),
    .workspace_size = sizeof(coll_geom_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = mm_init,
            .bind = mm_bind,
            .reinit = mm_reinit,
            .destroy = mm_destroy,
            .workspace_free = coll_geom_ws_free},
    .roles = {[PL_ROLE_COLLISION_MODEL] = &MODEL_OPS},
};
