/* test_hyper_material.c - the material laws: rest state, invariance,
 * derivatives against finite differences, PSD projection, the ADMM local
 * solve's optimality condition, ARAP projections, small-strain moduli. */
#include <check.h>
#include <math.h>
#include <string.h>

#include <pliant/roles.h>

#include "hyper_test_util.h"
#include "hyperelastic.h"

static const double E_ = 1e6, NU_ = 0.3;

static pl_hyper_law make_law(pl_hyper_material mat, int d)
{
    pl_hyper_law m = {mat, d, 0.0, 0.0};
    ck_assert_int_eq(hyper_lame(E_, NU_, d == 2, &m.mu, &m.lambda, NULL), PL_OK);
    return m;
}

/* A random F (3 x d) near a rotation, det > 0 (|perturbation| <= amp). */
static void random_F(unsigned long long *st, int d, double amp, double *F)
{
    double R[9];
    ht_random_rotation(st, R);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < d; ++b) F[a * d + b] = R[a * 3 + b] + amp * ht_rand(st);
}

START_TEST(lame_parameters)
{
    double mu, la;
    ck_assert_int_eq(hyper_lame(1e6, 0.3, 0, &mu, &la, NULL), PL_OK);
    ck_assert_double_eq_tol(mu, 1e6 / 2.6, 1e-6);
    ck_assert_double_eq_tol(la, 1e6 * 0.3 / (1.3 * 0.4), 1e-6);
    ck_assert_int_eq(hyper_lame(1e6, 0.3, 1, &mu, &la, NULL), PL_OK);
    ck_assert_double_eq_tol(la, 1e6 * 0.3 / (1 - 0.09), 1e-6); /* plane stress E nu/(1-nu^2) */
    pl_error err;
    ck_assert_int_eq(hyper_lame(1e6, 0.5, 0, &mu, &la, &err), PL_EINPUT);
    ck_assert_int_eq(hyper_lame(-1, 0.3, 0, &mu, &la, &err), PL_EINPUT);
}
END_TEST

START_TEST(energy_zero_at_rest_and_rotation_invariant)
{
    unsigned long long st = 1;
    for (int mat = 0; mat < 3; ++mat)
        for (int d = 2; d <= 3; ++d) {
            pl_hyper_law m = make_law((pl_hyper_material)mat, d);
            for (int t = 0; t < 50; ++t) {
                double R[9], Q[9], F0[9], P[9], F[9], G[9];
                ht_random_rotation(&st, R);
                /* rest: the first d columns of a rotation */
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < d; ++b) F0[a * d + b] = R[a * 3 + b];
                ck_assert_double_eq_tol(hyper_psi(&m, F0), 0.0, 1e-9);
                hyper_piola(&m, F0, P);
                for (int i = 0; i < 3 * d; ++i) ck_assert_double_eq_tol(P[i], 0.0, 1e-9);
                /* psi(R F) = psi(F) and psi(F Q) = psi(F) (isotropy) */
                random_F(&st, d, 0.3, F);
                ht_random_rotation(&st, Q);
                double psi = hyper_psi(&m, F);
                ck_assert(psi > 0.0);
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < d; ++b) {
                        G[a * d + b] = 0.0;
                        for (int k = 0; k < 3; ++k) G[a * d + b] += R[a * 3 + k] * F[k * d + b];
                    }
                ck_assert_double_eq_tol(hyper_psi(&m, G), psi, 1e-10 * psi);
                double Q2[4] = {Q[0], Q[1], Q[3], Q[4]}, l = hypot(Q[0], Q[3]);
                Q2[0] = Q[0] / l, Q2[2] = Q[3] / l, Q2[1] = -Q2[2], Q2[3] = Q2[0];
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < d; ++b) {
                        G[a * d + b] = 0.0;
                        for (int k = 0; k < d; ++k)
                            G[a * d + b] += F[a * d + k] * (d == 3 ? Q[k * 3 + b] : Q2[k * 2 + b]);
                    }
                ck_assert_double_eq_tol(hyper_psi(&m, G), psi, 1e-10 * psi);
            }
        }
}
END_TEST

