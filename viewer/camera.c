/* camera.c - the orbiting camera (camera.h). */
#include "camera.h"

#include <math.h>
#include <string.h>

#include "vw_math.h"

/* Makes up orthogonal to back (Gram-Schmidt), falling back on the
 * coordinate axis least aligned with back when up is (nearly) parallel. */
static void fix_up(vw_camera *c)
{
    double u[3] = {c->up[0], c->up[1], c->up[2]};
    double d = vw_dot(u, c->back);
    for (int k = 0; k < 3; ++k) u[k] -= d * c->back[k];
    if (vw_normalize(u) < 1e-6) {
        int a = 0;
        for (int k = 1; k < 3; ++k)
            if (fabs(c->back[k]) < fabs(c->back[a])) a = k;
        double e[3] = {0.0, 0.0, 0.0};
        e[a] = 1.0;
        d = vw_dot(e, c->back);
        for (int k = 0; k < 3; ++k) u[k] = e[k] - d * c->back[k];
        vw_normalize(u);
    }
    memcpy(c->up, u, sizeof u);
}

static void set_world_up(vw_camera *c, const double g[3])
{
    double w[3] = {0.0, 1.0, 0.0};
    if (g && vw_norm(g) > 0.0) {
        for (int k = 0; k < 3; ++k) w[k] = -g[k];
        vw_normalize(w);
    }
    memcpy(c->world_up, w, sizeof w);
}

void vw_camera_frame(vw_camera *c, const double lo[3], const double hi[3], const double g[3])
{
    memset(c, 0, sizeof *c);
    set_world_up(c, g);
    double ext[3];
    vw_sub(hi, lo, ext);
    for (int k = 0; k < 3; ++k) c->target[k] = 0.5 * (lo[k] + hi[k]);
    c->radius = 0.5 * vw_norm(ext);
    if (!(c->radius > 1e-4)) c->radius = 1e-4;
    c->fov = 40.0;
    /* a horizontal "front": +z for a y-up scene, -y for a z-up one */
    const double *w = c->world_up;
    double front[3] = {0.0, 0.0, 1.0};
    if (fabs(w[2]) > fabs(w[1])) front[1] = -1.0, front[2] = 0.0;
    double d = vw_dot(front, w);
    for (int k = 0; k < 3; ++k) front[k] -= d * w[k];
    vw_normalize(front);
    vw_rotate(front, w, 30.0 * M_PI / 180.0);
    double el = 25.0 * M_PI / 180.0;
    for (int k = 0; k < 3; ++k) c->back[k] = cos(el) * front[k] + sin(el) * w[k];
    vw_normalize(c->back);
    memcpy(c->up, w, sizeof c->up);
    fix_up(c);
    c->dist = 1.1 * c->radius / sin(0.5 * c->fov * M_PI / 180.0);
}

void vw_camera_look(vw_camera *c, const double eye[3], const double at[3], const double up[3],
                    double fov)
{
    vw_sub(eye, at, c->back);
    c->dist = vw_normalize(c->back);
    if (!(c->dist > 0.0)) c->dist = 1.0, c->back[2] = 1.0;
    memcpy(c->target, at, sizeof c->target);
    memcpy(c->up, up ? up : c->world_up, sizeof c->up);
    if (vw_normalize(c->up) == 0.0) memcpy(c->up, c->world_up, sizeof c->up);
    fix_up(c);
    if (fov > 0.0 && fov < 180.0) c->fov = fov;
    if (c->radius < c->dist * 0.05) c->radius = c->dist; /* clip planes cover the view */
}

void vw_camera_eye(const vw_camera *c, double eye[3])
{
    for (int k = 0; k < 3; ++k) eye[k] = c->target[k] + c->dist * c->back[k];
}

void vw_camera_orbit(vw_camera *c, double dx, double dy)
{
    const double speed = 0.01; /* rad per pixel */
    vw_rotate(c->back, c->world_up, -dx * speed);
    vw_rotate(c->up, c->world_up, -dx * speed);
    double right[3], back[3], up[3];
    vw_cross(c->up, c->back, right);
    vw_normalize(right);
    memcpy(back, c->back, sizeof back);
    memcpy(up, c->up, sizeof up);
    vw_rotate(back, right, -dy * speed);
    vw_rotate(up, right, -dy * speed);
    /* no flip over the pole: the screen's up keeps pointing up-ish */
    if (vw_dot(up, c->world_up) > 0.02) {
        memcpy(c->back, back, sizeof back);
        memcpy(c->up, up, sizeof up);
    }
    vw_normalize(c->back);
    fix_up(c);
}

