/* pipeline.c - CollisionPipeline: detection between the scene's collision
 * models (deformable surfaces, mapped surfaces, cloth, mesh obstacles) and
 * the contact rows of what it finds.  Once per step (it plays the
 * constraint role, so the LocalGlobalSolver calls it at the start of every
 * step, Algorithm 4) it:
 *   1. updates every model's geometry: deformables at the start of the step
 *      (x0 = q_t) and predicted (x1 = q_t + h v_t); obstacles posed at the
 *      end of the step (x1) and back along their surface velocity (x0);
 *   2. refits the BVHs of every model and detects, for every pair of models
 *      that may touch (not two obstacles, not sharing a collision group, a
 *      model with itself only with selfCollision), vertex-triangle (both
 *      ways) and edge-edge proximities within alarmDistance (detect.c);
 *   3. emits one normal and two friction rows per proximity (pair_rows.c)
 *      with the pair's mu and contactDistance, and records the contacts in
 *      the data slot "contacts", which receive their forces after the step.
 * The whole is timed as "Detection", apart from the paper's columns. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "models.h"
#include "pipeline.h"
#include "shape_draw.h"

static const char *const RULES[] = {"min", "max", "mean", "product", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD(collision_pipeline, alarm, "alarmDistance", PL_F_DOUBLE, "0.01",
             "detection radius [m]: primitives closer than this (after the predicted motion of "
             "the step) get a contact",
             PL_FIELD_RUNTIME),
    PL_FIELD(collision_pipeline, contact, "contactDistance", PL_F_DOUBLE, "0.001",
             "gap [m] that contacts keep between surfaces (<= alarmDistance)", PL_FIELD_RUNTIME),
    PL_FIELD(collision_pipeline, mu, "mu", PL_F_DOUBLE, "0",
             "Coulomb friction coefficient of pairs where neither model sets its own mu",
             PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(collision_pipeline, rule, "frictionRule", RULES, "min",
                  "friction of a pair whose two models both set mu: min (the slipperier wins), "
                  "max, mean or product; a model with mu -1 is ignored",
                  PL_FIELD_RUNTIME),
    PL_FIELD(collision_pipeline, self, "selfCollision", PL_F_BOOL, "0",
             "also detect each deformable model against itself (primitives sharing a vertex "
             "excepted; alarmDistance must stay below the mesh spacing)",
             PL_FIELD_RUNTIME),
    PL_FIELD(collision_pipeline, vertex_face, "vertexFace", PL_F_BOOL, "1",
             "detect vertex-triangle proximities (both ways)", PL_FIELD_RUNTIME),
    PL_FIELD(collision_pipeline, edge_edge, "edgeEdge", PL_F_BOOL, "1",
             "detect edge-edge proximities (a knife or cube edge across a cloth)",
             PL_FIELD_RUNTIME),
    PL_FIELD(collision_pipeline, max_per_vertex, "maxContactsPerVertex", PL_F_INT, "3",
             "vertex-triangle contacts kept per vertex and pair of models (the closest, then "
             "those with clearly different normals: concave corners)",
             PL_FIELD_RUNTIME),
    PL_FIELD(collision_pipeline, out_count, "contactCount", PL_F_INT, "0",
             "contacts of the last step", PL_FIELD_OUTPUT),
    PL_FIELD(collision_pipeline, out_ee, "edgeEdgeCount", PL_F_INT, "0",
             "edge-edge contacts among them", PL_FIELD_OUTPUT),
    PL_FIELD(collision_pipeline, out_points, "contactPoints", PL_F_DOUBLES, NULL,
             "closest points on side B of the last step's contacts [m], x y z each",
             PL_FIELD_OUTPUT),
    PL_FIELD(collision_pipeline, out_normals, "contactNormals", PL_F_DOUBLES, NULL,
             "unit normals (from B to A) of the last step's contacts, x y z each",
             PL_FIELD_OUTPUT),
    PL_FIELD(collision_pipeline, out_forces, "contactForces", PL_F_DOUBLES, NULL,
             "forces on side A of the last step's contacts [N] (B gets the opposite), x y z each",
             PL_FIELD_OUTPUT),
};

static int check(const collision_pipeline *p, pl_error *err)
{
    if (!isfinite(p->alarm) || p->alarm < 0.0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "alarmDistance must be a finite value >= 0 [m], got %g", p->alarm);
    if (!isfinite(p->contact) || p->contact < 0.0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "contactDistance must be a finite value >= 0 [m], got %g", p->contact);
    if (p->contact > p->alarm)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "contactDistance (%g m) exceeds alarmDistance (%g m): surfaces are "
                            "only detected within alarmDistance, so the kept gap must not be "
                            "larger",
                            p->contact, p->alarm);
    if (!isfinite(p->mu) || p->mu < 0.0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "mu must be >= 0, got %g", p->mu);
    if (p->max_per_vertex < 1)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "maxContactsPerVertex must be >= 1, got %d",
                            p->max_per_vertex);
    return PL_OK;
}

static void free_models(collision_pipeline *p)
{
    free(p->models);
    p->models = NULL;
    p->nmodels = 0;
}

static int collect_model(pl_component *c, void *user)
{
    collision_pipeline *p = user;
    pl_component **m = realloc(p->models, (size_t)(p->nmodels + 1) * sizeof *m);
    if (!m) return 1;
    p->models = m;
    m[p->nmodels++] = c;
    return 0;
}

/* Restored contacts (a saved state is input): kinds, models and vertex
 * counts in range, vertices non-negative, finite numbers. */
