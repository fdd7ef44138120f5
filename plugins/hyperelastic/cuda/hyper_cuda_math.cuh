/* hyper_cuda_math.cuh - device versions of the tetrahedral (3x3) local-step
 * math of the hyperelastic core: signed SVD by one-sided Jacobi (svd.c),
 * the laws on singular values (material_law.c) and the ADMM-PD prox solved
 * by Newton on the singular values (local_solve.c, sym_eigen.c).  Same
 * algorithms, same constants and tolerances, written with compile-time
 * indices so that the small arrays stay in registers; the CPU files are the
 * reference (tests/gpu/gpu_check compares the two). */
#ifndef PLIANT_HYPER_CUDA_MATH_CUH
#define PLIANT_HYPER_CUDA_MATH_CUH

#include <math.h>

namespace hcu {

__device__ __forceinline__ double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

__device__ __forceinline__ void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

__device__ __forceinline__ double det3(const double *A)
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* One Jacobi rotation of columns i, j of A (3x3) and V (svd.c, hestenes). */
template <int i, int j>
__device__ __forceinline__ void jacobi_pair(double *A, double *V, double *nrm, double &tmax)
{
    double gamma = A[i] * A[j] + A[3 + i] * A[3 + j] + A[6 + i] * A[6 + j];
    if (gamma * gamma <= 1e-30 * nrm[i] * nrm[j]) return;
    double zeta = (nrm[j] - nrm[i]) / (2.0 * gamma);
    double t = fabs(zeta) > 1e150 ? 0.5 / zeta
                                  : (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
    double c = 1.0 / sqrt(1.0 + t * t), s = c * t;
#pragma unroll
    for (int r = 0; r < 3; ++r) {
        double ai = A[r * 3 + i], aj = A[r * 3 + j];
        A[r * 3 + i] = c * ai - s * aj;
        A[r * 3 + j] = s * ai + c * aj;
        double vi = V[r * 3 + i], vj = V[r * 3 + j];
        V[r * 3 + i] = c * vi - s * vj;
        V[r * 3 + j] = s * vi + c * vj;
    }
    nrm[i] -= t * gamma;
    nrm[j] += t * gamma;
    tmax = fmax(tmax, fabs(t));
}

__device__ inline void hestenes3(double *A, double *V)
{
    double nrm[3];
#pragma unroll
    for (int k = 0; k < 9; ++k) V[k] = (k % 4 == 0) ? 1.0 : 0.0;
#pragma unroll
    for (int j = 0; j < 3; ++j) nrm[j] = A[j] * A[j] + A[3 + j] * A[3 + j] + A[6 + j] * A[6 + j];
    for (int sweep = 0; sweep < 40; ++sweep) {
        double tmax = 0.0;
        jacobi_pair<0, 1>(A, V, nrm, tmax);
        jacobi_pair<0, 2>(A, V, nrm, tmax);
        jacobi_pair<1, 2>(A, V, nrm, tmax);
        if (tmax < 1e-8) break;
    }
}

template <int i, int j>
__device__ __forceinline__ void swap_cols(double *A, double *V, double *s)
{
    double t = s[i];
    s[i] = s[j];
    s[j] = t;
#pragma unroll
    for (int r = 0; r < 3; ++r) {
        t = A[r * 3 + i], A[r * 3 + i] = A[r * 3 + j], A[r * 3 + j] = t;
        t = V[r * 3 + i], V[r * 3 + i] = V[r * 3 + j], V[r * 3 + j] = t;
    }
}

/* Selection sort by decreasing column norm (svd.c, sort_columns), unrolled. */
__device__ inline void sort_columns3(double *A, double *V, double *s)
{
#pragma unroll
    for (int j = 0; j < 3; ++j) s[j] = sqrt(A[j] * A[j] + A[3 + j] * A[3 + j] + A[6 + j] * A[6 + j]);
    int best = 0;
    if (s[1] > s[best]) best = 1;
    if (s[2] > s[best]) best = 2;
    if (best == 1) swap_cols<0, 1>(A, V, s);
    if (best == 2) swap_cols<0, 2>(A, V, s);
    if (s[2] > s[1]) swap_cols<1, 2>(A, V, s);
}

__device__ inline void any_orthogonal(const double *a, double *out)
{
    double e[3] = {0.0, 0.0, 0.0};
    int k = 0;
    if (fabs(a[1]) < fabs(a[k])) k = 1;
    if (fabs(a[2]) < fabs(a[k])) k = 2;
    e[0] = k == 0, e[1] = k == 1, e[2] = k == 2;
    cross(a, e, out);
    double l = sqrt(dot3(out, out));
#pragma unroll
    for (int r = 0; r < 3; ++r) out[r] /= l;
}

__device__ inline void left_vectors(const double *a0, double s0, const double *a1, double s1,
                                    double *u0, double *u1)
{
    const double tiny = 1e-300;
    if (s0 > tiny) {
#pragma unroll
        for (int r = 0; r < 3; ++r) u0[r] = a0[r] / s0;
    } else {
        u0[0] = 1.0;
        u0[1] = u0[2] = 0.0;
    }
    if (s1 > 1e-14 * s0 && s1 > tiny) {
#pragma unroll
        for (int r = 0; r < 3; ++r) u1[r] = a1[r] / s1;
        double c = dot3(u0, u1);
#pragma unroll
        for (int r = 0; r < 3; ++r) u1[r] -= c * u0[r];
        double l = sqrt(dot3(u1, u1));
#pragma unroll
        for (int r = 0; r < 3; ++r) u1[r] /= l;
    } else {
        any_orthogonal(u0, u1);
    }
}

__device__ inline int scale_exponent9(const double *F)
{
    double m = 0.0;
#pragma unroll
    for (int i = 0; i < 9; ++i) m = fmax(m, fabs(F[i]));
    int e = 0;
    if (m > 0.0 && isfinite(m)) frexp(m, &e);
    return e < -1000 ? -1000 : e > 1000 ? 1000 : e;
}

/* Signed SVD F = U diag(s) V^T, U and V rotations (pl_hyper_svd3). */
__device__ inline void svd3(const double *F, double *U, double *s, double *V)
{
    double A[9];
    int ex = scale_exponent9(F);
    const double down = ldexp(1.0, -ex), up = ldexp(1.0, ex);
#pragma unroll
    for (int i = 0; i < 9; ++i) A[i] = F[i] * down;
    hestenes3(A, V);
    sort_columns3(A, V, s);
    if (det3(V) < 0.0) {
#pragma unroll
        for (int r = 0; r < 3; ++r) {
            V[r * 3 + 2] = -V[r * 3 + 2];
            A[r * 3 + 2] = -A[r * 3 + 2];
        }
    }
    double a0[3] = {A[0], A[3], A[6]}, a1[3] = {A[1], A[4], A[7]}, a2[3] = {A[2], A[5], A[8]};
    double u0[3], u1[3], u2[3];
    left_vectors(a0, s[0], a1, s[1], u0, u1);
    cross(u0, u1, u2);
    s[2] = dot3(u2, a2);
#pragma unroll
    for (int i = 0; i < 3; ++i) s[i] *= up;
#pragma unroll
    for (int r = 0; r < 3; ++r) {
        U[r * 3 + 0] = u0[r];
        U[r * 3 + 1] = u1[r];
        U[r * 3 + 2] = u2[r];
    }
}

/* psi_hat(s), its gradient and Hessian for d = D singular values
 * (hyper_sv_eval): D = 3 for tetrahedra, 2 for membranes; material 0 ARAP,
 * 1 corotational, 2 Neo-Hookean.  -1 outside the domain. */
template <int D>
__device__ inline int sv_eval_d(int material, double mu, double la, const double *s, double *psi,
                                double *g, double *H)
{
    const int d = D;
    if (material == 2) {
        double lnJ = 0.0, I1 = 0.0;
#pragma unroll
        for (int i = 0; i < d; ++i) {
            if (!(s[i] > 0.0)) {
                *psi = INFINITY;
                return -1;
            }
            lnJ += log(s[i]);
            I1 += s[i] * s[i];
        }
        *psi = 0.5 * mu * (I1 - d) - mu * lnJ + 0.5 * la * lnJ * lnJ;
        if (g)
#pragma unroll
            for (int i = 0; i < d; ++i) g[i] = mu * s[i] + (la * lnJ - mu) / s[i];
        if (H)
#pragma unroll
            for (int i = 0; i < d; ++i)
#pragma unroll
                for (int j = 0; j < d; ++j)
                    H[i * d + j] = la / (s[i] * s[j]) +
                                   (i == j ? mu + (mu - la * lnJ) / (s[i] * s[i]) : 0.0);
        return 0;
    }
    double lc = material == 1 ? la : 0.0;
    double tr = -d, sq = 0.0;
#pragma unroll
    for (int i = 0; i < d; ++i) {
        tr += s[i];
        sq += (s[i] - 1.0) * (s[i] - 1.0);
    }
    *psi = mu * sq + 0.5 * lc * tr * tr;
    if (g)
#pragma unroll
        for (int i = 0; i < d; ++i) g[i] = 2.0 * mu * (s[i] - 1.0) + lc * tr;
    if (H)
#pragma unroll
        for (int i = 0; i < d; ++i)
#pragma unroll
            for (int j = 0; j < d; ++j) H[i * d + j] = lc + (i == j ? 2.0 * mu : 0.0);
    return 0;
}

__device__ inline int sv_eval(int material, double mu, double la, const double *s, double *psi,
                              double *g, double *H)
{
    return sv_eval_d<3>(material, mu, la, s, psi, g, H);
}

template <int p, int q>
__device__ __forceinline__ void jacobi_sym(double *M, double *Q)
{
    double apq = M[p * 3 + q];
    if (apq == 0.0) return;
    double theta = (M[q * 3 + q] - M[p * 3 + p]) / (2.0 * apq);
    double t = fabs(theta) > 1e150
                   ? 0.5 / theta
                   : (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(1.0 + theta * theta));
    double c = 1.0 / sqrt(1.0 + t * t), s = t * c;
#pragma unroll
    for (int k = 0; k < 3; ++k) {
        double mkp = M[k * 3 + p], mkq = M[k * 3 + q];
        M[k * 3 + p] = c * mkp - s * mkq;
        M[k * 3 + q] = s * mkp + c * mkq;
    }
#pragma unroll
    for (int k = 0; k < 3; ++k) {
        double mpk = M[p * 3 + k], mqk = M[q * 3 + k];
        M[p * 3 + k] = c * mpk - s * mqk;
        M[q * 3 + k] = s * mpk + c * mqk;
    }
    M[p * 3 + q] = M[q * 3 + p] = 0.0;
#pragma unroll
    for (int k = 0; k < 3; ++k) {
        double qkp = Q[k * 3 + p], qkq = Q[k * 3 + q];
        Q[k * 3 + p] = c * qkp - s * qkq;
        Q[k * 3 + q] = s * qkp + c * qkq;
    }
}

template <int i, int j>
__device__ __forceinline__ void swap_eig(double *lam, double *Q)
{
    double t = lam[i];
    lam[i] = lam[j];
    lam[j] = t;
#pragma unroll
    for (int k = 0; k < 3; ++k) t = Q[k * 3 + i], Q[k * 3 + i] = Q[k * 3 + j], Q[k * 3 + j] = t;
}

/* Cyclic Jacobi eigen-decomposition of a symmetric 3x3 (pl_hyper_sym_eigen),
 * eigenvalues ascending. */
__device__ inline void sym_eigen3(const double *A, double *lam, double *Q)
{
    double M[9];
#pragma unroll
    for (int i = 0; i < 3; ++i)
#pragma unroll
        for (int j = 0; j < 3; ++j) M[i * 3 + j] = 0.5 * (A[i * 3 + j] + A[j * 3 + i]);
#pragma unroll
    for (int k = 0; k < 9; ++k) Q[k] = (k % 4 == 0) ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = M[1] * M[1] + M[2] * M[2] + M[5] * M[5];
        double diag = M[0] * M[0] + M[4] * M[4] + M[8] * M[8];
        if (off <= 1e-32 * diag || off == 0.0) break;
        jacobi_sym<0, 1>(M, Q);
        jacobi_sym<0, 2>(M, Q);
        jacobi_sym<1, 2>(M, Q);
    }
    lam[0] = M[0], lam[1] = M[4], lam[2] = M[8];
    int best = 0;
    if (lam[1] < lam[best]) best = 1;
    if (lam[2] < lam[best]) best = 2;
    if (best == 1) swap_eig<0, 1>(lam, Q);
    if (best == 2) swap_eig<0, 2>(lam, Q);
    if (lam[2] < lam[1]) swap_eig<1, 2>(lam, Q);
}

/* dx = -H^-1 r (local_solve.c, newton_direction) for d = 3. */
__device__ inline void newton_direction3(const double *H, const double *r, double floor_, double *dx)
{
    double L[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    bool pd = true;
#pragma unroll
    for (int j = 0; j < 3; ++j) {
        if (!pd) break;
        double v = H[j * 3 + j];
#pragma unroll
        for (int k = 0; k < j; ++k) v -= L[j * 3 + k] * L[j * 3 + k];
        if (!(v > floor_)) {
            pd = false;
            break;
        }
        L[j * 3 + j] = sqrt(v);
#pragma unroll
        for (int i = j + 1; i < 3; ++i) {
            double w = H[i * 3 + j];
#pragma unroll
            for (int k = 0; k < j; ++k) w -= L[i * 3 + k] * L[j * 3 + k];
            L[i * 3 + j] = w / L[j * 3 + j];
        }
    }
    if (pd) {
#pragma unroll
        for (int i = 0; i < 3; ++i) {
            double v = -r[i];
#pragma unroll
            for (int k = 0; k < i; ++k) v -= L[i * 3 + k] * dx[k];
            dx[i] = v / L[i * 3 + i];
        }
#pragma unroll
        for (int i = 2; i >= 0; --i) {
            double v = dx[i];
#pragma unroll
            for (int k = i + 1; k < 3; ++k) v -= L[k * 3 + i] * dx[k];
            dx[i] = v / L[i * 3 + i];
        }
        return;
    }
    double lam[3], Q[9];
    sym_eigen3(H, lam, Q);
#pragma unroll
    for (int i = 0; i < 3; ++i) dx[i] = 0.0;
#pragma unroll
    for (int k = 0; k < 3; ++k) {
        double proj = 0.0;
#pragma unroll
        for (int i = 0; i < 3; ++i) proj += Q[i * 3 + k] * r[i];
        double l = fmax(lam[k], floor_);
#pragma unroll
        for (int i = 0; i < 3; ++i) dx[i] -= Q[i * 3 + k] * proj / l;
    }
}

/* The prox objective psi_hat(s) + what / 2 |s - zh|^2 and its residual's
 * max norm (r = gradient, H = psi_hat's Hessian), for D singular values. */
template <int D>
__device__ inline double objective_d(int mat, double mu, double la, double what, const double *s,
                                     const double *zh)
{
    double psi, q = 0.0;
    if (sv_eval_d<D>(mat, mu, la, s, &psi, NULL, NULL) != 0) return INFINITY;
#pragma unroll
    for (int i = 0; i < D; ++i) q += (s[i] - zh[i]) * (s[i] - zh[i]);
    return psi + 0.5 * what * q;
}

template <int D>
__device__ inline double residual_d(int mat, double mu, double la, double what, const double *s,
                                    const double *zh, double *r, double *H)
{
    double psi, g[D], rn = 0.0;
    if (sv_eval_d<D>(mat, mu, la, s, &psi, g, H) != 0) return INFINITY;
#pragma unroll
    for (int i = 0; i < D; ++i) {
        r[i] = g[i] + what * (s[i] - zh[i]);
        rn = fmax(rn, fabs(r[i]));
    }
    return rn;
}

__device__ __forceinline__ double inf_norm3(const double *v)
{
    return fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
}

/* Newton with backtracking on the singular values (solve_singular_values). */
__device__ inline int solve_singular_values3(int mat, double mu, double la, double what,
                                             const double *zh, double *s)
{
    const int max_iter = 100;
    double scale = inf_norm3(zh);
    const double tol = 1e-13 * what * fmax(1.0, scale);
#pragma unroll
    for (int i = 0; i < 3; ++i) s[i] = mat == 2 ? fmax(zh[i], 0.1 * fmax(1.0, scale)) : zh[i];
    double f = objective_d<3>(mat, mu, la, what, s, zh);
    for (int it = 0; it < max_iter; ++it) {
        double H[9], r[3], rt[3];
        double rn = residual_d<3>(mat, mu, la, what, s, zh, r, H);
        if (rn <= tol) return it;
#pragma unroll
        for (int i = 0; i < 3; ++i) H[i * 3 + i] += what;
        double dx[3];
        newton_direction3(H, r, 1e-8 * what, dx);
        double alpha = 1.0;
        if (mat == 2)
#pragma unroll
            for (int i = 0; i < 3; ++i)
                if (dx[i] < 0.0) alpha = fmin(alpha, -0.95 * s[i] / dx[i]);
        double slope = r[0] * dx[0] + r[1] * dx[1] + r[2] * dx[2], trial[3], ft = INFINITY;
        bool accepted = false;
        for (int ls = 0; ls < 60; ++ls) {
#pragma unroll
            for (int i = 0; i < 3; ++i) trial[i] = s[i] + alpha * dx[i];
            ft = objective_d<3>(mat, mu, la, what, trial, zh);
            if (ft <= f + 1e-4 * alpha * slope) {
                accepted = true;
            } else if (ls == 0 && fabs(ft - f) <= 1e-11 * fabs(f)) {
                double Ht[9];
                accepted = residual_d<3>(mat, mu, la, what, trial, zh, rt, Ht) < rn;
            }
            if (accepted) break;
            alpha *= 0.5;
        }
        if (!accepted || alpha * inf_norm3(dx) <= 1e-16 * inf_norm3(s))
            return rn <= 1e4 * tol ? it : -1;
#pragma unroll
        for (int i = 0; i < 3; ++i) s[i] = trial[i];
        f = ft;
    }
    return -1;
}

/* p = the local step of z (pl_hyper_local_solve, d = 3): the closest
 * rotation (ARAP) or the prox of psi with weight what.  Iterations or -1. */
__device__ inline int local_solve3(int mat, double mu, double la, double what, const double *z,
                                   double *p)
{
#pragma unroll
    for (int i = 0; i < 9; ++i)
        if (!isfinite(z[i])) return -1;
    double U[9], zh[3], V[9];
    svd3(z, U, zh, V);
    if (mat == 0) {
#pragma unroll
        for (int a = 0; a < 3; ++a)
#pragma unroll
            for (int b = 0; b < 3; ++b)
                p[a * 3 + b] = U[a * 3] * V[b * 3] + U[a * 3 + 1] * V[b * 3 + 1] +
                               U[a * 3 + 2] * V[b * 3 + 2];
        return 0;
    }
    double s[3];
    int it = solve_singular_values3(mat, mu, la, what, zh, s);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            double v = 0.0;
#pragma unroll
            for (int i = 0; i < 3; ++i) v += U[a * 3 + i] * s[i] * V[b * 3 + i];
            p[a * 3 + b] = v;
        }
    return it;
}

} // namespace hcu

#endif
