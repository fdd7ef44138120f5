/* position_target.c - PositionTarget: soft attachments stiffness/2 |x_a -
 * t_a(t)|^2 pulling selected vertices towards targets that start at their
 * rest positions and move (constant velocity, rotation about an axis, or
 * keyframes).  A PD term with a constant matrix (PAPER_NOTES.md item 3);
 * the motion's fields are inputs (their values live in each pl_data, so two
 * simulations of one scene can move their targets differently); the
 * targets of the step being taken (time t + dt, implicit Euler) live in
 * the pl_data slot "target", written at bind (t) and at each begin_step.
 * project() on device buffers (CUDA builds) goes to stencil_device.c, which
 * uploads the slot's targets once per step. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"
#include "fem_term.h"
#include "hyperelastic.h"
#include "term_ws.h"
#ifdef PLIANT_HAVE_CUDA
#include "stencil_device.h"
#endif

typedef struct position_target {
    pl_component base;
    /* fields */
    pl_ints indices;
    double stiffness;         /* [N/m] */
    int motion;               /* pl_hyper_motion_kind */
    double velocity[3], center[3], axis[3];
    double angular_velocity;  /* [rad/s] */
    pl_doubles times, values;
    /* model */
    pl_component *state;
    double *base_pos;         /* n x 3 rest positions of the indices */
    pl_hyper_stencils s;
    int slot;
} position_target;

static const char *const MOTIONS[] = {"none", "velocity", "rotation", "keyframes", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD(position_target, indices, "indices", PL_F_INTS, NULL,
             "vertices (of the node's state) pulled towards their targets", PL_FIELD_REQUIRED),
    PL_FIELD(position_target, stiffness, "stiffness", PL_F_DOUBLE, "1000",
             "spring stiffness [N/m] of each attachment", 0),
    PL_FIELD_ENUM(position_target, motion, "motion", MOTIONS, "none",
                  "how the targets move from the rest positions: none, velocity, rotation "
                  "(about center/axis) or keyframes (times/values)",
                  PL_FIELD_INPUT),
    PL_FIELD(position_target, velocity, "velocity", PL_F_VEC3, "0 0 0",
             "target velocity [m/s] (motion=velocity)", PL_FIELD_INPUT),
    PL_FIELD(position_target, center, "center", PL_F_VEC3, "0 0 0",
             "a point of the rotation axis [m] (motion=rotation)", PL_FIELD_INPUT),
    PL_FIELD(position_target, axis, "axis", PL_F_VEC3, "0 0 1",
             "rotation axis direction (motion=rotation)", PL_FIELD_INPUT),
    PL_FIELD(position_target, angular_velocity, "angularVelocity", PL_F_DOUBLE, "0",
             "rotation speed [rad/s], right-handed about axis (motion=rotation)", PL_FIELD_INPUT),
    PL_FIELD(position_target, times, "times", PL_F_DOUBLES, NULL,
             "keyframe times [s], increasing (motion=keyframes)", PL_FIELD_INPUT),
    PL_FIELD(position_target, values, "values", PL_F_DOUBLES, NULL,
             "keyframe values [m]: one offset x y z per time (added to the rest positions), or "
             "x y z of every vertex per time (motion=keyframes)",
             PL_FIELD_INPUT),
};

/* The motion as d's inputs describe it now (d NULL: the scene's values). */
static pl_hyper_motion motion_of(const position_target *p, const pl_data *d)
{
    const pl_component *c = &p->base;
    pl_doubles times = pl_input_doubles(d, c, &p->times), values = pl_input_doubles(d, c, &p->values);
    pl_hyper_motion m = {.kind = (pl_hyper_motion_kind)pl_input_int(d, c, &p->motion),
                         .angular_velocity = pl_input_double(d, c, &p->angular_velocity),
                         .times = times.v,
                         .ntimes = times.n,
                         .values = values.v,
                         .nvalues = values.n};
    memcpy(m.velocity, pl_input_vec3(d, c, p->velocity), sizeof m.velocity);
    memcpy(m.center, pl_input_vec3(d, c, p->center), sizeof m.center);
    memcpy(m.axis, pl_input_vec3(d, c, p->axis), sizeof m.axis);
    return m;
}

