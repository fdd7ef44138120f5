/* template_constraint.c - PointOnPlaneConstraint: selected vertices slide on a
 * plane (n . x = n . point) without friction.  A complete small plugin to
 * copy when writing your own constraint (docs/writing-a-plugin.md walks
 * through it):
 *   1. the component struct: pl_component first, then the fields, then what
 *      the component builds (model) - never state that changes in time;
 *   2. the field table: name, kind, default, help with the unit, flags
 *      (the plane is an input: its value lives in each pl_data, so a
 *      Keyframes controller or pl_sim_set moves it per simulation);
 *   3. the lifecycle: init (check fields, declare state slots), bind (find
 *      partners by role), get (outputs computed from the state), destroy;
 *   4. the role: PL_ROLE_CONSTRAINT's build_rows appends one bilateral row
 *      per vertex, n . x_a - n . point = 0, and accept_multipliers stores
 *      the step's multipliers (the plane's push on each vertex [N]).  During
 *      a step the component is only read: what the step produces goes into
 *      the pl_data (slots; a workspace for scratch, see model.h);
 *   5. the type descriptor and the plugin entry point.
 * Row convention (pliant/rows.h): a row is H q - d with per-vertex entries;
 * here H has one entry, the unit normal n on vertex a, and d = n . point, so
 * delta = n . x_a - n . point is the signed distance to the plane [m].  The
 * multiplier lambda [N] adds the force lambda n to the vertex. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/pliant.h"
#include "pliant/util.h"

typedef struct point_on_plane {
    pl_component base;            /* must come first */
    /* fields */
    pl_ints indices;
    pl_doubles box;
    double normal[3];
    double point[3];
    double compliance;
    double out_force;
    /* model: built at bind from the fields */
    pl_component *state;
    int *sel;                     /* selected vertices of the state */
    int nsel;
    int slot;                     /* state slot "force": the sum of the multipliers [N] */
} point_on_plane;

static const pl_field FIELDS[] = {
    PL_FIELD(point_on_plane, indices, "indices", PL_F_INTS, NULL,
             "vertices that slide on the plane (0-based, in the node's MechanicalObject)", 0),
    PL_FIELD(point_on_plane, box, "box", PL_F_DOUBLES, NULL,
             "boxes selecting more vertices by rest position [m]: xmin ymin zmin xmax ymax zmax "
             "each",
             0),
    PL_FIELD(point_on_plane, normal, "normal", PL_F_VEC3, "0 1 0",
             "normal of the plane (normalised on use)", PL_FIELD_INPUT),
    PL_FIELD(point_on_plane, point, "point", PL_F_VEC3, "0 0 0", "a point of the plane [m]",
             PL_FIELD_INPUT),
    PL_FIELD(point_on_plane, compliance, "compliance", PL_F_DOUBLE, "0",
             "compliance of each row [m/N] (0 = hard)", PL_FIELD_RUNTIME),
    PL_FIELD(point_on_plane, out_force, "force", PL_F_DOUBLE, "0",
             "total force of the plane on the vertices along the normal in the last step [N]",
             PL_FIELD_OUTPUT),
};

/* Unit normal from the input as d holds it (d NULL: the scene's value);
 * PL_EINPUT for a zero vector. */
static int unit_normal(const point_on_plane *p, const pl_data *d, double n[3])
{
    const double *v = pl_input_vec3(d, &p->base, p->normal);
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(l > 0) || !isfinite(l)) return PL_EINPUT;
    for (int k = 0; k < 3; ++k) n[k] = v[k] / l;
    return PL_OK;
}

static int pop_init(pl_component *c, pl_ctx *ctx)
{
    point_on_plane *p = (point_on_plane *)c;
    if (p->indices.n == 0 && p->box.n == 0)
        return pl_component_error(c, ctx, PL_EINPUT, "select vertices with indices or box");
    double n[3];
    if (unit_normal(p, NULL, n) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "normal: must not be zero");
    if (!(p->compliance >= 0))
        return pl_component_error(c, ctx, PL_EINPUT, "compliance must be >= 0 [m/N]");
    if (pl_util_check_boxes(c, ctx, "box", &p->box) != PL_OK) return PL_EINPUT;
    /* what changes in time lives in the state (pl_data), never in the struct */
    p->slot = pl_model_add_slot(ctx->build, c, "force", sizeof(double));
    return p->slot < 0 ? pl_component_error(c, ctx, PL_EINTERNAL, "out of memory") : PL_OK;
}

