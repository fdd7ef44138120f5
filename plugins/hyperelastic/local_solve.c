/* local_solve.c - the per-element local step of the CPU: the public entry
 * point over local_solve.h, the implementation the GPU shares (ARAP
 * projection on rotations; ADMM-PD prox by Newton on the singular values). */
#include "local_solve.h"

#include "hyperelastic.h"

int hyper_local_solve_warm(const pl_hyper_law *m, double what, const double *z, double *p,
                           double *warm, int *halvings)
{
    /* d as a constant in each call: the shared code is written for it */
    if (m->d == 3)
        return hm_local_solve(3, (int)m->material, m->mu, m->lambda, what, z, p, warm, halvings);
    return hm_local_solve(2, (int)m->material, m->mu, m->lambda, what, z, p, warm, halvings);
}

int hyper_local_solve(const pl_hyper_law *m, double what, const double *z, double *p)
{
    int halvings = 0;
    return hyper_local_solve_warm(m, what, z, p, NULL, &halvings);
}