static int pt_init(pl_component *c, pl_ctx *ctx)
{
    position_target *p = (position_target *)c;
    p->slot = -1;
    if (p->indices.n == 0) return pl_component_error(c, ctx, PL_EINPUT, "indices: selects no vertex");
    if (!(p->stiffness >= 0.0) || !isfinite(p->stiffness))
        return pl_component_error(c, ctx, PL_EINPUT, "stiffness must be >= 0 [N/m], got %g",
                                  p->stiffness);
    pl_hyper_motion m = motion_of(p, NULL);
    pl_error err;
    if (hyper_motion_check(&m, p->indices.n, &err) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    p->slot = pl_model_add_slot(ctx->build, c, "target", (size_t)p->indices.n * 3 * sizeof(double));
    if (p->slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->build, p->slot, pl_slot_check_finite);
    return PL_OK;
}

static int pt_bind(pl_component *c, pl_ctx *ctx)
{
    position_target *p = (position_target *)c;
    p->state = pl_util_state(c, ctx, 1);
    if (!p->state) return PL_EINPUT;
    int n;
    const double *rest = pl_util_rest(p->state, &n);
    if (!rest) return pl_component_error(c, ctx, PL_EINPUT, "its state has no rest positions");
    for (int i = 0; i < p->indices.n; ++i)
        if (p->indices.v[i] < 0 || p->indices.v[i] >= n)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "indices: %d (entry %d) is out of range [0, %d)",
                                      p->indices.v[i], i, n);
    free(p->base_pos);
    p->base_pos = malloc((size_t)p->indices.n * 3 * sizeof(double));
    if (!p->base_pos) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    for (int i = 0; i < p->indices.n; ++i)
        memcpy(p->base_pos + 3 * i, rest + 3 * (size_t)p->indices.v[i], 3 * sizeof(double));
    /* initial state: the targets at the initial time */
    pl_hyper_motion m = motion_of(p, ctx->data);
    hyper_motion_eval(&m, p->indices.n, p->base_pos, ctx->data->time,
                         pl_data_slot(ctx->data, p->slot));
    return PL_OK;
}

static int pt_reinit(pl_component *c, pl_ctx *ctx)
{
    position_target *p = (position_target *)c;
    hyper_stencils_free(&p->s); /* workspaces (device copies) are remade after a reinit */
    if (!p->state) return PL_EINPUT;
    int n;
    pl_util_rest(p->state, &n);
    pl_error err;
    int rc = hyper_point_targets_build(&p->s, p->indices.v, p->indices.n, n, p->stiffness, &err);
    if (rc != PL_OK) return pl_component_error(c, ctx, rc, "%s", err.msg);
    pl_hyper_motion m = motion_of(p, NULL);
    if (hyper_motion_check(&m, p->indices.n, &err) != PL_OK) /* fields may have changed */
        return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    return PL_OK;
}

static int pt_begin_step(const pl_component *c, pl_ctx *ctx, pl_error *err)
{
    const position_target *p = (const position_target *)c;
    pl_hyper_motion m = motion_of(p, ctx->data);
    pl_error e;
    if (hyper_motion_check(&m, p->indices.n, &e) != PL_OK) /* runtime edits */
        return pl_component_fail(c, err, PL_EINPUT, "%s", e.msg);
    /* the step ends at t + dt: implicit Euler pulls towards the targets there */
    double t = ctx->data->time + pl_node_dt(c->node);
    hyper_motion_eval(&m, p->indices.n, p->base_pos, t, pl_data_slot(ctx->data, p->slot));
#ifdef PLIANT_HAVE_CUDA
    /* new targets go up at the next device project */
    hyper_term_ws *w = pl_data_workspace(ctx->data, c);
    if (w) hyper_stencil_device_begin_step(w->stencil);
#endif
    return PL_OK;
}

static void pt_destroy(pl_component *c)
{
    position_target *p = (position_target *)c;
    hyper_stencils_free(&p->s);
    free(p->base_pos);
}

