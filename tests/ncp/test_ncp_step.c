/* test_ncp_step.c - ncp_step driven as in Algorithm 4 (h != 1): a
 * particle on a plane sticks or slides with the exact Coulomb forces, a new
 * resting contact (0/0) gives finite and exact first steps, bilateral and
 * bounded rows reach their exact values, and a matrix-free W equals the
 * dense one. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ncp.h"
#include "ncp_test_util.h"

/* Algorithm 4's constraint part without elasticity: q_free = A^-1 b is
 * fixed, and after each update q^{k+1} = q_free + h^2 A^-1 H^T (Omega
 * lambda), i.e. delta^{k+1} = delta_free + h^2 W (Omega .* lambda). */
typedef struct lg_run {
    int iters;
    double residual;    /* pl_ncp_residual total at the end [m] */
    int max_cr;
} lg_run;

static int run_lg(const pl_ncp_rows *rows, const double *W, const double *diag, double h,
                  pl_ncp_function fn, const double *delta_free, double *lambda, double *delta,
                  int max_iter, double tol, lg_run *out)
{
    int m = rows->m;
    pl_ncp_work *w;
    pl_error err;
    if (ncp_work_create(rows, &w, &err) != PL_OK)
        return 1;
    double *Wd = malloc(sizeof(double) * m), *r = malloc(sizeof(double) * m);
    double *om = malloc(sizeof(double) * m), *dl = malloc(sizeof(double) * m), *t = malloc(sizeof(double) * m);
    for (int j = 0; j < m; ++j)
        Wd[j] = W[j * m + j];
    pl_ncp_operator op = {m, W, NULL, NULL, Wd};
    ncp_scaling(w, diag ? diag : Wd, h, r, &err);
    pl_ncp_params par;
    ncp_params_default(&par);
    par.fn = fn;
    par.h = h;
    par.cr_rtol = 1e-13;
    memset(lambda, 0, sizeof(double) * m);
    for (int j = 0; j < m; ++j)
        om[j] = 1.0;
    int rc = 0;
    memset(out, 0, sizeof(*out));
    for (int k = 0;; ++k) {
        for (int j = 0; j < m; ++j)
            t[j] = om[j] * lambda[j];
        ncp_operator_apply(&op, t, delta);
        for (int j = 0; j < m; ++j)
            delta[j] = delta_free[j] + h * h * delta[j];
        pl_ncp_residual res;
        ncp_residual_eval(w, r, h, delta, lambda, &res, &err);
        out->iters = k;
        out->residual = res.total;
        if (res.total <= tol || k == max_iter)
            break;
        pl_ncp_step_info si;
        if (ncp_step(w, &par, &op, r, delta, delta_free, lambda, dl, om, &si, &err) != PL_OK) {
            rc = 1;
            break;
        }
        if (si.cr_iters > out->max_cr)
            out->max_cr = si.cr_iters;
        for (int j = 0; j < m; ++j) {
            if (!isfinite(dl[j]))
                rc = 1;
            lambda[j] += dl[j];
        }
    }
    free(Wd); free(r); free(om); free(dl); free(t);
    ncp_work_destroy(w);
    return rc;
}

/* One particle of mass M on the plane z = 0: rows normal (z), tangents (x, y). */
static const pl_row_kind pk[3] = {PL_ROW_NORMAL, PL_ROW_FRICTION, PL_ROW_FRICTION};
static const int pp[3] = {1, 0, 0};
static const double M = 0.5, G = 9.81, H = 0.01, MU = 0.5;

static void particle(double vx, double vy, pl_ncp_function fn, const double *diag, double *lam, double *del,
                     lg_run *run)
{
    double mu[3] = {MU, 0, 0};
    pl_ncp_rows rows = {3, pk, pp, mu, NULL, NULL, NULL};
    double W[9] = {1 / M, 0, 0, 0, 1 / M, 0, 0, 0, 1 / M};
    /* q_t = 0 on the plane; q_free = q_t + h v - h^2 g e_z (A = M: no elasticity) */
    double df[3] = {-H * H * G, H * vx, H * vy};
    ck_assert_int_eq(run_lg(&rows, W, diag, H, fn, df, lam, del, 100, 1e-14, run), 0);
}

