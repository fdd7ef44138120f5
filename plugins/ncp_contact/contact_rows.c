/* contact_rows.c - a step's constraint rows as the core needs them: the
 * active rows (those a force on the unknowns can move), their entries
 * merged per unknown and split from the entries on prescribed vertices
 * (those count in H q but take no correction), the offsets that make
 * delta = H q - offset (Appendix A, end: friction rows measure
 * h dot(delta_f) = H_f (q - q_t) - h d_f), and the scalar rows over the
 * unknowns (the system is A (x) I3, so a 3D row is three scalar rows). */
#include "contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ncpc_rows_init(pl_ncpc_rows *r) { memset(r, 0, sizeof *r); }

void ncpc_rows_free(pl_ncpc_rows *r)
{
    free(r->full);
    free(r->sub);
    free(r->fstart);
    free(r->fcol);
    free(r->fcoef);
    free(r->pstart);
    free(r->pvert);
    free(r->pcoef);
    free(r->offset);
    free(r->kind);
    free(r->pair);
    free(r->mu);
    free(r->compliance);
    free(r->lo);
    free(r->hi);
    ncpc_rows_init(r);
}

static int nonzero3(const double *c) { return c[0] != 0.0 || c[1] != 0.0 || c[2] != 0.0; }

/* Merges row i's entries on unknowns into (col, coef) sorted by col, zero
 * sums dropped; returns the count (cols/coefs have room for the row's
 * entries).  Rows are short (a point of up to 4 vertices per side). */
static int merge_free(const pl_rows *rows, int i, const int *free_index, int *cols, double *coefs)
{
    int n = 0;
    for (int e = rows->start[i]; e < rows->start[i + 1]; ++e) {
        int f = free_index[rows->vertex[e]];
        if (f < 0) continue;
        const double *c = &rows->coef[3 * e];
        int t = 0;
        while (t < n && cols[t] < f) ++t;
        if (t < n && cols[t] == f) {
            for (int k = 0; k < 3; ++k) coefs[3 * t + k] += c[k];
            continue;
        }
        memmove(cols + t + 1, cols + t, sizeof *cols * (size_t)(n - t));
        memmove(coefs + 3 * (t + 1), coefs + 3 * t, sizeof *coefs * 3 * (size_t)(n - t));
        cols[t] = f;
        for (int k = 0; k < 3; ++k) coefs[3 * t + k] = c[k];
        ++n;
    }
    int kept = 0;
    for (int t = 0; t < n; ++t)
        if (nonzero3(coefs + 3 * t)) {
            cols[kept] = cols[t];
            memmove(coefs + 3 * kept, coefs + 3 * t, 3 * sizeof *coefs);
            ++kept;
        }
    return kept;
}

static int check_input(const pl_system *sys, const pl_rows *rows, pl_error *err)
{
    if (!sys || !sys->free_index || !sys->free_vertex || sys->nverts < 0 || sys->nfree < 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact", "incomplete system description");
    if (!rows || rows->n < 0 || (rows->n > 0 && (!rows->start || !rows->kind || !rows->d)))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact", "incomplete constraint rows");
    if (rows->n > 0 && rows->start[0] < 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact", "row 0 starts at entry %d",
                            rows->start[0]);
    for (int i = 0; i < rows->n; ++i) {
        /* entries in order: the build merges each row at its own offset */
        if (rows->start[i + 1] < rows->start[i])
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                                "row %d: its entries end (%d) before they start (%d)", i,
                                rows->start[i + 1], rows->start[i]);
        if ((int)rows->kind[i] < PL_ROW_BILATERAL || (int)rows->kind[i] > PL_ROW_BOUNDED)
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact", "row %d: unknown kind %d", i,
                                (int)rows->kind[i]);
        if (!isfinite(rows->d[i]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact", "row %d: d = %g", i, rows->d[i]);
        for (int e = rows->start[i]; e < rows->start[i + 1]; ++e) {
            int v = rows->vertex[e];
            const double *c = &rows->coef[3 * e];
            if (v < 0 || v >= sys->nverts)
                return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                                    "row %d: vertex %d is not among the %d vertices", i, v,
                                    sys->nverts);
            if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]))
                return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                                    "row %d: coefficient (%g, %g, %g) is not finite", i, c[0], c[1], c[2]);
        }
    }
    return PL_OK;
}

/* Pass 1: every row merged once, into fcol / fcoef at its raw offset
 * (rows->start[i]: merge_free writes at most a row's entry count), its kept
 * count in cnt[i]; which rows are active; the prescribed entries' count. */
