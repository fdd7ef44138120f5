/* local_solve.c - the per-element local step.
 *
 * ARAP: the projection on rotations (closest proper rotation, closest 3x2
 * matrix with orthonormal columns for membranes).
 *
 * ADMM-PD: p = argmin psi(p) + what/2 ||p - z||^2.  psi is isotropic, so by
 * von Neumann's trace inequality (in its signed form for 3x3) p shares the
 * singular vectors of z and only the d singular values are unknown:
 *   minimise f(s) = psi_hat(s) + what/2 ||s - z_hat||^2.
 * Newton on f with the Hessian's eigenvalues clamped positive and an Armijo
 * backtracking line search; for Neo-Hookean every step is also shortened to
 * keep s > 0 (ln J is the barrier).  Corotational f is quadratic: one step. */
#include <math.h>

#include "hyperelastic.h"
#include "material_internal.h"
#include "small_matrix.h"

/* f(s), or +INFINITY outside the law's domain. */
static double objective(const pl_hyper_law *m, double what, const double *s, const double *zh)
{
    double psi, q = 0.0;
    if (hyper_sv_eval(m, s, &psi, NULL, NULL) != 0) return INFINITY;
    for (int i = 0; i < m->d; ++i) q += (s[i] - zh[i]) * (s[i] - zh[i]);
    return psi + 0.5 * what * q;
}

/* dx = -H^-1 r by Cholesky when H (symmetric d x d) is comfortably positive
 * definite (the usual case: what I is added); otherwise through its
 * eigen-decomposition with eigenvalues clamped from below by floor_, which
 * still gives a descent direction. */
static void newton_direction(int d, const double *H, const double *r, double floor_, double *dx)
{
    double L[9] = {0};
    int pd = 1;
    for (int j = 0; j < d && pd; ++j) {
        double v = H[j * d + j];
        for (int k = 0; k < j; ++k) v -= L[j * d + k] * L[j * d + k];
        if (!(v > floor_)) {
            pd = 0;
            break;
        }
        L[j * d + j] = sqrt(v);
        for (int i = j + 1; i < d; ++i) {
            double w = H[i * d + j];
            for (int k = 0; k < j; ++k) w -= L[i * d + k] * L[j * d + k];
            L[i * d + j] = w / L[j * d + j];
        }
    }
    if (pd) {
        for (int i = 0; i < d; ++i) { /* L y = -r, then L^T dx = y */
            double v = -r[i];
            for (int k = 0; k < i; ++k) v -= L[i * d + k] * dx[k];
            dx[i] = v / L[i * d + i];
        }
        for (int i = d - 1; i >= 0; --i) {
            double v = dx[i];
            for (int k = i + 1; k < d; ++k) v -= L[k * d + i] * dx[k];
            dx[i] = v / L[i * d + i];
        }
        return;
    }
    double lam[3], Q[9];
    pl_hyper_sym_eigen(d, H, lam, Q);
    for (int i = 0; i < d; ++i) dx[i] = 0.0;
    for (int k = 0; k < d; ++k) {
        double proj = 0.0;
        for (int i = 0; i < d; ++i) proj += Q[i * d + k] * r[i];
        double l = fmax(lam[k], floor_);
        for (int i = 0; i < d; ++i) dx[i] -= Q[i * d + k] * proj / l;
    }
}

static double inf_norm(int d, const double *v)
{
    double m = 0.0;
    for (int i = 0; i < d; ++i) m = fmax(m, fabs(v[i]));
    return m;
}

/* max |grad f(s)|, +INFINITY outside the domain. */
static double residual(const pl_hyper_law *m, double what, const double *s, const double *zh,
                       double *r, double *H)
{
    double psi, g[3], rn = 0.0;
    if (hyper_sv_eval(m, s, &psi, g, H) != 0) return INFINITY;
    for (int i = 0; i < m->d; ++i) {
        r[i] = g[i] + what * (s[i] - zh[i]);
        rn = fmax(rn, fabs(r[i]));
    }
    return rn;
}

/* Minimises f over the singular values; returns iterations or -1. */
static int solve_singular_values(const pl_hyper_law *m, double what, const double *zh, double *s)
{
    const int d = m->d;
    const int max_iter = 100;
    double scale = 0.0;
    for (int i = 0; i < d; ++i) scale = fmax(scale, fabs(zh[i]));
    const double tol = 1e-13 * what * fmax(1.0, scale);
    /* start at z_hat; Neo-Hookean needs s > 0 (its barrier keeps the minimiser
     * of an inverted or collapsed z near 0.5, so start no lower than 0.1) */
    for (int i = 0; i < d; ++i)
        s[i] = m->material == PL_HYPER_NEOHOOKEAN ? fmax(zh[i], 0.1 * fmax(1.0, scale)) : zh[i];
    double f = objective(m, what, s, zh);
    for (int it = 0; it < max_iter; ++it) {
        double H[9], r[3], rt[3];
        double rn = residual(m, what, s, zh, r, H);
        if (rn <= tol) return it;
        for (int i = 0; i < d; ++i) H[i * d + i] += what;
        double dx[3];
        newton_direction(d, H, r, 1e-8 * what, dx);
        double alpha = 1.0;
        if (m->material == PL_HYPER_NEOHOOKEAN) /* stay inside s > 0 */
            for (int i = 0; i < d; ++i)
                if (dx[i] < 0.0) alpha = fmin(alpha, -0.95 * s[i] / dx[i]);
        double slope = hm_ddot(d, r, dx), trial[3], ft = INFINITY;
        int accepted = 0;
        for (int ls = 0; ls < 60; ++ls) {
            for (int i = 0; i < d; ++i) trial[i] = s[i] + alpha * dx[i];
            ft = objective(m, what, trial, zh);
            if (ft <= f + 1e-4 * alpha * slope) {
                accepted = 1;
            } else if (ls == 0 && fabs(ft - f) <= 1e-11 * fabs(f)) {
                /* near the minimum the decrease of f drowns in its round-off;
                 * there the residual judges the full Newton step */
                double Ht[9];
                accepted = residual(m, what, trial, zh, rt, Ht) < rn;
            }
            if (accepted) break;
            alpha *= 0.5;
        }
        if (!accepted || alpha * inf_norm(d, dx) <= 1e-16 * inf_norm(d, s))
            return rn <= 1e4 * tol ? it : -1; /* no representable progress */
        for (int i = 0; i < d; ++i) s[i] = trial[i];
        f = ft;
    }
    return -1;
}

int pl_hyper_local_solve(const pl_hyper_law *m, double what, const double *z, double *p)
{
    const int d = m->d;
    for (int i = 0; i < 3 * d; ++i)
        if (!isfinite(z[i])) return -1;
    if (m->material == PL_HYPER_ARAP) {
        if (d == 3)
            pl_hyper_polar3(z, p);
        else
            pl_hyper_polar32(z, p);
        return 0;
    }
    double U[9], zh[3], V[9], s[3];
    hyper_svd(d, z, U, zh, V);
    int it = solve_singular_values(m, what, zh, s);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < d; ++b) {
            double v = 0.0;
            for (int i = 0; i < d; ++i) v += U[a * 3 + i] * s[i] * V[b * d + i];
            p[a * d + b] = v;
        }
    return it;
}