/* max relative error of an analytic derivative against central FD */
START_TEST(piola_matches_finite_differences)
{
    unsigned long long st = 2;
    for (int mat = 0; mat < 3; ++mat)
        for (int d = 2; d <= 3; ++d) {
            pl_hyper_law m = make_law((pl_hyper_material)mat, d);
            for (int t = 0; t < 40; ++t) {
                double F[9], P[9];
                random_F(&st, d, 0.35, F);
                hyper_piola(&m, F, P);
                double pmax = 0.0, err = 0.0, h = 1e-6;
                for (int i = 0; i < 3 * d; ++i) pmax = fmax(pmax, fabs(P[i]));
                for (int i = 0; i < 3 * d; ++i) {
                    double Fp[9], Fm[9];
                    memcpy(Fp, F, sizeof F);
                    memcpy(Fm, F, sizeof F);
                    Fp[i] += h;
                    Fm[i] -= h;
                    double fd = (hyper_psi(&m, Fp) - hyper_psi(&m, Fm)) / (2 * h);
                    err = fmax(err, fabs(fd - P[i]));
                }
                ck_assert_msg(err <= 1e-6 * pmax, "material %d d %d: |P - FD| = %g, |P| = %g", mat,
                              d, err, pmax);
            }
        }
}
END_TEST

START_TEST(hessian_matches_finite_differences_and_projection_is_psd)
{
    unsigned long long st = 3;
    for (int mat = 0; mat < 3; ++mat)
        for (int d = 2; d <= 3; ++d) {
            pl_hyper_law m = make_law((pl_hyper_material)mat, d);
            const int n = 3 * d;
            for (int t = 0; t < 40; ++t) {
                double F[9], H[81], Hp[81], lam[9], Q[81];
                random_F(&st, d, t < 20 ? 0.35 : 0.8, F);
                if (mat == PL_HYPER_NEOHOOKEAN && hyper_psi(&m, F) == INFINITY) continue;
                pl_hyper_dPdF(&m, F, 0, H);
                double hmax = 0.0, err = 0.0, h = 1e-6;
                for (int i = 0; i < n * n; ++i) hmax = fmax(hmax, fabs(H[i]));
                for (int j = 0; j < n; ++j) {
                    double Fp[9], Fm[9], Pp[9], Pm[9];
                    memcpy(Fp, F, sizeof F);
                    memcpy(Fm, F, sizeof F);
                    Fp[j] += h;
                    Fm[j] -= h;
                    hyper_piola(&m, Fp, Pp);
                    hyper_piola(&m, Fm, Pm);
                    for (int i = 0; i < n; ++i)
                        err = fmax(err, fabs((Pp[i] - Pm[i]) / (2 * h) - H[i * n + j]));
                }
                ck_assert_msg(err <= 1e-5 * hmax, "material %d d %d: |H - FD| = %g, |H| = %g", mat,
                              d, err, hmax);
                pl_hyper_dPdF(&m, F, 1, Hp);
                hyper_sym_eigen(n, Hp, lam, Q);
                ck_assert_double_ge(lam[0], -1e-9 * hmax);
                /* where H is already PSD the projection leaves it alone */
                hyper_sym_eigen(n, H, lam, Q);
                if (lam[0] > 1e-6 * hmax)
                    for (int i = 0; i < n * n; ++i) ck_assert_double_eq_tol(Hp[i], H[i], 1e-9 * hmax);
            }
        }
}
END_TEST

/* Element-level: gradient = FD of energy; vertex Hessian = FD of gradient;
 * projected vertex Hessian PSD (tetrahedron and triangle). */
/* psd == PL_HESSIAN_FIXED_ROTATION (ARAP, corotational): the stiffness with
 * the element's rotation held fixed, SOFA's R K0 R^T with K0 linear
 * elasticity: dP = R [mu (G + G^T) + lambda tr(G) I], G = R^T dF (R the
 * polar rotation of F; ARAP has lambda = 0); it differs from the projected
 * Hessian away from rest, which carries the rotation's derivative. */
