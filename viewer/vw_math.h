/* vw_math.h - the few vector and matrix helpers the viewer needs (double
 * 3-vectors, column-major 4 x 4 matrices as OpenGL takes them). */
#ifndef PLIANT_VW_MATH_H
#define PLIANT_VW_MATH_H

#include <math.h>

static inline void vw_sub(const double a[3], const double b[3], double out[3])
{
    for (int k = 0; k < 3; ++k) out[k] = a[k] - b[k];
}
static inline double vw_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static inline void vw_cross(const double a[3], const double b[3], double out[3])
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    out[0] = c[0], out[1] = c[1], out[2] = c[2];
}
static inline double vw_norm(const double a[3])
{
    return sqrt(vw_dot(a, a));
}
/* Normalises a in place; returns its former length (a untouched if 0). */
static inline double vw_normalize(double a[3])
{
    double n = vw_norm(a);
    if (n > 0.0)
        for (int k = 0; k < 3; ++k) a[k] /= n;
    return n;
}
/* Rotates v about the unit axis by angle [rad] (Rodrigues). */
static inline void vw_rotate(double v[3], const double axis[3], double angle)
{
    double c = cos(angle), s = sin(angle), kv[3], d = vw_dot(axis, v);
    vw_cross(axis, v, kv);
    for (int k = 0; k < 3; ++k) v[k] = v[k] * c + kv[k] * s + axis[k] * d * (1.0 - c);
}

/* out = a b (column-major 4 x 4). */
static inline void vw_mat4_mul(const double a[16], const double b[16], double out[16])
{
    double r[16];
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr) {
            double s = 0.0;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    for (int k = 0; k < 16; ++k) out[k] = r[k];
}

#endif
