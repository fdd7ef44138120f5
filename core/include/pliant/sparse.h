/* sparse.h - the small sparse-matrix structs that cross interfaces.
 * Factorisation and products are done by CHOLMOD and the solver plugins;
 * the core only carries matrices between components (CSparse-style). */
#ifndef PLIANT_SPARSE_H
#define PLIANT_SPARSE_H

#include "api.h"
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Coordinate form; duplicates are summed when compressed. */
typedef struct pl_triplets {
    int nrows, ncols;
    int nnz, cap;
    int *i, *j;
    double *x;
} pl_triplets;

/* Compressed sparse column: column k holds rows i[p[k] .. p[k+1]-1]. */
typedef struct pl_csc {
    int nrows, ncols;
    int *p;       /* ncols + 1 */
    int *i;       /* nnz row indices, sorted within a column */
    double *x;    /* nnz values */
} pl_csc;

/* Compressed sparse row: row k holds columns j[p[k] .. p[k+1]-1]. */
typedef struct pl_csr {
    int nrows, ncols;
    int *p;       /* nrows + 1 */
    int *j;       /* nnz column indices, sorted within a row */
    double *x;    /* nnz values */
} pl_csr;

PL_API int pl_triplets_init(pl_triplets *t, int nrows, int ncols, int cap);
PL_API void pl_triplets_free(pl_triplets *t);
/* Appends (i, j, x); returns PL_EINTERNAL on allocation failure. */
PL_API int pl_triplets_add(pl_triplets *t, int i, int j, double x);
/* Compresses to CSC, summing duplicates and sorting rows; 0 on success. */
PL_API int pl_triplets_to_csc(const pl_triplets *t, pl_csc *out);
PL_API void pl_csc_free(pl_csc *a);
PL_API void pl_csr_free(pl_csr *a);
static inline int pl_csc_nnz(const pl_csc *a) { return a->p[a->ncols]; }
static inline int pl_csr_nnz(const pl_csr *a) { return a->p[a->nrows]; }

#ifdef __cplusplus
}
#endif
#endif
