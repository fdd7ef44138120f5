/* hyper_cuda.h - the local step of a FEM element set (tetrahedra, or
 * membrane triangles with a 3x2 F) on an NVIDIA GPU: ARAP (closest
 * rotation / closest orthonormal 3x2), corotational and Neo-Hookean
 * (ADMM-PD prox on the singular values, scaled duals updated on the
 * device), float64.
 *
 * The element data of a pl_hyper_elements (verts, D, mu, lambda, w, and the
 * vertex incidence vptr/vinc) is copied to the device once.  project() runs
 * the same algorithm as hyper_elements_project: per element F = X D,
 * p = local solve of F (+ u), u += F - p, and h2 w (p - u) D^T added to the
 * right-hand side.  The right-hand side is assembled either
 *  - GATHER: each element writes its k corner 3-vectors to its own slots,
 *    then one thread per vertex sums its slots in the CPU's order (no
 *    atomics, deterministic), or
 *  - ATOMIC: elements add into rhs with atomicAdd (one launch; the order of
 *    the sums varies from run to run).
 * Pointers are DEVICE pointers; work is queued on `stream` (NULL: the legacy
 * default stream) and never waited for, so it can be captured in a CUDA
 * graph. */
#ifndef PLIANT_HYPER_CUDA_H
#define PLIANT_HYPER_CUDA_H

#include "hyperelastic.h"
#include "pliant/error.h"

#ifdef __cplusplus
extern "C" {
#endif

struct CUstream_st;

typedef enum pl_hyper_cuda_assembly {
    PL_HYPER_CUDA_GATHER = 0,
    PL_HYPER_CUDA_ATOMIC = 1
} pl_hyper_cuda_assembly;

typedef struct pl_hyper_cuda pl_hyper_cuda;

/* Copies the element set (k = 4, d = 3 or k = 3, d = 2) to the current
 * device.  NULL with err set for other shapes, out of device memory or on
 * a CUDA error. */
pl_hyper_cuda *hyper_cuda_create(const pl_hyper_elements *e, pl_error *err);
void hyper_cuda_destroy(pl_hyper_cuda *g);

/* The local step: q global positions (device, >= offset + nverts rows x 3);
 * dual (device, n x 3d; NULL for ARAP) updated in place; rhs (device, global
 * n x 3) += h2 w (p - u) D^T. */
int hyper_cuda_project(pl_hyper_cuda *g, int offset, double h2, const double *q, double *dual,
                          double *rhs, pl_hyper_cuda_assembly mode, struct CUstream_st *stream,
                          pl_error *err);
/* The same with over-relaxed ADMM (hyper_elements_project_relaxed): with
 * relax the device keeps each element's last p (without, nothing is kept
 * and alpha must be 1); alpha must be 1 on a step's first project (the
 * host's rule), alpha != 1 later uses that p. */
int hyper_cuda_project_relaxed(pl_hyper_cuda *g, int offset, double h2, const double *q,
                               double *dual, int relax, double alpha, double *rhs,
                               pl_hyper_cuda_assembly mode, struct CUstream_st *stream,
                               pl_error *err);

/* Waits for the step's projects and reads their statistics since
 * hyper_cuda_begin_step (or creation) in one copy: stats[0] the largest
 * Newton iteration count, stats[1] the element solves that missed their
 * tolerance, summed over the projects (reset once a step, not at each
 * project: one launch less per iteration), and (out not NULL) the counts
 * (solves, Newton iterations, halvings, capped solves, histogram) added to
 * *out.  PL_EINTERNAL, naming the first element, if some F was not
 * finite. */
int hyper_cuda_step_stats(pl_hyper_cuda *g, struct CUstream_st *stream, int stats[2],
                          hyper_prox_stats *out, pl_error *err);

/* Queues the start of a step on stream: every element's prox starts cold
 * (the warm-start rows, n x HM_WARM_LEN(d) on the device, zeroed: as the CPU's
 * workspace, hyper_term_warm) and the counts and statistics restart (one
 * memset). */
int hyper_cuda_begin_step(pl_hyper_cuda *g, struct CUstream_st *stream, pl_error *err);

/* Queues out[offset + v] += the sum of vertex v's slots (n x 3k corner
 * 3-vectors, incidence vptr/vinc as in pl_hyper_elements), in increasing
 * slot order (hyper_incidence_gather's order; also the device gradient's). */
int hyper_cuda_gather(int nverts, const int *vptr, const int *vinc, const double *slots,
                      int offset, double *out, struct CUstream_st *stream, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