START_TEST(fixed_rotation_stiffness_is_sofas_corotational_stiffness)
{
    unsigned long long st = 11;
    for (int mat = 0; mat < 2; ++mat) {
        pl_hyper_law m = make_law((pl_hyper_material)mat, 3);
        double la = mat == PL_HYPER_COROTATIONAL ? m.lambda : 0.0, differs = 0.0;
        for (int t = 0; t < 20; ++t) {
            double F[9], H[81], Hp[81], U[9], sv[3], V[9], R[9];
            random_F(&st, 3, 0.35, F);
            hyper_svd3(F, U, sv, V);
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) {
                    R[a * 3 + b] = 0.0;
                    for (int i = 0; i < 3; ++i) R[a * 3 + b] += U[a * 3 + i] * V[b * 3 + i];
                }
            pl_hyper_dPdF(&m, F, PL_HESSIAN_FIXED_ROTATION, H);
            pl_hyper_dPdF(&m, F, 1, Hp);
            double hmax = 0.0, err = 0.0;
            for (int i = 0; i < 81; ++i) hmax = fmax(hmax, fabs(H[i]));
            for (int j = 0; j < 9; ++j) { /* column j: dF = e_j */
                double G[9], S[9], dP[9];
                for (int a = 0; a < 3; ++a) /* G = R^T dF: row a of G = R[j/3][a] e_(j%3) */
                    for (int b = 0; b < 3; ++b) G[a * 3 + b] = b == j % 3 ? R[(j / 3) * 3 + a] : 0.0;
                double tr = G[0] + G[4] + G[8];
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        S[a * 3 + b] = m.mu * (G[a * 3 + b] + G[b * 3 + a]) + (a == b ? la * tr : 0.0);
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) {
                        dP[a * 3 + b] = 0.0;
                        for (int k = 0; k < 3; ++k) dP[a * 3 + b] += R[a * 3 + k] * S[k * 3 + b];
                    }
                for (int i = 0; i < 9; ++i) {
                    err = fmax(err, fabs(dP[i] - H[i * 9 + j]));
                    differs = fmax(differs, fabs(Hp[i * 9 + j] - H[i * 9 + j]) / hmax);
                }
            }
            ck_assert_msg(err <= 1e-9 * hmax, "material %d: |H - R K0 R^T| = %g, |H| = %g", mat,
                          err, hmax);
        }
        ck_assert_double_gt(differs, 1e-2); /* the option changes K */
    }
}
END_TEST

/* SOFA's 'large' rotation (edge_rotation.c): for any rest tetrahedron
 * (shape matrix D) and any rotation Q, the deformation F = Q has R = Q and
 * no stress; at F = Q its stiffness is the exact Hessian there (both are
 * R K0 R^T at a rotated rest shape); a small symmetric stretch in the frame
 * gives linear elasticity's stress, rotated. */
