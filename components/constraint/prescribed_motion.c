/* prescribed_motion.c - PrescribedMotion: vertices moved rigidly by a
 * rotation about an axis and a translation (the twisted ends of a bar, a
 * gripper's base following a sequence of poses).  The pose at time t is
 *   x(t) = c + s(t) + R(axis, theta(t)) (x0 - c),
 *   s(t) = velocity t + the keyframed translation,
 *   theta(t) = angularVelocity t + the keyframed angle,
 * keyframes interpolated linearly and held outside their times; c is the
 * rotation centre at t = 0 (it travels with s).  Like fixed vertices, they
 * are not unknowns: the right-hand side gets -A_fp q_p and A_ff stays
 * constant. */
#include <math.h>
#include <stdlib.h>

#include "pliant/util.h"
#include "controller/controller.h"
#include "prescribed.h"

typedef struct prescribed_motion {
    pl_component base;
    pl_ints indices;
    pl_doubles box;
    double axis[3];
    pl_doubles center;
    double angular_velocity;
    double velocity[3];
    pl_doubles times, translations, angles; /* keyframed pose (optional) */
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
    PL_FIELD(prescribed_motion, times, "times", PL_F_DOUBLES, NULL,
             "keyframe times [s], increasing, of a sequence of rigid poses (with translations "
             "and/or angles; added to velocity and angularVelocity)",
             0),
    PL_FIELD(prescribed_motion, translations, "translations", PL_F_DOUBLES, NULL,
             "keyframed translation [m], x y z per time (linear in between, held outside)", 0),
    PL_FIELD(prescribed_motion, angles, "angles", PL_F_DOUBLES, NULL,
             "keyframed rotation angle [rad] about axis through center, one per time (linear in "
             "between, held outside)",
             0),
};

/* The keyframe fields: increasing finite times; 3 translations and 1 angle
 * per time when given. */
static int check_keys(const prescribed_motion *p, pl_component *c, pl_ctx *ctx)
{
    int nt = p->times.n;
    if (nt == 0) {
        if (p->translations.n || p->angles.n)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "translations and angles need times (one keyframe per time)");
        return PL_OK;
    }
    for (int i = 0; i < nt; ++i)
        if (!isfinite(p->times.v[i]) || (i > 0 && !(p->times.v[i] > p->times.v[i - 1])))
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "times must be finite and strictly increasing (value %d: %g)",
                                      i + 1, p->times.v[i]);
    if (p->translations.n != 0 && p->translations.n != 3 * nt)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "translations: expected 3 values per time (%d), found %d", 3 * nt,
                                  p->translations.n);
    if (p->angles.n != 0 && p->angles.n != nt)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "angles: expected one value per time (%d), found %d", nt,
                                  p->angles.n);
    if (!p->translations.n && !p->angles.n)
        return pl_component_error(c, ctx, PL_EINPUT, "times given without translations or angles");
    for (int i = 0; i < p->translations.n; ++i)
        if (!isfinite(p->translations.v[i]))
            return pl_component_error(c, ctx, PL_EINPUT, "translations: value %d is not finite",
                                      i + 1);
    for (int i = 0; i < p->angles.n; ++i)
        if (!isfinite(p->angles.v[i]))
            return pl_component_error(c, ctx, PL_EINPUT, "angles: value %d is not finite", i + 1);
    return PL_OK;
}

static int pm_bind(pl_component *c, pl_ctx *ctx)
{
    prescribed_motion *p = (prescribed_motion *)c;
    int n;
    if (p->center.n != 0 && p->center.n != 3)
        return pl_component_error(c, ctx, PL_EINPUT, "center: expected 3 numbers (x y z)");
    double len = sqrt(p->axis[0] * p->axis[0] + p->axis[1] * p->axis[1] + p->axis[2] * p->axis[2]);
    if (!(len > 0)) return pl_component_error(c, ctx, PL_EINPUT, "axis must not be zero");
    for (int k = 0; k < 3; ++k) p->unit_axis[k] = p->axis[k] / len;
    if (check_keys(p, c, ctx) != PL_OK) return PL_EINPUT;
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
    (void)d, (void)err;
    const prescribed_motion *p = (const prescribed_motion *)c;
    int n;
    double R[9], s[3], theta = p->angular_velocity * t;
    for (int j = 0; j < 3; ++j) s[j] = p->velocity[j] * t;
    if (p->times.n > 0) {
        double key[3];
        if (p->translations.n) {
            pl_keyframes_eval(p->times.v, p->times.n, p->translations.v, 3, 0, t, key);
            for (int j = 0; j < 3; ++j) s[j] += key[j];
        }
        if (p->angles.n) {
            pl_keyframes_eval(p->times.v, p->times.n, p->angles.v, 1, 0, t, key);
            theta += key[0];
        }
    }
    const double *x = pl_util_rest(p->state, &n);
    pl_util_axis_angle(p->unit_axis, theta, R);
    for (int k = 0; k < p->nsel; ++k) {
        const double *x0 = &x[3 * p->sel[k]];
        double r[3] = {x0[0] - p->c[0], x0[1] - p->c[1], x0[2] - p->c[2]};
        for (int j = 0; j < 3; ++j)
            out[3 * k + j] =
                p->c[j] + s[j] + R[3 * j] * r[0] + R[3 * j + 1] * r[1] + R[3 * j + 2] * r[2];
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
    .help = "Moves vertices rigidly: rotation about an axis (angularVelocity and/or keyframed "
            "angles) plus a translation (velocity and/or keyframed translations); they are "
            "removed from the unknowns.",
    .size = sizeof(prescribed_motion),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.bind = pm_bind, .destroy = pm_destroy},
    .roles = {[PL_ROLE_PRESCRIBED] = &OPS},
};
