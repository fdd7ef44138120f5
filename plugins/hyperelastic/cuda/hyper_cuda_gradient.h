/* hyper_cuda_gradient.h - grad += d psi / dq of a FEM element set
 * (tetrahedra, or membrane triangles) on an NVIDIA GPU, float64: the device
 * twin of hyper_elements_add_gradient (same formula, same per-vertex
 * summation order), used by the force residual of a device loop
 * (LocalGlobalSolver forceTolerance; fem_term_device.c).  The element data
 * is copied to the device once; work is queued on `stream` and never waited
 * for (it can be captured in a CUDA graph).  Pointers are device pointers. */
#ifndef PLIANT_HYPER_CUDA_GRADIENT_H
#define PLIANT_HYPER_CUDA_GRADIENT_H

#include "hyper_cuda.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pl_hyper_cuda_grad pl_hyper_cuda_grad;

/* NULL with err set for other shapes, the edge rotation (no energy), out
 * of device memory or a CUDA error. */
pl_hyper_cuda_grad *hyper_cuda_grad_create(const pl_hyper_elements *e, pl_error *err);
void hyper_cuda_grad_destroy(pl_hyper_cuda_grad *g);
/* grad (global n x 3) += the gradient at q (global n x 3), this set's
 * vertices starting at row offset. */
int hyper_cuda_grad_add(pl_hyper_cuda_grad *g, int offset, const double *q, double *grad,
                        struct CUstream_st *stream, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