START_TEST(edge_rotation_is_rigid_invariant_and_linear_elastic)
{
    unsigned long long st = 5;
    pl_hyper_law m = make_law(PL_HYPER_COROTATIONAL, 3);
    for (int t = 0; t < 20; ++t) {
        double Dm[9], D[12], Q[9], R[9], P[9], He[81], Hx[81];
        for (int i = 0; i < 9; ++i) Dm[i] = (i % 4 == 0 ? 1.0 : 0.0) + 0.3 * ht_rand(&st);
        double det = Dm[0] * (Dm[4] * Dm[8] - Dm[5] * Dm[7]) - Dm[1] * (Dm[3] * Dm[8] - Dm[5] * Dm[6]) +
                     Dm[2] * (Dm[3] * Dm[7] - Dm[4] * Dm[6]);
        double *G = D + 3; /* rows 1..3 of D: Dm^-1 */
        G[0] = (Dm[4] * Dm[8] - Dm[5] * Dm[7]) / det;
        G[1] = (Dm[2] * Dm[7] - Dm[1] * Dm[8]) / det;
        G[2] = (Dm[1] * Dm[5] - Dm[2] * Dm[4]) / det;
        G[3] = (Dm[5] * Dm[6] - Dm[3] * Dm[8]) / det;
        G[4] = (Dm[0] * Dm[8] - Dm[2] * Dm[6]) / det;
        G[5] = (Dm[2] * Dm[3] - Dm[0] * Dm[5]) / det;
        G[6] = (Dm[3] * Dm[7] - Dm[4] * Dm[6]) / det;
        G[7] = (Dm[1] * Dm[6] - Dm[0] * Dm[7]) / det;
        G[8] = (Dm[0] * Dm[4] - Dm[1] * Dm[3]) / det;
        for (int b = 0; b < 3; ++b) D[b] = -(G[b] + G[3 + b] + G[6 + b]);
        ht_random_rotation(&st, Q);
        hyper_edge_rotation(Q, D, R);
        for (int i = 0; i < 9; ++i) ck_assert_double_eq_tol(R[i], Q[i], 1e-12);
        hyper_edge_piola(&m, Q, D, P);
        for (int i = 0; i < 9; ++i) ck_assert_double_eq_tol(P[i], 0.0, 1e-9 * m.mu);
        hyper_edge_dPdF(&m, Q, D, He);
        pl_hyper_dPdF(&m, Q, 0, Hx);
        for (int i = 0; i < 81; ++i) ck_assert_double_eq_tol(He[i], Hx[i], 1e-9 * m.lambda);
        /* F = Q (I + e E) with E symmetric: P = Q sigma(e E) to first order in e */
        double E[9] = {0.3, 0.1, -0.2, 0.1, -0.4, 0.25, -0.2, 0.25, 0.5}, e = 1e-6, F[9];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                F[a * 3 + b] = 0.0;
                for (int k = 0; k < 3; ++k) F[a * 3 + b] += Q[a * 3 + k] * ((k == b ? 1.0 : 0.0) + e * E[k * 3 + b]);
            }
        hyper_edge_piola(&m, F, D, P);
        double tr = E[0] + E[4] + E[8];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                double want = 0.0;
                for (int k = 0; k < 3; ++k)
                    want += Q[a * 3 + k] * e * (2 * m.mu * E[k * 3 + b] + (k == b ? m.lambda * tr : 0.0));
                ck_assert_double_eq_tol(P[a * 3 + b], want, 1e-4 * e * m.lambda);
            }
    }
}
END_TEST

