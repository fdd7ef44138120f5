/* mesh_obstacle.c - MeshObstacle: a rigid triangle mesh (a file, a loader
 * or generator, or triangles written in the scene) with a prescribed rigid
 * motion (translation, spin about an axis, keyframes: the same fields as the
 * analytic obstacles).  It plays the collision model role without DOFs: the
 * CollisionPipeline detects bodies against it and its surface velocity at
 * the contact point enters the friction rows (rolling cylinders drive bodies
 * by friction).  Thin open meshes (knife blades) repel on both sides. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "models.h"

typedef struct mesh_obstacle {
    pl_component base;
    coll_mesh_source source;
    double mu;
    pl_ints group;
    int sides;
    pl_mesh_sides use_sides;   /* sides, with auto resolved for a messy surface at bind */
    double velocity[3], rotation_axis[3], angular_velocity;
    pl_doubles rotation_center, times, translations;
    /* model */
    pl_mesh mesh;              /* at the scene pose */
    int *edges, nedges;
    double center[3];          /* centre of the bounding box */
    int *map_vertex;           /* all -1: no DOFs */
    double *map_weight;
} mesh_obstacle;

static const char *const SIDES[] = {"auto", "one", "two", NULL};

static const pl_field FIELDS[] = {
    COLL_MESH_SOURCE_FIELDS(mesh_obstacle, source, "obstacle's surface"),
    PL_FIELD(mesh_obstacle, mu, "mu", PL_F_DOUBLE, "-1",
             "Coulomb friction coefficient (-1: unset, the pipeline combines the models' values "
             "or uses its own mu)",
             PL_FIELD_RUNTIME),
    PL_FIELD(mesh_obstacle, group, "group", PL_F_INTS, "0",
             "collision groups it belongs to, a list (\"1 2\"; 0: none): models that share a "
             "group never collide",
             PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(mesh_obstacle, sides, "sides", SIDES, "auto",
                  "which sides repel: one (a closed surface: its outside; points inside are pushed "
                  "out), two (a thin sheet such as a knife blade: both sides, each point kept on "
                  "the side it starts the step on) or auto (one when the surface is closed, or encloses "
                  "a volume after cleaning: at most 1 percent of its edges borders or misoriented)",
                  0),
    PL_FIELD(mesh_obstacle, velocity, "velocity", PL_F_VEC3, "0 0 0",
             "constant translation velocity [m/s]", PL_FIELD_RUNTIME),
    PL_FIELD(mesh_obstacle, rotation_axis, "rotationAxis", PL_F_VEC3, "0 0 0",
             "direction of the axis it spins about (with angularVelocity)", PL_FIELD_RUNTIME),
    PL_FIELD(mesh_obstacle, angular_velocity, "angularVelocity", PL_F_DOUBLE, "0",
             "spin rate [rad/s], right-handed about rotationAxis", PL_FIELD_RUNTIME),
    PL_FIELD(mesh_obstacle, rotation_center, "rotationCenter", PL_F_DOUBLES, NULL,
             "a point of the spin axis [m] at t = 0 (x y z; default: the centre of the mesh's "
             "bounding box); it travels with the translation",
             PL_FIELD_RUNTIME),
    PL_FIELD(mesh_obstacle, times, "times", PL_F_DOUBLES, NULL,
             "keyframe times [s], strictly increasing", PL_FIELD_RUNTIME),
    PL_FIELD(mesh_obstacle, translations, "translations", PL_F_DOUBLES, NULL,
             "keyframe translations [m] from the scene pose, x y z per time (linear in between, "
             "held before the first and after the last)",
             PL_FIELD_RUNTIME),
};

/* The motion from the fields as they are now (RUNTIME: checked every step),
 * and the group list as a mask (groups may be NULL). */
static int motion_of(const mesh_obstacle *o, pl_motion *m, unsigned *groups, pl_error *err)
{
    unsigned mask;
    if (!isfinite(o->mu) || !(o->mu >= 0.0 || o->mu == -1.0))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "mu must be >= 0, or -1 (unset), got %g",
                            o->mu);
    if (collision_groups(&o->group, &mask, err) != PL_OK) return err->code;
    if (groups) *groups = mask;
    if (o->rotation_center.n != 0 && o->rotation_center.n != 3)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "rotationCenter: expected 3 values (x y z), found %d",
                            o->rotation_center.n);
    memset(m, 0, sizeof *m);
    memcpy(m->velocity, o->velocity, sizeof m->velocity);
    memcpy(m->axis, o->rotation_axis, sizeof m->axis);
    m->angular_velocity = o->angular_velocity;
    memcpy(m->center, o->rotation_center.n == 3 ? o->rotation_center.v : o->center,
           sizeof m->center);
    m->times = o->times.v;
    m->ntimes = o->times.n;
    m->translations = o->translations.v;
    return motion_prepare(m, o->translations.n, err);
}