/* |v_t| <= mu g h: the particle sticks, lambda_t = -M v_t / h, no slip. */
START_TEST(test_particle_sticks)
{
    double diag_mass[3] = {2 / M, 2 / M, 2 / M}; /* another scaling, same solution */
    for (int variant = 0; variant < 4; ++variant) {
        double lam[3], del[3];
        lg_run run;
        particle(0.03, 0.02, variant & 1 ? PL_NCP_MINMAP : PL_NCP_FB, variant & 2 ? diag_mass : NULL, lam, del,
                 &run);
        ck_assert_msg(run.residual <= 1e-14, "variant %d: residual %g after %d", variant, run.residual, run.iters);
        ck_assert_double_eq_tol(lam[0], M * G, 1e-9);
        ck_assert_double_eq_tol(lam[1], -M * 0.03 / H, 1e-9);
        ck_assert_double_eq_tol(lam[2], -M * 0.02 / H, 1e-9);
        ck_assert(fabs(del[0]) < 1e-13 && fabs(del[1]) < 1e-13 && fabs(del[2]) < 1e-13);
        ck_assert(hypot(lam[1], lam[2]) <= MU * lam[0] * (1 + 1e-12));
    }
}
END_TEST

/* |v_t| > mu g h: it slides, lambda_t = -mu M g v_t / |v_t| and the slip
 * over the step is h v_t (1 - mu g h / |v_t|). */
START_TEST(test_particle_slides)
{
    for (int variant = 0; variant < 2; ++variant) {
        double lam[3], del[3];
        lg_run run;
        particle(0.3, -0.4, variant ? PL_NCP_MINMAP : PL_NCP_FB, NULL, lam, del, &run);
        ck_assert_msg(run.residual <= 1e-14, "residual %g after %d", run.residual, run.iters);
        ck_assert_int_le(run.iters, 30);
        ck_assert_double_eq_tol(lam[0], M * G, 1e-9);
        ck_assert_double_eq_tol(lam[1], -MU * M * G * 0.6, 1e-9);
        ck_assert_double_eq_tol(lam[2], MU * M * G * 0.8, 1e-9);
        double f = 1 - MU * G * H / 0.5;
        ck_assert_double_eq_tol(del[1], H * 0.3 * f, 1e-12);
        ck_assert_double_eq_tol(del[2], -H * 0.4 * f, 1e-12);
        ck_assert(fabs(del[0]) < 1e-13);
        ck_assert(hypot(lam[1], lam[2]) <= MU * lam[0] * (1 + 1e-6));
    }
}
END_TEST

/* The first step at a new resting contact, delta = lambda = 0: FB divides
 * 0/0 there.  Exact values: FB (omega = 1, e = r = h^2 / M) gives
 * dlambda_n = M g / 2, min map (e = 0) M g; tangents stay 0 (omega = 0). */
