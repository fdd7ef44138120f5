/* material_law.h - the isotropic laws on the singular values, the one
 * implementation for the CPU (material_law.c: energy, stress, Hessian;
 * local_solve.h) and the GPU (cuda/hyper_cuda.cu through local_solve.h);
 * compiled as C and as CUDA (pliant/hostdevice.h).
 *
 * All three laws are isotropic, so psi(F) = psi_hat(s) on the singular
 * values (signed for 3x3: an inverted element has s2 < 0):
 *   ARAP          psi_hat = mu sum (s_i - 1)^2
 *   corotational  + lambda/2 (sum s_i - d)^2       (tr(R^T F - I) = sum s_i - d)
 *   Neo-Hookean   mu/2 (sum s_i^2 - d) - mu ln J + lambda/2 (ln J)^2,  J = prod s_i
 * For membranes (d = 2) these are the same formulas on the two singular
 * values of the 3x2 F; lambda is then the plane-stress value (elements.c). */
#ifndef PLIANT_HYPER_MATERIAL_LAW_H
#define PLIANT_HYPER_MATERIAL_LAW_H

#include <math.h>

#include "hyperelastic.h"
#include "pliant/hostdevice.h"

/* psi_hat(s) for the d singular values s (d = 3 or 2, a constant in every
 * caller) of law `material` (pl_hyper_material) with Lame parameters mu,
 * la; when g / H are not NULL, its gradient g[d] and Hessian H (d x d).
 * Returns 0, or -1 outside the law's domain (Neo-Hookean with some
 * s <= 0), where psi is +INFINITY and g, H are left unset. */
PL_HD int hm_sv_eval(const int d, int material, double mu, double la, const double *s,
                     double *psi, double *g, double *H)
{
    if (material == PL_HYPER_NEOHOOKEAN) {
        double lnJ = 0.0, I1 = 0.0;
        PL_UNROLL
        for (int i = 0; i < d; ++i) {
            if (!(s[i] > 0.0)) {
                *psi = INFINITY;
                return -1;
            }
            lnJ += log(s[i]);
            I1 += s[i] * s[i];
        }
        *psi = 0.5 * mu * (I1 - d) - mu * lnJ + 0.5 * la * lnJ * lnJ;
        /* d divisions, not d (d + 1) + d: the prox's Newton evaluates this
         * at every step, and on the GPU each division is a long dependent
         * sequence (docs/benchmarks.md, "The local step's Newton in fewer
         * divisions") */
        double inv[3] = {0, 0, 0};
        if (g || H) /* not for psi alone (the line search's objective) */
            PL_UNROLL
            for (int i = 0; i < d; ++i) inv[i] = 1.0 / s[i];
        if (g)
            PL_UNROLL
            for (int i = 0; i < d; ++i) g[i] = mu * s[i] + (la * lnJ - mu) * inv[i];
        if (H)
            PL_UNROLL
            for (int i = 0; i < d; ++i)
                PL_UNROLL
                for (int j = 0; j < d; ++j)
                    H[i * d + j] = la * (inv[i] * inv[j]) +
                                   (i == j ? mu + (mu - la * lnJ) * (inv[i] * inv[i]) : 0.0);
        return 0;
    }
    /* ARAP and corotational: quadratic in the (signed) singular values */
    double lc = material == PL_HYPER_COROTATIONAL ? la : 0.0;
    double tr = -d, sq = 0.0;
    PL_UNROLL
    for (int i = 0; i < d; ++i) {
        tr += s[i];
        sq += (s[i] - 1.0) * (s[i] - 1.0);
    }
    *psi = mu * sq + 0.5 * lc * tr * tr;
    if (g)
        PL_UNROLL
        for (int i = 0; i < d; ++i) g[i] = 2.0 * mu * (s[i] - 1.0) + lc * tr;
    if (H)
        PL_UNROLL
        for (int i = 0; i < d; ++i)
            PL_UNROLL
            for (int j = 0; j < d; ++j) H[i * d + j] = lc + (i == j ? 2.0 * mu : 0.0);
    return 0;
}

/* Neo-Hookean's first Piola-Kirchhoff stress of a tetrahedron (F 3 x 3,
 * row-major) without an SVD:
 *     P = mu F + (lambda ln J - mu) F^-T,   F^-T = cof(F) / J,  J = det F,
 * the tensor U diag(g) V^T that hm_sv_eval's gradient g on the singular
 * values gives (mu s_i + (lambda ln J - mu) / s_i), to round-off.  Outside
 * the domain (J <= 0, where the signed singular values have one s <= 0) P
 * is NaN, as there.  The force residual evaluates it at every iteration
 * (forceTolerance): an SVD is most of its cost on the CPU and a long
 * dependent chain on the GPU (docs/benchmarks.md, "The cable finger's
 * iteration at about 73 us"). */
PL_HD void hm_neohookean_piola3(double mu, double la, const double *F, double *P)
{
    double C[9]; /* cof(F): C[a][b] = (-1)^(a+b) minor(a, b) */
    C[0] = F[4] * F[8] - F[5] * F[7];
    C[1] = F[5] * F[6] - F[3] * F[8];
    C[2] = F[3] * F[7] - F[4] * F[6];
    C[3] = F[2] * F[7] - F[1] * F[8];
    C[4] = F[0] * F[8] - F[2] * F[6];
    C[5] = F[1] * F[6] - F[0] * F[7];
    C[6] = F[1] * F[5] - F[2] * F[4];
    C[7] = F[2] * F[3] - F[0] * F[5];
    C[8] = F[0] * F[4] - F[1] * F[3];
    const double J = F[0] * C[0] + F[1] * C[1] + F[2] * C[2];
    const double c = J > 0.0 ? (la * log(J) - mu) / J : NAN;
    PL_UNROLL
    for (int i = 0; i < 9; ++i) P[i] = mu * F[i] + c * C[i];
}

#endif
