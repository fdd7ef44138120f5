/* rows.h - constraint rows over 3D DOFs (the paper's H, d, E, Appendix A).
 *
 * A row is c . C_j q: per vertex a of the constraint, an entry holding the
 * global vertex index and the 3-vector w_a c (its barycentric weight times the
 * direction).  Rows between two bodies carry -w_b c on body B's vertices.
 * Constraint components append rows once per time step; the contact solver
 * reads them.  Multipliers lambda are forces [N] along the row direction. */
#ifndef PLIANT_ROWS_H
#define PLIANT_ROWS_H

#include "api.h"
#include "component.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pl_row_kind {
    PL_ROW_BILATERAL = 0, /* H q - d + E_b lambda = 0 (E_b = compliance, 0 = hard) */
    PL_ROW_NORMAL = 1,    /* 0 <= H q - d  perp  lambda >= 0 (Signorini) */
    PL_ROW_FRICTION = 2,  /* Coulomb, paired with its normal row; two per contact */
    PL_ROW_BOUNDED = 3    /* H q - d = 0 unless lambda hits [lo, hi] (box complementarity) */
} pl_row_kind;

typedef struct pl_rows {
    int n, cap;              /* rows */
    int *start;              /* n + 1: entries of row r are start[r] .. start[r+1]-1 */
    int nent, cap_ent;       /* entries */
    int *vertex;             /* per entry: global vertex index */
    double *coef;            /* per entry: 3 doubles, w_a * c */
    pl_row_kind *kind;       /* per row */
    double *d;               /* per row: bilateral/normal/bounded: target so that delta = H q - d;
                                friction: the obstacle surface velocity term d_f [m/s] */
    double *compliance;      /* per row: E_b [m/N] for bilateral rows, else 0 */
    double *lo, *hi;         /* per row: bounds of bounded rows [N] */
    int *pair;               /* per row: friction -> its normal row; normal -> its first friction row; else -1 */
    double *mu;              /* per row: friction coefficient (normal rows) */
    const pl_component **owner; /* per row: the component that emitted it */
} pl_rows;

PL_API void pl_rows_init(pl_rows *r);
PL_API void pl_rows_free(pl_rows *r);
PL_API void pl_rows_clear(pl_rows *r);
/* Starts a new row; returns its index (or -1 on allocation failure).  Its
 * per-row values default to d 0, compliance 0, lo -inf, hi +inf, pair -1, mu 0. */
PL_API int pl_rows_begin(pl_rows *r, pl_row_kind kind, const pl_component *owner);
/* Adds an entry (vertex, c) to the last row begun. */
PL_API int pl_rows_add(pl_rows *r, int vertex, double cx, double cy, double cz);
#if PL_ABI_TARGET_MINOR >= 9
/* Room for `rows` more rows and `entries` more entries (0, or -1 on
 * allocation failure): for an emitter that writes rows in parallel at
 * offsets it computed (pl_rows_put), then sets n, nent and start[n].
 * Since ABI 5.9. */
PL_API int pl_rows_reserve(pl_rows *r, int rows, int entries);
/* Row k (room reserved) starting at entry `first`, with pl_rows_begin's
 * defaults; writes no other row and leaves n, nent and start[k + 1].
 * Since ABI 5.9. */
PL_API void pl_rows_put(pl_rows *r, int k, pl_row_kind kind, const pl_component *owner, int first);
#endif
/* H q for one row, q an n x 3 row-major block over global vertices. */
PL_API double pl_rows_dot(const pl_rows *r, int row, const double *q);
/* y += alpha * H^T lambda over global vertices (y: n x 3). */
PL_API void pl_rows_add_transpose(const pl_rows *r, const double *lambda, double alpha, double *y);

#ifdef __cplusplus
}
#endif
#endif
