/* cuda_device.h - the CudaDevice component (internal to the cuda plugin):
 * one GPU, one stream; plays PL_ROLE_DEVICE through its backend,
 * cuda_device_ops.c in a CUDA build, cuda_device_none.c otherwise (the
 * component and its fields are the same in every build). */
#ifndef PLIANT_CUDA_DEVICE_H
#define PLIANT_CUDA_DEVICE_H

#include "pliant/pliant.h"

struct CUstream_st;

typedef struct cuda_device {
    pl_component base;
    int index;            /* field device: CUDA device ordinal */
    int graph;            /* field graph: capture iterations as CUDA graphs */
    int profile;          /* field profile: sync after each phase for the timers */
    struct CUstream_st *stream; /* cudaStream_t, created at init */
    int absent;           /* no device here: flags() says PL_DEVICE_ABSENT */
    int loops;            /* the driver runs conditional graph nodes (pl_device_ops.loop) */
    /* allocations handed out by alloc and not yet freed: the GPU's state,
     * kept outside the component (a step that allocates a data's device
     * buffers must not change the model: test_cable_two_data) */
    long *live;
    /* the side streams of pl_device_ops.branch and which one is current
     * (CUDA builds; made by open, outside the component for the same reason) */
    struct cuda_branches *branches;
} cuda_device;

/* The backend.  open: selects the GPU and creates the stream (idempotent:
 * the loader may try an implicit device first); where no GPU answers, or
 * the build has no CUDA, it warns once and marks the device absent (the
 * scene then runs on the CPU); an ordinal that is not a GPU of this
 * machine is an error.  close: frees what open made. */
int cuda_device_open(cuda_device *d, pl_ctx *ctx);
void cuda_device_close(cuda_device *d);
extern const pl_device_ops pl_cuda_device_ops;

#endif
