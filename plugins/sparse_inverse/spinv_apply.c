/* spinv_apply.c - the global step x = P^T S^T (S (P b)) on n x k row-major
 * blocks (one pass over each matrix, the k columns updated together), its
 * direct-mode counterpart through CHOLMOD's solves, and diag(A^-1). */
#include "spinv_internal.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* y += sum_t v[t] x_t over a segment of consecutive columns (a profile row or a run). */
static inline void segment_dot(const double *v, int len, const double *x, double *y, int k)
{
    if (k == 3) {
        /* two interleaved sums per component shorten the add chains */
        double a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;
        int t = 0;
        for (; t + 1 < len; t += 2) {
            const double *p = x + 3 * (size_t)t;
            a0 += v[t] * p[0];
            a1 += v[t] * p[1];
            a2 += v[t] * p[2];
            b0 += v[t + 1] * p[3];
            b1 += v[t + 1] * p[4];
            b2 += v[t + 1] * p[5];
        }
        if (t < len) {
            const double *p = x + 3 * (size_t)t;
            a0 += v[t] * p[0];
            a1 += v[t] * p[1];
            a2 += v[t] * p[2];
        }
        y[0] += a0 + b0;
        y[1] += a1 + b1;
        y[2] += a2 + b2;
    } else {
        for (int t = 0; t < len; ++t)
            for (int c = 0; c < k; ++c) y[c] += v[t] * x[(size_t)t * k + c];
    }
}

/* The row loops as orphaned worksharing: inside a parallel region they
 * share its threads (the global step runs in one region), outside one they
 * run serially. */
static void profile_rows(const pl_spinv_profile *S, const double *x, double *y, int k,
                         const int *bounds, int nchunks)
{
#pragma omp for schedule(dynamic, 1)
    for (int c = 0; c < nchunks; ++c) {
        for (int i = bounds[c]; i < bounds[c + 1]; ++i) {
            double *yi = y + (size_t)i * k;
            for (int q = 0; q < k; ++q) yi[q] = 0.0;
            int f = S->first[i];
            segment_dot(S->val + S->start[i], i - f + 1, x + (size_t)f * k, yi, k);
        }
    }
}

static void runs_rows(const pl_spinv_runs *ST, const double *x, double *y, int k,
                      const int *bounds, int nchunks)
{
#pragma omp for schedule(dynamic, 1)
    for (int c = 0; c < nchunks; ++c) {
        for (int j = bounds[c]; j < bounds[c + 1]; ++j) {
            double *yj = y + (size_t)j * k;
            for (int q = 0; q < k; ++q) yj[q] = 0.0;
            const double *v = ST->val + ST->start[j];
            for (int64_t r = ST->run_ptr[j]; r < ST->run_ptr[j + 1]; ++r) {
                int len = ST->run_len[r];
                segment_dot(v, len, x + (size_t)ST->run_col[r] * k, yj, k);
                v += len;
            }
        }
    }
}

void spinv_profile_mult(const pl_spinv_profile *S, const double *x, double *y, int k,
                           const int *bounds, int nchunks, int threads)
{
#pragma omp parallel num_threads(threads)
    profile_rows(S, x, y, k, bounds, nchunks);
}

void spinv_runs_mult(const pl_spinv_runs *ST, const double *x, double *y, int k,
                        const int *bounds, int nchunks, int threads)
{
#pragma omp parallel num_threads(threads)
    runs_rows(ST, x, y, k, bounds, nchunks);
}

int spinv_reserve_work(pl_sparse_inverse *s, int k, pl_error *err)
{
    size_t need = (size_t)s->n * (size_t)k;
    if (need <= s->work_cap) return PL_OK;
    free(s->work_a);
    free(s->work_b);
    s->work_a = malloc(need * sizeof *s->work_a);
    s->work_b = malloc(need * sizeof *s->work_b);
    if (!s->work_a || !s->work_b) {
        free(s->work_a);
        free(s->work_b);
        s->work_a = s->work_b = NULL;
        s->work_cap = 0;
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse: out of memory");
    }
    s->work_cap = need;
    return PL_OK;
}

