/* bench_spinv.c - sizes and times of the sparse inverse on tetrahedral bars.
 *
 *   bench_spinv [ordering] [repetitions]     (ordering: metis nesdis amd; default metis)
 *
 * For the 6-tet grids 44x11x11 and 72x17x17 (vertices per axis) with
 * A = M + h^2 w G: nnz(A), nnz(L), nnz(S), memory, factor and inverse times,
 * and median times of the global step on n x 3 blocks: sparse (S^T S b),
 * direct (CHOLMOD's solves).  Also the products alone: S y (profile), S^T y
 * with S^T as runs and as CSR.  MB = 2^20 bytes; CSR[MB] is what S would
 * take in float64 CSR (8 + 4 bytes a nonzero); diff = |x_sparse - x_direct|
 * / |x_direct|. */
#include "sparse_inverse.h"
#include "spinv_testmat.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Median ms of x = A^-1 b over reps calls. */
static double time_solve(pl_sparse_inverse *s, const double *b, double *x, int reps)
{
    double *t = malloc((size_t)reps * sizeof *t);
    pl_error err;
    sparse_inverse_solve(s, b, x, 3, &err); /* warm up */
    for (int r = 0; r < reps; ++r) {
        double t0 = omp_get_wtime();
        sparse_inverse_solve(s, b, x, 3, &err);
        t[r] = 1e3 * (omp_get_wtime() - t0);
    }
    double m = median(t, reps);
    free(t);
    return m;
}

/* S^T as CSR (column indices), built from the runs, for comparison. */
static void csr_mult(int n, const int64_t *start, const int *col, const double *val,
                     const double *x, double *y)
{
#pragma omp parallel for schedule(dynamic, 64)
    for (int j = 0; j < n; ++j) {
        double a0 = 0, a1 = 0, a2 = 0;
        for (int64_t q = start[j]; q < start[j + 1]; ++q) {
            const double *p = x + 3 * (size_t)col[q];
            a0 += val[q] * p[0];
            a1 += val[q] * p[1];
            a2 += val[q] * p[2];
        }
        y[3 * (size_t)j] = a0;
        y[3 * (size_t)j + 1] = a1;
        y[3 * (size_t)j + 2] = a2;
    }
}

/* Median ms of S y (profile), of S^T y with the runs layout and with a CSR copy. */
static void time_products(const pl_spinv_profile *S, const pl_spinv_runs *ST, const double *x,
                          double *y, int reps, double *ms_s, double *ms_runs, double *ms_csr)
{
    int n = ST->n, nt = omp_get_max_threads(), nch = 16 * nt < n ? 16 * nt : n;
    int64_t nnz = ST->start[n];
    int *col = malloc((size_t)nnz * sizeof *col), *bounds = malloc((size_t)(nch + 1) * sizeof *bounds);
    double *t = malloc((size_t)reps * sizeof *t);
    if (!col || !bounds || !t) {
        *ms_s = *ms_runs = *ms_csr = NAN;
        free(col), free(bounds), free(t);
        return;
    }
    for (int j = 0; j < n; ++j) {
        int64_t q = ST->start[j];
        for (int64_t r = ST->run_ptr[j]; r < ST->run_ptr[j + 1]; ++r)
            for (int u = 0; u < ST->run_len[r]; ++u) col[q++] = ST->run_col[r] + u;
    }
    spinv_balance(S->start, n, nch, bounds);
    for (int r = 0; r <= reps; ++r) {
        double t0 = omp_get_wtime();
        spinv_profile_mult(S, x, y, 3, bounds, nch, nt);
        if (r) t[r - 1] = 1e3 * (omp_get_wtime() - t0);
    }
    *ms_s = median(t, reps);
    spinv_balance(ST->start, n, nch, bounds);
    for (int r = 0; r <= reps; ++r) {
        double t0 = omp_get_wtime();
        spinv_runs_mult(ST, x, y, 3, bounds, nch, nt);
        if (r) t[r - 1] = 1e3 * (omp_get_wtime() - t0);
    }
    *ms_runs = median(t, reps);
    for (int r = 0; r <= reps; ++r) {
        double t0 = omp_get_wtime();
        csr_mult(n, ST->start, col, ST->val, x, y);
        if (r) t[r - 1] = 1e3 * (omp_get_wtime() - t0);
    }
    *ms_csr = median(t, reps);
    free(col);
    free(bounds);
    free(t);
}