START_TEST(element_gradient_and_hessian_match_finite_differences)
{
    unsigned long long st = 4;
    const double tet[12] = {0, 0, 0, 0.1, 0, 0, 0.01, 0.12, 0, 0.02, 0.01, 0.09};
    const double tri[9] = {0, 0, 0, 0.1, 0.01, 0, 0.03, 0.1, 0.02};
    for (int mat = 0; mat < 3; ++mat)
        for (int k = 3; k <= 4; ++k) {
            pl_hyper_elements e;
            int idx[4] = {0, 1, 2, 3};
            double E = E_, nu = NU_;
            ck_assert_int_eq(hyper_elements_build(&e, (pl_hyper_material)mat, k, idx, 1,
                                                     k == 4 ? tet : tri, k, &E, 1, &nu, 1, 1e-3,
                                                     NULL),
                             PL_OK);
            const int n = 3 * k;
            double q[12], g[12], gp[12], gm[12], H[144], lam[12], Q[144];
            for (int i = 0; i < n; ++i) q[i] = (k == 4 ? tet : tri)[i] * 1.1 + 0.02 * ht_rand(&st);
            memset(g, 0, sizeof g);
            hyper_elements_add_gradient(&e, 0, q, g, NULL);
            double gmax = 0.0, err = 0.0, h = 1e-8;
            for (int i = 0; i < n; ++i) gmax = fmax(gmax, fabs(g[i]));
            for (int i = 0; i < n; ++i) {
                double qp[12], qm[12];
                memcpy(qp, q, sizeof q);
                memcpy(qm, q, sizeof q);
                qp[i] += h;
                qm[i] -= h;
                double fd = (hyper_elements_energy(&e, 0, qp) - hyper_elements_energy(&e, 0, qm)) / (2 * h);
                err = fmax(err, fabs(fd - g[i]));
            }
            ck_assert_msg(err <= 1e-5 * gmax, "gradient: %g vs %g", err, gmax);
            for (int psd = 0; psd <= 1; ++psd) {
                pl_triplets T;
                pl_triplets_init(&T, n, n, 16);
                ck_assert_int_eq(hyper_elements_add_hessian(&e, 0, q, psd, &T, NULL), PL_OK);
                ck_assert_int_eq(T.nnz, n * n);
                memset(H, 0, sizeof H);
                ht_triplets_to_dense(&T, H, n);
                pl_triplets_free(&T);
                double hmax = 0.0;
                for (int i = 0; i < n * n; ++i) hmax = fmax(hmax, fabs(H[i]));
                if (psd) {
                    hyper_sym_eigen(n, H, lam, Q);
                    ck_assert_double_ge(lam[0], -1e-9 * hmax);
                    continue;
                }
                err = 0.0;
                for (int j = 0; j < n; ++j) {
                    double qp[12], qm[12];
                    memcpy(qp, q, sizeof q);
                    memcpy(qm, q, sizeof q);
                    qp[j] += 1e-7;
                    qm[j] -= 1e-7;
                    memset(gp, 0, sizeof gp);
                    memset(gm, 0, sizeof gm);
                    hyper_elements_add_gradient(&e, 0, qp, gp, NULL);
                    hyper_elements_add_gradient(&e, 0, qm, gm, NULL);
                    for (int i = 0; i < n; ++i)
                        err = fmax(err, fabs((gp[i] - gm[i]) / 2e-7 - H[i * n + j]));
                }
                ck_assert_msg(err <= 1e-5 * hmax, "Hessian: %g vs %g", err, hmax);
            }
            hyper_elements_free(&e);
        }
}
END_TEST

START_TEST(admm_local_solve_satisfies_optimality)
{
    unsigned long long st = 5;
    for (int mat = 1; mat < 3; ++mat)
        for (int d = 2; d <= 3; ++d) {
            pl_hyper_law m = make_law((pl_hyper_material)mat, d);
            double what = hyper_law_weight(&m);
            for (int t = 0; t < 200; ++t) {
                double z[9], p[9], P[9];
                random_F(&st, d, t < 100 ? 0.3 : 1.0, z);
                if (d == 3 && t % 10 == 0) /* inverted input */
                    for (int a = 0; a < 3; ++a) z[a * 3 + 2] = -z[a * 3 + 2];
                int it = hyper_local_solve(&m, what, z, p);
                ck_assert_msg(it >= 0, "material %d d %d: no convergence", mat, d);
                hyper_piola(&m, p, P);
                double res = 0.0, scale = 0.0;
                for (int i = 0; i < 3 * d; ++i) {
                    res = fmax(res, fabs(P[i] + what * (p[i] - z[i])));
                    scale = fmax(scale, what * fabs(z[i]));
                }
                ck_assert_msg(res <= 1e-10 * scale, "material %d d %d: residual %g (scale %g)", mat,
                              d, res, scale);
                if (mat == PL_HYPER_NEOHOOKEAN) ck_assert(hyper_psi(&m, p) < INFINITY);
                if (mat == PL_HYPER_COROTATIONAL) ck_assert_int_le(it, 2); /* quadratic */
            }
        }
}
END_TEST

