/* ncp_step.c - one constraint update of Algorithm 4:
 *   (h^2 Omega W S + Et) dlambda = rhs,
 *   rhs = -phi + Omega (delta^k - delta_free - h^2 W S lambda^k)
 * solved by conjugate residual (derivation: DERIVATION.md).  S is the
 * scale of lambda in the correction q = A^-1 (b + h^2 H^T S lambda): the
 * paper's S = Omega (J = Omega H), except S = 1 on bounded rows, whose
 * force at a bound (Omega = 0, lambda = lo or hi != 0) must not vanish.
 * Those clamped rows are eliminated first (their rows are diagonal), so
 * CR sees the symmetric h^2 Omega W Omega + Et. */
#include "ncp.h"

#include <math.h>
#include <stdlib.h>

#include "ncp_functions.h"

void ncp_params_default(pl_ncp_params *p)
{
    p->fn = PL_NCP_FB;
    p->h = 1.0;
    p->fb_eps = 1e-12;
    p->cr_max_iter = 0;
    p->cr_rtol = 1e-10;
    p->full_force = 0;
    p->cr_jacobi = 1;
}

void ncp_work_destroy(pl_ncp_work *w)
{
    if (!w)
        return;
    free(w->contact);
    free(w->contact_of);
    free(w->omega);
    free(w->scale);
    free(w->clamped);
    free(w->is_clamped);
    free(w->op_omega);
    free(w->op_e);
    free(w->cr_scale);
    free(w->e);
    free(w->phi);
    free(w->rhs);
    free(w->tmp);
    free(w->tmp2);
    free(w->cr);
    free(w);
}

/* Checks the per-row data; fills the contact table. */
static int build_contacts(pl_ncp_work *w, pl_error *err)
{
    const pl_ncp_rows *R = &w->rows;
    int m = w->m, nc = 0;
    for (int j = 0; j < m; ++j) {
        w->contact_of[j] = -1;
        switch (R->kind[j]) {
        case PL_ROW_NORMAL:
            w->contact_of[j] = nc++;
            if (R->mu && !(R->mu[j] >= 0.0 && isfinite(R->mu[j])))
                return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp", "row %d: mu = %g must be >= 0", j, R->mu[j]);
            break;
        case PL_ROW_BILATERAL:
            if (R->compliance && !(R->compliance[j] >= 0.0 && isfinite(R->compliance[j])))
                return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp", "row %d: compliance = %g must be >= 0", j,
                                    R->compliance[j]);
            break;
        case PL_ROW_BOUNDED:
            if (R->lo && R->hi && !(R->lo[j] <= R->hi[j]))
                return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp", "row %d: bounds [%g, %g] are empty", j,
                                    R->lo[j], R->hi[j]);
            break;
        case PL_ROW_FRICTION:
            break;
        default:
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp", "row %d: unknown kind %d", j, (int)R->kind[j]);
        }
    }
    w->nc = nc;
    w->contact = malloc(sizeof(int) * 3 * (size_t)(nc > 0 ? nc : 1));
    if (!w->contact)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp", "out of memory");
    for (int j = 0; j < m; ++j)
        if (R->kind[j] == PL_ROW_NORMAL) {
            int *ct = w->contact + 3 * w->contact_of[j];
            ct[0] = j;
            ct[1] = ct[2] = -1;
        }
    for (int j = 0; j < m; ++j) {
        if (R->kind[j] != PL_ROW_FRICTION)
            continue;
        int n = R->pair ? R->pair[j] : -1;
        if (n < 0 || n >= m || R->kind[n] != PL_ROW_NORMAL)
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp", "friction row %d: pair %d is not a normal row", j, n);
        int c = w->contact_of[n];
        int *ct = w->contact + 3 * c;
        if (ct[1] < 0)
            ct[1] = j;
        else if (ct[2] < 0)
            ct[2] = j;
        else
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp", "normal row %d has more than two friction rows", n);
        w->contact_of[j] = c;
    }
    return PL_OK;
}

