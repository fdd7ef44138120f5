/* ncp_solve.c - a plain 3D frictional contact problem (Siconos' fc3d
 * convention: u = W r + q) solved by the plugin's machinery, so that the
 * core can be tested alone.
 *
 * It is Algorithm 4 with h = 1 and nothing elastic: q_free <-> q, and the
 * iterate's constraint values are delta^k = q + W (Omega^{k-1} .* lambda^k),
 * exactly what the local-global loop sees after its correction
 * q^k = A^-1 (b + h^2 H^T Omega^{k-1} lambda^k). */
#include "ncp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ncp_solve_opts_default(pl_ncp_solve_opts *o)
{
    o->fn = PL_NCP_FB;
    o->max_iter = 500;
    o->tol = 1e-12;
    o->cr_max_iter = 0;
    o->cr_rtol = 1e-12;
}

/* Rows 3i (normal), 3i+1, 3i+2 (tangents of contact i). */
typedef struct fc3d_rows {
    pl_row_kind *kind;
    int *pair;
    double *mu;
} fc3d_rows;

static void fc3d_rows_free(fc3d_rows *f)
{
    free(f->kind);
    free(f->pair);
    free(f->mu);
}

static int fc3d_rows_make(int nc, const double *mu, fc3d_rows *f, pl_ncp_rows *view, pl_error *err)
{
    size_t m = 3 * (size_t)(nc > 0 ? nc : 1);
    f->kind = malloc(sizeof(pl_row_kind) * m);
    f->pair = malloc(sizeof(int) * m);
    f->mu = calloc(m, sizeof(double));
    if (!f->kind || !f->pair || !f->mu) {
        fc3d_rows_free(f);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_fc3d", "out of memory");
    }
    for (int i = 0; i < nc; ++i) {
        f->kind[3 * i] = PL_ROW_NORMAL;
        f->kind[3 * i + 1] = f->kind[3 * i + 2] = PL_ROW_FRICTION;
        f->pair[3 * i] = 3 * i + 1;
        f->pair[3 * i + 1] = f->pair[3 * i + 2] = 3 * i;
        f->mu[3 * i] = mu[i];
    }
    pl_ncp_rows v = {3 * nc, f->kind, f->pair, f->mu, NULL, NULL, NULL};
    *view = v;
    return PL_OK;
}

static void diagonal(int m, const double *W, double *d)
{
    for (int j = 0; j < m; ++j)
        d[j] = W[(size_t)j * (size_t)m + (size_t)j];
}

int ncp_residual_fc3d(int nc, const double *W, const double *mu, const double *reaction,
                         const double *u, pl_ncp_residual *res, pl_error *err)
{
    if (nc < 0 || (nc > 0 && (!W || !mu || !reaction || !u)))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_fc3d", "missing input");
    int m = 3 * nc, st;
    fc3d_rows f;
    pl_ncp_rows view;
    pl_ncp_work *w = NULL;
    if ((st = fc3d_rows_make(nc, mu, &f, &view, err)) != PL_OK)
        return st;
    double *d = malloc(sizeof(double) * 2 * (size_t)(m > 0 ? m : 1));
    if (!d) {
        st = pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_fc3d", "out of memory");
        goto done;
    }
    diagonal(m, W, d);
    if ((st = ncp_work_create(&view, &w, err)) != PL_OK)
        goto done;
    if ((st = ncp_scaling(w, d, 1.0, d + m, err)) != PL_OK)
        goto done;
    st = ncp_residual_eval(w, d + m, 1.0, u, reaction, res, err);
done:
    ncp_work_destroy(w);
    free(d);
    fc3d_rows_free(&f);
    return st;
}

/* u = q + W (s .* x), s = NULL for the identity. */
static void affine(int m, const pl_ncp_operator *W, const double *q, const double *s, const double *x,
                   double *tmp, double *u)
{
    for (int j = 0; j < m; ++j)
        tmp[j] = s ? s[j] * x[j] : x[j];
    ncp_operator_apply(W, tmp, u);
    for (int j = 0; j < m; ++j)
        u[j] += q[j];
}

