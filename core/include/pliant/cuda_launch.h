/* cuda_launch.h - kernel launches with programmatic dependent launch (PDL)
 * for the CUDA plugins' small kernels (CUDA C++ only; empty in C).
 *
 * A device-loop iteration of a small scene is a chain of about 17 dependent
 * kernels that each do a few microseconds of work; between two of them the
 * GPU spends a launch latency.  With PDL (compute capability 9.0), a kernel
 * launched by pl_cuda_launch may be scheduled while the kernel before it on
 * the stream still runs, once that one has called PL_CUDA_LAUNCH_DEPENDENTS;
 * it then waits in PL_CUDA_GRID_WAIT until its predecessor has finished and
 * its writes are visible.  So every kernel launched through pl_cuda_launch
 * MUST call PL_CUDA_GRID_WAIT() before its first global memory access (read
 * or write); both macros do nothing without a programmatic predecessor, so
 * such a kernel is also correct when launched plainly.
 *
 * Off by default: PLIANT_PDL=1 turns it on (an experiment, read once per
 * plugin); otherwise pl_cuda_launch is a plain launch.  Stream capture
 * records a programmatic edge where the predecessor is a kernel, a plain one
 * otherwise. */
#ifndef PLIANT_CUDA_LAUNCH_H
#define PLIANT_CUDA_LAUNCH_H

#ifdef __CUDACC__
#include <cuda_runtime.h>
#include <stdlib.h>
#include <string.h>

#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
#define PL_CUDA_GRID_WAIT() asm volatile("griddepcontrol.wait;" ::: "memory")
#define PL_CUDA_LAUNCH_DEPENDENTS() asm volatile("griddepcontrol.launch_dependents;" :::)
#else
#define PL_CUDA_GRID_WAIT() ((void)0)
#define PL_CUDA_LAUNCH_DEPENDENTS() ((void)0)
#endif

/* Whether PLIANT_PDL=1 (read once). */
static inline int pl_cuda_pdl(void)
{
    static int on = -1;
    if (on < 0) {
        const char *v = getenv("PLIANT_PDL");
        on = v && !strcmp(v, "1");
    }
    return on;
}

/* kernel<<<grid, block, shmem, st>>>(args...), with the PDL attribute when
 * pl_cuda_pdl(); returns the launch's error. */
template <typename... Params, typename... Args>
static inline cudaError_t pl_cuda_launch(void (*kernel)(Params...), dim3 grid, dim3 block,
                                         size_t shmem, cudaStream_t st, Args &&...args)
{
    cudaLaunchAttribute attr[1];
    attr[0].id = cudaLaunchAttributeProgrammaticStreamSerialization;
    attr[0].val.programmaticStreamSerializationAllowed = 1;
    cudaLaunchConfig_t cfg = {};
    cfg.gridDim = grid;
    cfg.blockDim = block;
    cfg.dynamicSmemBytes = shmem;
    cfg.stream = st;
    cfg.attrs = pl_cuda_pdl() ? attr : NULL;
    cfg.numAttrs = pl_cuda_pdl() ? 1 : 0;
    return cudaLaunchKernelEx(&cfg, kernel, static_cast<Params>(args)...);
}
#endif

#endif