static int mark_active(pl_ncpc_rows *r, const pl_system *sys, const pl_rows *rows, int *cnt,
                       int *npre_ent, pl_error *err)
{
    int N = rows->n;
    for (int i = 0; i < N; ++i)
        cnt[i] = merge_free(rows, i, sys->free_index, r->fcol + rows->start[i],
                            r->fcoef + 3 * (size_t)rows->start[i]);
    int m = 0;
    *npre_ent = 0;
    for (int i = 0; i < N; ++i) {
        int ok = cnt[i] > 0;
        if (rows->kind[i] == PL_ROW_FRICTION) {
            int n = rows->pair ? rows->pair[i] : -1;
            if (n < 0 || n >= N || rows->kind[n] != PL_ROW_NORMAL)
                return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_contact",
                                    "friction row %d: its pair %d is not a normal row", i, n);
            ok = ok && cnt[n] > 0;
        }
        if (!ok) continue;
        r->full[m++] = i;
        for (int e = rows->start[i]; e < rows->start[i + 1]; ++e)
            *npre_ent += sys->free_index[rows->vertex[e]] < 0;
    }
    r->m = m;
    for (int i = 0; i < N; ++i) r->sub[i] = -1;
    for (int j = 0; j < m; ++j) r->sub[r->full[j]] = j;
    return PL_OK;
}

/* Row i's merged entries from its raw offset down to entry `to` (to <=
 * rows->start[i], rows in increasing order: nothing not yet moved is
 * overwritten). */
static void move_merged(pl_ncpc_rows *r, int from, int to, int n)
{
    for (int t = 0; t < n; ++t) {
        r->fcol[to + t] = r->fcol[from + t];
        for (int k = 0; k < 3; ++k) r->fcoef[3 * (to + t) + k] = r->fcoef[3 * (from + t) + k];
    }
}

int ncpc_rows_build(pl_ncpc_rows *r, const pl_system *sys, const pl_rows *rows,
                       const double *q_t, pl_error *err)
{
    ncpc_rows_free(r);
    int st = check_input(sys, rows, err);
    if (st != PL_OK) return st;
    int N = rows->n;
    size_t N1 = (size_t)(N > 0 ? N : 1), E1 = (size_t)(N > 0 && rows->start[N] > 0 ? rows->start[N] : 1);
    r->nall = N;
    r->full = malloc(sizeof *r->full * N1);
    r->sub = malloc(sizeof *r->sub * N1);
    /* room for every row's entries: pass 1 merges there, pass 2 packs */
    r->fcol = malloc(sizeof(int) * E1);
    r->fcoef = malloc(sizeof(double) * 3 * E1);
    int *cnt = malloc(sizeof *cnt * N1), np = 0;
    if (!r->full || !r->sub || !r->fcol || !r->fcoef || !cnt) {
        free(cnt);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact", "out of memory");
    }
    st = mark_active(r, sys, rows, cnt, &np, err);
    int m = r->m;
    size_t m1 = (size_t)(m > 0 ? m : 1);
    if (st == PL_OK) {
        r->fstart = malloc(sizeof(int) * (m1 + 1));
        r->pstart = malloc(sizeof(int) * (m1 + 1));
        r->pvert = malloc(sizeof(int) * (size_t)(np > 0 ? np : 1));
        r->pcoef = malloc(sizeof(double) * 3 * (size_t)(np > 0 ? np : 1));
        r->offset = malloc(sizeof(double) * m1);
        r->kind = malloc(sizeof(pl_row_kind) * m1);
        r->pair = malloc(sizeof(int) * m1);
        r->mu = malloc(sizeof(double) * m1);
        r->compliance = malloc(sizeof(double) * m1);
        r->lo = malloc(sizeof(double) * m1);
        r->hi = malloc(sizeof(double) * m1);
        if (!r->fstart || !r->pstart || !r->pvert || !r->pcoef || !r->offset || !r->kind ||
            !r->pair || !r->mu || !r->compliance || !r->lo || !r->hi)
            st = pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact", "out of memory");
    }
    if (st != PL_OK) {
        free(cnt);
        return st;
    }
    r->fstart[0] = r->pstart[0] = 0;
    for (int j = 0; j < m; ++j) {
        int i = r->full[j];
        move_merged(r, rows->start[i], r->fstart[j], cnt[i]);
        r->fstart[j + 1] = r->fstart[j] + cnt[i];
        int p = r->pstart[j];
        for (int e = rows->start[i]; e < rows->start[i + 1]; ++e)
            if (sys->free_index[rows->vertex[e]] < 0) {
                r->pvert[p] = rows->vertex[e];
                memcpy(r->pcoef + 3 * p, &rows->coef[3 * e], 3 * sizeof(double));
                ++p;
            }
        r->pstart[j + 1] = p;
        r->kind[j] = rows->kind[i];
        r->pair[j] = r->kind[j] == PL_ROW_FRICTION ? r->sub[rows->pair[i]] : -1;
        r->mu[j] = rows->mu ? rows->mu[i] : 0.0;
        r->compliance[j] = rows->compliance ? rows->compliance[i] : 0.0;
        r->lo[j] = rows->lo ? rows->lo[i] : -INFINITY;
        r->hi[j] = rows->hi ? rows->hi[i] : INFINITY;
        /* friction rows measure y = H_f (q - q_t) - h d_f */
        r->offset[j] = r->kind[j] == PL_ROW_FRICTION ? pl_rows_dot(rows, i, q_t) + sys->h * rows->d[i]
                                                     : rows->d[i];
    }
    free(cnt);
    return PL_OK;
}

