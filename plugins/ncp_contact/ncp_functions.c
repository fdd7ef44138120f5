/* ncp_functions.c - the NCP functions of one row or one contact (ncp.h):
 * entry points over ncp_functions.h, the implementation the GPU shares. */
#include "ncp_functions.h"

#include "ncp.h"

void ncp_eval_normal(pl_ncp_function fn, double delta, double lambda, double r, double eps,
                   double *phi, double *omega, double *e)
{
    ncp_normal((int)fn, delta, lambda, r, eps, phi, omega, e);
}

void ncp_eval_friction(pl_ncp_function fn, int nt, const double *y, const double *lf, double ln,
                     double mu, double rho, double *phi, double *omega, double *e)
{
    ncp_friction((int)fn, nt, y, lf, ln, mu, rho, phi, omega, e);
}

void ncp_eval_bounded(double delta, double lambda, double lo, double hi, double r,
                    double *phi, double *omega, double *e)
{
    ncp_bounded(delta, lambda, lo, hi, r, phi, omega, e);
}

void ncp_eval_bilateral(double delta, double lambda, double compliance,
                      double *phi, double *omega, double *e)
{
    ncp_bilateral(delta, lambda, compliance, phi, omega, e);
}