static int pop_bind(pl_component *c, pl_ctx *ctx)
{
    point_on_plane *p = (point_on_plane *)c;
    if (!(p->state = pl_util_state(c, ctx, 1))) return PL_EINPUT;
    int n;
    const double *x = pl_util_rest(p->state, &n);
    for (int k = 0; k < p->indices.n; ++k)
        if (p->indices.v[k] < 0 || p->indices.v[k] >= n)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "indices: %d is out of range (the MechanicalObject has %d "
                                      "vertices)",
                                      p->indices.v[k], n);
    free(p->sel);
    p->nsel = pl_util_select(x, n, &p->box, &p->indices, &p->sel);
    if (p->nsel < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    if (p->nsel == 0) pl_component_warn(c, ctx, "selects no vertex");
    return PL_OK;
}

static void pop_destroy(pl_component *c) { free(((point_on_plane *)c)->sel); }

/* Outputs read the state given, so several states over one model work. */
static int pop_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                   size_t size)
{
    const point_on_plane *p = (const point_on_plane *)c;
    if (strcmp(field, "force") || p->slot < 0) return PL_EINPUT;
    int k = snprintf(buf, size, "%.17g", *(const double *)pl_data_slot(d, p->slot));
    return (k < 0 || (size_t)k >= size) ? PL_EINTERNAL : PL_OK;
}

/* ---- PL_ROLE_CONSTRAINT: one bilateral row per vertex -------------------- */

static int pop_build_rows(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                          const pl_buffer *q, pl_rows *rows, pl_error *err)
{
    const point_on_plane *p = (const point_on_plane *)c;
    (void)sys;
    (void)q; /* the rows are linear: they do not depend on the positions */
    double n[3];
    if (unit_normal(p, ctx->data, n) != PL_OK) /* an input: check this data's value */
        return pl_component_fail(c, err, PL_EINPUT, "normal: must not be zero");
    const double *point = pl_input_vec3(ctx->data, c, p->point);
    const pl_state_ops *sops = pl_component_role(p->state, PL_ROLE_STATE);
    int offset = sops->offset(p->state); /* first vertex of this state in the global system */
    double d = n[0] * point[0] + n[1] * point[1] + n[2] * point[2];
    for (int k = 0; k < p->nsel; ++k) {
        int r = pl_rows_begin(rows, PL_ROW_BILATERAL, c);
        if (r < 0 || pl_rows_add(rows, offset + p->sel[k], n[0], n[1], n[2]) != PL_OK)
            return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        rows->d[r] = d;
        rows->compliance[r] = p->compliance;
    }
    return PL_OK;
}

static void pop_accept(const pl_component *c, pl_data *d, const pl_rows *rows, const double *lambda,
                       int first, int count)
{
    const point_on_plane *p = (const point_on_plane *)c;
    double f = 0;
    (void)rows;
    for (int k = 0; k < count; ++k) f += lambda[first + k];
    *(double *)pl_data_slot(d, p->slot) = f;
}

static const pl_constraint_ops CONSTRAINT = {.version = PL_CONSTRAINT_OPS_VERSION,
                                             .build_rows = pop_build_rows,
                                             .accept_multipliers = pop_accept};

static const pl_type point_on_plane_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "PointOnPlaneConstraint",
    .help = "Selected vertices slide without friction on a plane (one bilateral row each); "
            "the template of a custom constraint.",
    .size = sizeof(point_on_plane),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = pop_init, .bind = pop_bind, .destroy = pop_destroy, .get = pop_get},
    .roles = {[PL_ROLE_CONSTRAINT] = &CONSTRAINT},
};

/* ---- the plugin's single entry point ------------------------------------- */
static const pl_type *const types[] = {&point_on_plane_type};
PL_PLUGIN_DEFINE(types)