START_TEST(arap_projection_of_rotated_rest_element_is_the_rotation)
{
    unsigned long long st = 6;
    const double tet[12] = {0, 0, 0, 1, 0, 0, 0.2, 0.9, 0, 0.1, 0.3, 1.1};
    const double tri[9] = {0, 0, 0, 1, 0.1, 0.2, 0.3, 0.8, -0.1};
    for (int k = 3; k <= 4; ++k) {
        const double *rest = k == 4 ? tet : tri;
        double D[12], vol, R[9], X[12], F[9], p[9];
        if (k == 4)
            ck_assert_int_eq(hyper_tet_shape(rest, D, &vol), PL_OK);
        else
            ck_assert_int_eq(hyper_tri_shape(rest, D, &vol), PL_OK);
        int d = k - 1;
        ht_random_rotation(&st, R);
        for (int c = 0; c < k; ++c)
            for (int a = 0; a < 3; ++a) {
                X[3 * c + a] = 0.5; /* plus a translation */
                for (int b = 0; b < 3; ++b) X[3 * c + a] += R[a * 3 + b] * rest[3 * c + b];
            }
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < d; ++b) {
                F[a * d + b] = 0.0;
                for (int c = 0; c < k; ++c) F[a * d + b] += X[3 * c + a] * D[c * d + b];
            }
        pl_hyper_law m = {PL_HYPER_ARAP, d, 1.0, 0.0};
        ck_assert_int_eq(hyper_local_solve(&m, 2.0, F, p), 0);
        if (k == 4)
            for (int i = 0; i < 9; ++i) ck_assert_double_eq_tol(p[i], R[i], 1e-12);
        /* triangle: p = F (orthonormal columns), F maps the rest frame */
        for (int i = 0; i < 3 * d; ++i) ck_assert_double_eq_tol(p[i], F[i], 1e-12);
    }
}
END_TEST

/* Uniaxial stress: stretch e along x, free lateral strain et with zero
 * lateral stress; then P_xx / e -> E and -et / e -> nu as e -> 0. */
START_TEST(small_strain_uniaxial_stress_recovers_young_and_poisson)
{
    for (int mat = 1; mat < 3; ++mat)
        for (int d = 2; d <= 3; ++d) {
            pl_hyper_law m = make_law((pl_hyper_material)mat, d);
            const double e = 1e-5;
            double et = 0.0, F[9], P[9];
            for (int it = 0; it < 30; ++it) { /* secant-free: lateral stress is linear in et */
                double Fl[9], Pl[9], h = 1e-7;
                memset(F, 0, sizeof F);
                for (int i = 0; i < d; ++i) F[i * d + i] = i == 0 ? 1 + e : 1 + et;
                hyper_piola(&m, F, P);
                memcpy(Fl, F, sizeof F);
                for (int i = 1; i < d; ++i) Fl[i * d + i] += h;
                hyper_piola(&m, Fl, Pl);
                double slope = (Pl[d + 1] - P[d + 1]) / h;
                et -= P[d + 1] / slope;
                if (fabs(P[d + 1]) < 1e-12 * E_ * e) break;
            }
            ck_assert_double_eq_tol(P[0] / e, E_, 1e-3 * E_);
            ck_assert_double_eq_tol(-et / e, NU_, 1e-3);
        }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("hyper_material");
    TCase *tc = tcase_create("material");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, lame_parameters);
    tcase_add_test(tc, energy_zero_at_rest_and_rotation_invariant);
    tcase_add_test(tc, piola_matches_finite_differences);
    tcase_add_test(tc, hessian_matches_finite_differences_and_projection_is_psd);
    tcase_add_test(tc, fixed_rotation_stiffness_is_sofas_corotational_stiffness);
    tcase_add_test(tc, edge_rotation_is_rigid_invariant_and_linear_elastic);
    tcase_add_test(tc, element_gradient_and_hessian_match_finite_differences);
    tcase_add_test(tc, admm_local_solve_satisfies_optimality);
    tcase_add_test(tc, arap_projection_of_rotated_rest_element_is_the_rotation);
    tcase_add_test(tc, small_strain_uniaxial_stress_recovers_young_and_poisson);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
