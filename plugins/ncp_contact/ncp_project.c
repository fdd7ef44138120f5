/* ncp_project.c - the admissible set of the multipliers: lambda_n >= 0,
 * |lambda_f| <= mu lambda_n (the 2-norm over a contact's tangent rows),
 * lo <= lambda <= hi on bounded rows.  Every solution of the NCP lies in
 * it, so projecting an iterate onto it leaves the solution unchanged while
 * keeping the force applied by an unfinished iteration admissible (a
 * friction force never exceeds Coulomb's bound, a contact never pulls).
 * The projection of one row or contact is ncp_project.h, shared with the
 * GPU. */
#include "ncp_project.h"

#include "ncp.h"

#include <math.h>

int ncp_project(const pl_ncp_work *w, double *lambda)
{
    const pl_ncp_rows *R = &w->rows;
    int changed = 0;
    for (int j = 0; j < w->m; ++j) {
        double l = ncp_project_row(R->kind[j], lambda[j], R->lo ? R->lo[j] : -INFINITY,
                                   R->hi ? R->hi[j] : INFINITY);
        changed += l != lambda[j];
        lambda[j] = l;
    }
    for (int c = 0; c < w->nc; ++c) {
        const int *ct = w->contact + 3 * c;
        changed += ncp_project_contact(ct, R->mu ? R->mu[ct[0]] : 0.0, lambda);
    }
    return changed;
}
