/* keep_norm.h - the local step of a KEEP_NORM stencil row (Laplace-Beltrami
 * bending, Bouaziz et al. 2014): the one implementation for the CPU
 * (stencils.c) and the GPU (cuda/stencil_cuda.cu); compiled as C and as
 * CUDA (pliant/hostdevice.h). */
#ifndef PLIANT_HYPER_KEEP_NORM_H
#define PLIANT_HYPER_KEEP_NORM_H

#include <math.h>

#include "pliant/hostdevice.h"
#include "small_matrix.h"

/* p = |y0| y / |y|, the closest vector to y with the rest value y0's norm
 * (y = g_r x, y0 = g_r x_rest; all 3-vectors). */
PL_HD void hm_keep_norm_target(const double *y0, const double *y, double *p)
{
    double r0 = hm_norm3(y0), ny = hm_norm3(y);
    if (r0 == 0.0) {
        p[0] = p[1] = p[2] = 0.0;
    } else if (ny > 1e-300) {
        PL_UNROLL
        for (int a = 0; a < 3; ++a) p[a] = r0 * y[a] / ny;
    } else { /* no direction: keep the rest vector (any vector of norm r0 is a minimiser) */
        PL_UNROLL
        for (int a = 0; a < 3; ++a) p[a] = y0[a];
    }
}

#endif