START_TEST(test_new_resting_contact_first_step)
{
    double mu[3] = {MU, 0, 0};
    pl_ncp_rows rows = {3, pk, pp, mu, NULL, NULL, NULL};
    double W[9] = {1 / M, 0, 0, 0, 1 / M, 0, 0, 0, 1 / M}, Wd[3] = {1 / M, 1 / M, 1 / M};
    pl_ncp_operator op = {3, W, NULL, NULL, Wd};
    pl_ncp_work *w;
    pl_error err;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    double r[3], zero[3] = {0, 0, 0}, df[3] = {-H * H * G, 0, 0}, dl[3], om[3];
    ck_assert_int_eq(ncp_scaling(w, Wd, H, r, &err), PL_OK);
    pl_ncp_params par;
    ncp_params_default(&par);
    par.h = H;
    par.cr_rtol = 1e-14;
    for (int fn = 0; fn < 2; ++fn) {
        par.fn = (pl_ncp_function)fn;
        /* unloaded: nothing happens */
        ck_assert_int_eq(ncp_step(w, &par, &op, r, zero, zero, zero, dl, om, NULL, &err), PL_OK);
        for (int j = 0; j < 3; ++j)
            ck_assert(isfinite(dl[j]) && fabs(dl[j]) < 1e-7);
        /* loaded by gravity */
        ck_assert_int_eq(ncp_step(w, &par, &op, r, zero, df, zero, dl, om, NULL, &err), PL_OK);
        ck_assert_double_eq_tol(dl[0], (fn == PL_NCP_FB ? M * G / 2 : M * G), 1e-7);
        ck_assert(dl[1] == 0.0 && dl[2] == 0.0);
        ck_assert(om[0] == 1.0 && om[1] == 0.0 && om[2] == 0.0);
        /* next: lambda_n > 0, friction at stick with lf = 0 = y (0/0): e = 0, finite */
        double lam[3] = {dl[0], 0, 0}, del[3] = {-H * H * G + H * H * dl[0] / M, 0, 0};
        ck_assert_int_eq(ncp_step(w, &par, &op, r, del, df, lam, dl, om, NULL, &err), PL_OK);
        ck_assert(om[1] == 1.0 && w->e[1] == 0.0 && w->e[2] == 0.0);
        for (int j = 0; j < 3; ++j)
            ck_assert(isfinite(dl[j]));
        ck_assert_double_eq_tol(lam[0] + dl[0], M * G, (fn == PL_NCP_MINMAP ? 1e-9 : 0.5 * M * G));
    }
    ncp_work_destroy(w);
}
END_TEST

/* A bilateral row with compliance coupled to a bounded row: exact values
 * with the bounded multiplier free, at hi and at lo. */
START_TEST(test_bilateral_and_bounded_rows)
{
    pl_row_kind k[2] = {PL_ROW_BILATERAL, PL_ROW_BOUNDED};
    double comp[2] = {2e-4, 0}, W[4] = {2.0, 0.5, 0.5, 1.0}, h = 0.02;
    double df[2] = {-1e-3, -3e-3}, lam[2], del[2];
    /* unconstrained: (h^2 W + diag(Eb, 0)) lambda = -df */
    double a11 = h * h * W[0] + comp[0], a12 = h * h * W[1], a22 = h * h * W[3];
    double det = a11 * a22 - a12 * a12;
    double l1 = (-df[0] * a22 + df[1] * a12) / det, l2 = (-df[1] * a11 + df[0] * a12) / det;
    lg_run run;
    for (int c = 0; c < 3; ++c) {
        double lo[2] = {0, -INFINITY}, hi[2] = {0, INFINITY};
        double fixed = NAN;
        if (c == 1)
            hi[1] = fixed = 0.5 * l2; /* the row cannot push that hard */
        if (c == 2)
            lo[1] = fixed = 1.5 * l2; /* it must push at least this much */
        pl_ncp_rows rows = {2, k, NULL, NULL, comp, lo, hi};
        ck_assert_int_eq(run_lg(&rows, W, NULL, h, PL_NCP_FB, df, lam, del, 50, 1e-15, &run), 0);
        ck_assert_msg(run.residual <= 1e-15, "case %d residual %g", c, run.residual);
        if (c == 0) {
            ck_assert_double_eq_tol(lam[0], l1, 1e-9 * fabs(l1));
            ck_assert_double_eq_tol(lam[1], l2, 1e-9 * fabs(l2));
            ck_assert(fabs(del[1]) < 1e-15);
        } else {
            double e1 = (-df[0] - a12 * fixed) / a11;
            ck_assert_double_eq_tol(lam[1], fixed, 1e-12 * fabs(fixed));
            ck_assert_double_eq_tol(lam[0], e1, 1e-9 * fabs(e1));
            ck_assert(c == 1 ? del[1] < 0.0 : del[1] > 0.0); /* the bound holds against the motion */
        }
        ck_assert_double_eq_tol(del[0] + comp[0] * lam[0], 0.0, 1e-15);
    }
}
END_TEST