int ncp_work_create(const pl_ncp_rows *rows, pl_ncp_work **out, pl_error *err)
{
    *out = NULL;
    if (!rows || rows->m < 0 || (rows->m > 0 && !rows->kind))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp", "rows: missing kinds");
    pl_ncp_work *w = calloc(1, sizeof(*w));
    if (!w)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp", "out of memory");
    w->rows = *rows;
    w->m = rows->m;
    size_t m1 = (size_t)(w->m > 0 ? w->m : 1);
    w->contact_of = malloc(sizeof(int) * m1);
    w->omega = malloc(sizeof(double) * m1);
    w->scale = malloc(sizeof(double) * m1);
    w->clamped = malloc(sizeof(double) * m1);
    w->is_clamped = malloc(sizeof(int) * m1);
    w->op_omega = malloc(sizeof(double) * m1);
    w->op_e = malloc(sizeof(double) * m1);
    w->cr_scale = malloc(sizeof(double) * m1);
    w->e = malloc(sizeof(double) * m1);
    w->phi = malloc(sizeof(double) * m1);
    w->rhs = malloc(sizeof(double) * m1);
    w->tmp = malloc(sizeof(double) * m1);
    w->tmp2 = malloc(sizeof(double) * m1);
    w->cr = malloc(sizeof(double) * 4 * m1);
    if (!w->contact_of || !w->omega || !w->scale || !w->clamped || !w->is_clamped || !w->op_omega ||
        !w->op_e || !w->cr_scale || !w->e || !w->phi || !w->rhs || !w->tmp || !w->tmp2 || !w->cr) {
        ncp_work_destroy(w);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp", "out of memory");
    }
    int st = build_contacts(w, err);
    if (st != PL_OK) {
        ncp_work_destroy(w);
        return st;
    }
    *out = w;
    return PL_OK;
}

/* phi, omega and e of every row at (delta, lambda); friction per contact. */
static void evaluate_rows(pl_ncp_work *w, const pl_ncp_params *par, const double *r,
                          const double *delta, const double *lambda)
{
    const pl_ncp_rows *R = &w->rows;
    for (int j = 0; j < w->m; ++j) {
        switch (R->kind[j]) {
        case PL_ROW_BILATERAL:
            ncp_bilateral(delta[j], lambda[j], R->compliance ? R->compliance[j] : 0.0,
                          &w->phi[j], &w->omega[j], &w->e[j]);
            break;
        case PL_ROW_NORMAL:
            ncp_normal((int)par->fn, delta[j], lambda[j], r[j], par->fb_eps, &w->phi[j],
                       &w->omega[j], &w->e[j]);
            break;
        case PL_ROW_BOUNDED:
            ncp_bounded(delta[j], lambda[j], R->lo ? R->lo[j] : -INFINITY, R->hi ? R->hi[j] : INFINITY,
                        r[j], &w->phi[j], &w->omega[j], &w->e[j]);
            break;
        case PL_ROW_FRICTION:
            break; /* below, per contact */
        }
    }
    for (int c = 0; c < w->nc; ++c) {
        const int *ct = w->contact + 3 * c;
        int nt = 0, t[2];
        double y[2], lf[2], phi[2], om, e;
        for (int i = 1; i <= 2; ++i)
            if (ct[i] >= 0) {
                t[nt] = ct[i];
                y[nt] = delta[ct[i]];
                lf[nt] = lambda[ct[i]];
                ++nt;
            }
        if (nt == 0)
            continue;
        double mu = R->mu ? R->mu[ct[0]] : 0.0;
        /* rho = h r_f: the friction scaling at the position level. */
        ncp_friction((int)par->fn, nt, y, lf, lambda[ct[0]], mu, par->h * r[t[0]], phi, &om, &e);
        for (int i = 0; i < nt; ++i) {
            w->phi[t[i]] = phi[i];
            w->omega[t[i]] = om;
            w->e[t[i]] = e;
        }
    }
}

typedef struct step_op {
    const pl_ncp_operator *W;
    const double *omega, *e;
    double h2;
    double *ox, *wox;
} step_op;

/* y = h^2 Omega W (Omega x) + Et x: never forms Omega W Omega (PAPER_NOTES 7). */
static int apply_system(void *user, const double *x, double *y)
{
    step_op *o = user;
    int m = o->W->m;
    for (int i = 0; i < m; ++i)
        o->ox[i] = o->omega[i] * x[i];
    int st = ncp_operator_apply(o->W, o->ox, o->wox);
    if (st != PL_OK)
        return st;
    for (int i = 0; i < m; ++i)
        y[i] = o->h2 * o->omega[i] * o->wox[i] + o->e[i] * x[i];
    return PL_OK;
}

