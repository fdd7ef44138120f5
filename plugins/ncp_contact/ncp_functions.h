/* ncp_functions.h - NCP functions of one row or one contact and their
 * derivatives (paper Appendix B), at the position level (see ncp.h): the
 * one implementation for the CPU (ncp_functions.c, ncp_step.c) and the GPU
 * (ncp_cuda_step.cu); compiled as C and as CUDA (pliant/hostdevice.h).
 *
 * Every function returns phi, omega = dphi/ddelta (the non-smooth indicator
 * split out of the Jacobian, Section 5.3) and e = dphi/dlambda (the
 * compliance), so that the linearisation phi + omega ddelta + e dlambda = 0
 * is the row of the Newton system.  The contracts are those of
 * ncp_eval_normal, ncp_eval_friction, ncp_eval_bounded and ncp_eval_bilateral
 * (ncp.h). */
#ifndef PLIANT_NCP_FUNCTIONS_H
#define PLIANT_NCP_FUNCTIONS_H

#include <math.h>

#include "ncp.h"
#include "pliant/hostdevice.h"

/* Keeps the friction compliance finite when mu ln is tiny: a contact that
 * barely touches gets a huge but finite e (its friction force ~ 0). */
#define PL_NCP_E_CAP 1e20

/* full_force: rows with Omega at most this are solved as clamped rows
 * (ncp_step on the CPU, phase A of ncp_cuda_step.cu on the GPU)
 * (e dlambda = rhs); dropping their Omega h^2 W dlambda term changes the
 * Newton step by a relative O(Omega), while dividing by a tiny Omega would
 * put an outlier of size e / Omega into CR's spectrum. */
#define PL_NCP_OMEGA_CLAMP 1e-3

/* Normal row (ncp_eval_normal). */
PL_HD void ncp_normal(int fn, double delta, double lambda, double r, double eps, double *phi,
                      double *omega, double *e)
{
    double a = delta, b = r * lambda;
    if (fn == PL_NCP_MINMAP) {
        /* min(delta, r lambda): delta active when delta <= r lambda (ties: the
         * position branch, so a new resting contact gets a Jacobian row). */
        if (a <= b) {
            *phi = a, *omega = 1.0, *e = 0.0;
        } else {
            *phi = b, *omega = 0.0, *e = r;
        }
        return;
    }
    /* Fischer-Burmeister, regularised: s = sqrt(a^2 + b^2 + eps^2).  The
     * differences a + b - s, s - a and s - b are formed from their conjugate
     * expressions when they would cancel. */
    double s = hypot(hypot(a, b), eps);
    if (s == 0.0) {
        /* delta = lambda = 0 and eps = 0: the limit of the regularised
         * derivatives at (0, 0) for any eps > 0, a member of the generalised
         * Jacobian (its centre). */
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

/* Appendix B friction compliance e (position level) for an active contact
 * (mu ln > 0); a = |y|, L = |lf|, rho > 0. */
PL_HD double ncp_friction_compliance(int fn, double a, double L, double ln, double mu, double rho)
{
    double mln = mu * ln;       /* the cone radius [N] */
    double b = rho * (mln - L); /* distance to the cone boundary, scaled [m] */
    double e;
    if (fn == PL_NCP_MINMAP) {
        /* min(|y|, b): stick (e = 0) when |y| <= b, else (|y| - b) / (mu ln). */
        e = a > b ? (a - b) / mln : 0.0;
    } else {
        double s = hypot(a, b);
        if (b > 0.0) {
            /* Inside the cone: Appendix B's rho (s - b) / (a + rho mu ln - s)
             * with s - b = a^2 / (s + b) and rho mu ln = b + rho L, i.e.
             * rho a^2 / (a (s + b - a) + rho L (s + b)).  s - a is formed as
             * b^2 / (s + a): when b << a, s rounds to a (or an ulp below it,
             * as CUDA's hypot may), and s + b - a would cancel to 0 or go
             * negative (a negative compliance makes CR's system indefinite).
             * So s + b - a = b (s + a + b) / (s + a) > 0, and the
             * denominator is > 0 unless a = L = 0 (stick with lf = 0: the
             * 0/0 case, whose limit from every direction is 0). */
            const double sba = b * (s + a + b) / (s + a);
            e = a > 0.0 ? rho * a * a / (a * sba + rho * L * (s + b)) : 0.0;
        } else {
            /* On or outside the cone Appendix B's denominator a + rho mu ln
             * - s can vanish or go negative (L > 2 mu ln), which would make
             * the system indefinite.  (s - b) / (mu ln) is the FB analogue
             * of the min-map compliance: equal to Appendix B on the cone
             * (both a / (mu ln)), positive, and its fixed points outside the
             * cone do not exist, so the iteration is pulled back. */
            e = (s - b) / mln;
        }
    }
    double cap = PL_NCP_E_CAP * rho;
    if (!(e <= cap)) /* also catches NaN from mln underflow */
        e = cap;
    return e;
}

/* Coulomb friction of one contact with nt (1 or 2) tangent rows
 * (ncp_eval_friction). */
PL_HD void ncp_friction(int fn, int nt, const double *y, const double *lf, double ln, double mu,
                        double rho, double *phi, double *omega, double *e)
{
    if (!(mu > 0.0 && ln > 0.0)) {
        /* Inactive contact or no friction: phi = rho lf (Appendix B uses the
         * identity; rho keeps the row in the units and scale of the others),
         * so the Newton row reads rho (lf + dlf) = 0. */
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
    /* One compliance for the contact (2-norms over its tangents, PAPER_NOTES
     * 9): e I keeps lf parallel to y. */
    *omega = 1.0;
    *e = ncp_friction_compliance(fn, sqrt(a2), sqrt(L2), ln, mu, rho);
    for (int i = 0; i < nt; ++i) phi[i] = y[i] + *e * lf[i];
}

/* Bounded row, lambda in [lo, hi] (ncp_eval_bounded). */
PL_HD void ncp_bounded(double delta, double lambda, double lo, double hi, double r, double *phi,
                       double *omega, double *e)
{
    /* lambda - mid(lo, lambda - delta / r, hi), times r; r > 0, so the
     * comparisons hold for infinite bounds too. */
    double t = lambda - delta / r;
    /* Ties take the delta branch, as the min map does, so that a row at
     * rest on its bound (delta = 0, lambda = lo) keeps a Jacobian row. */
    if (t < lo) {
        *phi = r * (lambda - lo), *omega = 0.0, *e = r;
    } else if (t > hi) {
        *phi = r * (lambda - hi), *omega = 0.0, *e = r;
    } else {
        *phi = delta, *omega = 1.0, *e = 0.0;
    }
}

/* Bilateral row with compliance E_b (ncp_eval_bilateral). */
PL_HD void ncp_bilateral(double delta, double lambda, double compliance, double *phi,
                         double *omega, double *e)
{
    *phi = delta + compliance * lambda;
    *omega = 1.0;
    *e = compliance;
}

#endif
