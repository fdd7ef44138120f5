/* shapes.c - analytic obstacle shapes: signed distance, closest surface point
 * and outward normal of a world point.  Each query maps the point into the
 * shape's frame, solves there (axis-aligned box, z-axis capsule/cylinder,
 * z = 0 plane) and maps the answer back. */
#include <math.h>
#include <string.h>

#include "collision.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }

static int finite3(const double a[3])
{
    return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]);
}

void contact_tangents(const double n[3], double t1[3], double t2[3])
{
    /* the coordinate axis least aligned with n keeps Gram-Schmidt well conditioned */
    int k = 0;
    for (int i = 1; i < 3; ++i)
        if (fabs(n[i]) < fabs(n[k])) k = i;
    double e[3] = {0, 0, 0};
    e[k] = 1.0;
    double en = n[k];
    for (int i = 0; i < 3; ++i) t1[i] = e[i] - en * n[i];
    double l = norm3(t1);
    for (int i = 0; i < 3; ++i) t1[i] /= l;
    t2[0] = n[1] * t1[2] - n[2] * t1[1];
    t2[1] = n[2] * t1[0] - n[0] * t1[2];
    t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

/* R with columns (t1, t2, axis): local z maps to the unit axis. */
static void frame_from_axis(const double axis[3], double R[9])
{
    double t1[3], t2[3];
    contact_tangents(axis, t1, t2);
    for (int i = 0; i < 3; ++i) {
        R[3 * i + 0] = t1[i];
        R[3 * i + 1] = t2[i];
        R[3 * i + 2] = axis[i];
    }
}

static void identity(double R[9])
{
    static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(R, I, sizeof I);
}

static int bad_size(double v, const char *what, pl_error *err)
{
    if (isfinite(v) && v >= 0.0) return 0;
    pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s must be a finite value >= 0 [m], got %g",
                 what, v);
    return 1;
}

static int unit_or_fail(const double a[3], double u[3], const char *what, pl_error *err)
{
    double l = norm3(a);
    if (!finite3(a) || !(l > 0.0))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "%s must be a non-zero finite vector, got (%g, %g, %g)", what, a[0],
                            a[1], a[2]);
    for (int i = 0; i < 3; ++i) u[i] = a[i] / l;
    return PL_OK;
}

static int point_ok(const double p[3], const char *what, pl_error *err)
{
    if (finite3(p)) return PL_OK;
    return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s must be finite", what);
}

int shape_plane(pl_shape *s, const double point[3], const double normal[3], pl_error *err)
{
    memset(s, 0, sizeof *s);
    s->kind = PL_SHAPE_PLANE;
    double n[3];
    if (point_ok(point, "point", err) || unit_or_fail(normal, n, "normal", err)) return PL_EINPUT;
    memcpy(s->center, point, sizeof s->center);
    frame_from_axis(n, s->R);
    return PL_OK;
}

int shape_sphere(pl_shape *s, const double center[3], double radius, pl_error *err)
{
    memset(s, 0, sizeof *s);
    s->kind = PL_SHAPE_SPHERE;
    if (point_ok(center, "center", err) || bad_size(radius, "radius", err)) return PL_EINPUT;
    memcpy(s->center, center, sizeof s->center);
    identity(s->R);
    s->radius = radius;
    return PL_OK;
}

int shape_box(pl_shape *s, const double center[3], const double half[3], const double R[9],
                 pl_error *err)
{
    memset(s, 0, sizeof *s);
    s->kind = PL_SHAPE_BOX;
    if (point_ok(center, "center", err)) return PL_EINPUT;
    for (int i = 0; i < 3; ++i)
        if (bad_size(half[i], "halfExtents", err)) return PL_EINPUT;
    memcpy(s->center, center, sizeof s->center);
    memcpy(s->half, half, sizeof s->half);
    if (R) memcpy(s->R, R, sizeof s->R);
    else identity(s->R);
    return PL_OK;
}

int shape_capsule(pl_shape *s, const double p0[3], const double p1[3], double radius,
                     pl_error *err)
{
    memset(s, 0, sizeof *s);
    s->kind = PL_SHAPE_CAPSULE;
    if (point_ok(p0, "start", err) || point_ok(p1, "end", err) ||
        bad_size(radius, "radius", err))
        return PL_EINPUT;
    double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, u[3] = {0, 0, 1};
    double len = norm3(a);
    /* a capsule whose ends coincide is a sphere: any axis will do */
    if (len > 0.0)
        for (int i = 0; i < 3; ++i) u[i] = a[i] / len;
    for (int i = 0; i < 3; ++i) s->center[i] = 0.5 * (p0[i] + p1[i]);
    frame_from_axis(u, s->R);
    s->radius = radius;
    s->half[2] = 0.5 * len;
    return PL_OK;
}

int shape_cylinder(pl_shape *s, const double center[3], const double axis[3], double radius,
                      double length, pl_error *err)
{
    memset(s, 0, sizeof *s);
    s->kind = PL_SHAPE_CYLINDER;
    double u[3];
    if (point_ok(center, "center", err) || unit_or_fail(axis, u, "axis", err) ||
        bad_size(radius, "radius", err) || bad_size(length, "length", err))
        return PL_EINPUT;
    memcpy(s->center, center, sizeof s->center);
    frame_from_axis(u, s->R);
    s->radius = radius;
    s->half[2] = 0.5 * length;
    return PL_OK;
}

/* ---- local-frame queries: phi, closest point c, normal n ------------------ */

static double sgn(double v) { return v < 0.0 ? -1.0 : 1.0; }

