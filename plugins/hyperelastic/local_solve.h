/* local_solve.h - the per-element local step, the one implementation for
 * the CPU (local_solve.c, hyper_local_solve) and the GPU
 * (cuda/hyper_cuda.cu); compiled as C and as CUDA (pliant/hostdevice.h).
 *
 * ARAP: the projection on rotations (closest proper rotation, closest 3x2
 * matrix with orthonormal columns for membranes).
 *
 * ADMM-PD: p = argmin psi(p) + what/2 ||p - z||^2.  psi is isotropic, so by
 * von Neumann's trace inequality (in its signed form for 3x3) p shares the
 * singular vectors of z and only the d singular values are unknown:
 *   minimise f(s) = psi_hat(s) + what/2 ||s - z_hat||^2.
 * Newton on f with the Hessian's eigenvalues clamped positive, warm started
 * from the element's previous solution, and a residual test or an Armijo
 * backtracking line search; for Neo-Hookean every step is also shortened to
 * keep s > 0 (ln J is the barrier).  Corotational f is quadratic: solved in
 * closed form.
 *
 * d (3: tetrahedra, F 3x3; 2: membranes, F 3x2) is a parameter that every
 * caller passes as a constant, so that on the GPU the small arrays stay in
 * registers. */
#ifndef PLIANT_HYPER_LOCAL_SOLVE_H
#define PLIANT_HYPER_LOCAL_SOLVE_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "hyperelastic.h"
#include "material_law.h"
#include "pliant/hostdevice.h"
#include "svd.h"
#include "sym_eigen.h"

/* f(s), or +INFINITY outside the law's domain. */
PL_HD double hm_objective(const int d, int mat, double mu, double la, double what, const double *s,
                          const double *zh)
{
    double psi, q = 0.0;
    if (hm_sv_eval(d, mat, mu, la, s, &psi, NULL, NULL) != 0) return INFINITY;
    PL_UNROLL
    for (int i = 0; i < d; ++i) q += (s[i] - zh[i]) * (s[i] - zh[i]);
    return psi + 0.5 * what * q;
}

/* r = grad f(s) and H = psi_hat's Hessian; returns max |r_i|, +INFINITY
 * outside the domain. */
PL_HD double hm_residual(const int d, int mat, double mu, double la, double what, const double *s,
                         const double *zh, double *r, double *H)
{
    double psi, g[3], rn = 0.0;
    if (hm_sv_eval(d, mat, mu, la, s, &psi, g, H) != 0) return INFINITY;
    PL_UNROLL
    for (int i = 0; i < d; ++i) {
        r[i] = g[i] + what * (s[i] - zh[i]);
        rn = fmax(rn, fabs(r[i]));
    }
    return rn;
}

PL_HD double hm_inf_norm(const int d, const double *v)
{
    double m = fabs(v[0]);
    PL_UNROLL
    for (int i = 1; i < d; ++i) m = fmax(m, fabs(v[i]));
    return m;
}

/* dx = -H^-1 r by Cholesky when H (symmetric d x d) is comfortably positive
 * definite (the usual case: what I is added); otherwise through its
 * eigen-decomposition with eigenvalues clamped from below by floor_, which
 * still gives a descent direction.  Returns whether Cholesky did it. */