/* ---- PL_ROLE_LOCAL_TERM --------------------------------------------------- */

static pl_component *pt_state(const pl_component *c)
{
    return ((const position_target *)c)->state;
}

static int pt_add_matrix(pl_component *c, int offset, double h2, pl_triplets *A, pl_error *err)
{
    return hyper_stencils_add_matrix(&((position_target *)c)->s, offset, h2, A, err);
}

static int pt_project(const pl_component *c, pl_data *d, int offset, double h2, const pl_buffer *q,
                      pl_buffer *rhs, pl_error *err)
{
    const position_target *p = (const position_target *)c;
    if (q->location == PL_DEVICE || rhs->location == PL_DEVICE) {
#ifdef PLIANT_HAVE_CUDA
        hyper_term_ws *w = pl_data_workspace(d, c);
        if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
        return hyper_stencil_project_device(c, &p->s, &w->stencil, d, pl_data_slot(d, p->slot),
                                            offset, h2, q, rhs, err);
#else
        return pl_component_fail(c, err, PL_EINPUT,
                                 "project: device buffers, but this build has no CUDA");
#endif
    }
    const double *x = hyper_term_block(c, q, offset, p->s.nverts, "positions", err);
    double *r = x ? hyper_term_block(c, rhs, offset, p->s.nverts, "right-hand side", err) : NULL;
    if (!r) return PL_EINTERNAL;
    double *work = hyper_term_work(c, d, hyper_stencils_work_size(&p->s), err);
    if (!work) return err->code;
    return hyper_stencils_project(&p->s, offset, h2, x, pl_data_slot(d, p->slot), work, r, err);
}

static double pt_energy(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q)
{
    const position_target *p = (const position_target *)c;
    const double *x = pl_buffer_f64(q);
    if (!x || q->rows < (size_t)offset + (size_t)p->s.nverts) return NAN;
    return hyper_stencils_energy(&p->s, offset, x, pl_data_slot(d, p->slot));
}

static int pt_add_gradient(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                           pl_buffer *grad, pl_error *err)
{
    const position_target *p = (const position_target *)c;
    const double *x = hyper_term_block(c, q, offset, p->s.nverts, "positions", err);
    double *g = x ? hyper_term_block(c, grad, offset, p->s.nverts, "gradient", err) : NULL;
    if (!g) return PL_EINTERNAL;
    return hyper_stencils_add_gradient(&p->s, offset, x, pl_data_slot(d, p->slot), g, err);
}

static int pt_add_hessian(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                          int psd, pl_triplets *H, pl_error *err)
{
    const position_target *p = (const position_target *)c;
    (void)d;
    const double *x = hyper_term_block(c, q, offset, p->s.nverts, "positions", err);
    if (!x) return PL_EINTERNAL;
    return hyper_stencils_add_hessian(&p->s, offset, x, psd, H, err);
}

/* Host float64 always; device float64 in CUDA builds. */
static int pt_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    (void)c;
    if (prec != PL_F64) return 0;
#ifdef PLIANT_HAVE_CUDA
    return where == PL_HOST || where == PL_DEVICE;
#else
    return where == PL_HOST;
#endif
}

static const pl_local_term_ops LOCAL_TERM = {
    .version = PL_LOCAL_TERM_OPS_VERSION,
    .state = pt_state,
    .add_matrix = pt_add_matrix,
    .project = pt_project,
    .energy = pt_energy,
    .add_gradient = pt_add_gradient,
    .add_hessian = pt_add_hessian,
    .matrix_changed = NULL,
    .accepts = pt_accepts,
};

const pl_type hyper_position_target_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "PositionTarget",
    .help = "Soft attachments: springs (stiffness [N/m]) pulling vertices towards targets that "
            "start at their rest positions and may move (velocity, rotation, keyframes).",
    .size = sizeof(position_target),
    .workspace_size = sizeof(hyper_term_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = pt_init,
            .bind = pt_bind,
            .reinit = pt_reinit,
            .begin_step = pt_begin_step,
            .destroy = pt_destroy,
            .workspace_free = hyper_term_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &LOCAL_TERM},
};
