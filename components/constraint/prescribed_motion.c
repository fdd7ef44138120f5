/* prescribed_motion.c - PrescribedMotion: vertices moved rigidly by a
 * rotation about an axis and a translation velocity (the twisted ends of a
 * bar).  Like fixed vertices, they are not unknowns: the right-hand side
 * gets -A_fp q_p and A_ff stays constant. */
#include <math.h>
#include <stdlib.h>

#include "base/component_util.h"
#include "prescribed.h"

typedef struct prescribed_motion {
    pl_component base;
    pl_ints indices;
    pl_doubles box;
    double axis[3];
    pl_doubles center;
    double angular_velocity;
    double velocity[3];
    pl_component *state;
    int *sel;
    int nsel;
    double c[3];          /* rotation centre */
    double unit_axis[3];
} prescribed_motion;

static const pl_field FIELDS[] = {
    PL_FIELD(prescribed_motion, indices, "indices", PL_F_INTS, NULL, "vertices moved (0-based)", 0),
    PL_FIELD(prescribed_motion, box, "box", PL_F_DOUBLES, NULL,
             "boxes selecting vertices by rest position [m]: xmin ymin zmin xmax ymax zmax each", 0),
    PL_FIELD(prescribed_motion, axis, "axis", PL_F_VEC3, "1 0 0", "rotation axis (normalised)", 0),
    PL_FIELD(prescribed_motion, center, "center", PL_F_DOUBLES, NULL,
             "a point of the rotation axis [m] (default: centroid of the selected vertices)", 0),
    PL_FIELD(prescribed_motion, angular_velocity, "angularVelocity", PL_F_DOUBLE, "0",
             "rotation speed about the axis [rad/s]", 0),
    PL_FIELD(prescribed_motion, velocity, "velocity", PL_F_VEC3, "0 0 0",
             "translation velocity [m/s]", 0),
};

static int pm_bind(pl_component *c, pl_ctx *ctx)
{
    prescribed_motion *p = (prescribed_motion *)c;
    int n;
    if (p->center.n != 0 && p->center.n != 3)
        return pl_component_error(c, ctx, PL_EINPUT, "center: expected 3 numbers (x y z)");
    double len = sqrt(p->axis[0] * p->axis[0] + p->axis[1] * p->axis[1] + p->axis[2] * p->axis[2]);
    if (!(len > 0)) return pl_component_error(c, ctx, PL_EINPUT, "axis must not be zero");
    for (int k = 0; k < 3; ++k) p->unit_axis[k] = p->axis[k] / len;
    if (!(p->state = pl_util_state(c, ctx, 1))) return PL_EINPUT;
    const double *x = pl_util_rest(p->state, &n);
    p->nsel = pl_util_select_checked(c, ctx, p->state, &p->box, &p->indices, &p->sel);
    if (p->nsel < 0) return PL_EINPUT;
    if (p->nsel == 0) return pl_component_error(c, ctx, PL_EINPUT, "selects no vertex");
    if (p->center.n == 3) {
        for (int k = 0; k < 3; ++k) p->c[k] = p->center.v[k];
    } else {
        p->c[0] = p->c[1] = p->c[2] = 0.0;
        for (int i = 0; i < p->nsel; ++i)
            for (int k = 0; k < 3; ++k) p->c[k] += x[3 * p->sel[i] + k] / p->nsel;
    }
    return PL_OK;
}

static void pm_destroy(pl_component *c) { free(((prescribed_motion *)c)->sel); }

static pl_component *pm_state(const pl_component *c)
{
    return ((const prescribed_motion *)c)->state;
}

static int pm_indices(const pl_component *c, const int **idx)
{
    const prescribed_motion *p = (const prescribed_motion *)c;
    *idx = p->sel;
    return p->nsel;
}

static int pm_positions(const pl_component *c, const pl_data *d, double t, double *out,
                        pl_error *err)
{
    const prescribed_motion *p = (const prescribed_motion *)c;
    int n;
    double R[9];
    const double *x = pl_util_rest(p->state, &n);
    pl_util_axis_angle(p->unit_axis, p->angular_velocity * t, R);
    for (int k = 0; k < p->nsel; ++k) {
        const double *x0 = &x[3 * p->sel[k]];
        double r[3] = {x0[0] - p->c[0], x0[1] - p->c[1], x0[2] - p->c[2]};
        for (int j = 0; j < 3; ++j)
            out[3 * k + j] = p->c[j] + R[3 * j] * r[0] + R[3 * j + 1] * r[1] +
                             R[3 * j + 2] * r[2] + p->velocity[j] * t;
    }
    return PL_OK;
}

static const pl_prescribed_ops OPS = {.version = PL_PRESCRIBED_OPS_VERSION,
                                      .state = pm_state,
                                      .indices = pm_indices,
                                      .positions_at = pm_positions};

const pl_type pl_prescribed_motion_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "PrescribedMotion",
    .help = "Moves vertices rigidly: rotation about an axis at angularVelocity plus a translation "
            "velocity; they are removed from the unknowns.",
    .size = sizeof(prescribed_motion),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.bind = pm_bind, .destroy = pm_destroy},
    .roles = {[PL_ROLE_PRESCRIBED] = &OPS},
};