int ncp_solve_fc3d(int nc, const double *W, const double *q, const double *mu,
                      double *reaction, double *u, const pl_ncp_solve_opts *opts,
                      pl_ncp_solve_info *info, pl_error *err)
{
    pl_ncp_solve_opts o;
    if (opts)
        o = *opts;
    else
        ncp_solve_opts_default(&o);
    memset(info, 0, sizeof(*info));
    if (nc < 0 || (nc > 0 && (!W || !q || !mu || !reaction || !u)))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_fc3d", "missing input");
    int m = 3 * nc, st;
    for (int i = 0; i < nc; ++i)
        if (!(mu[i] >= 0.0 && isfinite(mu[i])))
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_fc3d", "contact %d: mu = %g", i, mu[i]);
    fc3d_rows f;
    pl_ncp_rows view;
    pl_ncp_work *w = NULL;
    if ((st = fc3d_rows_make(nc, mu, &f, &view, err)) != PL_OK)
        return st;
    size_t m1 = (size_t)(m > 0 ? m : 1);
    double *buf = malloc(sizeof(double) * 7 * m1);
    if (!buf) {
        st = pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_fc3d", "out of memory");
        goto done;
    }
    double *d = buf, *r = buf + m1, *delta = buf + 2 * m1, *dl = buf + 3 * m1, *om = buf + 4 * m1,
           *tmp = buf + 5 * m1, *trial = buf + 6 * m1, merit = 0.0;
    int accepted = 0;
    diagonal(m, W, d);
    pl_ncp_operator op = {m, W, NULL, NULL, d};
    if ((st = ncp_work_create(&view, &w, err)) != PL_OK)
        goto done;
    if ((st = ncp_scaling(w, d, 1.0, r, err)) != PL_OK)
        goto done;
    pl_ncp_params par;
    ncp_params_default(&par);
    par.fn = o.fn;
    par.h = 1.0;
    par.cr_max_iter = o.cr_max_iter;
    par.cr_rtol = o.cr_rtol;
    double qn = 0.0;
    for (int j = 0; j < m; ++j)
        qn = fmax(qn, fabs(q[j]));
    double scale = qn > 0.0 ? qn : 1.0;
    /* eps far below the problem's scale: it only matters at exact 0/0. */
    par.fb_eps = 1e-14 * scale;
    for (int j = 0; j < m; ++j)
        om[j] = 1.0; /* the first iterate has seen no split yet: delta = q + W lambda */
    for (int k = 0;; ++k) {
        pl_ncp_residual res;
        if (k == 0 || !accepted) {
            affine(m, &op, q, NULL, reaction, tmp, u);
            if ((st = ncp_residual_eval(w, r, 1.0, u, reaction, &res, err)) != PL_OK)
                goto done;
            merit = res.total;
        }
        info->iters = k;
        info->residual = merit / scale;
        if (info->residual <= o.tol) {
            info->converged = 1;
            break;
        }
        if (k >= o.max_iter)
            break;
        affine(m, &op, q, om, reaction, tmp, delta);
        pl_ncp_step_info si;
        if ((st = ncp_step(w, &par, &op, r, delta, q, reaction, dl, om, &si, err)) != PL_OK)
            goto done;
        info->cr_iters += si.cr_iters;
        /* Backtracking on the Signorini-Coulomb residual: the friction
         * compliance is a fixed point (Appendix B), which can cycle between
         * coupled sliding contacts; halving the step breaks the cycle. */
        double alpha = 1.0;
        accepted = 0;
        for (int ls = 0; ls < 12; ++ls, alpha *= 0.5) {
            for (int j = 0; j < m; ++j)
                trial[j] = reaction[j] + alpha * dl[j];
            affine(m, &op, q, NULL, trial, tmp, u);
            if ((st = ncp_residual_eval(w, r, 1.0, u, trial, &res, err)) != PL_OK)
                goto done;
            if ((accepted = res.total <= (1.0 - 1e-4 * alpha) * merit))
                break;
        }
        if (!accepted) /* no decrease along dl: take the full step anyway */
            alpha = 1.0;
        for (int j = 0; j < m; ++j)
            reaction[j] += alpha * dl[j];
        if (accepted)
            merit = res.total;
    }
    affine(m, &op, q, NULL, reaction, tmp, u);
done:
    ncp_work_destroy(w);
    free(buf);
    fc3d_rows_free(&f);
    return st;
}