static int check_restored(const pl_component *c, const void *data, size_t bytes, pl_error *err)
{
    const collision_pipeline *p = (const collision_pipeline *)c;
    const coll_contact_record *r = data;
    for (size_t k = 0; k < bytes / sizeof *r; ++k) {
        const pl_proximity *x = &r[k].prox;
        int bad = (x->kind != PL_PROX_VERTEX_FACE && x->kind != PL_PROX_EDGE_EDGE) ||
                  x->model_a < 0 || x->model_a >= p->nmodels || x->model_b < 0 ||
                  x->model_b >= p->nmodels || x->na < 1 || x->na > 3 || x->nb < 1 || x->nb > 3;
        for (int i = 0; !bad && i < x->na; ++i) bad = x->a[i] < 0 || !isfinite(x->wa[i]);
        for (int i = 0; !bad && i < x->nb; ++i) bad = x->b[i] < 0 || !isfinite(x->wb[i]);
        for (int i = 0; !bad && i < 3; ++i)
            bad = !isfinite(x->normal[i]) || !isfinite(r[k].lambda[i]) ||
                  !isfinite(r[k].force[i]) || !isfinite(r[k].point_a[i]) ||
                  !isfinite(r[k].point_b[i]) || !isfinite(r[k].t1[i]) || !isfinite(r[k].t2[i]);
        if (bad || !isfinite(x->gap))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "contact %zu is corrupt (kind "
                                "%d, models %d and %d of %d, or a non-finite value)", k, x->kind,
                                x->model_a, x->model_b, p->nmodels);
    }
    return PL_OK;
}

static void cp_workspace_free(const pl_component *c, void *ws)
{
    coll_ws *w = ws;
    const collision_pipeline *p = (const collision_pipeline *)c;
    for (int k = 0; w->models && k < p->nmodels; ++k) {
        coll_mesh_free(&w->models[k].mesh);
        free(w->models[k].x0);
        free(w->models[k].x1);
        free(w->models[k].active);
    }
    free(w->models);
    free(w->struck);
    proximities_free(&w->prox);
    side_hints_free(&w->hints);
    free(w->emit);
    free(w->work);
    coll_detect_ws_free(w);
}

/* This data's workspace, its models made on first use (NULL: out of
 * memory).  The workspace is remade when the model is (bind collects the
 * models again only then). */
static coll_ws *workspace(const collision_pipeline *p, pl_data *d)
{
    coll_ws *w = pl_data_workspace(d, &p->base);
    if (!w || w->models) return w;
    w->models = calloc((size_t)(p->nmodels ? p->nmodels : 1), sizeof *w->models);
    w->struck = calloc((size_t)(p->nmodels ? p->nmodels * p->nmodels : 1), sizeof *w->struck);
    if (!w->models || !w->struck) return NULL;
    for (int k = 0; k < p->nmodels; ++k) {
        w->models[k].c = p->models[k];
        coll_mesh_init(&w->models[k].mesh);
    }
    return w;
}