void vw_camera_pan(vw_camera *c, double dx, double dy, int h)
{
    double right[3];
    vw_cross(c->up, c->back, right);
    /* a pixel at the target's depth */
    double px = 2.0 * c->dist * tan(0.5 * c->fov * M_PI / 180.0) / (h > 0 ? h : 1);
    for (int k = 0; k < 3; ++k) c->target[k] += (-dx * right[k] + dy * c->up[k]) * px;
}

void vw_camera_zoom(vw_camera *c, double factor)
{
    if (factor > 0.0) c->dist /= factor;
    if (c->dist < 1e-5) c->dist = 1e-5;
}

static void clip_planes(const vw_camera *c, double *zn, double *zf)
{
    double r = c->radius > 0.0 ? c->radius : 1.0;
    *zf = c->dist + 4.0 * r;
    *zn = c->dist - 4.0 * r;
    if (*zn < *zf * 1e-4) *zn = *zf * 1e-4;
}

void vw_camera_matrices(const vw_camera *c, int w, int h, double view[16], double proj[16])
{
    double eye[3], r[3];
    vw_camera_eye(c, eye);
    vw_cross(c->up, c->back, r);
    const double *u = c->up, *b = c->back;
    double m[16] = {r[0], u[0], b[0], 0.0, r[1], u[1], b[1], 0.0,
                    r[2], u[2], b[2], 0.0, -vw_dot(r, eye), -vw_dot(u, eye), -vw_dot(b, eye), 1.0};
    memcpy(view, m, sizeof m);
    double zn, zf, aspect = h > 0 ? (double)w / h : 1.0;
    clip_planes(c, &zn, &zf);
    double f = 1.0 / tan(0.5 * c->fov * M_PI / 180.0);
    memset(proj, 0, 16 * sizeof *proj);
    proj[0] = f / aspect;
    proj[5] = f;
    proj[10] = (zf + zn) / (zn - zf);
    proj[11] = -1.0;
    proj[14] = 2.0 * zf * zn / (zn - zf);
}

int vw_camera_project(const vw_camera *c, int w, int h, const double p[3], double *px, double *py,
                      double *depth)
{
    double eye[3], v[3], r[3];
    vw_camera_eye(c, eye);
    vw_sub(p, eye, v);
    vw_cross(c->up, c->back, r);
    double z = -vw_dot(c->back, v);
    if (depth) *depth = z;
    if (!(z > 0.0)) return 0;
    double f = 1.0 / tan(0.5 * c->fov * M_PI / 180.0), aspect = h > 0 ? (double)w / h : 1.0;
    double nx = f / aspect * vw_dot(r, v) / z, ny = f * vw_dot(c->up, v) / z;
    *px = 0.5 * (nx + 1.0) * w;
    *py = 0.5 * (1.0 - ny) * h;
    return 1;
}

void vw_camera_ray(const vw_camera *c, int w, int h, double px, double py, double origin[3],
                   double dir[3])
{
    double r[3];
    vw_camera_eye(c, origin);
    vw_cross(c->up, c->back, r);
    double t = tan(0.5 * c->fov * M_PI / 180.0), aspect = h > 0 ? (double)w / h : 1.0;
    double nx = 2.0 * px / (w > 0 ? w : 1) - 1.0, ny = 1.0 - 2.0 * py / (h > 0 ? h : 1);
    for (int k = 0; k < 3; ++k)
        dir[k] = -c->back[k] + r[k] * nx * t * aspect + c->up[k] * ny * t;
    vw_normalize(dir);
}

void vw_camera_unproject_at(const vw_camera *c, int w, int h, double px, double py,
                            const double p[3], double out[3])
{
    double o[3], d[3], op[3];
    vw_camera_ray(c, w, h, px, py, o, d);
    vw_sub(p, o, op);
    /* the plane through p with normal back: (o + s d - p) . back = 0 */
    double den = vw_dot(d, c->back);
    double s = den != 0.0 ? vw_dot(op, c->back) / den : 0.0;
    for (int k = 0; k < 3; ++k) out[k] = o[k] + s * d[k];
}
