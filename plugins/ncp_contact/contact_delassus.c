/* contact_delassus.c - the Delassus operator W = H A^-1 H^T of a step
 * (Section 5.3, eq. schur-complement) and the diagonals of the two
 * complementarity scalings (Section 5.4).
 *
 * The system is scalar (A (x) I3), so W = sum_k H_k A^-1 H_k^T over the
 * three coordinates k, H_k the scalar rows of coordinate k over the
 * unknowns.  Explicit: the global solver returns Y = S P H^T for the 3 m
 * scalar rows (sparse columns: etree paths), and W_ij = sum_k
 * Y_{k,i} . Y_{k,j}.  It is formed SpGEMM-style from the rows of Y: for
 * each row i of W, each nonzero (r, y) of its columns meets the nonzeros
 * of row r of Y, so the work is sum_r nnz(Y row r)^2, not m^2 n.  Each row
 * of W is written by one thread, in a fixed order (deterministic, and W_ij
 * and W_ji are the same sum in the same order: bitwise symmetric).
 * Matrix-free: W x = H A^-1 (H^T x), one solve on an nfree x 3 block. */
#include "contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ncpc_delassus_init(pl_ncpc_delassus *D) { memset(D, 0, sizeof *D); }

void ncpc_delassus_free(pl_ncpc_delassus *D)
{
    free(D->W);
    free(D->diag);
    free(D->X);
    ncpc_delassus_init(D);
}

static int oom(pl_error *err) { return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact", "out of memory"); }

static const pl_global_solver_ops *solver_ops(const pl_system *sys, pl_error *err)
{
    const pl_global_solver_ops *ops =
        sys->global_solver ? pl_component_role(sys->global_solver, PL_ROLE_GLOBAL_SOLVER) : NULL;
    if (!ops || !ops->solve)
        pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact", "the system has no global solver");
    return ops && ops->solve ? ops : NULL;
}

static int prepare(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r, pl_error *err)
{
    ncpc_delassus_free(D);
    D->m = r->m;
    D->nfree = sys->nfree;
    D->rows = r;
    D->solver = sys->global_solver;
    if (!(D->ops = solver_ops(sys, err))) return PL_EINPUT;
    D->diag = malloc(sizeof(double) * (size_t)(r->m > 0 ? r->m : 1));
    D->X = malloc(sizeof(double) * 3 * (size_t)(sys->nfree > 0 ? sys->nfree : 1));
    return D->diag && D->X ? PL_OK : oom(err);
}

/* Y (n x 3 cnt, coordinate-major columns) -> rows of each coordinate block:
 * entries of (row rr, coordinate k) at rp[3 rr + k] .. rp[3 rr + k + 1] - 1,
 * holding the column within its block (rj) and the value (rx). */
typedef struct y_rows {
    int *rp, *rj;
    double *rx;
} y_rows;

static void y_rows_free(y_rows *t)
{
    free(t->rp);
    free(t->rj);
    free(t->rx);
}

static int y_rows_build(const pl_csc *Y, int cnt, y_rows *t, pl_error *err)
{
    int n = Y->nrows, nnz = Y->p[Y->ncols];
    t->rp = calloc(3 * (size_t)n + 1, sizeof(int));
    t->rj = malloc(sizeof(int) * (size_t)(nnz > 0 ? nnz : 1));
    t->rx = malloc(sizeof(double) * (size_t)(nnz > 0 ? nnz : 1));
    int *next = malloc(sizeof(int) * 3 * (size_t)(n > 0 ? n : 1));
    if (!t->rp || !t->rj || !t->rx || !next) {
        free(next);
        return oom(err);
    }
    for (int c = 0; c < Y->ncols; ++c)
        for (int p = Y->p[c]; p < Y->p[c + 1]; ++p) t->rp[3 * (size_t)Y->i[p] + (size_t)(c / cnt) + 1]++;
    for (size_t a = 0; a < 3 * (size_t)n; ++a) t->rp[a + 1] += t->rp[a];
    memcpy(next, t->rp, sizeof(int) * 3 * (size_t)n);
    for (int c = 0; c < Y->ncols; ++c)
        for (int p = Y->p[c]; p < Y->p[c + 1]; ++p) {
            int q = next[3 * (size_t)Y->i[p] + (size_t)(c / cnt)]++;
            t->rj[q] = c % cnt;
            t->rx[q] = Y->x[p];
        }
    free(next);
    return PL_OK;
}

/* Y of the active rows list[0..cnt-1] (all rows when list is NULL). */
static int compute_y(const pl_ncpc_delassus *D, const pl_ncpc_rows *r, const int *list, int cnt,
                     pl_csc *Y, pl_error *err)
{
    pl_csr H;
    int st = ncpc_rows_scalar_csr(r, D->nfree, list, cnt, &H, err);
    if (st != PL_OK) return st;
    memset(Y, 0, sizeof *Y);
    st = D->ops->apply_inverse_to_rows(D->solver, &H, Y, err);
    pl_csr_free(&H);
    if (st == PL_OK && (Y->ncols != 3 * cnt || !Y->p))
        st = pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact",
                          "the global solver returned Y with %d columns for %d rows", Y->ncols, 3 * cnt);
    return st;
}

