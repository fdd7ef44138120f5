/* ncp_project.c - the admissible set of the multipliers: lambda_n >= 0,
 * |lambda_f| <= mu lambda_n (the 2-norm over a contact's tangent rows),
 * lo <= lambda <= hi on bounded rows.  Every solution of the NCP lies in
 * it, so projecting an iterate onto it leaves the solution unchanged while
 * keeping the force applied by an unfinished iteration admissible (a
 * friction force never exceeds Coulomb's bound, a contact never pulls). */
#include "ncp.h"

#include <math.h>

int pl_ncp_project(const pl_ncp_work *w, double *lambda)
{
    const pl_ncp_rows *R = &w->rows;
    int changed = 0;
    for (int j = 0; j < w->m; ++j) {
        double l = lambda[j];
        if (R->kind[j] == PL_ROW_NORMAL && l < 0.0)
            l = 0.0;
        else if (R->kind[j] == PL_ROW_BOUNDED) {
            if (R->lo && l < R->lo[j]) l = R->lo[j];
            if (R->hi && l > R->hi[j]) l = R->hi[j];
        }
        changed += l != lambda[j];
        lambda[j] = l;
    }
    for (int c = 0; c < w->nc; ++c) {
        const int *ct = w->contact + 3 * c;
        double radius = (R->mu ? R->mu[ct[0]] : 0.0) * lambda[ct[0]], n2 = 0.0;
        for (int i = 1; i <= 2; ++i)
            if (ct[i] >= 0) n2 += lambda[ct[i]] * lambda[ct[i]];
        if (n2 <= radius * radius) continue;
        double s = radius > 0.0 ? radius / sqrt(n2) : 0.0;
        for (int i = 1; i <= 2; ++i)
            if (ct[i] >= 0) lambda[ct[i]] *= s;
        ++changed;
    }
    return changed;
}