static void free_model(mesh_obstacle *o)
{
    pl_mesh_free(&o->mesh);
    pl_mesh_init(&o->mesh);
    free(o->edges);
    free(o->map_vertex);
    free(o->map_weight);
    o->edges = o->map_vertex = NULL;
    o->map_weight = NULL;
    o->nedges = 0;
}

static int mo_init(pl_component *c, pl_ctx *ctx)
{
    mesh_obstacle *o = (mesh_obstacle *)c;
    pl_mesh_init(&o->mesh);
    pl_motion m;
    pl_error err;
    if (motion_of(o, &m, NULL, &err) != PL_OK) return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    return PL_OK;
}

/* Scanned meshes come with duplicate and degenerate triangles: removed,
 * with a warning that says what changed (mesh_clean.c). */
static int clean(mesh_obstacle *o, pl_ctx *ctx)
{
    pl_component *c = &o->base;
    pl_mesh *m = &o->mesh;
    int ntris = m->ntris;
    coll_clean_report r;
    if (coll_mesh_clean(m, &r)) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    if (m->ntris == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the surface has no triangle with an area (%d degenerate)",
                                  r.degenerate);
    if (r.degenerate || r.duplicate)
        pl_component_warn(c, ctx,
                          "cleaned on load: removed %d duplicate triangle(s) and %d degenerate "
                          "one(s) (a repeated vertex or no area); %d of %d triangles remain",
                          r.duplicate, r.degenerate, m->ntris, ntris);
    o->use_sides = (pl_mesh_sides)o->sides;
    if (!r.border_edges && !r.nonmanifold_edges && !r.misoriented_edges) return PL_OK;
    int one = o->sides == PL_SIDES_AUTO && coll_mesh_encloses(&r);
    if (one) o->use_sides = PL_SIDES_ONE;
    /* a plain open sheet (a blade, a plate) is what two sides are for */
    if (!one && !r.nonmanifold_edges && !r.misoriented_edges) return PL_OK;
    pl_component_warn(c, ctx,
                      "the surface is not closed: %d border edge(s), %d edge(s) shared by more "
                      "than two triangles, %d misoriented edge(s) of %d; %s",
                      r.border_edges, r.nonmanifold_edges, r.misoriented_edges, r.edges,
                      one ? "it encloses a volume all the same (at most 1 % of its edges are "
                            "borders or misoriented): only its outside repels (sides=\"one\")"
                          : o->sides == PL_SIDES_AUTO ? "both sides repel (sides=\"two\")"
                                                      : "sides as given");
    return PL_OK;
}

/* The mesh is read at bind: a linked loader or generator is ready then. */
static int mo_bind(pl_component *c, pl_ctx *ctx)
{
    mesh_obstacle *o = (mesh_obstacle *)c;
    free_model(o);
    int rc = coll_mesh_source_load(c, ctx, &o->source, &o->mesh);
    if (rc) return rc;
    if ((rc = clean(o, ctx))) return rc;
    if (triangle_edges(o->mesh.tris, o->mesh.ntris, &o->edges, &o->nedges))
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    size_t n = (size_t)(o->mesh.nverts ? o->mesh.nverts : 1);
    o->map_vertex = malloc(n * 4 * sizeof *o->map_vertex);
    o->map_weight = calloc(n * 4, sizeof *o->map_weight);
    if (!o->map_vertex || !o->map_weight)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    for (size_t k = 0; k < n * 4; ++k) o->map_vertex[k] = -1;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < o->mesh.nverts; ++i)
        for (int k = 0; k < 3; ++k) {
            double x = o->mesh.verts[3 * i + k];
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    for (int k = 0; k < 3; ++k) o->center[k] = o->mesh.nverts ? 0.5 * (lo[k] + hi[k]) : 0.0;
    pl_log_debug("MeshObstacle %s: %d vertices, %d triangles, %d edges", c->name, o->mesh.nverts,
                 o->mesh.ntris, o->nedges);
    return PL_OK;
}