/* The multiply-adds of W = Y^T Y from the rows of Y: each nonzero of a
 * row meets every other nonzero of it.  Contacts gathered in one region
 * share the etree paths up to the root: those rows hold nearly all 3 m
 * columns and the work nears m^2 times their count, far beyond an
 * estimate from the average column of S (pulling_through_gap_12k: 473 ms
 * for 2739 rows against 200 ms for the matrix-free step beside it). */
static double w_work(const y_rows *t, int n)
{
    double s = 0.0;
    for (size_t a = 0; a < 3 * (size_t)n; ++a) {
        double c = (double)(t->rp[a + 1] - t->rp[a]);
        s += c * c;
    }
    return s;
}

/* The first entry of row rr of Y (entries by increasing column) whose
 * column is at least i. */
static int first_from(const y_rows *t, size_t rr, int i)
{
    int lo = t->rp[rr], hi = t->rp[rr + 1];
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (t->rj[mid] < i)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* W from Y and its rows (OpenMP over the rows of W, deterministic): the
 * upper triangle, then mirrored.  W_ij and W_ji are the same products
 * summed in the same order (over the shared rows of Y by increasing index),
 * so the mirror is bitwise what the lower triangle's own sums were; it
 * halves the build, the Schur phase of the explicit frames. */
static int form_w(pl_ncpc_delassus *D, const pl_csc *Y, const y_rows *t, pl_error *err)
{
    int m = D->m;
    if (!(D->W = malloc(sizeof(double) * (size_t)(m > 0 ? m : 1) * (size_t)(m > 0 ? m : 1)))) return oom(err);
    D->explicit_w = 1;
    double *W = D->W;
#pragma omp parallel for schedule(dynamic, 16) if (m > 64)
    for (int i = 0; i < m; ++i) {
        double *row = W + (size_t)i * (size_t)m;
        memset(row + i, 0, sizeof(double) * (size_t)(m - i));
        for (int k = 0; k < 3; ++k) {
            int c = k * m + i;
            for (int p = Y->p[c]; p < Y->p[c + 1]; ++p) {
                size_t rr = 3 * (size_t)Y->i[p] + (size_t)k;
                double y = Y->x[p];
                for (int q = first_from(t, rr, i); q < t->rp[rr + 1]; ++q) row[t->rj[q]] += y * t->rx[q];
            }
        }
    }
#pragma omp parallel for schedule(static) if (m > 64)
    for (int j = 1; j < m; ++j)
        for (int i = 0; i < j; ++i) W[(size_t)j * (size_t)m + (size_t)i] = W[(size_t)i * (size_t)m + (size_t)j];
    for (int j = 0; j < m; ++j) D->diag[j] = W[(size_t)j * (size_t)m + (size_t)j];
    return PL_OK;
}

/* Y of all rows and its rows; D->work its exact cost. */
static int y_all(pl_ncpc_delassus *D, const pl_ncpc_rows *r, pl_csc *Y, y_rows *t, pl_error *err)
{
    if (!D->ops->apply_inverse_to_rows)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                            "delassus=explicit needs a global solver that applies its inverse to rows "
                            "(SparseInverseSolver); use delassus=matrix-free");
    int st = compute_y(D, r, NULL, r->m, Y, err);
    if (st != PL_OK) return st;
    if ((st = y_rows_build(Y, r->m > 0 ? r->m : 1, t, err)) == PL_OK) D->work = w_work(t, Y->nrows);
    return st;
}

int ncpc_delassus_explicit(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r,
                              pl_error *err)
{
    int st = prepare(D, sys, r, err);
    if (st != PL_OK) return st;
    pl_csc Y = {0};
    y_rows t = {NULL, NULL, NULL};
    if ((st = y_all(D, r, &Y, &t, err)) == PL_OK) st = form_w(D, &Y, &t, err);
    y_rows_free(&t);
    pl_csc_free(&Y);
    return st;
}

