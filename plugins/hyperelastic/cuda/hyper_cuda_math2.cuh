/* hyper_cuda_math2.cuh - device versions of the membrane (3x2) local-step
 * math of the hyperelastic core: the SVD of a 3x2 F by one-sided Jacobi
 * (svd.c, pl_hyper_svd32), the 2x2 eigen-decomposition (sym_eigen.c) and
 * the ADMM-PD prox by Newton on the singular values (local_solve.c); the
 * laws on the singular values and the prox objective are the templates of
 * hyper_cuda_math.cuh with D = 2.  Same algorithms,
 * constants and summation orders as the CPU files, which stay the
 * reference (tests/gpu/gpu_scenes compares whole cloth steps). */
#ifndef PLIANT_HYPER_CUDA_MATH2_CUH
#define PLIANT_HYPER_CUDA_MATH2_CUH

#include "hyper_cuda_math.cuh"

namespace hcu {

/* One-sided Jacobi on the two columns of A (3x2), V (2x2) accumulated
 * (svd.c, hestenes with n = 2). */
__device__ inline void hestenes2(double *A, double *V)
{
    V[0] = 1.0, V[1] = 0.0, V[2] = 0.0, V[3] = 1.0;
    double nrm0 = A[0] * A[0] + A[2] * A[2] + A[4] * A[4];
    double nrm1 = A[1] * A[1] + A[3] * A[3] + A[5] * A[5];
    for (int sweep = 0; sweep < 40; ++sweep) {
        double tmax = 0.0;
        double gamma = A[0] * A[1] + A[2] * A[3] + A[4] * A[5];
        if (!(gamma * gamma <= 1e-30 * nrm0 * nrm1)) {
            double zeta = (nrm1 - nrm0) / (2.0 * gamma);
            double t = fabs(zeta) > 1e150
                           ? 0.5 / zeta
                           : (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
            double c = 1.0 / sqrt(1.0 + t * t), s = c * t;
#pragma unroll
            for (int r = 0; r < 3; ++r) {
                double ai = A[r * 2], aj = A[r * 2 + 1];
                A[r * 2] = c * ai - s * aj;
                A[r * 2 + 1] = s * ai + c * aj;
            }
#pragma unroll
            for (int r = 0; r < 2; ++r) {
                double vi = V[r * 2], vj = V[r * 2 + 1];
                V[r * 2] = c * vi - s * vj;
                V[r * 2 + 1] = s * vi + c * vj;
            }
            nrm0 -= t * gamma;
            nrm1 += t * gamma;
            tmax = fmax(tmax, fabs(t));
        }
        if (tmax < 1e-8) break;
    }
}

__device__ inline int scale_exponent6(const double *F)
{
    double m = 0.0;
#pragma unroll
    for (int i = 0; i < 6; ++i) m = fmax(m, fabs(F[i]));
    int e = 0;
    if (m > 0.0 && isfinite(m)) frexp(m, &e);
    return e < -1000 ? -1000 : e > 1000 ? 1000 : e;
}

/* F (3x2) = U diag(s) V^T: U 3x2 orthonormal columns, s0 >= s1 >= 0, V a
 * 2x2 rotation (pl_hyper_svd32). */
__device__ inline void svd32(const double *F, double *U, double *s, double *V)
{
    double A[6], Fs[6];
    int ex = scale_exponent6(F);
    const double down = ldexp(1.0, -ex), up = ldexp(1.0, ex);
#pragma unroll
    for (int i = 0; i < 6; ++i) A[i] = Fs[i] = F[i] * down;
    hestenes2(A, V);
    s[0] = sqrt(A[0] * A[0] + A[2] * A[2] + A[4] * A[4]);
    s[1] = sqrt(A[1] * A[1] + A[3] * A[3] + A[5] * A[5]);
    if (s[1] > s[0]) {
        double t = s[0];
        s[0] = s[1], s[1] = t;
#pragma unroll
        for (int r = 0; r < 3; ++r) t = A[r * 2], A[r * 2] = A[r * 2 + 1], A[r * 2 + 1] = t;
#pragma unroll
        for (int r = 0; r < 2; ++r) t = V[r * 2], V[r * 2] = V[r * 2 + 1], V[r * 2 + 1] = t;
    }
    if (V[0] * V[3] - V[1] * V[2] < 0.0) V[1] = -V[1], V[3] = -V[3];
#pragma unroll
    for (int r = 0; r < 3; ++r) A[r * 2 + 1] = Fs[r * 2] * V[1] + Fs[r * 2 + 1] * V[3];
    double a0[3] = {A[0], A[2], A[4]}, a1[3] = {A[1], A[3], A[5]};
    double u0[3], u1[3];
    left_vectors(a0, s[0], a1, s[1], u0, u1);
    s[0] *= up;
    s[1] *= up;
#pragma unroll
    for (int r = 0; r < 3; ++r) U[r * 2] = u0[r], U[r * 2 + 1] = u1[r];
}

/* Cyclic Jacobi for a symmetric 2x2 (pl_hyper_sym_eigen, n = 2), ascending. */
__device__ inline void sym_eigen2(const double *A, double *lam, double *Q)
{
    double M[4];
    M[0] = 0.5 * (A[0] + A[0]);
    M[1] = 0.5 * (A[1] + A[2]);
    M[2] = 0.5 * (A[2] + A[1]);
    M[3] = 0.5 * (A[3] + A[3]);
    Q[0] = 1.0, Q[1] = 0.0, Q[2] = 0.0, Q[3] = 1.0;
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = M[1] * M[1], diag = M[0] * M[0] + M[3] * M[3];
        if (off <= 1e-32 * diag || off == 0.0) break;
        double apq = M[1];
        if (apq == 0.0) continue;
        double theta = (M[3] - M[0]) / (2.0 * apq);
        double t = fabs(theta) > 1e150
                       ? 0.5 / theta
                       : (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(1.0 + theta * theta));
        double c = 1.0 / sqrt(1.0 + t * t), s = t * c;
#pragma unroll
        for (int k = 0; k < 2; ++k) {
            double mkp = M[k * 2], mkq = M[k * 2 + 1];
            M[k * 2] = c * mkp - s * mkq;
            M[k * 2 + 1] = s * mkp + c * mkq;
        }
#pragma unroll
        for (int k = 0; k < 2; ++k) {
            double mpk = M[k], mqk = M[2 + k];
            M[k] = c * mpk - s * mqk;
            M[2 + k] = s * mpk + c * mqk;
        }
        M[1] = M[2] = 0.0;
#pragma unroll
        for (int k = 0; k < 2; ++k) {
            double qkp = Q[k * 2], qkq = Q[k * 2 + 1];
            Q[k * 2] = c * qkp - s * qkq;
            Q[k * 2 + 1] = s * qkp + c * qkq;
        }
    }
    lam[0] = M[0], lam[1] = M[3];
    if (lam[1] < lam[0]) {
        double t = lam[0];
        lam[0] = lam[1], lam[1] = t;
#pragma unroll
        for (int k = 0; k < 2; ++k) t = Q[k * 2], Q[k * 2] = Q[k * 2 + 1], Q[k * 2 + 1] = t;
    }
}

/* dx = -H^-1 r for d = 2 (local_solve.c, newton_direction). */
__device__ inline void newton_direction2(const double *H, const double *r, double floor_, double *dx)
{
    double L[4] = {0.0, 0.0, 0.0, 0.0};
    bool pd = true;
    double v = H[0];
    if (!(v > floor_)) pd = false;
    if (pd) {
        L[0] = sqrt(v);
        L[2] = H[2] / L[0];
        v = H[3] - L[2] * L[2];
        if (!(v > floor_)) pd = false;
        if (pd) L[3] = sqrt(v);
    }
    if (pd) {
        dx[0] = -r[0] / L[0];
        dx[1] = (-r[1] - L[2] * dx[0]) / L[3];
        dx[1] = dx[1] / L[3];
        dx[0] = (dx[0] - L[2] * dx[1]) / L[0];
        return;
    }
    double lam[2], Q[4];
    sym_eigen2(H, lam, Q);
    dx[0] = dx[1] = 0.0;
#pragma unroll
    for (int k = 0; k < 2; ++k) {
        double proj = Q[k] * r[0] + Q[2 + k] * r[1];
        double l = fmax(lam[k], floor_);
        dx[0] -= Q[k] * proj / l;
        dx[1] -= Q[2 + k] * proj / l;
    }
}

/* Newton with backtracking on the two singular values (solve_singular_values, d = 2). */
__device__ inline int solve_singular_values2(int mat, double mu, double la, double what,
                                             const double *zh, double *s)
{
    const int max_iter = 100;
    double scale = fmax(fabs(zh[0]), fabs(zh[1]));
    const double tol = 1e-13 * what * fmax(1.0, scale);
#pragma unroll
    for (int i = 0; i < 2; ++i) s[i] = mat == 2 ? fmax(zh[i], 0.1 * fmax(1.0, scale)) : zh[i];
    double f = objective_d<2>(mat, mu, la, what, s, zh);
    for (int it = 0; it < max_iter; ++it) {
        double H[4], r[2], rt[2];
        double rn = residual_d<2>(mat, mu, la, what, s, zh, r, H);
        if (rn <= tol) return it;
        H[0] += what;
        H[3] += what;
        double dx[2];
        newton_direction2(H, r, 1e-8 * what, dx);
        double alpha = 1.0;
        if (mat == 2)
#pragma unroll
            for (int i = 0; i < 2; ++i)
                if (dx[i] < 0.0) alpha = fmin(alpha, -0.95 * s[i] / dx[i]);
        double slope = 0.0;
        slope += r[0] * dx[0];
        slope += r[1] * dx[1];
        double trial[2], ft = INFINITY;
        bool accepted = false;
        for (int ls = 0; ls < 60; ++ls) {
            trial[0] = s[0] + alpha * dx[0];
            trial[1] = s[1] + alpha * dx[1];
            ft = objective_d<2>(mat, mu, la, what, trial, zh);
            if (ft <= f + 1e-4 * alpha * slope) {
                accepted = true;
            } else if (ls == 0 && fabs(ft - f) <= 1e-11 * fabs(f)) {
                double Ht[4];
                accepted = residual_d<2>(mat, mu, la, what, trial, zh, rt, Ht) < rn;
            }
            if (accepted) break;
            alpha *= 0.5;
        }
        double dn = fmax(fabs(dx[0]), fabs(dx[1])), sn = fmax(fabs(s[0]), fabs(s[1]));
        if (!accepted || alpha * dn <= 1e-16 * sn) return rn <= 1e4 * tol ? it : -1;
        s[0] = trial[0], s[1] = trial[1];
        f = ft;
    }
    return -1;
}

/* p (3x2) = the membrane local step of z (pl_hyper_local_solve, d = 2): the
 * closest matrix with orthonormal columns (ARAP) or the prox of psi.
 * Iterations or -1. */
__device__ inline int local_solve32(int mat, double mu, double la, double what, const double *z,
                                    double *p)
{
#pragma unroll
    for (int i = 0; i < 6; ++i)
        if (!isfinite(z[i])) return -1;
    double U[6], zh[2], V[4];
    svd32(z, U, zh, V);
    if (mat == 0) {
#pragma unroll
        for (int a = 0; a < 3; ++a)
#pragma unroll
            for (int b = 0; b < 2; ++b) {
                double v = 0.0;
                v += U[a * 2] * V[b * 2];
                v += U[a * 2 + 1] * V[b * 2 + 1];
                p[a * 2 + b] = v;
            }
        return 0;
    }
    double s[2];
    int it = solve_singular_values2(mat, mu, la, what, zh, s);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 2; ++b) {
            double v = 0.0;
            v += U[a * 2] * s[0] * V[b * 2];
            v += U[a * 2 + 1] * s[1] * V[b * 2 + 1];
            p[a * 2 + b] = v;
        }
    return it;
}

} // namespace hcu

#endif