static int solve_sparse(pl_sparse_inverse *s, const double *b, double *x, int k, pl_error *err)
{
    int status = spinv_reserve_work(s, k, err);
    if (status != PL_OK) return status;
    int n = s->n, nt = spinv_threads_for(s, 2.0 * (double)s->S.start[s->n] * k);
    const int *perm = s->perm;
    double *a = s->work_a, *y = s->work_b;
    /* one parallel region: permute in, S, S^T, permute out (b has been
     * read in full before x is written, so x may alias it) */
#pragma omp parallel num_threads(nt)
    {
#pragma omp for schedule(static)
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < k; ++c) a[(size_t)i * k + c] = b[(size_t)perm[i] * k + c];
        profile_rows(&s->S, a, y, k, s->S_bounds, s->nchunks);
        runs_rows(&s->ST, y, a, k, s->ST_bounds, s->nchunks);
#pragma omp for schedule(static)
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < k; ++c) x[(size_t)perm[i] * k + c] = a[(size_t)i * k + c];
    }
    return PL_OK;
}

/* CHOLMOD works on column-major blocks: transpose in and out. */
static int solve_direct(pl_sparse_inverse *s, const double *b, double *x, int k, pl_error *err)
{
    cholmod_common *cc = &s->cc;
    size_t n = (size_t)s->n;
    if (s->B && s->B->ncol != (size_t)k) cholmod_free_dense(&s->B, cc);
    if (!s->B) s->B = cholmod_allocate_dense(n, (size_t)k, n, CHOLMOD_REAL, cc);
    if (!s->B) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse: out of memory");
    double *B = s->B->x;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < k; ++c) B[(size_t)c * n + i] = b[i * k + c];
    if (!cholmod_solve2(CHOLMOD_A, s->L, s->B, NULL, &s->X, NULL, &s->Y, &s->E, cc))
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "sparse inverse: cholmod_solve2 failed, status %d", cc->status);
    const double *X = s->X->x;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < k; ++c) x[i * k + c] = X[(size_t)c * n + i];
    return PL_OK;
}

int sparse_inverse_solve(pl_sparse_inverse *s, const double *b, double *x, int k,
                            pl_error *err)
{
    if (!s || s->n == 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse: solve before factor");
    if (!b || !x || k < 1)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse: solve needs an n x k block with k >= 1 (k = %d)", k);
    return s->opt.mode == PL_SPINV_DIRECT ? solve_direct(s, b, x, k, err)
                                          : solve_sparse(s, b, x, k, err);
}

int sparse_inverse_inverse_diagonal(pl_sparse_inverse *s, double *diag, pl_error *err)
{
    if (!s || s->n == 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse: inverse_diagonal before factor");
    int n = s->n, nt = s->nthreads;
    const int *perm = s->perm;
    if (s->opt.mode == PL_SPINV_SPARSE) {
        const pl_spinv_runs *ST = &s->ST;
#pragma omp parallel for schedule(dynamic, 64) num_threads(nt)
        for (int j = 0; j < n; ++j) {
            double sum = 0.0;
            for (int64_t q = ST->start[j]; q < ST->start[j + 1]; ++q) sum += ST->val[q] * ST->val[q];
            diag[perm[j]] = sum;
        }
        return PL_OK;
    }
    /* direct mode keeps no S: solve each column on its path, keep its norm */
    double *w = calloc(2 * (size_t)n * (size_t)nt, sizeof *w);
    if (!w) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse: out of memory");
#pragma omp parallel num_threads(nt)
    {
        double *wt = w + 2 * (size_t)n * (size_t)omp_get_thread_num(), *col = wt + n;
#pragma omp for schedule(dynamic, 16)
        for (int j = 0; j < n; ++j) {
            int len = spinv_path_column(s->L, s->parent, j, wt, col);
            double sum = 0.0;
            for (int q = 0; q < len; ++q) sum += col[q] * col[q];
            diag[perm[j]] = sum;
        }
    }
    free(w);
    return PL_OK;
}
