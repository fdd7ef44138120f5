/* spinv_cuda_buffers.h - SparseInverseSolver's solve on pl_buffer
 * descriptors when device="cuda" (see spinv_cuda_buffers.c). */
#ifndef PLIANT_SPINV_CUDA_BUFFERS_H
#define PLIANT_SPINV_CUDA_BUFFERS_H

#include "pliant/buffer.h"
#include "spinv_cuda.h"

#ifdef __cplusplus
extern "C" {
#endif

/* x = A^-1 b: device n x 3 blocks on the GPU (asynchronously, on stream;
 * NULL: the legacy default stream), host float64 blocks through copies
 * (synchronously; k != 3 columns on the CPU solver cpu). */
int spinv_cuda_solve_buffers(pl_spinv_cuda *g, pl_sparse_inverse *cpu, const pl_buffer *b,
                                pl_buffer *x, struct CUstream_st *stream, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