int ncp_step(pl_ncp_work *w, const pl_ncp_params *par, const pl_ncp_operator *W,
                const double *r, const double *delta, const double *delta_free,
                const double *lambda, double *dlambda, double *force_scale,
                pl_ncp_step_info *info, pl_error *err)
{
    int m = w->m, st, nclamped = 0;
    if (W->m != m)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_step", "operator has %d rows, constraints %d", W->m, m);
    if (!(par->h > 0.0))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_step", "time step h = %g must be > 0", par->h);
    for (int j = 0; j < m; ++j)
        if (w->rows.kind[j] != PL_ROW_BILATERAL && !(r[j] > 0.0 && isfinite(r[j])))
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_step", "row %d: scaling r = %g must be > 0", j, r[j]);
    double h2 = par->h * par->h;
    evaluate_rows(w, par, r, delta, lambda);
    for (int j = 0; j < m; ++j) {
        if (par->full_force) {
            /* S = 1: rows whose Omega is (nearly) 0 read e dlambda = rhs */
            w->scale[j] = 1.0;
            w->is_clamped[j] = !(w->omega[j] > PL_NCP_OMEGA_CLAMP);
        } else {
            w->scale[j] = w->rows.kind[j] == PL_ROW_BOUNDED ? 1.0 : w->omega[j];
            w->is_clamped[j] = w->scale[j] != w->omega[j];
        }
        nclamped += w->is_clamped[j];
    }

    /* The linearisation gap p = delta^k - delta_free - h^2 W S lambda^k
     * = H (q^k - A^-1 (b^k + h^2 H^T S lambda^k)); then
     * rhs = -phi + Omega p (DERIVATION.md). */
    for (int j = 0; j < m; ++j)
        w->tmp[j] = w->scale[j] * lambda[j];
    if ((st = ncp_operator_apply(W, w->tmp, w->tmp2)) != PL_OK)
        return pl_error_set(err, st, NULL, 0, "ncp_step", "W product failed");
    double phin = 0.0;
    for (int j = 0; j < m; ++j) {
        double p = delta[j] - delta_free[j] - h2 * w->tmp2[j];
        w->rhs[j] = -w->phi[j] + w->omega[j] * p;
        if (fabs(w->phi[j]) > phin)
            phin = fabs(w->phi[j]);
        dlambda[j] = 0.0;
    }
    /* Clamped rows (Omega = 0, S = 1) read e dlambda = rhs: solve them, move
     * their force change to the other rows' right-hand side, and give CR a
     * zero right-hand side there (their rows and columns of h^2 Omega W
     * Omega + Et are diagonal, so CR keeps those entries at 0). */
    for (int j = 0; j < m; ++j) {
        int c = w->is_clamped[j];
        w->clamped[j] = c ? w->rhs[j] / w->e[j] : 0.0;
        w->tmp[j] = c ? w->scale[j] * w->clamped[j] : 0.0;
        if (c)
            w->rhs[j] = 0.0;
    }
    if (nclamped > 0) {
        if ((st = ncp_operator_apply(W, w->tmp, w->tmp2)) != PL_OK)
            return pl_error_set(err, st, NULL, 0, "ncp_step", "W product failed");
        for (int j = 0; j < m; ++j)
            if (!w->is_clamped[j]) /* (full_force clamps rows with a small Omega > 0) */
                w->rhs[j] -= h2 * w->omega[j] * w->tmp2[j];
    }
    /* CR's operator: h^2 Omega W Omega + Et (jacobian), or, with full_force,
     * row j divided by Omega_j: h^2 W + diag(e / Omega), symmetric positive
     * definite on the rows that are not clamped. */
    for (int j = 0; j < m; ++j) {
        int c = w->is_clamped[j];
        if (par->full_force) {
            w->op_omega[j] = c ? 0.0 : 1.0;
            w->op_e[j] = c ? w->e[j] : w->e[j] / w->omega[j];
            if (!c)
                w->rhs[j] /= w->omega[j];
        } else {
            w->op_omega[j] = w->omega[j];
            w->op_e[j] = w->e[j];
        }
    }
    /* Jacobi scaling: with s = D^-1/2, D = diag(h^2 op_omega^2 W_jj + op_e),
     * CR solves (S A S) y = S rhs and dlambda = S y; S A S has the same form
     * (op_omega s, op_e s^2), so the operator below serves both. */
    for (int j = 0; j < m; ++j) {
        double d = W->diag ? h2 * w->op_omega[j] * w->op_omega[j] * W->diag[j] + w->op_e[j] : 0.0;
        double sj = par->cr_jacobi && d > 0.0 && isfinite(d) ? 1.0 / sqrt(d) : 1.0;
        w->cr_scale[j] = sj;
        w->op_omega[j] *= sj;
        w->op_e[j] *= sj * sj;
        w->rhs[j] *= sj;
    }
    step_op op = {W, w->op_omega, w->op_e, h2, w->tmp, w->tmp2};
    int maxit = par->cr_max_iter > 0 ? par->cr_max_iter : 2 * m + 10;
    int its = 0;
    double relres = 0.0;
    st = ncp_cr(m, apply_system, &op, w->rhs, dlambda, maxit, par->cr_rtol, w->cr, &its, &relres, err);
    if (st != PL_OK)
        return st;
    for (int j = 0; j < m; ++j)
        dlambda[j] = w->cr_scale[j] * dlambda[j] + w->clamped[j];
    if (force_scale)
        for (int j = 0; j < m; ++j)
            force_scale[j] = w->scale[j];
    if (info) {
        info->cr_iters = its;
        info->cr_relres = relres;
        info->phi_norm = phin;
    }
    return PL_OK;
}
