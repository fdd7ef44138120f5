/* mechanical_object.c - MechanicalObject: positions, velocities and rest
 * positions of n vertices (n x 3 row-major doubles).  Rest positions are
 * model; current positions and velocities are state (pl_data slots). */
#include "mechanical_object.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"

typedef struct mechanical_object {
    pl_component base;
    pl_doubles position;   /* field: initial positions */
    pl_doubles velocity;   /* field: initial velocities */
    pl_doubles rest_position; /* field: rest positions when they differ from the initial ones */
    pl_link src;
    double translation[3], rotation[3], scale3d[3];
    /* model */
    int n;
    double *rest;          /* n x 3, after the transform */
    double *x0;            /* n x 3 initial positions (== rest unless rest_position is given) */
    double *v0;            /* n x 3 */
    int slot_x, slot_v, slot_f;
    int offset;
} mechanical_object;

static const pl_field FIELDS[] = {
    PL_FIELD(mechanical_object, position, "position", PL_F_DOUBLES, NULL,
             "initial positions [m], x y z per vertex (default: the mesh of src)", 0),
    PL_FIELD(mechanical_object, velocity, "velocity", PL_F_DOUBLES, NULL,
             "initial velocities [m/s], x y z per vertex, or one vector for all (default 0)", 0),
    PL_FIELD(mechanical_object, rest_position, "rest_position", PL_F_DOUBLES, NULL,
             "rest positions [m] when they differ from the initial ones (default: the initial "
             "positions); transformed like them",
             0),
    PL_FIELD(mechanical_object, src, "src", PL_F_LINK, NULL,
             "loader or generator whose vertices become the positions (default: the node's first)",
             0),
    PL_FIELD(mechanical_object, translation, "translation", PL_F_VEC3, "0 0 0",
             "translation applied to the initial positions [m]", 0),
    PL_FIELD(mechanical_object, rotation, "rotation", PL_F_VEC3, "0 0 0",
             "rotation applied before the translation [deg about x, then y, then z]", 0),
    PL_FIELD(mechanical_object, scale3d, "scale3d", PL_F_VEC3, "1 1 1",
             "scale applied first (e.g. 0.001 0.001 0.001 for a mesh in millimetres)", 0),
};

static int mo_init(pl_component *c, pl_ctx *ctx)
{
    mechanical_object *mo = (mechanical_object *)c;
    const double *x = NULL;
    if (mo->position.n) {
        if (mo->position.n % 3)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "position: expected 3 numbers per vertex, found %d numbers",
                                      mo->position.n);
        mo->n = mo->position.n / 3;
        x = mo->position.v;
    } else {
        const pl_mesh *m = pl_util_topology(c, &mo->src, ctx, 1);
        if (!m) return PL_EINPUT;
        mo->n = m->nverts;
        x = m->verts;
    }
    if (mo->n == 0) return pl_component_error(c, ctx, PL_EINPUT, "has no vertices");
    if (mo->velocity.n && mo->velocity.n != 3 && mo->velocity.n != 3 * mo->n)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "velocity: expected 3 numbers or 3 per vertex (%d), found %d",
                                  3 * mo->n, mo->velocity.n);
    size_t bytes = (size_t)mo->n * 3 * sizeof(double);
    if (mo->rest_position.n && mo->rest_position.n != 3 * mo->n)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "rest_position: expected 3 numbers per vertex (%d), found %d",
                                  3 * mo->n, mo->rest_position.n);
    mo->rest = malloc(bytes);
    mo->x0 = malloc(bytes);
    mo->v0 = calloc((size_t)mo->n * 3, sizeof(double));
    if (!mo->rest || !mo->x0 || !mo->v0)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    const double *xr = mo->rest_position.n ? mo->rest_position.v : x;
    double R[9];
    pl_util_rotation_deg(mo->rotation, R);
    for (int i = 0; i < mo->n; ++i) {
        double p[3], pr[3];
        for (int k = 0; k < 3; ++k) p[k] = x[3 * i + k] * mo->scale3d[k];
        for (int k = 0; k < 3; ++k) pr[k] = xr[3 * i + k] * mo->scale3d[k];
        for (int k = 0; k < 3; ++k) {
            mo->x0[3 * i + k] =
                R[3 * k] * p[0] + R[3 * k + 1] * p[1] + R[3 * k + 2] * p[2] + mo->translation[k];
            mo->rest[3 * i + k] =
                R[3 * k] * pr[0] + R[3 * k + 1] * pr[1] + R[3 * k + 2] * pr[2] + mo->translation[k];
        }
        for (int k = 0; k < 3 && mo->velocity.n; ++k)
            mo->v0[3 * i + k] = mo->velocity.v[mo->velocity.n == 3 ? k : 3 * i + k];
    }
    mo->slot_x = pl_model_add_slot(ctx->build, c, "position", bytes);
    mo->slot_v = pl_model_add_slot(ctx->build, c, "velocity", bytes);
    mo->slot_f = pl_model_add_slot(ctx->build, c, "constraintForce", bytes);
    mo->offset = -1;
    if (mo->slot_x < 0 || mo->slot_v < 0 || mo->slot_f < 0)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    /* a restored state must not bring NaN or infinity into the solvers */
    pl_model_set_slot_check(ctx->build, mo->slot_x, pl_slot_check_finite);
    pl_model_set_slot_check(ctx->build, mo->slot_v, pl_slot_check_finite);
    pl_model_set_slot_check(ctx->build, mo->slot_f, pl_slot_check_finite);
    return PL_OK;
}

