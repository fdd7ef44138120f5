/* ncp_cuda_correct.h - the correction q^{k+1} = q_free + h^2 A^-1 H^T (S
 * lambda) of a few rows as one dense product (CUDA builds; kernels in
 * ncp_cuda_correct.cu, used by contact_device.c).
 *
 * H is fixed within a step, so for few rows the columns U_j = A^-1 H_j^T
 * (nfree x 3 blocks, one a row) are made once per step, and each iteration's
 * correction is q_next = q_free + h^2 sum_j (S lambda)_j U_j: one launch
 * instead of H^T (scatter), the device solve and the sum.  The same values
 * up to round-off (A^-1 is linear).  Like ncp_cuda.h: every function queues
 * work on `stream` and returns the launch's cudaError_t as an int; the
 * kernels read the rows (m, the transposed entries) from the device
 * descriptor R, so a captured graph replays a later step's rows. */
#ifndef PLIANT_NCP_CUDA_CORRECT_H
#define PLIANT_NCP_CUDA_CORRECT_H

#include "ncp_cuda.h"

#ifdef __cplusplus
extern "C" {
#endif

/* U_j = H_j,free^T for j < R->m: U holds R->m blocks of nfree x 3
 * (block j at U + 3 nfree j), each unknown's entries summed in entry order
 * (ncp_cuda_scatter's order for one row); the caller then solves each
 * block with A in place. */
int ncp_cuda_rows_blocks(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int nfree, double *U);

/* force_j = scale_j lambda_j (j < R->m) and q_next = q_free + h2 sum_j
 * force_j U_j (3 nfree values, rows with a zero force skipped as the
 * scatter skips them); mcap >= R->m sizes the part of the grid that writes
 * force. */
int ncp_cuda_correct_dense(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap, int nfree,
                           const double *scale, const double *lambda, double h2, const double *U,
                           const double *q_free, double *force, double *q_next);

#ifdef __cplusplus
}
#endif
#endif
