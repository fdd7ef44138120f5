/* target_motion.c - where position targets are at time t: fixed, moving at
 * constant velocity, rotating about an axis, or following keyframes. */
#include <math.h>

#include "hyperelastic.h"
#include "small_matrix.h"

int hyper_motion_check(const pl_hyper_motion *m, int npoints, pl_error *err)
{
    switch (m->kind) {
    case PL_HYPER_MOTION_NONE:
    case PL_HYPER_MOTION_VELOCITY:
        return PL_OK;
    case PL_HYPER_MOTION_ROTATION:
        if (!(hm_norm3(m->axis) > 0.0))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "motion=\"rotation\" needs a non-zero axis");
        return PL_OK;
    case PL_HYPER_MOTION_KEYFRAMES:
        if (m->ntimes < 1 || !m->times)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "motion=\"keyframes\" needs at least one time in times");
        for (int i = 1; i < m->ntimes; ++i)
            if (!(m->times[i] > m->times[i - 1]))
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "keyframe times must increase: times[%d] = %g after %g", i,
                                    m->times[i], m->times[i - 1]);
        if (m->nvalues != 3 * m->ntimes && m->nvalues != 3 * m->ntimes * npoints)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "keyframe values: expected %d numbers (one offset xyz per time) or "
                                "%d (xyz of each of the %d points per time), got %d",
                                3 * m->ntimes, 3 * m->ntimes * npoints, npoints, m->nvalues);
        return PL_OK;
    }
    return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "unknown motion kind %d", (int)m->kind);
}

/* y = R x for the rotation by angle about the unit axis n (Rodrigues). */
static void rotate(const double *n, double angle, const double *x, double *y)
{
    double c = cos(angle), s = sin(angle), nx[3], d = hm_dot3(n, x);
    hm_cross(n, x, nx);
    for (int a = 0; a < 3; ++a) y[a] = c * x[a] + s * nx[a] + (1.0 - c) * d * n[a];
}

static void eval_keyframes(const pl_hyper_motion *m, int npoints, const double *base, double t,
                           double *out)
{
    int i0 = 0, i1 = 0;
    double alpha = 0.0;
    if (t >= m->times[m->ntimes - 1]) {
        i0 = i1 = m->ntimes - 1;
    } else if (t > m->times[0]) {
        while (!(t < m->times[i0 + 1])) ++i0; /* times[i0] <= t < times[i0+1] */
        i1 = i0 + 1;
        alpha = (t - m->times[i0]) / (m->times[i1] - m->times[i0]);
    }
    /* 3 * ntimes values are offsets, even when npoints == 1 */
    int offsets = m->nvalues == 3 * m->ntimes;
    for (int p = 0; p < npoints; ++p)
        for (int a = 0; a < 3; ++a) {
            size_t k0 = offsets ? 3 * (size_t)i0 + a : 3 * ((size_t)i0 * npoints + p) + a;
            size_t k1 = offsets ? 3 * (size_t)i1 + a : 3 * ((size_t)i1 * npoints + p) + a;
            double v = (1.0 - alpha) * m->values[k0] + alpha * m->values[k1];
            out[3 * p + a] = offsets ? base[3 * p + a] + v : v;
        }
}

void hyper_motion_eval(const pl_hyper_motion *m, int npoints, const double *base, double t,
                          double *out)
{
    switch (m->kind) {
    case PL_HYPER_MOTION_VELOCITY:
        for (int p = 0; p < npoints; ++p)
            for (int a = 0; a < 3; ++a) out[3 * p + a] = base[3 * p + a] + m->velocity[a] * t;
        return;
    case PL_HYPER_MOTION_ROTATION: {
        double l = hm_norm3(m->axis), n[3] = {m->axis[0] / l, m->axis[1] / l, m->axis[2] / l};
        for (int p = 0; p < npoints; ++p) {
            double x[3], y[3];
            hm_sub3(base + 3 * p, m->center, x);
            rotate(n, m->angular_velocity * t, x, y);
            for (int a = 0; a < 3; ++a) out[3 * p + a] = m->center[a] + y[a];
        }
        return;
    }
    case PL_HYPER_MOTION_KEYFRAMES:
        eval_keyframes(m, npoints, base, t, out);
        return;
    case PL_HYPER_MOTION_NONE:
    default:
        for (int i = 0; i < 3 * npoints; ++i) out[i] = base[i];
        return;
    }
}