static int mo_bind(pl_component *c, pl_ctx *ctx)
{
    mechanical_object *mo = (mechanical_object *)c;
    size_t bytes = (size_t)mo->n * 3 * sizeof(double);
    memcpy(pl_data_slot(ctx->data, mo->slot_x), mo->x0, bytes);
    memcpy(pl_data_slot(ctx->data, mo->slot_v), mo->v0, bytes);
    return PL_OK;
}

static void mo_destroy(pl_component *c)
{
    mechanical_object *mo = (mechanical_object *)c;
    free(mo->rest);
    free(mo->x0);
    free(mo->v0);
}

static int format_block(const double *x, int n, char *buf, size_t size)
{
    size_t w = 0;
    buf[0] = '\0';
    for (int i = 0; i < 3 * n; ++i) {
        int k = snprintf(buf + w, size - w, i ? " %.17g" : "%.17g", x[i]);
        if (k < 0 || (size_t)k >= size - w) return PL_EINTERNAL;
        w += (size_t)k;
    }
    return PL_OK;
}

static int mo_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                  size_t size)
{
    const mechanical_object *mo = (const mechanical_object *)c;
    if (!strcmp(field, "position"))
        return format_block(pl_data_slot(d, mo->slot_x), mo->n, buf, size);
    if (!strcmp(field, "velocity"))
        return format_block(pl_data_slot(d, mo->slot_v), mo->n, buf, size);
    if (!strcmp(field, "rest_position")) return format_block(mo->rest, mo->n, buf, size);
    if (!strcmp(field, "constraintForce"))
        return format_block(pl_data_slot(d, mo->slot_f), mo->n, buf, size);
    return PL_EINPUT;
}

static int st_count(const pl_component *c) { return ((const mechanical_object *)c)->n; }

static pl_buffer st_positions(const pl_component *c, const pl_data *d)
{
    const mechanical_object *mo = (const mechanical_object *)c;
    return pl_buffer_host_f64(pl_data_slot(d, mo->slot_x), (size_t)mo->n, 3);
}

static pl_buffer st_velocities(const pl_component *c, const pl_data *d)
{
    const mechanical_object *mo = (const mechanical_object *)c;
    return pl_buffer_host_f64(pl_data_slot(d, mo->slot_v), (size_t)mo->n, 3);
}

static pl_buffer st_forces(const pl_component *c, const pl_data *d)
{
    const mechanical_object *mo = (const mechanical_object *)c;
    return pl_buffer_host_f64(pl_data_slot(d, mo->slot_f), (size_t)mo->n, 3);
}

static pl_buffer st_rest(const pl_component *c)
{
    const mechanical_object *mo = (const mechanical_object *)c;
    return pl_buffer_host_f64(mo->rest, (size_t)mo->n, 3);
}

static int st_offset(const pl_component *c) { return ((const mechanical_object *)c)->offset; }
static void st_set_offset(pl_component *c, int offset)
{
    ((mechanical_object *)c)->offset = offset;
}

static const pl_state_ops STATE_OPS = {
    .version = PL_STATE_OPS_VERSION,
    .count = st_count,
    .positions = st_positions,
    .velocities = st_velocities,
    .rest_positions = st_rest,
    .offset = st_offset,
    .set_offset = st_set_offset,
    .constraint_forces = st_forces,
};

const pl_type pl_mechanical_object_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "MechanicalObject",
    .help = "The degrees of freedom of a body: positions, velocities, rest positions (n x 3).",
    .size = sizeof(mechanical_object),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = mo_init, .bind = mo_bind, .destroy = mo_destroy, .get = mo_get},
    .roles = {[PL_ROLE_STATE] = &STATE_OPS},
};