typedef struct mf_op {
    const double *W;
    int m, calls;
} mf_op;

static int mf_apply(void *u, const double *x, double *y)
{
    mf_op *o = u;
    ++o->calls;
    for (int i = 0; i < o->m; ++i) {
        double s = 0.0;
        for (int j = 0; j < o->m; ++j)
            s += o->W[j * o->m + i] * x[j]; /* column order: W^T x, = W x for symmetric W */
        y[i] = s;
    }
    return 0;
}

/* The matrix-free operator gives the same step as the explicit one. */
START_TEST(test_matrix_free_equals_dense)
{
    enum { NC = 6, MM = 18 };
    test_rng g = {99};
    double W[MM * MM], Wd[MM], r[MM], del[MM], df[MM], lam[MM], d1[MM], d2[MM], o1[MM], o2[MM];
    pl_row_kind k[MM];
    int pair[MM];
    double mu[MM];
    random_spd(&g, MM, 0.1, W);
    for (int i = 0; i < NC; ++i) {
        k[3 * i] = PL_ROW_NORMAL;
        k[3 * i + 1] = k[3 * i + 2] = PL_ROW_FRICTION;
        pair[3 * i] = 3 * i + 1;
        pair[3 * i + 1] = pair[3 * i + 2] = 3 * i;
        mu[3 * i] = 0.3;
    }
    for (int j = 0; j < MM; ++j) {
        Wd[j] = W[j * MM + j];
        del[j] = rng_normal(&g);
        df[j] = rng_normal(&g);
        lam[j] = k[j] == PL_ROW_NORMAL ? fabs(rng_normal(&g)) : 0.1 * rng_normal(&g);
    }
    pl_ncp_rows rows = {MM, k, pair, mu, NULL, NULL, NULL};
    pl_ncp_work *w;
    pl_error err;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    ck_assert_int_eq(ncp_scaling(w, Wd, 0.01, r, &err), PL_OK);
    pl_ncp_params par;
    ncp_params_default(&par);
    par.h = 0.01;
    par.cr_rtol = 1e-14;
    par.cr_max_iter = 500;
    mf_op mo = {W, MM, 0};
    pl_ncp_operator dense = {MM, W, NULL, NULL, Wd}, mfree = {MM, NULL, mf_apply, &mo, Wd};
    pl_ncp_step_info i1, i2;
    ck_assert_int_eq(ncp_step(w, &par, &dense, r, del, df, lam, d1, o1, &i1, &err), PL_OK);
    ck_assert_int_eq(ncp_step(w, &par, &mfree, r, del, df, lam, d2, o2, &i2, &err), PL_OK);
    ck_assert_int_eq(mo.calls, i2.cr_iters + 1); /* CR products + the W Omega lambda^k product */
    double nrm = 0;
    for (int j = 0; j < MM; ++j)
        nrm = fmax(nrm, fabs(d1[j]));
    for (int j = 0; j < MM; ++j) {
        ck_assert(o1[j] == o2[j]);
        ck_assert_double_eq_tol(d1[j], d2[j], 1e-10 * nrm);
    }
    ck_assert(i1.cr_relres <= 1e-14 && i2.cr_relres <= 1e-14);
    ncp_work_destroy(w);
}
END_TEST

/* A local-global loop whose right-hand side changes every iteration (a
 * Jacobi splitting of an extra spring term, standing in for the local
 * step): the contact solution it converges to equals the direct fc3d
 * solution of the full system, W' = h^2 H (A + K)^-1 H^T.  This checks
 * the right-hand side of DERIVATION.md with delta^k != delta_free + h^2 W S lambda^k. */
