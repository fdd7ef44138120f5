/* cuda_device.h - the CudaDevice component (internal to the cuda plugin):
 * one GPU, one stream; plays PL_ROLE_DEVICE through cuda_device_ops.c. */
#ifndef PLIANT_CUDA_DEVICE_H
#define PLIANT_CUDA_DEVICE_H

#include <cuda_runtime_api.h>

#include "pliant/pliant.h"

typedef struct cuda_device {
    pl_component base;
    int index;            /* field device: CUDA device ordinal */
    int graph;            /* field graph: capture iterations as CUDA graphs */
    int profile;          /* field profile: sync after each phase for the timers */
    cudaStream_t stream;  /* created at init */
    long live;            /* allocations handed out by alloc and not yet freed */
} cuda_device;

extern const pl_device_ops pl_cuda_device_ops;

/* Fills err from a failed CUDA call about c; returns PL_EINTERNAL. */
int pl_cuda_fail(const pl_component *c, pl_error *err, cudaError_t e, const char *what);

#endif