static int cp_init(pl_component *c, pl_ctx *ctx)
{
    collision_pipeline *p = (collision_pipeline *)c;
    pl_error err;
    if (check(p, &err)) return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    p->slot = pl_model_add_var_slot(ctx->build, c, "contacts", sizeof(coll_contact_record),
                                    INT_MAX);
    if (p->slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->build, p->slot, check_restored);
    return PL_OK;
}

/* Every collision model of the whole scene, in scene order. */
static int cp_bind(pl_component *c, pl_ctx *ctx)
{
    collision_pipeline *p = (collision_pipeline *)c;
    free_models(p);
    pl_node *root = c->node;
    while (root->parent) root = root->parent;
    if (pl_node_visit_role(root, PL_ROLE_COLLISION_MODEL, collect_model, p))
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    if (p->nmodels < 2)
        pl_component_warn(c, ctx,
                          "the scene has %d collision model(s): mesh contacts need two (e.g. a "
                          "SurfaceCollisionModel and a MeshObstacle)",
                          p->nmodels);
    return PL_OK;
}

static int cp_reinit(pl_component *c, pl_ctx *ctx)
{
    collision_pipeline *p = (collision_pipeline *)c;
    pl_error err;
    if (check(p, &err)) return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    p->t_detect = pl_timer_id(ctx->timers, "Detection");
    pl_timer_watch(ctx->timers, p->t_detect); /* host detection's spikes: docs/benchmarks.md */
    return PL_OK;
}

static void cp_destroy(pl_component *c)
{
    free_models((collision_pipeline *)c);
}

static int cp_build_rows(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                         const pl_buffer *q, pl_rows *rows, pl_error *err)
{
    const collision_pipeline *p = (const collision_pipeline *)c;
    pl_error e;
    if (check(p, &e)) return pl_component_fail(c, err, PL_EINPUT, "%s", e.msg);
    coll_ws *w = workspace(p, ctx->data);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    pl_timer_start(ctx->timers, p->t_detect);
    w->nwork = 0;
    w->pairs_ms = w->cand_ms = 0.0;
    w->dev_step = 0;
    /* Detection's parts as series (docs/benchmarks.md reads them): the
     * models' geometry, the pairs' proximities, the rows */
    double t0 = pl_now();
    int rc = coll_pipeline_update_models(p, w, ctx, sys, q, err);
    if (rc == PL_OK) pl_series_push(ctx->timers, "detection models ms", 1e3 * (pl_now() - t0));
    if (rc == PL_OK) rc = coll_pipeline_detect(p, w, ctx->data, sys->h, err);
    if (rc == PL_OK) pl_series_push(ctx->timers, "detection pairs ms", w->pairs_ms);
    if (rc == PL_OK && w->dev_step) {
        pl_series_push(ctx->timers, "detection candidates ms", w->cand_ms);
        w->dev_steps++;
    }
    if (rc == PL_OK && w->dev_state > 0)
        pl_stat_max(ctx->timers, "detection steps on the GPU", w->dev_steps);
    if (rc == PL_OK) pl_series_push(ctx->timers, "detection box overlaps",
                                    (double)w->counts.candidates);
    double t1 = pl_now();
    if (rc == PL_OK) rc = coll_pipeline_emit(p, w, sys, rows, err);
    if (rc == PL_OK) pl_series_push(ctx->timers, "detection rows ms", 1e3 * (pl_now() - t1));
    pl_timer_stop(ctx->timers, p->t_detect);
    if (rc) return rc;
    pl_stat_max(ctx->timers, "detection contacts max", w->nwork);
    pl_stat_max(ctx->timers, "detection candidates max", (double)w->counts.candidates);
    pl_stat_max(ctx->timers, "detection margin max [mm]", 1e3 * w->margin_max);
    if (pl_data_store(ctx->data, p->slot, w->work, (size_t)w->nwork * sizeof *w->work))
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    return PL_OK;
}