static double plane_local(const double x[3], double c[3], double n[3])
{
    c[0] = x[0], c[1] = x[1], c[2] = 0.0;
    n[0] = 0.0, n[1] = 0.0, n[2] = 1.0;
    return x[2];
}

static double sphere_local(double r, const double x[3], double c[3], double n[3])
{
    double l = norm3(x);
    if (l > 0.0)
        for (int i = 0; i < 3; ++i) n[i] = x[i] / l;
    else
        n[0] = 1.0, n[1] = 0.0, n[2] = 0.0;
    for (int i = 0; i < 3; ++i) c[i] = r * n[i];
    return l - r;
}

static double box_local(const double e[3], const double x[3], double c[3], double n[3])
{
    double q[3], out2 = 0.0;
    int inside = 1;
    for (int i = 0; i < 3; ++i) {
        q[i] = fabs(x[i]) - e[i];
        if (q[i] > 0.0) inside = 0, out2 += q[i] * q[i];
    }
    if (!inside) {
        double phi = sqrt(out2);
        for (int i = 0; i < 3; ++i) {
            c[i] = x[i] < -e[i] ? -e[i] : (x[i] > e[i] ? e[i] : x[i]);
            n[i] = (x[i] - c[i]) / phi;
        }
        return phi;
    }
    /* inside or on the surface: the nearest face (lowest axis on ties) */
    int k = 0;
    for (int i = 1; i < 3; ++i)
        if (q[i] > q[k]) k = i;
    memcpy(c, x, 3 * sizeof *c);
    c[k] = sgn(x[k]) * e[k];
    n[0] = n[1] = n[2] = 0.0;
    n[k] = sgn(x[k]);
    return q[k];
}

/* unit radial direction of x about the z axis (+x on the axis) and its length */
static double radial(const double x[3], double u[3])
{
    double rho = sqrt(x[0] * x[0] + x[1] * x[1]);
    if (rho > 0.0) u[0] = x[0] / rho, u[1] = x[1] / rho;
    else u[0] = 1.0, u[1] = 0.0;
    u[2] = 0.0;
    return rho;
}

static double capsule_local(double r, double hl, const double x[3], double c[3], double n[3])
{
    double z = x[2] < -hl ? -hl : (x[2] > hl ? hl : x[2]);
    double d[3] = {x[0], x[1], x[2] - z};
    double l = norm3(d);
    if (l > 0.0)
        for (int i = 0; i < 3; ++i) n[i] = d[i] / l;
    else
        n[0] = 1.0, n[1] = 0.0, n[2] = 0.0;
    c[0] = r * n[0], c[1] = r * n[1], c[2] = z + r * n[2];
    return l - r;
}

static double cylinder_local(double r, double hl, const double x[3], double c[3], double n[3])
{
    double u[3];
    double rho = radial(x, u);
    double dr = rho - r, dz = fabs(x[2]) - hl, sz = sgn(x[2]);
    if (dr > 0.0 && dz > 0.0) { /* nearest the rim */
        c[0] = r * u[0], c[1] = r * u[1], c[2] = sz * hl;
        double phi = sqrt(dr * dr + dz * dz);
        for (int i = 0; i < 3; ++i) n[i] = (x[i] - c[i]) / phi;
        return phi;
    }
    /* side when it is the larger (less negative or positive) of the two */
    if (dr > dz) {
        c[0] = r * u[0], c[1] = r * u[1], c[2] = x[2];
        memcpy(n, u, 3 * sizeof *n);
        return dr;
    }
    c[0] = x[0], c[1] = x[1], c[2] = sz * hl;
    n[0] = 0.0, n[1] = 0.0, n[2] = sz;
    return dz;
}

double shape_query(const pl_shape *s, const double x[3], double closest[3], double normal[3])
{
    const double *R = s->R;
    double d[3] = {x[0] - s->center[0], x[1] - s->center[1], x[2] - s->center[2]};
    double xl[3], cl[3], nl[3];
    for (int j = 0; j < 3; ++j) xl[j] = R[j] * d[0] + R[3 + j] * d[1] + R[6 + j] * d[2];
    double phi;
    switch (s->kind) {
    case PL_SHAPE_PLANE: phi = plane_local(xl, cl, nl); break;
    case PL_SHAPE_SPHERE: phi = sphere_local(s->radius, xl, cl, nl); break;
    case PL_SHAPE_BOX: phi = box_local(s->half, xl, cl, nl); break;
    case PL_SHAPE_CAPSULE: phi = capsule_local(s->radius, s->half[2], xl, cl, nl); break;
    case PL_SHAPE_CYLINDER: phi = cylinder_local(s->radius, s->half[2], xl, cl, nl); break;
    default: return NAN;
    }
    for (int i = 0; i < 3; ++i) {
        const double *Ri = &R[3 * i];
        if (closest) closest[i] = s->center[i] + Ri[0] * cl[0] + Ri[1] * cl[1] + Ri[2] * cl[2];
        if (normal) normal[i] = Ri[0] * nl[0] + Ri[1] * nl[1] + Ri[2] * nl[2];
    }
    return phi;
}

void shape_transform(const pl_shape *s, const double Rm[9], const double tm[3], pl_shape *out)
{
    pl_shape t = *s;
    for (int i = 0; i < 3; ++i) {
        const double *r = &Rm[3 * i];
        t.center[i] = r[0] * s->center[0] + r[1] * s->center[1] + r[2] * s->center[2] + tm[i];
        for (int j = 0; j < 3; ++j)
            t.R[3 * i + j] = r[0] * s->R[j] + r[1] * s->R[3 + j] + r[2] * s->R[6 + j];
    }
    *out = t;
}