int ncpc_delassus_explicit_device(pl_ncpc_delassus *D, const pl_system *sys,
                                     const pl_ncpc_rows *r, double *W_dev, pl_error *err)
{
    int st = prepare(D, sys, r, err);
    if (st != PL_OK) return st;
    if (D->ops->version < 3 || !D->ops->delassus_device)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                            "the global solver cannot build W on its device");
    pl_csr H;
    if ((st = ncpc_rows_scalar_csr(r, D->nfree, NULL, r->m, &H, err)) != PL_OK) return st;
    st = D->ops->delassus_device(D->solver, &H, r->m, W_dev, D->diag, err);
    pl_csr_free(&H);
    if (st == PL_OK) D->explicit_w = 1, D->W_dev = W_dev;
    return st;
}

int ncpc_delassus_apply(void *user, const double *x, double *y)
{
    pl_ncpc_delassus *D = user;
    if (D->explicit_w) {
        pl_ncp_operator op = {D->m, D->W, NULL, NULL, D->diag};
        return ncp_operator_apply(&op, x, y);
    }
    ncpc_rows_scatter(D->rows, D->nfree, x, 1.0, D->X);
    pl_buffer b = pl_buffer_host_f64(D->X, (size_t)D->nfree, 3);
    int st = D->ops->solve(D->solver, &b, &b, &D->err);
    if (st != PL_OK) {
        if (D->status == PL_OK) D->status = st;
        return st;
    }
    ncpc_rows_gather(D->rows, D->X, y);
    return PL_OK;
}

/* Diagonal entries of the rows list[0..cnt-1] from their Y columns, in
 * chunks of at most CHUNK rows (Y's memory stays bounded). */
enum { CHUNK = 1024 };

static int diag_from_y(pl_ncpc_delassus *D, const pl_ncpc_rows *r, const int *list, int cnt,
                       pl_error *err)
{
    for (int first = 0; first < cnt; first += CHUNK) {
        int c = cnt - first < CHUNK ? cnt - first : CHUNK;
        pl_csc Y;
        int st = compute_y(D, r, list + first, c, &Y, err);
        if (st != PL_OK) return st;
        for (int t = 0; t < c; ++t) {
            double s = 0.0;
            for (int k = 0; k < 3; ++k)
                for (int p = Y.p[k * c + t]; p < Y.p[k * c + t + 1]; ++p) s += Y.x[p] * Y.x[p];
            D->diag[list[first + t]] = s;
        }
        pl_csc_free(&Y);
    }
    return PL_OK;
}

/* (W e_j)_j by the matrix-free product, one solve per row. */
static int diag_from_products(pl_ncpc_delassus *D, const int *list, int cnt, pl_error *err)
{
    double *e = calloc((size_t)D->m, sizeof(double)), *y = malloc(sizeof(double) * (size_t)D->m);
    int st = e && y ? PL_OK : oom(err);
    for (int t = 0; t < cnt && st == PL_OK; ++t) {
        e[list[t]] = 1.0;
        if ((st = ncpc_delassus_apply(D, e, y)) != PL_OK) *err = D->err;
        D->diag[list[t]] = y[list[t]];
        e[list[t]] = 0.0;
    }
    free(e);
    free(y);
    return st;
}

/* The rows of several unknowns into multi (count returned); the others'
 * diagonal from inv_diag. */
static int split_rows(pl_ncpc_delassus *D, const pl_ncpc_rows *r, const double *inv_diag, int *multi)
{
    int nmulti = 0;
    for (int j = 0; j < r->m; ++j) {
        int e = r->fstart[j];
        if (inv_diag && r->fstart[j + 1] - e == 1) {
            /* one unknown a: W_jj = |c|^2 [A^-1]_aa (PAPER_NOTES 5) */
            const double *c = r->fcoef + 3 * e;
            D->diag[j] = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) * inv_diag[r->fcol[e]];
        } else {
            /* several unknowns: sum_ab (c_a . c_b) [A^-1]_ab needs the
             * off-diagonal entries of A^-1 */
            multi[nmulti++] = j;
        }
    }
    return nmulti;
}

/* The rows list[0..*cnt-1]' diagonal on the global solver's device
 * (delassus_device with W NULL); list keeps those it did not make (a NaN:
 * more unknowns than the device's walk holds), *cnt their count. */