int coll_pipeline_contacts(const pl_component *c, const pl_data *d,
                           const coll_contact_record **items)
{
    const collision_pipeline *p = (const collision_pipeline *)c;
    *items = pl_data_slot(d, p->slot);
    return (int)(pl_data_slot_bytes(d, p->slot) / sizeof(coll_contact_record));
}

static void cp_accept_multipliers(const pl_component *c, pl_data *d, const pl_rows *rows,
                                  const double *lambda, int first, int count)
{
    const collision_pipeline *p = (const collision_pipeline *)c;
    coll_contact_record *items = pl_data_slot(d, p->slot);
    int n = (int)(pl_data_slot_bytes(d, p->slot) / sizeof *items);
    /* 3 rows per contact in emission order, starting at first */
    if (count != 3 * n || (n && rows->kind[first] != PL_ROW_NORMAL)) return;
    for (int k = 0; k < n; ++k) {
        const double *l = &lambda[first + 3 * k];
        for (int i = 0; i < 3; ++i) {
            items[k].lambda[i] = l[i];
            items[k].force[i] =
                l[0] * items[k].prox.normal[i] + l[1] * items[k].t1[i] + l[2] * items[k].t2[i];
        }
    }
}

static const pl_constraint_ops CONSTRAINT_OPS = {
    .version = PL_CONSTRAINT_OPS_VERSION,
    .build_rows = cp_build_rows,
    .accept_multipliers = cp_accept_multipliers,
};

static int format_vectors(const coll_contact_record *items, int n, size_t member, char *buf,
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

static int cp_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                  size_t size)
{
    const coll_contact_record *items;
    int n = coll_pipeline_contacts(c, d, &items);
    if (!strcmp(field, "contactCount") || !strcmp(field, "edgeEdgeCount")) {
        int count = n;
        if (field[0] == 'e') {
            count = 0;
            for (int k = 0; k < n; ++k) count += items[k].prox.kind == PL_PROX_EDGE_EDGE;
        }
        int len = snprintf(buf, size, "%d", count);
        return (len < 0 || (size_t)len >= size) ? PL_EINTERNAL : PL_OK;
    }
    if (!strcmp(field, "contactPoints"))
        return format_vectors(items, n, offsetof(coll_contact_record, point_b), buf, size);
    if (!strcmp(field, "contactNormals"))
        return format_vectors(items, n, offsetof(coll_contact_record, prox.normal), buf, size);
    if (!strcmp(field, "contactForces"))
        return format_vectors(items, n, offsetof(coll_contact_record, force), buf, size);
    return PL_EINPUT;
}

static int cp_draw(const pl_component *c, const pl_data *d, pl_drawing *dw, pl_error *err)
{
    const coll_contact_record *items;
    int n = coll_pipeline_contacts(c, d, &items);
    if (coll_draw_contacts(c, dw, items, n, sizeof *items, offsetof(coll_contact_record, point_b),
                           offsetof(coll_contact_record, force)) != PL_OK)
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    return PL_OK;
}

static const pl_visual_ops VISUAL_OPS = {.version = PL_VISUAL_OPS_VERSION, .draw = cp_draw};

const pl_type coll_pipeline_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "CollisionPipeline",
    .help = "Detects the scene's collision models against each other (BVH broad phase; "
            "vertex-triangle and edge-edge proximities within alarmDistance) and emits their "
            "contact rows for the contact solver; timed as \"Detection\", its parts as the "
            "series \"detection models ms\" (the models' geometry, boxes and trees), "
            "\"detection pairs ms\" (the proximities) and \"detection rows ms\".",
    .size = sizeof(collision_pipeline),
    .workspace_size = sizeof(coll_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = cp_init,
            .bind = cp_bind,
            .reinit = cp_reinit,
            .destroy = cp_destroy,
            .get = cp_get,
            .workspace_free = cp_workspace_free},
    .roles = {[PL_ROLE_CONSTRAINT] = &CONSTRAINT_OPS, [PL_ROLE_VISUAL] = &VISUAL_OPS},
};
