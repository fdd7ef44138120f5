/* stencil_device.h - the device path of the stencil terms (bending,
 * PositionTarget): their project() on device buffers in CUDA builds,
 * through cuda/stencil_cuda.h on the stream of the scene's device service.
 * Internal to the plugin; stencil_device.c. */
#ifndef PLIANT_HYPER_STENCIL_DEVICE_H
#define PLIANT_HYPER_STENCIL_DEVICE_H

#include "hyperelastic.h"
#include "pliant/pliant.h"

typedef struct hyper_stencil_gpu hyper_stencil_gpu;

/* rhs += h2 w g^T p on device float64 n x 3 blocks.  The device copy of
 * the stencils is made on first use (*gpu).  targets: the term's host
 * targets (n x 3, in d's slot) or NULL (zero targets: isometric bending,
 * whose rows then add nothing, so no kernel is queued).  Targets go up
 * once per step: at the first call after begin_step with a given d. */
int hyper_stencil_project_device(const pl_component *c, const pl_hyper_stencils *s,
                                 hyper_stencil_gpu **gpu, const pl_data *d, const double *targets,
                                 int offset, double h2, const pl_buffer *q, pl_buffer *rhs,
                                 pl_error *err);
/* The next device project uploads the targets again. */
void hyper_stencil_device_begin_step(hyper_stencil_gpu *gpu);
void hyper_stencil_device_free(hyper_stencil_gpu **gpu);

#endif
