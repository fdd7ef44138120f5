/* sparse_inverse.h - the global step through an explicit sparse inverse
 * S = L^-1 of the Cholesky factor (the paper's Section 4).
 *
 * A (n x n, scalar, SPD) is factored by CHOLMOD as a simplicial LL^T of
 * P A P^T with a fill-reducing ordering followed by a postorder of the
 * elimination tree.  Then A^-1 = P^T S^T S P.  S stays in CHOLMOD's permuted,
 * postordered index space: right-hand sides are permuted in and results out.
 *
 * Layouts (flat arrays, meant to be copied as they are to a GPU):
 *  - S, profile: row i of S holds exactly the etree descendants of i, the
 *    contiguous columns first[i] .. i (postorder), so a row is its first
 *    column plus its values: val[start[i] + (j - first[i])] = S(i, j).
 *  - S^T, runs: row j of S^T (column j of S) is the ancestor path of j,
 *    ascending; stored as runs of consecutive columns:
 *    run_col[r] .. run_col[r] + run_len[r] - 1 for r in run_ptr[j] ..
 *    run_ptr[j+1]-1, values val[start[j] ..] in the same order.
 *
 * One object is not safe to use from several threads at once (it keeps
 * workspaces); its own loops use OpenMP and are deterministic. */
#ifndef PLIANT_SPARSE_INVERSE_H
#define PLIANT_SPARSE_INVERSE_H

#include <stdint.h>
#include "pliant/error.h"
#include "pliant/sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pl_spinv_ordering {
    PL_SPINV_METIS = 0,   /* METIS_NodeND nested dissection */
    PL_SPINV_NESDIS = 1,  /* CHOLMOD's nested dissection */
    PL_SPINV_AMD = 2,     /* approximate minimum degree */
    PL_SPINV_NATURAL = 3  /* no fill-reducing ordering (still postordered) */
} pl_spinv_ordering;

typedef enum pl_spinv_mode {
    PL_SPINV_SPARSE = 0,  /* products with the explicit S and S^T */
    PL_SPINV_DIRECT = 1   /* CHOLMOD's triangular solves (the CPU reference) */
} pl_spinv_mode;

typedef struct pl_spinv_options {
    pl_spinv_ordering ordering;
    pl_spinv_mode mode;
    int threads;          /* OpenMP threads; 0 = OpenMP's default */
} pl_spinv_options;

/* S = L^-1, profile layout (see above). */
typedef struct pl_spinv_profile {
    int n;
    int *first;           /* n: first column of row i */
    int64_t *start;       /* n + 1: offset of row i in val */
    double *val;          /* start[n] values */
} pl_spinv_profile;

/* S^T, runs layout (see above). */
typedef struct pl_spinv_runs {
    int n;
    int64_t *start;       /* n + 1: offset of row j in val */
    int64_t *run_ptr;     /* n + 1: runs of row j */
    int *run_col;         /* run_ptr[n]: first column of each run */
    int *run_len;         /* run_ptr[n]: columns in each run */
    double *val;          /* start[n] values */
} pl_spinv_runs;

typedef struct pl_spinv_stats {
    int n;
    int64_t nnz_A;        /* both triangles */
    int64_t nnz_L;
    int64_t nnz_S;        /* sum of the etree path lengths (also in direct mode) */
    int64_t runs_ST;      /* runs of consecutive columns in the rows of S^T */
    double bytes_S;       /* profile of S (0 in direct mode) */
    double bytes_ST;      /* runs of S^T (0 in direct mode) */
    double factor_s;      /* ordering + symbolic + numeric factorisation [s] */
    double inverse_s;     /* computing S and S^T [s] (0 in direct mode) */
    int ordering_used;    /* CHOLMOD's L->ordering */
} pl_spinv_stats;

typedef struct pl_sparse_inverse pl_sparse_inverse;

/* A new solver with the given options (NULL = metis, sparse, default threads);
 * NULL on allocation failure. */
pl_sparse_inverse *sparse_inverse_create(const pl_spinv_options *opt);
void sparse_inverse_destroy(pl_sparse_inverse *s);

/* Factors A (square, both triangles or the lower one; the upper is ignored)
 * and, in sparse mode, computes S and S^T.  PL_EINPUT when A is malformed or
 * not positive definite.  May be called again with another A. */
int sparse_inverse_factor(pl_sparse_inverse *s, const pl_csc *A, pl_error *err);

/* x = A^-1 b for an n x k row-major block; x may equal b. */
int sparse_inverse_solve(pl_sparse_inverse *s, const double *b, double *x, int k,
                            pl_error *err);

/* Y = S P H^T (n x m CSC, rows in the permuted space, sorted) for H (m x n
 * CSR over the original indices), so that H A^-1 H^T = Y^T Y.  Y is
 * allocated here and freed by the caller with pl_csc_free. */
int sparse_inverse_apply_inverse_to_rows(pl_sparse_inverse *s, const pl_csr *H, pl_csc *Y,
                                            pl_error *err);

/* diag[i] = [A^-1]_ii in the original indices (n values). */
int sparse_inverse_inverse_diagonal(pl_sparse_inverse *s, double *diag, pl_error *err);

/* Unknowns factored (0 before factor). */
int sparse_inverse_size(const pl_sparse_inverse *s);
const pl_spinv_stats *sparse_inverse_stats(const pl_sparse_inverse *s);
/* The explicit factors (NULL in direct mode or before factor). */
const pl_spinv_profile *pl_sparse_inverse_S(const pl_sparse_inverse *s);
const pl_spinv_runs *pl_sparse_inverse_ST(const pl_sparse_inverse *s);
/* perm[k] = original index of permuted index k; parent[k] = etree parent of
 * k in the permuted space (-1 at a root).  NULL before factor. */
const int *sparse_inverse_perm(const pl_sparse_inverse *s);
const int *sparse_inverse_parent(const pl_sparse_inverse *s);

/* Names of orderings and modes ("metis", "sparse"), for logs. */
const char *spinv_ordering_name(pl_spinv_ordering o);
const char *spinv_mode_name(pl_spinv_mode m);

/* ---- building blocks (used above; exposed for tests and benchmarks) ---- */

/* Checks that parent[] (parent > child, -1 at roots) is postordered: the
 * descendants of every i are the contiguous range first[i] .. i.  Fills
 * first (n) when it is; PL_EINTERNAL otherwise. */
int spinv_check_postorder(int n, const int *parent, int *first, pl_error *err);

/* y = S x and y = S^T x on n x k row-major blocks (x, y distinct), rows in
 * parallel over the nnz-balanced row ranges bounds[0..nchunks]. */
void spinv_profile_mult(const pl_spinv_profile *S, const double *x, double *y, int k,
                           const int *bounds, int nchunks, int threads);
void spinv_runs_mult(const pl_spinv_runs *ST, const double *x, double *y, int k,
                        const int *bounds, int nchunks, int threads);
/* Splits rows 0..n-1 into nchunks ranges of about equal nnz (start: n + 1
 * row offsets); bounds gets nchunks + 1 entries. */
void spinv_balance(const int64_t *start, int n, int nchunks, int *bounds);

void spinv_profile_free(pl_spinv_profile *S);
void spinv_runs_free(pl_spinv_runs *ST);

#ifdef __cplusplus
}
#endif
#endif
