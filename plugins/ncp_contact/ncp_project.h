/* ncp_project.h - the admissible set of the multipliers, per row and per
 * contact: the one implementation for the CPU (ncp_project.c) and the GPU
 * (ncp_cuda_step.cu); compiled as C and as CUDA (pliant/hostdevice.h).
 * See ncp_project (ncp.h) for why iterates are projected. */
#ifndef PLIANT_NCP_PROJECT_H
#define PLIANT_NCP_PROJECT_H

#include <math.h>

#include "ncp.h"
#include "pliant/hostdevice.h"

/* l projected on its row's set: lambda_n >= 0 on normal rows, lo <= lambda
 * <= hi on bounded rows (infinite bounds for none), unchanged otherwise. */
PL_HD double ncp_project_row(int kind, double l, double lo, double hi)
{
    if (kind == PL_ROW_NORMAL && l < 0.0)
        l = 0.0;
    else if (kind == PL_ROW_BOUNDED) {
        if (l < lo) l = lo;
        if (l > hi) l = hi;
    }
    return l;
}

/* Scales the friction multipliers of contact ct (normal row, friction
 * rows, -1 if absent) into the disk |lambda_f| <= mu lambda_n (2-norm over
 * its tangent rows).  Returns 1 if they changed. */
PL_HD int ncp_project_contact(const int *ct, double mu, double *lambda)
{
    double radius = mu * lambda[ct[0]], n2 = 0.0;
    for (int i = 1; i <= 2; ++i)
        if (ct[i] >= 0) n2 += lambda[ct[i]] * lambda[ct[i]];
    if (n2 <= radius * radius) return 0;
    double s = radius > 0.0 ? radius / sqrt(n2) : 0.0;
    for (int i = 1; i <= 2; ++i)
        if (ct[i] >= 0) lambda[ct[i]] *= s;
    return 1;
}

#endif