static int mo_reinit(pl_component *c, pl_ctx *ctx)
{
    pl_motion m;
    pl_error err;
    if (motion_of((const mesh_obstacle *)c, &m, NULL, &err) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    return PL_OK;
}

static void mo_destroy(pl_component *c) { free_model((mesh_obstacle *)c); }

/* Posed at the end of the step being taken (t + dt): the unknowns are
 * positions at t + dt. */
static int mo_update(const pl_component *c, pl_ctx *ctx, const pl_buffer *q,
                     pl_collision_geometry *out, pl_error *err)
{
    (void)q;
    const mesh_obstacle *o = (const mesh_obstacle *)c;
    coll_geom_ws *w = coll_geom_ws_get(c, ctx->data, o->mesh.nverts, 0);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    pl_motion m;
    pl_error e;
    unsigned groups = 0;
    if (motion_of(o, &m, &groups, &e) != PL_OK) return pl_component_fail(c, err, PL_EINPUT, "%s", e.msg);
    double t1 = ctx->data->time + pl_node_dt(c->node), R[9], tr[3];
    motion_pose(&m, t1, R, tr);
    for (int i = 0; i < o->mesh.nverts; ++i) {
        const double *p = &o->mesh.verts[3 * i];
        double *x = &w->x[3 * i];
        for (int k = 0; k < 3; ++k)
            x[k] = R[3 * k] * p[0] + R[3 * k + 1] * p[1] + R[3 * k + 2] * p[2] + tr[k];
        motion_velocity(&m, t1, x, &w->v[3 * i]);
    }
    *out = (pl_collision_geometry){.nverts = o->mesh.nverts, .x = w->x, .v = w->v,
                                   .map_vertex = o->map_vertex, .map_weight = o->map_weight,
                                   .ntris = o->mesh.ntris, .tris = o->mesh.tris,
                                   .nedges = o->nedges, .edges = o->edges,
                                   .is_obstacle = 1, .mu = o->mu, .groups = groups};
    return PL_OK;
}

/* Whether c is a MeshObstacle (the registry keeps types by pointer). */
static int is_mesh_obstacle(const pl_component *c)
{
    return c && c->type == &coll_mesh_obstacle_type;
}

pl_mesh_sides coll_model_sides(const pl_component *c)
{
    if (is_mesh_obstacle(c)) return ((const mesh_obstacle *)c)->use_sides;
    return coll_surface_model_solid(c) ? PL_SIDES_ONE : PL_SIDES_AUTO;
}

static const pl_collision_model_ops MODEL_OPS = {
    .version = PL_COLLISION_MODEL_OPS_VERSION,
    .update = mo_update,
};

/* Visual role: the mesh posed at the state's time. */
static int mo_draw(const pl_component *c, const pl_data *d, pl_drawing *dw, pl_error *err)
{
    const mesh_obstacle *o = (const mesh_obstacle *)c;
    pl_motion m;
    pl_error e;
    if (motion_of(o, &m, NULL, &e) != PL_OK) return pl_component_fail(c, err, PL_EINPUT, "%s", e.msg);
    double R[9], tr[3];
    motion_pose(&m, d->time, R, tr);
    pl_draw_part *p = pl_drawing_add(dw, c, PL_DRAW_OBSTACLE);
    int first = p ? pl_draw_vertices(p, o->mesh.verts, NULL, o->mesh.nverts) : -1;
    if (first < 0 || pl_draw_triangles(p, o->mesh.tris, o->mesh.ntris, first) != PL_OK)
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    for (int i = 0; i < o->mesh.nverts; ++i) {
        double *x = &p->x[3 * (size_t)(first + i)], x0[3] = {x[0], x[1], x[2]};
        for (int k = 0; k < 3; ++k)
            x[k] = R[3 * k] * x0[0] + R[3 * k + 1] * x0[1] + R[3 * k + 2] * x0[2] + tr[k];
    }
    return PL_OK;
}

static const pl_visual_ops VISUAL_OPS = {.version = PL_VISUAL_OPS_VERSION, .draw = mo_draw};

const pl_type coll_mesh_obstacle_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "MeshObstacle",
    .help = "A rigid triangle-mesh obstacle (file, loader/generator, or triangles in the scene) "
            "with prescribed motion; needs a CollisionPipeline.  Thin open meshes repel on both "
            "sides (knife blades).",
    .size = sizeof(mesh_obstacle),
    .workspace_size = sizeof(coll_geom_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = mo_init,
            .bind = mo_bind,
            .reinit = mo_reinit,
            .destroy = mo_destroy,
            .workspace_free = coll_geom_ws_free},
    .roles = {[PL_ROLE_COLLISION_MODEL] = &MODEL_OPS, [PL_ROLE_VISUAL] = &VISUAL_OPS},
};
