/* material_hessian.c - dP/dF of an isotropic law, optionally projected to
 * PSD, or (ARAP and corotational, psd == PL_HESSIAN_FIXED_ROTATION) with the
 * element's rotation held fixed: SOFA's corotational stiffness R K0 R^T
 * with K0 linear elasticity, dP/dF = R (mu (I + T) + lambda vec(I) vec(I)^T)
 * R^T (T: transposition), PSD by construction.
 *
 * In the singular frame, F^ = U^T F V (U the full 3x3 left rotation), the
 * Hessian of psi(F^) at F^ = diag(s) is block-diagonal (Irving et al. 2004,
 * Teran et al. 2005):
 *   - the d x d block on the diagonal entries F^_ii: d2 psi_hat / ds2;
 *   - for each pair i < j < d a 2x2 block on (F^_ij, F^_ji):
 *     [[A, B], [B, A]], A = (c + t)/2, B = (c - t)/2 with
 *     c = (g_i - g_j)/(s_i - s_j), t = (g_i + g_j)/(s_i + s_j);
 *   - membranes (d = 2): the out-of-plane entries F^_2j each see g_j / s_j
 *     (stretching s_j to sqrt(s_j^2 + e^2) costs g_j e^2 / (2 s_j)).
 * H = T H^ T^T with T_(ab),(ij) = U_ai V_bj orthogonal, so clamping each
 * block's eigenvalues at zero is exactly the PSD projection of H. */
#include <math.h>
#include <string.h>

#include <pliant/roles.h>

#include "hyperelastic.h"
#include "material_internal.h"

/* Clamps the 2x2 block [[A, B], [B, A]] (eigenvalues A + B, A - B). */
static void clamp_pair(double *A, double *B)
{
    double l1 = fmax(0.0, *A + *B), l2 = fmax(0.0, *A - *B);
    *A = 0.5 * (l1 + l2);
    *B = 0.5 * (l1 - l2);
}

void pl_hyper_dPdF(const pl_hyper_law *m, const double *F, int psd, double *H)
{
    const int d = m->d, n = 3 * d;
    double U[9], s[3], V[9], g[3], Hs[9], psi;
    hyper_svd(d, F, U, s, V);
    if (hyper_sv_eval(m, s, &psi, g, Hs) != 0) {
        for (int i = 0; i < n * n; ++i) H[i] = NAN;
        return;
    }
    double Hh[81];
    memset(Hh, 0, sizeof Hh);
    if (psd) hyper_project_psd(d, Hs);
    for (int i = 0; i < d; ++i)
        for (int j = 0; j < d; ++j) Hh[(i * d + i) * n + (j * d + j)] = Hs[i * d + j];
    for (int i = 0; i < d; ++i)
        for (int j = i + 1; j < d; ++j) {
            double c, t;
            hyper_sv_pair(m, s, g, i, j, &c, &t);
            /* the rotation held fixed (psd == 2, the quadratic laws): R K0 R^T with K0
             * linear elasticity (symmetric strain): pair blocks [[mu, mu], [mu, mu]],
             * c = 2 mu, t = 0 (an infinitesimal rotation of the element costs nothing) */
            if (psd == PL_HESSIAN_FIXED_ROTATION && m->material != PL_HYPER_NEOHOOKEAN) t = 0.0;
            double A = 0.5 * (c + t), B = 0.5 * (c - t);
            if (psd) clamp_pair(&A, &B);
            int p = i * d + j, q = j * d + i;
            Hh[p * n + p] = Hh[q * n + q] = A;
            Hh[p * n + q] = Hh[q * n + p] = B;
        }
    if (d == 2)
        for (int j = 0; j < 2; ++j) {
            double c, t;
            hyper_sv_pair(m, s, g, j, 2, &c, &t);
            int p = 2 * d + j;
            Hh[p * n + p] = psd ? fmax(0.0, c) : c;
        }
    /* T_(ab),(ij) = U_ai V_bj;  H = T Hh T^T */
    double T[81], W[81];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < d; ++b)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < d; ++j) T[(a * d + b) * n + (i * d + j)] = U[a * 3 + i] * V[b * d + j];
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            double v = 0.0;
            for (int k = 0; k < n; ++k) v += T[r * n + k] * Hh[k * n + c];
            W[r * n + c] = v;
        }
    for (int r = 0; r < n; ++r)
        for (int c = r; c < n; ++c) {
            double v = 0.0;
            for (int k = 0; k < n; ++k) v += W[r * n + k] * T[c * n + k];
            H[r * n + c] = H[c * n + r] = v;
        }
}
