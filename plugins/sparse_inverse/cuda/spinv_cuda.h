/* spinv_cuda.h - the global step x = P^T S^T S P b on an NVIDIA GPU.
 *
 * S = L^-1 is copied to the device once, in float64 or float32, in the
 * profile layout of sparse_inverse.h (no column indices): row i holds the
 * columns first[i] .. i, padded with zeros to whole blocks of 8 columns so
 * that every vector load is aligned (spinv_cuda_layout.h).  Both products
 * read this one array, so S^T needs no copy of its own:
 *  - y = S a: warps walk rows (long rows are split across warps, short
 *    rows take one lane each); each value is read once and updates the x,
 *    y and z sums together; consecutive rows with one first column (the
 *    chains of a separator) go in pairs, so each piece of a is read once
 *    for both rows;
 *  - z = S^T y: a warp owns a tile of consecutive columns (128 in float32,
 *    64 in float64) and walks the rows that meet it: the tile's own rows and
 *    the etree ancestors of its last column, reading each row's segment as
 *    one coalesced 512-byte stretch.  Long row lists are split across warps.
 * Split rows and tiles are combined by the last warp to finish, in a fixed
 * order: the result is deterministic.  Nothing in solve allocates or
 * synchronises, so a caller may capture it in a CUDA graph.
 *
 * (A cuSPARSE path, SpMM CSR_ALG3 on CSR copies of S and S^T, was measured
 * 3.5 to 6 times slower with 4 times the memory, docs/benchmarks.md, and
 * deleted: no scene chose it.)
 *
 * All pointers passed to solve are DEVICE pointers to n x 3 row-major
 * blocks in the original (unpermuted) numbering; x may equal b.  Work is
 * queued on `stream` (NULL: the legacy default stream). */
#ifndef PLIANT_SPINV_CUDA_H
#define PLIANT_SPINV_CUDA_H

#include "pliant/buffer.h"
#include "pliant/error.h"
#include "pliant/sparse.h"
#include "sparse_inverse.h"

#ifdef __cplusplus
extern "C" {
#endif

struct CUstream_st; /* cudaStream_t without including the CUDA headers */

typedef struct pl_spinv_cuda pl_spinv_cuda;

/* Copies S (and perm) of a factored sparse-mode solver to the current
 * device.  precision: PL_F64 or PL_F32 (values and arithmetic).  NULL with
 * err set when s has no S (direct mode, not factored), on a bad precision,
 * out of device memory or on a CUDA error. */
pl_spinv_cuda *spinv_cuda_create(const pl_sparse_inverse *s, pl_precision precision,
                                    pl_error *err);
void spinv_cuda_destroy(pl_spinv_cuda *g);

/* x = A^-1 b on device n x 3 blocks whose element type is io (PL_F64 or
 * PL_F32, independent of the object's precision). */
int spinv_cuda_solve(pl_spinv_cuda *g, const void *b, void *x, pl_precision io,
                        struct CUstream_st *stream, pl_error *err);

/* The same from and to HOST n x 3 float64 blocks (copies in and out through
 * device buffers of the object; returns when x is written). */
int spinv_cuda_solve_host(pl_spinv_cuda *g, const double *b, double *x,
                             struct CUstream_st *stream, pl_error *err);

int spinv_cuda_size(const pl_spinv_cuda *g);
pl_precision spinv_cuda_precision(const pl_spinv_cuda *g);
/* 1 when solve runs as one single-block launch (small systems:
 * spinv_cuda_small.cu), 0 when as three launches. */
int spinv_cuda_single_block(const pl_spinv_cuda *g);
/* Device bytes held (matrix, metadata, workspaces). */
double spinv_cuda_device_bytes(const pl_spinv_cuda *g);
/* Bytes of matrix values one global step must read: the floor on its
 * memory traffic. */
double spinv_cuda_step_bytes(const pl_spinv_cuda *g);

/* ---- the Delassus operator ------------------------------------------- */

/* Scalar rows of a constraint step for spinv_cuda_delassus: rows of
 * coordinate k of constraint row j are k m + j (as in the global solver's
 * apply_inverse_to_rows); their unknowns renumbered 0 .. nu-1. */
typedef struct pl_spinv_cuda_rows {
    int m;       /* constraint rows (W is m x m) */
    int nu;      /* distinct unknowns the rows touch */
    int *pos;    /* nu: each one's permuted index (its column of S) */
    int *rp;     /* 3m + 1: row r's entries rp[r] .. rp[r+1]-1 */
    int *ru;     /* each entry's unknown, 0 .. nu-1 */
    double *rx;  /* each entry's coefficient */
} pl_spinv_cuda_rows;

/* From H (3m x n CSR over the unknowns, original numbering) and perm
 * (perm[k] = original index of permuted k).  PL_EINPUT when H is not
 * 3m x n. */
int spinv_cuda_rows_build(const pl_csr *H, int m, const int *perm, int n,
                             pl_spinv_cuda_rows *R, pl_error *err);
void spinv_cuda_rows_free(pl_spinv_cuda_rows *R);

/* W = H A^-1 H^T (m x m, float64, symmetric, row-major = column-major) into
 * the DEVICE array W, and its diagonal into the HOST array diag_host; queued
 * on stream, returns when diag_host is written.  Device memory: n x nu + nu^2
 * doubles (kept for the next call). */
int spinv_cuda_delassus(pl_spinv_cuda *g, const pl_spinv_cuda_rows *R, double *W,
                           double *diag_host, struct CUstream_st *stream, pl_error *err);

/* The Delassus path's one-time setup ahead of its first call: the cuBLAS
 * handle and the first use of its kernels (with CUDA's lazy loading, about
 * 33 ms on the H100, which the frame of the first contact paid before).
 * Returns when done; nothing to do the second time. */
int spinv_cuda_delassus_prepare(pl_spinv_cuda *g, struct CUstream_st *stream, pl_error *err);

/* ---- building blocks (tests and benchmarks) -------------------------- */

/* create() with the row-kernel tuning given: rows of S taken together by
 * one warp at most `group` (1, 2, 4, 8; 0 = default), ROWS items of
 * item_blocks blocks of 8 columns (0 = default). */
pl_spinv_cuda *spinv_cuda_create_tuned(const pl_sparse_inverse *s, pl_precision precision,
                                          int group, int item_blocks,
                                          pl_error *err);

/* y = S x or y = S^T x on device n x 3 blocks (element type: the object's
 * precision) in the PERMUTED numbering; x and y distinct. */
int pl_spinv_cuda_apply_S(pl_spinv_cuda *g, const void *x, void *y, struct CUstream_st *stream,
                          pl_error *err);
int pl_spinv_cuda_apply_ST(pl_spinv_cuda *g, const void *x, void *y,
                           struct CUstream_st *stream, pl_error *err);

typedef enum pl_spinv_cuda_stage {
    PL_SPINV_CUDA_STAGE_PERMUTE = 0, /* a = P b */
    PL_SPINV_CUDA_STAGE_S = 1,       /* y = S a (internal buffers) */
    PL_SPINV_CUDA_STAGE_ST = 2       /* x = P^T S^T y */
} pl_spinv_cuda_stage;

/* Runs one stage of the last solve again on the same buffers (b and x of
 * that solve must still be valid), for timing the products alone. */
int spinv_cuda_run_stage(pl_spinv_cuda *g, pl_spinv_cuda_stage stage,
                            struct CUstream_st *stream, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
