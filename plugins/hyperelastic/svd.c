/* svd.c - SVD and polar decomposition of 3x3 and 3x2 matrices: the public
 * entry points of the hyperelastic core over svd.h, which holds the one
 * implementation (one-sided Jacobi, signed for 3x3) shared with the GPU;
 * the _from variants start the Jacobi sweeps from a nearby matrix's V. */
#include "hyperelastic.h"
#include "svd.h"

void hyper_svd3(const double F[9], double U[9], double s[3], double V[9])
{
    hm_svd3(F, U, s, V);
}

void hyper_svd32(const double F[6], double U[6], double s[2], double V[4])
{
    hm_svd32(F, U, s, V);
}

void hyper_svd3_from(const double F[9], const double V0[9], double U[9], double s[3], double V[9])
{
    hm_svd3_from(F, V0, V0 != NULL, U, s, V);
}

void hyper_svd32_from(const double F[6], const double V0[4], double U[6], double s[2],
                      double V[4])
{
    hm_svd32_from(F, V0, V0 != NULL, U, s, V);
}

void hyper_polar3(const double F[9], double R[9])
{
    double U[9], s[3], V[9];
    hm_svd3(F, U, s, V);
    hm_polar_from_svd(3, U, V, R);
}

void hyper_polar32(const double F[6], double R[6])
{
    double U[6], s[2], V[4];
    hm_svd32(F, U, s, V);
    hm_polar_from_svd(2, U, V, R);
}
