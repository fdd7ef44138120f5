/* material_law.c - ARAP, corotational and Neo-Hookean energy densities and
 * their first Piola-Kirchhoff stress, on the CPU.
 *
 * The laws on the singular values (psi_hat, its gradient g and Hessian)
 * are material_law.h, shared with the GPU; here: the Lame parameters, the
 * full-U SVD the Hessian needs, psi(F) and P = U diag(g) V^T. */
#include <math.h>

#include "hyperelastic.h"
#include "material_internal.h"
#include "material_law.h"
#include "small_matrix.h"
#include "svd.h"

int hyper_lame(double E, double nu, int membrane, double *mu, double *lambda, pl_error *err)
{
    if (!(E > 0.0) || !isfinite(E))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "youngModulus must be a positive number [Pa], got %g", E);
    if (!(nu > -1.0 && nu < 0.5))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "poissonRatio must lie in (-1, 0.5), got %g", nu);
    double m = E / (2.0 * (1.0 + nu));
    double l = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    /* plane stress: eliminating the out-of-plane strain of a thin sheet */
    if (membrane) l = 2.0 * m * l / (l + 2.0 * m);
    *mu = m;
    *lambda = l;
    return PL_OK;
}

double hyper_law_weight(const pl_hyper_law *m)
{
    return m->material == PL_HYPER_ARAP ? 2.0 * m->mu : 2.0 * m->mu + m->lambda;
}

void hyper_svd(int d, const double *F, double *U, double *s, double *V)
{
    if (d == 3) {
        hm_svd3(F, U, s, V);
        return;
    }
    double U2[6];
    hm_svd32(F, U2, s, V);
    double u0[3] = {U2[0], U2[2], U2[4]}, u1[3] = {U2[1], U2[3], U2[5]}, u2[3];
    hm_cross(u0, u1, u2);
    for (int r = 0; r < 3; ++r) {
        U[r * 3 + 0] = u0[r];
        U[r * 3 + 1] = u1[r];
        U[r * 3 + 2] = u2[r];
    }
}

int hyper_sv_eval(const pl_hyper_law *m, const double *s, double *psi, double *g, double *H)
{
    /* d as a constant in each call: the shared code is written for it */
    if (m->d == 3) return hm_sv_eval(3, (int)m->material, m->mu, m->lambda, s, psi, g, H);
    return hm_sv_eval(2, (int)m->material, m->mu, m->lambda, s, psi, g, H);
}

/* Keeps a denominator away from zero, with its sign. */
static double guard(double x)
{
    const double eps = 1e-12;
    if (fabs(x) >= eps) return x;
    return x < 0.0 ? -eps : eps;
}

void hyper_sv_pair(const pl_hyper_law *m, const double *s, const double *g, int i, int j,
                   double *c, double *t)
{
    const int d = m->d;
    const double mu = m->mu, la = m->lambda;
    if (j == d) { /* membrane out-of-plane: s_j = 0, g_j = 0 */
        *c = *t = g[i] / guard(s[i]);
        return;
    }
    if (m->material == PL_HYPER_NEOHOOKEAN) {
        double lnJ = 0.0;
        for (int k = 0; k < d; ++k) lnJ += log(s[k]);
        double q = (la * lnJ - mu) / (s[i] * s[j]);
        *c = mu - q;
        *t = mu + q;
        return;
    }
    double lc = m->material == PL_HYPER_COROTATIONAL ? la : 0.0;
    double tr = -d;
    for (int k = 0; k < d; ++k) tr += s[k];
    *c = 2.0 * mu; /* the coupling term is the same for every i: it cancels */
    *t = 2.0 * mu + (2.0 * lc * tr - 4.0 * mu) / guard(s[i] + s[j]);
}

double hyper_psi(const pl_hyper_law *m, const double *F)
{
    const int d = m->d;
    if (m->material == PL_HYPER_NEOHOOKEAN) {
        /* from the invariants directly (independent of the SVD) */
        double I1 = hm_ddot(3 * d, F, F), J;
        if (d == 3) {
            J = hm_det3(F);
        } else {
            double c00 = F[0] * F[0] + F[2] * F[2] + F[4] * F[4];
            double c11 = F[1] * F[1] + F[3] * F[3] + F[5] * F[5];
            double c01 = F[0] * F[1] + F[2] * F[3] + F[4] * F[5];
            double detC = c00 * c11 - c01 * c01;
            J = detC > 0.0 ? sqrt(detC) : 0.0;
        }
        if (!(J > 0.0)) return INFINITY;
        double lnJ = log(J);
        return 0.5 * m->mu * (I1 - d) - m->mu * lnJ + 0.5 * m->lambda * lnJ * lnJ;
    }
    double U[9], s[3], V[9], psi;
    hyper_svd(d, F, U, s, V);
    hyper_sv_eval(m, s, &psi, NULL, NULL);
    return psi;
}

void hyper_piola(const pl_hyper_law *m, const double *F, double *P)
{
    const int d = m->d;
    if (d == 3 && m->material == PL_HYPER_NEOHOOKEAN) { /* no SVD needed */
        hm_neohookean_piola3(m->mu, m->lambda, F, P);
        return;
    }
    double U[9], s[3], V[9], g[3], psi;
    hyper_svd(d, F, U, s, V);
    if (hyper_sv_eval(m, s, &psi, g, NULL) != 0) {
        for (int i = 0; i < 3 * d; ++i) P[i] = NAN;
        return;
    }
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < d; ++b) {
            double v = 0.0;
            for (int i = 0; i < d; ++i) v += U[a * 3 + i] * g[i] * V[b * d + i];
            P[a * d + b] = v;
        }
}