PL_HD bool hm_newton_direction(const int d, const double *H, const double *r, double floor_,
                               double *dx)
{
    /* L's off-diagonal entries and rinv[j] = 1 / L_jj: the solves below
     * multiply, so the dependent chain has d divisions, not 3 d (on the GPU
     * each is a long sequence; docs/benchmarks.md, "The local step's Newton
     * in fewer divisions") */
    double L[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, rinv[3] = {0, 0, 0};
    bool pd = true;
    PL_UNROLL
    for (int j = 0; j < d; ++j) {
        if (!pd) break;
        double v = H[j * d + j];
        PL_UNROLL
        for (int k = 0; k < j; ++k) v -= L[j * d + k] * L[j * d + k];
        if (!(v > floor_)) {
            pd = false;
            break;
        }
        rinv[j] = 1.0 / sqrt(v);
        PL_UNROLL
        for (int i = j + 1; i < d; ++i) {
            double w = H[i * d + j];
            PL_UNROLL
            for (int k = 0; k < j; ++k) w -= L[i * d + k] * L[j * d + k];
            L[i * d + j] = w * rinv[j];
        }
    }
    if (pd) {
        PL_UNROLL
        for (int i = 0; i < d; ++i) { /* L y = -r, then L^T dx = y */
            double v = -r[i];
            PL_UNROLL
            for (int k = 0; k < i; ++k) v -= L[i * d + k] * dx[k];
            dx[i] = v * rinv[i];
        }
        PL_UNROLL
        for (int i = d - 1; i >= 0; --i) {
            double v = dx[i];
            PL_UNROLL
            for (int k = i + 1; k < d; ++k) v -= L[k * d + i] * dx[k];
            dx[i] = v * rinv[i];
        }
        return true;
    }
    double lam[3], Q[9], M[9];
    hm_sym_eigen(d, H, M, lam, Q);
    PL_UNROLL
    for (int i = 0; i < d; ++i) dx[i] = 0.0;
    PL_UNROLL
    for (int k = 0; k < d; ++k) {
        double proj = 0.0;
        PL_UNROLL
        for (int i = 0; i < d; ++i) proj += Q[i * d + k] * r[i];
        double l = fmax(lam[k], floor_);
        PL_UNROLL
        for (int i = 0; i < d; ++i) dx[i] -= Q[i * d + k] * proj / l;
    }
    return false;
}

/* The prox's stopping rule and its cap.  Tolerance: max_i |df/ds_i| <=
 * HM_PROX_TOL what max(1, |z_hat|); f's Hessian is at least about what
 * I, so s is then within HM_PROX_TOL max(1, |z_hat|) of the minimiser, and
 * p = U diag(s) V^T within that of the exact prox.  The global step sees p
 * through w (p - u) in its right-hand side, and the ADMM fixed point keeps
 * the prox's error: the force residual of the hanging bar after 1000
 * local-global iterations (test_cable_equilibrium, < 1e-7 N) is 3.8e-7 N
 * with 1e-10, 2.8e-9 N with 1e-12, so 1e-12 it is: about 10^4 ulps of
 * what |z_hat|, where round-off does not yet stall the iteration (1e-13
 * did, and then spent up to 60 halvings per Newton step chasing it).
 * Newton converges quadratically, and from the warm start of the previous
 * local-global iterate 1 or 2 steps reach it.  A solve that reaches
 * HM_PROX_MAX_ITER, or stalls above 100 times the tolerance, is counted as
 * capped (fem_term.c publishes the count; bench_local prints it). */
#define HM_PROX_TOL 1e-12
#define HM_PROX_MAX_ITER 30
#define HM_PROX_MAX_HALVINGS 30

/* Corotational: f is quadratic, (2 mu + what) s_i + lc (sum s - d) =
 * 2 mu + what zh_i; summing gives sum s, then each s_i. */
PL_HD void hm_corotational_prox(const int d, double mu, double lc, double what, const double *zh,
                                double *s)
{
    const double a = 2.0 * mu + what;
    double sz = 0.0;
    PL_UNROLL
    for (int i = 0; i < d; ++i) sz += zh[i];
    const double t = (2.0 * mu * d + what * sz + lc * d * d) / (a + d * lc);
    PL_UNROLL
    for (int i = 0; i < d; ++i) s[i] = (2.0 * mu + what * zh[i] - lc * (t - d)) / a;
}

/* Minimises f over the d singular values from z_hat; returns the
 * iterations or -1 (capped, or no progress above the tolerance).
 * warm (d values, or NULL): in, the previous solve's s of this element
 * (used as the start when warm[0] > 0, i.e. it was set); out, this
 * solve's s.  *halvings (if not NULL) += the line-search halvings.
 * Each iteration: the Newton step on f (Hessian eigenvalues clamped
 * positive; for Neo-Hookean shortened to keep s > 0).  Where the Hessian
 * is positive definite (Cholesky succeeds) the step is taken when it
 * lowers the residual, which the next iteration needs anyway; otherwise,
 * and when it does not, an Armijo backtracking on f decides. */
PL_HD int hm_solve_singular_values(const int d, int mat, double mu, double la, double what,
                                   const double *zh, double *s, double *warm, int *halvings)
{
    const double scale = hm_inf_norm(d, zh);
    const double tol = HM_PROX_TOL * what * fmax(1.0, scale);
    if (mat == PL_HYPER_COROTATIONAL) { /* closed form */
        hm_corotational_prox(d, mu, la, what, zh, s);
        return 0;
    }
    /* start at the previous solve's s, else at z_hat; Neo-Hookean needs
     * s > 0 (its barrier keeps the minimiser of an inverted or collapsed z
     * near 0.5, so start no lower than 0.1) */
    const bool warm_ok = warm && warm[0] > 0.0;
    PL_UNROLL
    for (int i = 0; i < d; ++i)
        s[i] = warm_ok ? warm[i]
                       : mat == PL_HYPER_NEOHOOKEAN ? fmax(zh[i], 0.1 * fmax(1.0, scale)) : zh[i];
    /* zeroed: gcc cannot see that hm_residual fills the d x d block (and a
     * Release build warns); the device compiler drops the dead stores */
    double H[9] = {0}, r[3] = {0};
    double rn = hm_residual(d, mat, mu, la, what, s, zh, r, H);
    if (!(rn < INFINITY)) { /* a stale warm start outside the domain: cold */
        PL_UNROLL
        for (int i = 0; i < d; ++i) s[i] = fmax(zh[i], 0.1 * fmax(1.0, scale));
        rn = hm_residual(d, mat, mu, la, what, s, zh, r, H);
    }
    int it = 0, status = -1;
    for (;; ++it) {
        if (rn <= tol) {
            status = it;
            break;
        }
        if (it == HM_PROX_MAX_ITER) break;
        PL_UNROLL
        for (int i = 0; i < d; ++i) H[i * d + i] += what;
        double dx[3];
        const bool pd = hm_newton_direction(d, H, r, 1e-8 * what, dx);
        double alpha = 1.0;
        if (mat == PL_HYPER_NEOHOOKEAN) /* stay inside s > 0 */
            PL_UNROLL
            for (int i = 0; i < d; ++i)
                if (dx[i] < 0.0) alpha = fmin(alpha, -0.95 * s[i] / dx[i]);
        double trial[3], rt[3] = {0}, Ht[9] = {0};
        PL_UNROLL
        for (int i = 0; i < d; ++i) trial[i] = s[i] + alpha * dx[i];
        double rnt = hm_residual(d, mat, mu, la, what, trial, zh, rt, Ht);
        if (!(pd && rnt < rn)) { /* Armijo backtracking on f from this step */
            const double f = hm_objective(d, mat, mu, la, what, s, zh);
            double slope = r[0] * dx[0];
            PL_UNROLL
            for (int i = 1; i < d; ++i) slope += r[i] * dx[i];
            bool accepted = false;
            for (int ls = 0; ls < HM_PROX_MAX_HALVINGS; ++ls) {
                if (ls > 0) {
                    alpha *= 0.5;
                    if (halvings) ++*halvings;
                    PL_UNROLL
                    for (int i = 0; i < d; ++i) trial[i] = s[i] + alpha * dx[i];
                }
                const double ft = hm_objective(d, mat, mu, la, what, trial, zh);
                if (ft <= f + 1e-4 * alpha * slope) {
                    accepted = true;
                    break;
                }
            }
            if (!accepted || alpha * hm_inf_norm(d, dx) <= 1e-16 * hm_inf_norm(d, s)) {
                status = rn <= 1e2 * tol ? it : -1; /* no representable progress */
                break;
            }
            rnt = hm_residual(d, mat, mu, la, what, trial, zh, rt, Ht);
        }
        PL_UNROLL
        for (int i = 0; i < d; ++i) s[i] = trial[i], r[i] = rt[i];
        PL_UNROLL
        for (int i = 0; i < d * d; ++i) H[i] = Ht[i];
        rn = rnt;
    }
    if (warm)
        PL_UNROLL
        for (int i = 0; i < d; ++i) warm[i] = s[i];
    return status;
}

/* p (3 x d) = the local step of z (3 x d), both row-major: the closest
 * rotation (ARAP; closest orthonormal columns for d = 2) or the prox of the
 * law `mat` with weight what (warm: HM_WARM_LEN(d) values in and out, or
 * NULL: the element's previous solve, set when warm[0] > 0; its V starts
 * the SVD's sweeps, and for Neo-Hookean its s the Newton of
 * hm_solve_singular_values; *halvings, if not NULL, += its line-search
 * halvings).  Returns the Newton iterations (0 for ARAP),
 * or -1 if z is not finite or the Newton iteration missed its tolerance
 * (p is then its last iterate). */
PL_HD int hm_local_solve(const int d, int mat, double mu, double la, double what, const double *z,
                         double *p, double *warm, int *halvings)
{
    PL_UNROLL
    for (int i = 0; i < 3 * d; ++i)
        if (!isfinite(z[i])) return -1;
    double U[9], zh[3], V[9]; /* U: 3 x d */
    /* the previous solve's V starts the SVD's Jacobi sweeps (warm[0] > 0:
     * set; see HM_WARM_LEN) */
    const bool use = warm && warm[0] > 0.0;
    if (d == 3)
        hm_svd3_from(z, warm ? warm + d : NULL, use, U, zh, V);
    else
        hm_svd32_from(z, warm ? warm + d : NULL, use, U, zh, V);
    if (warm) {
        PL_UNROLL
        for (int k = 0; k < d * d; ++k) warm[d + k] = V[k];
        /* the flag warm[0] > 0: z's largest singular value; for Neo-Hookean
         * hm_solve_singular_values puts its s there (its Newton's start) */
        if (mat != PL_HYPER_NEOHOOKEAN)
            PL_UNROLL
            for (int k = 0; k < d; ++k) warm[k] = zh[k];
    }
    if (mat == PL_HYPER_ARAP) {
        hm_polar_from_svd(d, U, V, p);
        return 0;
    }
    double s[3];
    /* (the corotational closed form neither reads nor writes warm) */
    int it = hm_solve_singular_values(d, mat, mu, la, what, zh, s, warm, halvings);
    PL_UNROLL
    for (int a = 0; a < 3; ++a)
        PL_UNROLL
        for (int b = 0; b < d; ++b) {
            double v = 0.0;
            PL_UNROLL
            for (int i = 0; i < d; ++i) v += U[a * d + i] * s[i] * V[b * d + i];
            p[a * d + b] = v;
        }
    return it;
}

#endif
