/* spinv_rows.c - Y = S P H^T for sparse rows H (the Delassus operator's
 * factor: H A^-1 H^T = Y^T Y).  Column r of Y is L^-1 applied to the
 * permuted row r of H; its pattern is the union of the etree paths of that
 * row's nonzeros.  Columns are independent: two parallel passes (count,
 * then fill), each column by one thread, so the result is deterministic. */
#include "spinv_internal.h"

#include <limits.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* The end of the ascending run of a[0 .. len) that starts at i < len. */
static int run_end(const int *a, int i, int len)
{
    int j = i + 1;
    while (j < len && a[j - 1] < a[j]) ++j;
    return j;
}

/* Sorts a row's pattern ascending.  row_pattern lists it as a few
 * ascending runs (an etree path climbs to larger indices, one piece per
 * nonzero of the row), so a natural merge sort takes about log2(runs)
 * passes with inline comparisons: qsort's log2(len) passes through a
 * comparison function were 16% of a CPU raptor run's samples
 * (docs/benchmarks.md, "Y's patterns merged").  The entries are distinct,
 * so the result is qsort's.  tmp holds len ints.  Each run is scanned once
 * a pass: a merge's second run end is where the next merge starts. */
static void sort_runs(int *a, int len, int *tmp)
{
    int *src = a, *dst = tmp;
    for (int j; len > 0 && (j = run_end(src, 0, len)) < len;) { /* more than one run: a pass */
        for (int i = 0; i < len;) { /* merge [i, j) and [j, k), the next two runs */
            int k = j < len ? run_end(src, j, len) : j;
            int x = i, y = j, o = i;
            while (x < j && y < k) dst[o++] = src[x] < src[y] ? src[x++] : src[y++];
            while (x < j) dst[o++] = src[x++];
            while (y < k) dst[o++] = src[y++];
            i = k;
            if (i < len) j = run_end(src, i, len);
        }
        int *t = src;
        src = dst;
        dst = t;
    }
    if (src != a) memcpy(a, src, (size_t)len * sizeof *a);
}

/* Pattern of column r into list (unsorted); mark is all zero before and after. */
static int row_pattern(const pl_sparse_inverse *s, const pl_csr *H, int r, char *mark, int *list)
{
    int len = 0;
    for (int q = H->p[r]; q < H->p[r + 1]; ++q) {
        /* paths merge on the way up: stop where an earlier one passed */
        for (int k = s->pinv[H->j[q]]; k != -1 && !mark[k]; k = s->parent[k]) {
            mark[k] = 1;
            list[len++] = k;
        }
    }
    for (int t = 0; t < len; ++t) mark[list[t]] = 0;
    return len;
}

/* Sparse mode: w = sum_q h_q * (column pinv[j_q] of S), read from S^T. */
static void row_values_sparse(const pl_sparse_inverse *s, const pl_csr *H, int r, double *w)
{
    const pl_spinv_runs *ST = &s->ST;
    for (int q = H->p[r]; q < H->p[r + 1]; ++q) {
        double h = H->x[q];
        int k = s->pinv[H->j[q]];
        const double *v = ST->val + ST->start[k];
        for (int64_t u = ST->run_ptr[k]; u < ST->run_ptr[k + 1]; ++u) {
            double *wc = w + ST->run_col[u];
            for (int t = 0; t < ST->run_len[u]; ++t) wc[t] += h * v[t];
            v += ST->run_len[u];
        }
    }
}

/* Direct mode: the sparse triangular solve L w = P h over the sorted
 * pattern (ascending order is a topological order of the etree). */
static void row_values_direct(const pl_sparse_inverse *s, const pl_csr *H, int r,
                              const int *pattern, int len, double *w)
{
    const cholmod_factor *L = s->L;
    const int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
    const double *Lx = L->x;
    for (int q = H->p[r]; q < H->p[r + 1]; ++q) w[s->pinv[H->j[q]]] += H->x[q];
    for (int t = 0; t < len; ++t) {
        int k = pattern[t], p0 = Lp[k];
        double v = w[k] / Lx[p0];
        w[k] = v;
        for (int q = p0 + 1; q < p0 + Lnz[k]; ++q) w[Li[q]] -= Lx[q] * v;
    }
}

