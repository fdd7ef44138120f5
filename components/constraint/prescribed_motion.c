/* prescribed_motion.c - PrescribedMotion: vertices moved rigidly by a
 * rotation about an axis and a translation (the twisted ends of a bar, a
 * gripper's base following a sequence of poses).  The pose at time t is
 *   x(t) = c + s(t) + R(axis, theta(t)) (x0 - c),
 *   s(t) = velocity t + the keyframed translation,
 *   theta(t) = angularVelocity t + the keyframed angle,
 * keyframes interpolated linearly and held outside their times; c is the
 * rotation centre at t = 0 (it travels with s).  Like fixed vertices, they
 * are not unknowns: the right-hand side gets -A_fp q_p and A_ff stays
 * constant.  The motion (velocity, angularVelocity and the keyframes) is an
 * input: its values live in each pl_data, so two simulations of one scene
 * can move the vertices differently (the pose is a function of t: a value
 * changed during a run moves them to the new pose at once). */
#include <math.h>
#include <stdio.h>
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
             "rotation speed about the axis [rad/s]", PL_FIELD_INPUT),
    PL_FIELD(prescribed_motion, velocity, "velocity", PL_F_VEC3, "0 0 0",
             "translation velocity [m/s]", PL_FIELD_INPUT),
    PL_FIELD(prescribed_motion, times, "times", PL_F_DOUBLES, NULL,
             "keyframe times [s], increasing, of a sequence of rigid poses (with translations "
             "and/or angles; added to velocity and angularVelocity)",
             PL_FIELD_INPUT),
    PL_FIELD(prescribed_motion, translations, "translations", PL_F_DOUBLES, NULL,
             "keyframed translation [m], x y z per time (linear in between, held outside)",
             PL_FIELD_INPUT),
    PL_FIELD(prescribed_motion, angles, "angles", PL_F_DOUBLES, NULL,
             "keyframed rotation angle [rad] about axis through center, one per time (linear in "
             "between, held outside)",
             PL_FIELD_INPUT),
};

/* The keyframes as d holds them (d NULL: the scene's). */
typedef struct keys {
    pl_doubles times, translations, angles;
} keys;

static keys keys_of(const prescribed_motion *p, const pl_data *d)
{
    const pl_component *c = &p->base;
    keys k = {pl_input_doubles(d, c, &p->times), pl_input_doubles(d, c, &p->translations),
              pl_input_doubles(d, c, &p->angles)};
    return k;
}

/* The keyframes: increasing finite times; 3 translations and 1 angle per
 * time when given.  PL_EINPUT with a message in msg. */
static int check_keys(const keys *k, char *msg, size_t size)
{
    int nt = k->times.n;
    if (nt == 0) {
        if (k->translations.n || k->angles.n)
            return snprintf(msg, size, "translations and angles need times (one keyframe per "
                                       "time)"), PL_EINPUT;
        return PL_OK;
    }
    for (int i = 0; i < nt; ++i)
        if (!isfinite(k->times.v[i]) || (i > 0 && !(k->times.v[i] > k->times.v[i - 1])))
            return snprintf(msg, size, "times must be finite and strictly increasing (value %d: "
                                       "%g)", i + 1, k->times.v[i]), PL_EINPUT;
    if (k->translations.n != 0 && k->translations.n != 3 * nt)
        return snprintf(msg, size, "translations: expected 3 values per time (%d), found %d",
                        3 * nt, k->translations.n), PL_EINPUT;
    if (k->angles.n != 0 && k->angles.n != nt)
        return snprintf(msg, size, "angles: expected one value per time (%d), found %d", nt,
                        k->angles.n), PL_EINPUT;
    if (!k->translations.n && !k->angles.n)
        return snprintf(msg, size, "times given without translations or angles"), PL_EINPUT;
    for (int i = 0; i < k->translations.n; ++i)
        if (!isfinite(k->translations.v[i]))
            return snprintf(msg, size, "translations: value %d is not finite", i + 1), PL_EINPUT;
    for (int i = 0; i < k->angles.n; ++i)
        if (!isfinite(k->angles.v[i]))
            return snprintf(msg, size, "angles: value %d is not finite", i + 1), PL_EINPUT;
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
    char msg[256];
    keys k = keys_of(p, NULL);
    if (check_keys(&k, msg, sizeof msg) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "%s", msg);
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
    char msg[256];
    keys k = keys_of(p, d);
    if (check_keys(&k, msg, sizeof msg) != PL_OK) /* d's inputs may have changed */
        return pl_component_fail(c, err, PL_EINPUT, "%s", msg);
    const double *vel = pl_input_vec3(d, c, p->velocity);
    double R[9], s[3], theta = pl_input_double(d, c, &p->angular_velocity) * t;
    for (int j = 0; j < 3; ++j) s[j] = vel[j] * t;
    if (k.times.n > 0) {
        double key[3];
        if (k.translations.n) {
            pl_keyframes_eval(k.times.v, k.times.n, k.translations.v, 3, 0, t, key);
            for (int j = 0; j < 3; ++j) s[j] += key[j];
        }
        if (k.angles.n) {
            pl_keyframes_eval(k.times.v, k.times.n, k.angles.v, 1, 0, t, key);
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