static int run_bar(int nx, int ny, int nz, pl_spinv_ordering ord, int reps)
{
    pl_csc A;
    if (spinv_grid_matrix(nx, ny, nz, 50.0, &A) != PL_OK) return 1;
    int n = A.ncols;
    pl_spinv_options so = {ord, PL_SPINV_SPARSE, 0}, dopt = {ord, PL_SPINV_DIRECT, 0};
    pl_sparse_inverse *sp = sparse_inverse_create(&so), *di = sparse_inverse_create(&dopt);
    double *b = malloc((size_t)n * 3 * sizeof *b), *xs = malloc((size_t)n * 3 * sizeof *xs);
    double *xd = malloc((size_t)n * 3 * sizeof *xd);
    pl_error err;
    if (!sp || !di || !b || !xs || !xd || sparse_inverse_factor(sp, &A, &err) != PL_OK ||
        sparse_inverse_factor(di, &A, &err) != PL_OK) {
        fprintf(stderr, "bench: setup failed: %s\n", err.msg);
        return 1;
    }
    srand(1);
    for (int i = 0; i < 3 * n; ++i) b[i] = rand() / (double)RAND_MAX - 0.5;
    double ms_sparse = time_solve(sp, b, xs, reps), ms_direct = time_solve(di, b, xd, reps);
    double num = 0, den = 0;
    for (int i = 0; i < 3 * n; ++i) num += (xs[i] - xd[i]) * (xs[i] - xd[i]), den += xd[i] * xd[i];
    double ms_s, ms_runs, ms_csr;
    time_products(pl_sparse_inverse_S(sp), pl_sparse_inverse_ST(sp), b, xs, reps, &ms_s, &ms_runs,
                  &ms_csr);
    const pl_spinv_stats *st = sparse_inverse_stats(sp);
    const double mb = 1024.0 * 1024.0;
    printf("%2dx%2dx%2d %6d %7lld %8lld %9lld %6.1f %6.1f %6.1f %6.3f %6.3f %8.3f %8.3f %7.3f "
           "%7.3f %7.3f %6lld %.0e\n",
           nx, ny, nz, n, (long long)st->nnz_A, (long long)st->nnz_L, (long long)st->nnz_S,
           st->bytes_S / mb, st->bytes_ST / mb, (double)st->nnz_S * 12.0 / mb, st->factor_s,
           st->inverse_s, ms_sparse, ms_direct, ms_s, ms_runs, ms_csr, (long long)st->runs_ST,
           sqrt(num / den));
    sparse_inverse_destroy(sp);
    sparse_inverse_destroy(di);
    pl_csc_free(&A);
    free(b);
    free(xs);
    free(xd);
    return 0;
}

int main(int argc, char **argv)
{
    pl_spinv_ordering ord = PL_SPINV_METIS;
    if (argc > 1) {
        if (!strcmp(argv[1], "nesdis")) ord = PL_SPINV_NESDIS;
        else if (!strcmp(argv[1], "amd")) ord = PL_SPINV_AMD;
        else if (strcmp(argv[1], "metis")) {
            fprintf(stderr, "usage: bench_spinv [metis|nesdis|amd] [repetitions]\n");
            return 2;
        }
    }
    int reps = argc > 2 ? atoi(argv[2]) : 30;
    if (reps < 1) reps = 1;
    printf("sparse inverse, %s ordering, %d threads, medians of %d global steps (n x 3, float64)\n",
           spinv_ordering_name(ord), omp_get_max_threads(), reps);
    printf("grid          n  nnz(A)   nnz(L)    nnz(S)  S[MB] ST[MB] CSR[MB] fac[s] inv[s] "
           "sparse[ms] direct[ms] S[ms] ST:runs ST:csr  runs diff\n");
    if (run_bar(44, 11, 11, ord, reps) || run_bar(72, 17, 17, ord, reps)) return 1;
    return 0;
}
