/* ncp_cuda_math.cuh - device versions of the NCP functions of one row or
 * one contact (ncp_functions.c) and of the residual parts
 * (ncp_residual.c): the same formulas and branches; the CPU files are the
 * reference. */
#ifndef PLIANT_NCP_CUDA_MATH_CUH
#define PLIANT_NCP_CUDA_MATH_CUH

#include <math.h>

namespace ncu {

enum { BILATERAL = 0, NORMAL = 1, FRICTION = 2, BOUNDED = 3 };
enum { FB = 0, MINMAP = 1 };

constexpr double kECap = 1e20; /* PL_NCP_E_CAP */

__device__ inline void normal(int fn, double delta, double lambda, double r, double eps,
                              double *phi, double *omega, double *e)
{
    double a = delta, b = r * lambda;
    if (fn == MINMAP) {
        if (a <= b) {
            *phi = a, *omega = 1.0, *e = 0.0;
        } else {
            *phi = b, *omega = 0.0, *e = r;
        }
        return;
    }
    double s = hypot(hypot(a, b), eps);
    if (s == 0.0) {
        *phi = 0.0, *omega = 1.0, *e = r;
        return;
    }
    if (a + b > 0.0)
        *phi = (2.0 * a * b - eps * eps) / (a + b + s);
    else
        *phi = a + b - s;
    *omega = a > 0.0 ? (b * b + eps * eps) / (s * (s + a)) : 1.0 - a / s;
    *e = r * (b > 0.0 ? (a * a + eps * eps) / (s * (s + b)) : 1.0 - b / s);
}

__device__ inline double friction_compliance(int fn, double a, double L, double ln, double mu,
                                             double rho)
{
    double mln = mu * ln;
    double b = rho * (mln - L);
    double e;
    if (fn == MINMAP) {
        e = a > b ? (a - b) / mln : 0.0;
    } else {
        double s = hypot(a, b);
        if (b > 0.0) {
            /* s + b - a without cancellation (ncp_functions.c): CUDA's
             * hypot may round an ulp below a */
            const double sba = b * (s + a + b) / (s + a);
            e = a > 0.0 ? rho * a * a / (a * sba + rho * L * (s + b)) : 0.0;
        } else {
            e = (s - b) / mln;
        }
    }
    double cap = kECap * rho;
    if (!(e <= cap)) e = cap;
    return e;
}

__device__ inline void friction(int fn, int nt, const double *y, const double *lf, double ln,
                                double mu, double rho, double *phi, double *omega, double *e)
{
    if (!(mu > 0.0 && ln > 0.0)) {
        *omega = 0.0;
        *e = rho;
        for (int i = 0; i < nt; ++i) phi[i] = rho * lf[i];
        return;
    }
    double a2 = 0.0, L2 = 0.0;
    for (int i = 0; i < nt; ++i) {
        a2 += y[i] * y[i];
        L2 += lf[i] * lf[i];
    }
    *omega = 1.0;
    *e = friction_compliance(fn, sqrt(a2), sqrt(L2), ln, mu, rho);
    for (int i = 0; i < nt; ++i) phi[i] = y[i] + *e * lf[i];
}

__device__ inline void bounded(double delta, double lambda, double lo, double hi, double r,
                               double *phi, double *omega, double *e)
{
    double t = lambda - delta / r;
    if (t < lo) {
        *phi = r * (lambda - lo), *omega = 0.0, *e = r;
    } else if (t > hi) {
        *phi = r * (lambda - hi), *omega = 0.0, *e = r;
    } else {
        *phi = delta, *omega = 1.0, *e = 0.0;
    }
}

/* One row's square in the residual's 2-norm (ncp_residual.c; friction rows
 * count per contact: 0 here). */
__device__ inline double row_residual2(int kind, double delta, double lambda, double compliance,
                                       double r, double lo, double hi)
{
    double v;
    switch (kind) {
    case BILATERAL:
        v = fabs(delta + compliance * lambda);
        break;
    case NORMAL:
        v = fabs(fmin(delta, r * lambda));
        break;
    case BOUNDED: {
        double t = fmin(fmax(lambda - delta / r, lo), hi);
        v = fabs(r * (lambda - t));
        break;
    }
    default:
        return 0.0;
    }
    return v * v;
}

/* A contact's friction part of the squared 2-norm: fric^2 + (rho cone)^2
 * (ncp_residual.c, friction_residual). */
__device__ inline double friction_residual2(int nt, const double *y, const double *lf, double ln,
                                            double mu, double rho)
{
    double lnp = ln > 0.0 ? ln : 0.0, L2 = 0.0, z[2], z2 = 0.0;
    for (int i = 0; i < nt; ++i) {
        L2 += lf[i] * lf[i];
        z[i] = rho * lf[i] - y[i];
        z2 += z[i] * z[i];
    }
    double radius = rho * mu * lnp, zn = sqrt(z2);
    double scale = zn > radius ? radius / zn : 1.0;
    double f2 = 0.0;
    for (int i = 0; i < nt; ++i) {
        double d = rho * lf[i] - scale * z[i];
        f2 += d * d;
    }
    double ex = sqrt(L2) - mu * lnp;
    double cone = ex > 0.0 ? ex : 0.0, fric = sqrt(f2);
    return fric * fric + rho * cone * rho * cone;
}

} // namespace ncu

#endif
