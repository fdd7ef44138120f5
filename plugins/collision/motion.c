/* motion.c - prescribed rigid motion of an obstacle: constant translation
 * velocity, rotation about an axis through a point, and keyframed
 * translations (linear in between), combined as
 *     x(t) = c + s(t) + Rot(axis, w t) (x0 - c),   s(t) = v t + key(t). */
#include <math.h>
#include <string.h>

#include "collision.h"

int motion_prepare(pl_motion *m, int ntrans, pl_error *err)
{
    for (int i = 0; i < 3; ++i)
        if (!isfinite(m->velocity[i]) || !isfinite(m->axis[i]) || !isfinite(m->center[i]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "velocity, rotationAxis and rotationCenter must be finite");
    if (!isfinite(m->angular_velocity))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "angularVelocity must be finite");
    double l = sqrt(m->axis[0] * m->axis[0] + m->axis[1] * m->axis[1] + m->axis[2] * m->axis[2]);
    if (l > 0.0) {
        for (int i = 0; i < 3; ++i) m->axis[i] /= l;
    } else if (m->angular_velocity != 0.0) {
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "rotationAxis is zero but angularVelocity is %g rad/s: give the "
                            "direction of the rotation axis",
                            m->angular_velocity);
    }
    if (m->ntimes < 0 || ntrans != 3 * m->ntimes)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "translations: expected 3 values (x y z) per keyframe time, i.e. %d "
                            "for %d times, found %d",
                            3 * m->ntimes, m->ntimes, ntrans);
    for (int k = 0; k < m->ntimes; ++k) {
        if (!isfinite(m->times[k]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "times: value %d is not finite",
                                k + 1);
        if (k > 0 && !(m->times[k] > m->times[k - 1]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "times must be strictly increasing: time %d (%g s) does not "
                                "follow time %d (%g s)",
                                k + 1, m->times[k], k, m->times[k - 1]);
        for (int i = 0; i < 3; ++i)
            if (!isfinite(m->translations[3 * k + i]))
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "translations: keyframe %d is not finite", k + 1);
    }
    return PL_OK;
}

int motion_is_static(const pl_motion *m)
{
    if (m->velocity[0] != 0.0 || m->velocity[1] != 0.0 || m->velocity[2] != 0.0) return 0;
    if (m->angular_velocity != 0.0) return 0;
    for (int k = 0; k < 3 * m->ntimes; ++k)
        if (m->translations[k] != 0.0) return 0;
    return 1;
}

/* Keyframed translation at t and its left derivative (0 outside the keys). */
static void keyframe(const pl_motion *m, double t, double s[3], double ds[3])
{
    s[0] = s[1] = s[2] = 0.0;
    ds[0] = ds[1] = ds[2] = 0.0;
    int n = m->ntimes;
    if (n == 0) return;
    const double *T = m->times, *P = m->translations;
    if (t <= T[0] || n == 1) {
        memcpy(s, t <= T[0] ? P : P + 3 * (n - 1), 3 * sizeof *s);
        return;
    }
    if (t > T[n - 1]) {
        memcpy(s, P + 3 * (n - 1), 3 * sizeof *s);
        return;
    }
    /* the segment (T[k-1], T[k]] holding t: binary search for the first T[k] >= t */
    int lo = 1, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (T[mid] >= t) hi = mid;
        else lo = mid + 1;
    }
    int k = lo;
    double dt = T[k] - T[k - 1], a = (t - T[k - 1]) / dt;
    for (int i = 0; i < 3; ++i) {
        double p0 = P[3 * (k - 1) + i], p1 = P[3 * k + i];
        s[i] = (1.0 - a) * p0 + a * p1;
        ds[i] = (p1 - p0) / dt;
    }
}

static void translation(const pl_motion *m, double t, double s[3], double ds[3])
{
    keyframe(m, t, s, ds);
    for (int i = 0; i < 3; ++i) {
        s[i] += m->velocity[i] * t;
        ds[i] += m->velocity[i];
    }
}

static void rodrigues(const double a[3], double angle, double R[9])
{
    double c = cos(angle), s = sin(angle), t = 1.0 - c;
    double x = a[0], y = a[1], z = a[2];
    R[0] = t * x * x + c;     R[1] = t * x * y - s * z; R[2] = t * x * z + s * y;
    R[3] = t * x * y + s * z; R[4] = t * y * y + c;     R[5] = t * y * z - s * x;
    R[6] = t * x * z - s * y; R[7] = t * y * z + s * x; R[8] = t * z * z + c;
}

void motion_pose(const pl_motion *m, double t, double R[9], double tr[3])
{
    double s[3], ds[3];
    translation(m, t, s, ds);
    if (m->angular_velocity != 0.0) {
        rodrigues(m->axis, m->angular_velocity * t, R);
    } else {
        static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        memcpy(R, I, sizeof I);
    }
    /* x(t) = R x0 + (c - R c + s) */
    const double *c = m->center;
    for (int i = 0; i < 3; ++i)
        tr[i] = c[i] - (R[3 * i] * c[0] + R[3 * i + 1] * c[1] + R[3 * i + 2] * c[2]) + s[i];
}

void motion_velocity(const pl_motion *m, double t, const double p[3], double v[3])
{
    double s[3], ds[3];
    translation(m, t, s, ds);
    double w = m->angular_velocity;
    double r[3] = {p[0] - m->center[0] - s[0], p[1] - m->center[1] - s[1],
                   p[2] - m->center[2] - s[2]};
    const double *a = m->axis;
    v[0] = ds[0] + w * (a[1] * r[2] - a[2] * r[1]);
    v[1] = ds[1] + w * (a[2] * r[0] - a[0] * r[2]);
    v[2] = ds[2] + w * (a[0] * r[1] - a[1] * r[0]);
}

void motion_step_map(const pl_motion *m, double t0, double t1, double R[9], double tr[3])
{
    double R0[9], t0v[3], R1[9], t1v[3];
    motion_pose(m, t0, R0, t0v);
    motion_pose(m, t1, R1, t1v);
    /* x(t1) = R1 R0^T (x(t0) - tr0) + tr1 */
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            R[3 * i + j] = R1[3 * i] * R0[3 * j] + R1[3 * i + 1] * R0[3 * j + 1] +
                           R1[3 * i + 2] * R0[3 * j + 2];
    for (int i = 0; i < 3; ++i)
        tr[i] = t1v[i] - (R[3 * i] * t0v[0] + R[3 * i + 1] * t0v[1] + R[3 * i + 2] * t0v[2]);
}
