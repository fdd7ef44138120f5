/* contact.h - internals of the NonSmoothNewtonContactSolver component (the
 * scene side of Algorithm 4).  The numbers live in ncp.h; this header holds
 * what turns a step's pl_rows into the core's inputs:
 *   contact_rows.c       the active rows, scalarised over the unknowns
 *   contact_delassus.c   W = H A^-1 H^T (explicit Y^T Y or matrix-free) and
 *                        the diagonals of the two complementarity scalings
 *   contact_warmstart.c  lambda of persisting rows, kept in a pl_data slot
 *   contact_solver.c     the component: fields, begin / iterate / multipliers
 * Names are pl_ncpc_*: shared between these files, hidden in the plugin. */
#ifndef PLIANT_NCP_CONTACT_H
#define PLIANT_NCP_CONTACT_H

#include <stdint.h>

#include "ncp.h"
#include "pliant/model.h"
#include "pliant/roles.h"
#include "pliant/sparse.h"

/* ---- the active rows of one step ----------------------------------------
 * A row is active when it has an entry with a nonzero coefficient on an
 * unknown (a row on prescribed vertices only has W_jj = 0: no force can
 * correct it, so it is left out with lambda = 0); a friction row also needs
 * its normal row active.  Entries on the same unknown are merged. */
typedef struct pl_ncpc_rows {
    int nall;                 /* rows given (N) */
    int m;                    /* active rows */
    int *full;                /* m: index among the given rows */
    int *sub;                 /* N: active index, or -1 */
    int *fstart;              /* m + 1: free entries of active row j */
    int *fcol;                /* per free entry: unknown index (sorted within a row) */
    double *fcoef;            /* per free entry: 3 coefficients */
    int *pstart;              /* m + 1: entries on prescribed vertices */
    int *pvert;               /* per prescribed entry: global vertex */
    double *pcoef;            /* per prescribed entry: 3 coefficients */
    double *offset;           /* m: delta = H q - offset (friction: H_f q_t + h d_f) */
    pl_row_kind *kind;        /* m */
    int *pair;                /* m: friction -> its normal's active index */
    double *mu, *compliance, *lo, *hi; /* m */
} pl_ncpc_rows;

void ncpc_rows_init(pl_ncpc_rows *r);
void ncpc_rows_free(pl_ncpc_rows *r);
/* Builds the active rows of `rows` for the system `sys`; q_t (n x 3) gives
 * the friction offsets.  Checks vertices and coefficients. */
int ncpc_rows_build(pl_ncpc_rows *r, const pl_system *sys, const pl_rows *rows,
                       const double *q_t, pl_error *err);
/* The core's view of the active rows. */
pl_ncp_rows ncpc_rows_view(const pl_ncpc_rows *r);
/* delta_j = H_j [x; q_p] - offset_j: x over the unknowns (nfree x 3), the
 * prescribed vertices read from q (n x 3). */
void ncpc_rows_delta(const pl_ncpc_rows *r, const double *x, const double *q, double *delta);
/* delta_j = H_j q - offset_j, q over all vertices (n x 3). */
void ncpc_rows_delta_all(const pl_ncpc_rows *r, const int *free_vertex, const double *q,
                            double *delta);
/* X (nfree x 3) = alpha H_free^T x (overwrites X; rows with x_j = 0 skipped). */
void ncpc_rows_scatter(const pl_ncpc_rows *r, int nfree, const double *x, double alpha,
                          double *X);
/* y_j = H_j,free X (X: nfree x 3). */
void ncpc_rows_gather(const pl_ncpc_rows *r, const double *X, double *y);
/* The scalar rows of the active rows list[0..count-1] as a CSR over the
 * unknowns: 3 count rows, coordinate-major (row k count + t is coordinate k
 * of row list[t]); zero coefficients dropped. */
int ncpc_rows_scalar_csr(const pl_ncpc_rows *r, int nfree, const int *list, int count,
                            pl_csr *H, pl_error *err);

/* ---- the Delassus operator ---------------------------------------------- */
typedef struct pl_ncpc_delassus {
    int m, nfree;
    int explicit_w;           /* 1: dense W (m x m) below; 0: matrix-free */
    double *W;                /* m x m row-major, or NULL */
    const double *W_dev;      /* explicit W built on the device instead (not owned), or NULL */
    double *diag;             /* m: W_jj */
    /* matrix-free product: one solve on an nfree x 3 block */
    pl_component *solver;
    const pl_global_solver_ops *ops;
    const pl_ncpc_rows *rows;
    double *X;                /* nfree x 3 scratch */
    int status;               /* first failure of a matrix-free product */
    pl_error err;             /* its message */
    double work;              /* multiply-adds that forming W from Y costs (sum over the rows
                                 of Y of nnz^2), when Y was formed on the host; else 0 */
} pl_ncpc_delassus;

