/* cuda_loop.cu - pl_device_ops.loop on CUDA (device ops version 3): an
 * iteration loop as one CUDA graph with a conditional WHILE node (CUDA
 * 12.4 and later), so that the device decides when to stop and the host
 * launches the whole loop once and waits once.
 *
 * The graph is
 *     rule -> WHILE(handle) { body; rule }
 * where rule is a one-thread kernel that applies pl_device_loop_rule
 * (pliant/device_loop.h, the CPU's stopping rule) to the state in device
 * memory and sets the WHILE node's condition with cudaGraphSetConditional.
 * The first rule judges the iteration queued before the launch (the
 * caller's eager first iteration); the body is recorded by stream capture
 * into the WHILE node's body graph (cudaStreamBeginCaptureToGraph), so
 * whatever the body queues on the stream (kernels of other components,
 * cuBLAS and cuSPARSE calls, device memsets and copies) becomes part of the
 * loop, as with a plain captured iteration. */
#include "cuda_loop.h"

#include <cuda_runtime.h>
#include "pliant/cuda_launch.h"

#include "pliant/device_loop.h"

namespace {

/* One thread: the rule, and the WHILE node's condition from it. */
__global__ void k_loop_rule(cudaGraphConditionalHandle h, pl_device_loop *s,
                            const double *change, const double *residual)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    cudaGraphSetConditional(h, pl_device_loop_rule(s, change, residual) ? 1u : 0u);
}

} // namespace

extern "C" int cuda_loop_supported(void)
{
    int v = 0;
    if (cudaDriverGetVersion(&v) != cudaSuccess) {
        cudaGetLastError();
        return 0;
    }
    return v >= 12040;
}

extern "C" int cuda_loop_build(struct CUstream_st *st, int (*body)(void *arg), void *arg,
                               struct pl_device_loop *state, const double *change,
                               const double *residual, void **exec_out, int *body_rc)
{
    cudaGraph_t parent = NULL;
    cudaGraphExec_t exec = NULL;
    cudaGraphConditionalHandle h;
    cudaGraphNode_t rule = NULL, loop = NULL;
    *exec_out = NULL;
    *body_rc = 0;
    cudaError_t e = cudaGraphCreate(&parent, 0);
    /* reset to 0 at every launch; the first rule sets it before the WHILE
     * node reads it */
    if (e == cudaSuccess) e = cudaGraphConditionalHandleCreate(&h, parent, 0, cudaGraphCondAssignDefault);
    void *args[] = {&h, &state, &change, &residual};
    if (e == cudaSuccess) {
        cudaKernelNodeParams kp = {};
        kp.func = (void *)k_loop_rule;
        kp.gridDim = dim3(1);
        kp.blockDim = dim3(1);
        kp.kernelParams = args;
        e = cudaGraphAddKernelNode(&rule, parent, NULL, 0, &kp);
    }
    cudaGraph_t inside = NULL;
    if (e == cudaSuccess) {
        cudaGraphNodeParams cp = {};
        cp.type = cudaGraphNodeTypeConditional;
        cp.conditional.handle = h;
        cp.conditional.type = cudaGraphCondTypeWhile;
        cp.conditional.size = 1;
        e = cudaGraphAddNode(&loop, parent, &rule, NULL, 1, &cp);
        if (e == cudaSuccess) inside = cp.conditional.phGraph_out[0];
    }
    if (e == cudaSuccess)
        e = cudaStreamBeginCaptureToGraph(st, inside, NULL, NULL, 0,
                                          cudaStreamCaptureModeThreadLocal);
    if (e == cudaSuccess) {
        *body_rc = body(arg);
        if (!*body_rc) pl_cuda_launch(k_loop_rule, 1, 1, 0, st, h, state, change, residual);
        cudaError_t launch = cudaGetLastError();
        cudaGraph_t captured = NULL; /* the body graph itself, owned by the node */
        e = cudaStreamEndCapture(st, &captured);
        if (e == cudaSuccess) e = launch;
    }
    if (e == cudaSuccess && !*body_rc) e = cudaGraphInstantiate(&exec, parent, 0);
    if (parent) cudaGraphDestroy(parent);
    if (e != cudaSuccess || *body_rc) {
        if (exec) cudaGraphExecDestroy(exec);
        return (int)e;
    }
    *exec_out = exec;
    return 0;
}