static int check_rows(const pl_sparse_inverse *s, const pl_csr *H, pl_error *err)
{
    if (!s || s->n == 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse: apply_inverse_to_rows before factor");
    if (!H || !H->p || H->nrows < 0 || H->ncols != s->n || H->p[0] != 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse: rows must be a CSR matrix with %d columns", s->n);
    for (int r = 0; r < H->nrows; ++r) {
        if (H->p[r + 1] < H->p[r])
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "sparse inverse: row pointers decrease at row %d", r);
        for (int q = H->p[r]; q < H->p[r + 1]; ++q)
            if (H->j[q] < 0 || H->j[q] >= s->n)
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "sparse inverse: column %d of row %d out of range", H->j[q], r);
    }
    return PL_OK;
}

/* Pass 1: Y->p from the pattern sizes; allocates Y->i and Y->x. */
static int count_columns(const pl_sparse_inverse *s, const pl_csr *H, pl_csc *Y, char *mark,
                         int *list, int nt, pl_error *err)
{
    int m = H->nrows, n = s->n;
    int64_t *cnt = malloc(((size_t)m + 1) * sizeof *cnt);
    if (!cnt) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse: out of memory");
#pragma omp parallel num_threads(nt)
    {
        size_t tid = (size_t)omp_get_thread_num();
        char *mk = mark + tid * (size_t)n;
        int *ls = list + tid * (size_t)n;
#pragma omp for schedule(dynamic, 8)
        for (int r = 0; r < m; ++r) cnt[r] = row_pattern(s, H, r, mk, ls);
    }
    int64_t total = 0;
    for (int r = 0; r < m; ++r) {
        Y->p[r] = (int)total;
        total += cnt[r];
        if (total > INT_MAX) {
            free(cnt);
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "sparse inverse: Y would have more than %d nonzeros", INT_MAX);
        }
    }
    Y->p[m] = (int)total;
    free(cnt);
    size_t cap = total ? (size_t)total : 1;
    Y->i = malloc(cap * sizeof *Y->i);
    Y->x = malloc(cap * sizeof *Y->x);
    if (!Y->i || !Y->x) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    return PL_OK;
}

int sparse_inverse_apply_inverse_to_rows(pl_sparse_inverse *s, const pl_csr *H, pl_csc *Y,
                                            pl_error *err)
{
    if (!Y) return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse: no output");
    memset(Y, 0, sizeof *Y);
    int status = check_rows(s, H, err);
    if (status != PL_OK) return status;
    /* work: about a path of S per row (at most n) */
    int n = s->n, m = H->nrows, nt = spinv_threads_for(s, (double)m * n);
    Y->nrows = n;
    Y->ncols = m;
    Y->p = malloc(((size_t)m + 1) * sizeof *Y->p);
    char *mark = calloc((size_t)n * (size_t)nt, 1);
    int *list = malloc((size_t)n * (size_t)nt * sizeof *list);
    double *w = calloc((size_t)n * (size_t)nt, sizeof *w);
    if (!Y->p || !mark || !list || !w)
        status = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse: out of memory");
    if (status == PL_OK) status = count_columns(s, H, Y, mark, list, nt, err);
    if (status == PL_OK) {
        int direct = s->opt.mode == PL_SPINV_DIRECT;
#pragma omp parallel num_threads(nt)
        {
            size_t tid = (size_t)omp_get_thread_num();
            char *mk = mark + tid * (size_t)n;
            int *tmp = list + tid * (size_t)n;
            double *wt = w + tid * (size_t)n;
#pragma omp for schedule(dynamic, 8)
            for (int r = 0; r < m; ++r) {
                int *pat = Y->i + Y->p[r];
                int len = row_pattern(s, H, r, mk, pat);
                sort_runs(pat, len, tmp);
                if (direct) row_values_direct(s, H, r, pat, len, wt);
                else row_values_sparse(s, H, r, wt);
                double *yx = Y->x + Y->p[r];
                for (int t = 0; t < len; ++t) {
                    yx[t] = wt[pat[t]];
                    wt[pat[t]] = 0.0;
                }
            }
        }
    }
    free(mark);
    free(list);
    free(w);
    if (status != PL_OK) pl_csc_free(Y);
    return status;
}
