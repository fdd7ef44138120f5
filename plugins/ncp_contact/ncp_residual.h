/* ncp_residual.h - how far one row or one contact is from the bilateral,
 * box and Signorini-Coulomb conditions (Appendix A.2), each part in its own
 * units: the one implementation for the CPU (ncp_residual.c) and the GPU's
 * line search (ncp_cuda_step.cu); compiled as C and as CUDA
 * (pliant/hostdevice.h). */
#ifndef PLIANT_NCP_RESIDUAL_H
#define PLIANT_NCP_RESIDUAL_H

#include <math.h>

#include "ncp.h"
#include "pliant/hostdevice.h"

/* |residual| of a bilateral (|delta + E_b lambda|), normal
 * (|min(delta, r lambda)|) or bounded (|r lambda - mid(r lo, r lambda -
 * delta, r hi)|) row [m]; 0 for friction rows, which count per contact. */
PL_HD double ncp_row_residual(int kind, double delta, double lambda, double compliance, double r,
                              double lo, double hi)
{
    switch (kind) {
    case PL_ROW_BILATERAL:
        return fabs(delta + compliance * lambda);
    case PL_ROW_NORMAL:
        return fabs(fmin(delta, r * lambda));
    case PL_ROW_BOUNDED: {
        double t = fmin(fmax(lambda - delta / r, lo), hi);
        return fabs(r * (lambda - t));
    }
    default:
        return 0.0;
    }
}

/* Friction part of one contact with nt (1 or 2) tangent rows: cone excess
 * (|lf| - mu ln+)+ [N] and the natural-map residual
 * |rho lf - P_disk(rho mu ln+)(rho lf - y)| [m], which is zero iff y = 0
 * with |lf| <= mu ln (stick) or lf = -mu ln y / |y| (slide). */
PL_HD void ncp_friction_residual(int nt, const double *y, const double *lf, double ln, double mu,
                                 double rho, double *cone, double *fric)
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
    *cone = ex > 0.0 ? ex : 0.0;
    *fric = sqrt(f2);
}

/* One contact's share of the residual's squared 2-norm: fric^2 +
 * (rho cone)^2 (rho cone: the cone excess in metres). */
PL_HD double ncp_friction_residual2(double rho, double cone, double fric)
{
    return fric * fric + rho * cone * rho * cone;
}

#endif