pl_ncp_rows ncpc_rows_view(const pl_ncpc_rows *r)
{
    pl_ncp_rows v = {r->m, r->kind, r->pair, r->mu, r->compliance, r->lo, r->hi};
    return v;
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double prescribed_part(const pl_ncpc_rows *r, int j, const double *q)
{
    double s = 0.0;
    for (int p = r->pstart[j]; p < r->pstart[j + 1]; ++p) s += dot3(r->pcoef + 3 * p, q + 3 * r->pvert[p]);
    return s;
}

void ncpc_rows_delta(const pl_ncpc_rows *r, const double *x, const double *q, double *delta)
{
    /* each row writes its own delta[j] (deterministic) */
#pragma omp parallel for schedule(static) if (r->m >= 2048)
    for (int j = 0; j < r->m; ++j) {
        double s = prescribed_part(r, j, q);
        for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e) s += dot3(r->fcoef + 3 * e, x + 3 * r->fcol[e]);
        delta[j] = s - r->offset[j];
    }
}

void ncpc_rows_delta_all(const pl_ncpc_rows *r, const int *free_vertex, const double *q,
                            double *delta)
{
#pragma omp parallel for schedule(static) if (r->m >= 2048)
    for (int j = 0; j < r->m; ++j) {
        double s = prescribed_part(r, j, q);
        for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e)
            s += dot3(r->fcoef + 3 * e, q + 3 * free_vertex[r->fcol[e]]);
        delta[j] = s - r->offset[j];
    }
}

void ncpc_rows_scatter(const pl_ncpc_rows *r, int nfree, const double *x, double alpha,
                          double *X)
{
    /* rows share unknowns: sequential, in row order (deterministic) */
    memset(X, 0, sizeof(double) * 3 * (size_t)nfree);
    for (int j = 0; j < r->m; ++j) {
        double l = alpha * x[j];
        if (l == 0.0) continue;
        for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e) {
            double *xe = X + 3 * r->fcol[e];
            const double *c = r->fcoef + 3 * e;
            xe[0] += l * c[0];
            xe[1] += l * c[1];
            xe[2] += l * c[2];
        }
    }
}

void ncpc_rows_gather(const pl_ncpc_rows *r, const double *X, double *y)
{
#pragma omp parallel for schedule(static) if (r->m >= 2048)
    for (int j = 0; j < r->m; ++j) {
        double s = 0.0;
        for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e) s += dot3(r->fcoef + 3 * e, X + 3 * r->fcol[e]);
        y[j] = s;
    }
}

int ncpc_rows_scalar_csr(const pl_ncpc_rows *r, int nfree, const int *list, int count,
                            pl_csr *H, pl_error *err)
{
    memset(H, 0, sizeof *H);
    int nnz = 0;
    for (int t = 0; t < count; ++t) {
        int j = list ? list[t] : t;
        for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e)
            for (int k = 0; k < 3; ++k) nnz += r->fcoef[3 * e + k] != 0.0;
    }
    H->nrows = 3 * count;
    H->ncols = nfree;
    H->p = malloc(sizeof(int) * ((size_t)H->nrows + 1));
    H->j = malloc(sizeof(int) * (size_t)(nnz > 0 ? nnz : 1));
    H->x = malloc(sizeof(double) * (size_t)(nnz > 0 ? nnz : 1));
    if (!H->p || !H->j || !H->x) {
        pl_csr_free(H);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact", "out of memory");
    }
    int q = 0;
    for (int k = 0; k < 3; ++k)
        for (int t = 0; t < count; ++t) {
            int j = list ? list[t] : t;
            H->p[k * count + t] = q;
            for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e) {
                double c = r->fcoef[3 * e + k];
                if (c == 0.0) continue;
                H->j[q] = r->fcol[e]; /* sorted: fcol is sorted within a row */
                H->x[q++] = c;
            }
        }
    H->p[H->nrows] = q;
    return PL_OK;
}
