/* stencil_cuda.h - the local step of the constant-matrix stencil terms
 * (pl_hyper_stencils: cloth bending, position targets) on an NVIDIA GPU,
 * float64: per row r, y = g_r x, its projection p_r (the given target, or
 * |g_r x_rest| y / |y| for KEEP_NORM), then h2 w g_r^T p_r into the
 * right-hand side through per-entry slots and a per-vertex gather in the
 * CPU's order (deterministic, as hyper_stencils_project).  Pointers
 * are DEVICE pointers; work is queued on `stream` and never waited for
 * (capturable in a CUDA graph). */
#ifndef PLIANT_STENCIL_CUDA_H
#define PLIANT_STENCIL_CUDA_H

#include "hyperelastic.h"
#include "pliant/error.h"

#ifdef __cplusplus
extern "C" {
#endif

struct CUstream_st;
typedef struct pl_stencil_cuda pl_stencil_cuda;

/* Copies the stencils to the current device (and room for n x 3 targets).
 * NULL with err set on failure. */
pl_stencil_cuda *stencil_cuda_create(const pl_hyper_stencils *s, pl_error *err);
void stencil_cuda_destroy(pl_stencil_cuda *g);
/* Queues the copy of n x 3 host targets to the device copy. */
int stencil_cuda_set_targets(pl_stencil_cuda *g, const double *targets,
                                struct CUstream_st *stream, pl_error *err);
/* rhs (device, global n x 3) += h2 w g^T p for positions q (device);
 * with_targets: p of FIXED rows from the device targets (else zero). */
int stencil_cuda_project(pl_stencil_cuda *g, int offset, double h2, const double *q,
                            int with_targets, double *rhs, struct CUstream_st *stream,
                            pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