static int diag_on_device(pl_ncpc_delassus *D, const pl_ncpc_rows *r, int *list, int *cnt,
                          pl_error *err)
{
    double *d = malloc(sizeof(double) * (size_t)*cnt);
    if (!d) return oom(err);
    pl_csr H = {0};
    int st = ncpc_rows_scalar_csr(r, D->nfree, list, *cnt, &H, err), left = 0;
    if (st == PL_OK) st = D->ops->delassus_device(D->solver, &H, *cnt, NULL, d, err);
    pl_csr_free(&H);
    for (int u = 0; st == PL_OK && u < *cnt; ++u) {
        if (isnan(d[u])) list[left++] = list[u];
        else D->diag[list[u]] = d[u];
    }
    if (st == PL_OK) *cnt = left;
    free(d);
    return st;
}

/* Both matrix-free entries: one-vertex rows from inv_diag, the others on the
 * device when asked and able, the rest from Y columns (or products). */
static int matrix_free(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r,
                       const double *inv_diag, int device, pl_error *err)
{
    int st = prepare(D, sys, r, err), m = r->m;
    if (st != PL_OK) return st;
    int *multi = malloc(sizeof(int) * (size_t)(m > 0 ? m : 1));
    if (!multi) return oom(err);
    int nmulti = split_rows(D, r, inv_diag, multi);
    if (nmulti > 0 && device && D->ops->version >= 3 && D->ops->delassus_device)
        st = diag_on_device(D, r, multi, &nmulti, err);
    if (st == PL_OK && nmulti > 0)
        st = D->ops->apply_inverse_to_rows ? diag_from_y(D, r, multi, nmulti, err)
                                           : diag_from_products(D, multi, nmulti, err);
    free(multi);
    return st;
}

int ncpc_delassus_matrix_free(pl_ncpc_delassus *D, const pl_system *sys,
                                 const pl_ncpc_rows *r, const double *inv_diag, pl_error *err)
{
    return matrix_free(D, sys, r, inv_diag, 0, err);
}

int ncpc_delassus_matrix_free_device(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r,
                                     const double *inv_diag, pl_error *err)
{
    return matrix_free(D, sys, r, inv_diag, 1, err);
}

int ncpc_delassus_auto(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r,
                       double max_work, const double *inv_diag, pl_error *err)
{
    int st = prepare(D, sys, r, err), m = r->m;
    if (st != PL_OK) return st;
    pl_csc Y = {0};
    y_rows t = {NULL, NULL, NULL};
    int *multi = NULL;
    if ((st = y_all(D, r, &Y, &t, err)) != PL_OK) goto done;
    if (D->work <= max_work) {
        st = form_w(D, &Y, &t, err);
        goto done;
    }
    /* matrix-free: the multi rows' diagonal from their columns of this Y
     * (each column is computed alone: the values diag_from_y gets) */
    if (!(multi = malloc(sizeof(int) * (size_t)(m > 0 ? m : 1)))) {
        st = oom(err);
        goto done;
    }
    int nmulti = split_rows(D, r, inv_diag, multi);
    for (int u = 0; u < nmulti; ++u) {
        int j = multi[u];
        double s = 0.0;
        for (int k = 0; k < 3; ++k)
            for (int p = Y.p[k * m + j]; p < Y.p[k * m + j + 1]; ++p) s += Y.x[p] * Y.x[p];
        D->diag[j] = s;
    }
done:
    free(multi);
    y_rows_free(&t);
    pl_csc_free(&Y);
    return st;
}

pl_ncp_operator ncpc_delassus_operator(pl_ncpc_delassus *D)
{
    pl_ncp_operator op = {D->m, D->explicit_w ? D->W : NULL, ncpc_delassus_apply, D, D->diag};
    return op;
}

int ncpc_mass_diagonal(const pl_ncpc_rows *r, const pl_system *sys, double *diag, pl_error *err)
{
    if (!sys->mass)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                            "preconditioner=mass: the animation loop gives no vertex masses");
    for (int j = 0; j < r->m; ++j) {
        double s = 0.0;
        for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e) {
            const double *c = r->fcoef + 3 * e;
            double mass = sys->mass[sys->free_vertex[r->fcol[e]]];
            if (!(mass > 0.0))
                return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                                    "preconditioner=mass: vertex %d has mass %g",
                                    sys->free_vertex[r->fcol[e]], mass);
            s += (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / mass;
        }
        diag[j] = s;
    }
    return PL_OK;
}