START_TEST(test_local_global_matches_direct)
{
    enum { NV = 4, ND = 12, NC = 2, MM = 6 };
    const double h = 0.01, g = 9.81, ka = 1e3, kb = 5e2, mu[NC] = {0.3, 0.9};
    /* chain 0-1-2-3 in A; springs 0-2 and 1-3 handled by the splitting */
    const int ea[3][2] = {{0, 1}, {1, 2}, {2, 3}}, eb[2][2] = {{0, 2}, {1, 3}};
    double X[ND] = {0, 0, 0, 0.1, 0, 0, 0, 0, 0.1, 0.1, 0, 0.1};
    double V[ND] = {0.5, 0.1, 0, 0.01, 0.02, 0, 0.3, 0, 0, 0, 0, 0};
    double A[ND * ND] = {0}, K[ND * ND] = {0}, b0[ND], s[ND];
    for (int i = 0; i < ND; ++i)
        A[i * ND + i] = 1.0; /* unit masses */
    for (int pass = 0; pass < 2; ++pass)
        for (int e = 0; e < (pass ? 2 : 3); ++e) {
            int a = pass ? eb[e][0] : ea[e][0], c = pass ? eb[e][1] : ea[e][1];
            double *T = pass ? K : A, k = h * h * (pass ? kb : ka);
            for (int d = 0; d < 3; ++d) {
                int ia = 3 * a + d, ic = 3 * c + d;
                T[ia * ND + ia] += k; T[ic * ND + ic] += k;
                T[ia * ND + ic] -= k; T[ic * ND + ia] -= k;
            }
        }
    /* b0 = M s + h^2 (ka La + kb Lb) X: springs at rest in X */
    for (int i = 0; i < ND; ++i) {
        s[i] = X[i] + h * V[i] - (i % 3 == 2 ? h * h * g : 0.0);
        b0[i] = s[i];
        for (int j = 0; j < ND; ++j)
            b0[i] += (A[i * ND + j] - (i == j) + K[i * ND + j]) * X[j];
    }
    /* rows: vertices 0 and 1 on the plane z = 0: normal z, tangents x, y */
    pl_row_kind kind[MM];
    int pair[MM], vert[MM], dir[MM];
    double mur[MM];
    for (int c = 0; c < NC; ++c) {
        for (int t = 0; t < 3; ++t) {
            int j = 3 * c + t;
            kind[j] = t == 0 ? PL_ROW_NORMAL : PL_ROW_FRICTION;
            pair[j] = t == 0 ? j + 1 : 3 * c;
            mur[j] = t == 0 ? mu[c] : 0.0;
            vert[j] = c;
            dir[j] = t == 0 ? 2 : t - 1;
        }
    }
    /* A^-1 H^T and (A + K)^-1 H^T column by column */
    double AiHt[ND * MM], FiHt[ND * MM], F[ND * ND], col[ND], x[ND];
    for (int i = 0; i < ND * ND; ++i)
        F[i] = A[i] + K[i];
    for (int j = 0; j < MM; ++j) {
        for (int i = 0; i < ND; ++i)
            col[i] = i == 3 * vert[j] + dir[j];
        ck_assert_int_eq(dense_cholesky_solve(ND, A, col, x), 0);
        for (int i = 0; i < ND; ++i)
            AiHt[i * MM + j] = x[i];
        ck_assert_int_eq(dense_cholesky_solve(ND, F, col, x), 0);
        for (int i = 0; i < ND; ++i)
            FiHt[i * MM + j] = x[i];
    }
    double W[MM * MM], Wd[MM], Wf[MM * MM];
    for (int i = 0; i < MM; ++i)
        for (int j = 0; j < MM; ++j) {
            int ri = 3 * vert[i] + dir[i];
            W[i * MM + j] = AiHt[ri * MM + j];
            Wf[i * MM + j] = h * h * FiHt[ri * MM + j];
        }
    for (int j = 0; j < MM; ++j)
        Wd[j] = W[j * MM + j];
    /* row values at q: z for normals, (q - q_t) for tangents (q_t = X) */
#define ROWVAL(q, j) ((q)[3 * vert[j] + dir[j]] - (kind[j] == PL_ROW_FRICTION ? X[3 * vert[j] + dir[j]] : 0.0))
    /* direct reference */
    double qff[ND], qref[MM], rref[MM], uref[MM];
    ck_assert_int_eq(dense_cholesky_solve(ND, F, b0, qff), 0);
    for (int j = 0; j < MM; ++j)
        qref[j] = ROWVAL(qff, j);
    pl_ncp_solve_opts o;
    ncp_solve_opts_default(&o);
    o.max_iter = 5000;
    pl_ncp_solve_info si;
    pl_error err;
    memset(rref, 0, sizeof(rref));
    ck_assert_int_eq(ncp_solve_fc3d(NC, Wf, qref, mu, rref, uref, &o, &si, &err), PL_OK);
    ck_assert(si.converged);
    ck_assert(rref[0] > 0.1 && rref[3] > 0.1); /* both contacts pressed */
    /* the local-global loop, Algorithm 4 */
    pl_ncp_rows rows = {MM, kind, pair, mur, NULL, NULL, NULL};
    pl_ncp_work *w;
    ck_assert_int_eq(ncp_work_create(&rows, &w, &err), PL_OK);
    double r[MM], lam[MM] = {0}, dl[MM], S[MM], del[MM], dfree[MM], q[ND], qf[ND], b[ND];
    ck_assert_int_eq(ncp_scaling(w, Wd, h, r, &err), PL_OK);
    pl_ncp_operator op = {MM, W, NULL, NULL, Wd};
    pl_ncp_params par;
    ncp_params_default(&par);
    par.h = h;
    par.cr_rtol = 1e-14;
    memcpy(q, X, sizeof(q));
    int k;
    for (k = 0; k < 3000; ++k) {
        for (int i = 0; i < ND; ++i) { /* "local step": b^k = b0 - K q^k */
            b[i] = b0[i];
            for (int j = 0; j < ND; ++j)
                b[i] -= K[i * ND + j] * q[j];
        }
        ck_assert_int_eq(dense_cholesky_solve(ND, A, b, qf), 0);
        for (int j = 0; j < MM; ++j) {
            del[j] = ROWVAL(q, j);
            dfree[j] = ROWVAL(qf, j);
        }
        ck_assert_int_eq(ncp_step(w, &par, &op, r, del, dfree, lam, dl, S, NULL, &err), PL_OK);
        double change = 0.0;
        for (int j = 0; j < MM; ++j) {
            lam[j] += dl[j];
            change = fmax(change, fabs(dl[j]));
        }
        double qold0 = q[0];
        for (int i = 0; i < ND; ++i) { /* correction */
            q[i] = qf[i];
            for (int j = 0; j < MM; ++j)
                q[i] += h * h * AiHt[i * MM + j] * S[j] * lam[j];
        }
        if (change < 1e-11 && fabs(q[0] - qold0) < 1e-15)
            break;
    }
#undef ROWVAL
    fprintf(stderr, "local-global with a changing right-hand side: %d iterations, lambda %g %g %g, %g %g %g\n", k,
            lam[0], lam[1], lam[2], lam[3], lam[4], lam[5]);
    ck_assert_int_lt(k, 3000);
    /* delta = delta_free + h^2 W_full lambda: fc3d's r with W' = h^2 W_full is lambda [N] */
    for (int j = 0; j < MM; ++j)
        ck_assert_msg(fabs(lam[j] - rref[j]) <= 1e-8 * fabs(rref[0]), "row %d: local-global %.12g, direct %.12g",
                      j, lam[j], rref[j]);
    /* both regimes: contact 0 slides (on the cone), contact 1 sticks (inside) */
    ck_assert_double_eq_tol(hypot(lam[1], lam[2]), mu[0] * lam[0], 1e-8 * lam[0]);
    ck_assert(hypot(lam[4], lam[5]) < 0.95 * mu[1] * lam[3]);
    ncp_work_destroy(w);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("ncp_step");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_particle_sticks);
    tcase_add_test(tc, test_particle_slides);
    tcase_add_test(tc, test_new_resting_contact_first_step);
    tcase_add_test(tc, test_bilateral_and_bounded_rows);
    tcase_add_test(tc, test_matrix_free_equals_dense);
    tcase_add_test(tc, test_local_global_matches_direct);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *sr = srunner_create(suite());
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