void ncpc_delassus_init(pl_ncpc_delassus *D);
void ncpc_delassus_free(pl_ncpc_delassus *D);
/* Builds W explicitly: Y = S P H^T (apply_inverse_to_rows on the 3 m
 * scalar rows), W = sum over coordinates Y_k^T Y_k (dense, OpenMP over
 * rows of W, deterministic).  Also fills diag. */
int ncpc_delassus_explicit(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r,
                              pl_error *err);
/* Builds W explicitly on the global solver's device (its delassus_device
 * op, cuBLAS) into the device array W_dev (m x m); diag comes back to the
 * host.  D->W stays NULL: only the device path can use this W. */
int ncpc_delassus_explicit_device(pl_ncpc_delassus *D, const pl_system *sys,
                                     const pl_ncpc_rows *r, double *W_dev, pl_error *err);
/* Prepares the matrix-free W and its exact diagonal: rows with one free
 * vertex a get |c|^2 [A^-1]_aa from inv_diag (the global solver's inverse
 * diagonal; NULL if it has none); rows with several vertices get the
 * squared norms of their Y columns (apply_inverse_to_rows, in chunks so
 * that Y never holds more than a bounded number of columns), or (W e_j)_j
 * when the solver cannot apply its inverse to rows. */
int ncpc_delassus_matrix_free(pl_ncpc_delassus *D, const pl_system *sys,
                                 const pl_ncpc_rows *r, const double *inv_diag, pl_error *err);
/* ncpc_delassus_matrix_free with the several-vertex rows' diagonal made on
 * the global solver's device (its delassus_device with W NULL: the etree
 * paths of S, no Y on the host); the same values up to round-off. */
int ncpc_delassus_matrix_free_device(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r,
                                     const double *inv_diag, pl_error *err);
/* delassus=auto on the host: forms Y for all rows and counts the exact
 * work of W = Y^T Y from its pattern (D->work); W explicit (as
 * ncpc_delassus_explicit) when that is at most max_work, else matrix-free
 * with the diagonal of ncpc_delassus_matrix_free (the same values, the
 * squared norms of the Y columns taken from this Y). */
int ncpc_delassus_auto(pl_ncpc_delassus *D, const pl_system *sys, const pl_ncpc_rows *r,
                       double max_work, const double *inv_diag, pl_error *err);
/* The core's operator (dense or matrix-free) over D. */
pl_ncp_operator ncpc_delassus_operator(pl_ncpc_delassus *D);
/* y = W x (matrix-free: scatter, solve, gather). */
int ncpc_delassus_apply(void *user, const double *x, double *y);
/* The mass scaling's diagonal: (H M^-1 H^T)_jj = sum_a |c_a|^2 / m_a over
 * the free entries (entries merged per vertex, M lumped). */
int ncpc_mass_diagonal(const pl_ncpc_rows *r, const pl_system *sys, double *diag,
                          pl_error *err);

/* ---- warm start ---------------------------------------------------------
 * One record per active row of the last step, kept in a pl_data slot so
 * that save/restore/reset and several states over one model stay exact. */
typedef struct pl_ncpc_key {
    uint64_t owner;           /* FNV-1a hash of the owner's path (stable across runs) */
    int32_t kind;             /* pl_row_kind */
    int32_t vertex;           /* global vertex of the row's first entry */
    int32_t pair;             /* friction: record index of its normal row; else -1 */
    int32_t pad;
    double dir[3];            /* the first entry's coefficient, normalised */
    double lambda;            /* the multiplier at the end of the step [N] */
} pl_ncpc_key;

/* The check of restored warm-start records (a pl_slot_check): kinds known,
 * friction pairs in range, directions and multipliers finite. */
int ncpc_keys_check(const pl_component *owner, const void *data, size_t bytes, pl_error *err);

/* Keys of the active rows (lambda left 0). */
int ncpc_keys_build(const pl_ncpc_rows *r, const pl_rows *rows, pl_ncpc_key *keys,
                       pl_error *err);
/* lambda (m) from the previous step's records `old` (nold): see
 * contact_warmstart.c for the matching rule.  Returns the rows matched, or
 * -(error code) (err filled). */
int ncpc_warm_start(const pl_ncpc_key *keys, int m, const pl_ncpc_key *old, int nold,
                       double *lambda, pl_error *err);

/* ---- first iteration: contacts without force -----------------------------
 * contact_stick_start.c: lambda of the contacts that start the step with
 * lambda = 0 and that the free motion closes (delta_n < 0 at delta_free +
 * h^2 W lambda) <- the forces holding them still (normal and friction rows
 * as equalities, conjugate residual, cr_iterations products), projected on
 * the cone.  delta_free: row values at q_free = A^-1 b^0.  Returns the rows
 * started, or -(error code). */
int ncpc_stick_start(const pl_ncpc_rows *r, const pl_ncp_operator *W, double h,
                        const double *delta_free, double *lambda, int cr_iterations,
                        pl_error *err);

#endif
