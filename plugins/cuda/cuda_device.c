/* cuda_device.c - CudaDevice: selects a GPU and creates the stream every
 * device-side component of the scene queues its work on (PL_ROLE_DEVICE);
 * the plugin's entry point.  Components find it with
 * pl_node_find_role_up(node, PL_ROLE_DEVICE), so it belongs in the root node
 * (or an ancestor of the bodies), before the solvers that use it: a node's
 * components are destroyed in reverse order, and its users free their
 * device memory through it. */
#include "cuda_device.h"

#include <stdio.h>

#include "pliant/plugin.h"

static const pl_field FIELDS[] = {
    PL_FIELD(cuda_device, index, "device", PL_F_INT, "0",
             "CUDA device ordinal [index] (0: the first GPU; see nvidia-smi)", 0),
    PL_FIELD(cuda_device, graph, "graph", PL_F_BOOL, "1",
             "capture a local-global iteration as a CUDA graph once and replay it (fewer launch "
             "costs); 0: launch every kernel each iteration",
             PL_FIELD_RUNTIME),
    PL_FIELD(cuda_device, profile, "profile", PL_F_BOOL, "0",
             "wait for the GPU after each phase so that the Local, Assembly and Global timers "
             "measure device time (slower; no graphs)",
             PL_FIELD_RUNTIME),
};

int pl_cuda_fail(const pl_component *c, pl_error *err, cudaError_t e, const char *what)
{
    /* reported here: later cudaGetLastError() calls of other components must
     * not see it again (a sticky error stays anyway) */
    cudaGetLastError();
    return pl_component_fail(c, err, PL_EINTERNAL, "%s: %s (%s)", what, cudaGetErrorString(e),
                             cudaGetErrorName(e));
}

static int device_init(pl_component *c, pl_ctx *ctx)
{
    cuda_device *d = (cuda_device *)c;
    int count = 0;
    cudaError_t e = cudaGetDeviceCount(&count);
    if (e != cudaSuccess || count == 0)
        return pl_component_error(c, ctx, PL_EINPUT, "no CUDA device usable here: %s",
                                  e != cudaSuccess ? cudaGetErrorString(e) : "none found");
    if (d->index < 0 || d->index >= count)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "device: %d is not a CUDA device ordinal (this machine has %d: "
                                  "0 .. %d)",
                                  d->index, count, count - 1);
    struct cudaDeviceProp prop;
    e = cudaSetDevice(d->index);
    if (e == cudaSuccess) e = cudaGetDeviceProperties(&prop, d->index);
    /* a blocking stream: work on the legacy default stream (host copies of
     * components that do not know the device) still orders with it */
    int first = !d->stream; /* the loader may have tried an implicit device already */
    if (e == cudaSuccess && first) e = cudaStreamCreate(&d->stream);
    if (e != cudaSuccess)
        return pl_component_error(c, ctx, PL_EINTERNAL, "CUDA device %d: %s", d->index,
                                  cudaGetErrorString(e));
    if (first)
        pl_log_info("%s: CUDA device %d, %s, %d SMs, %.1f GiB, compute capability %d.%d%s%s", c->name,
                d->index, prop.name, prop.multiProcessorCount,
                (double)prop.totalGlobalMem / (1024.0 * 1024.0 * 1024.0), prop.major, prop.minor,
                d->graph && !d->profile ? ", CUDA graphs" : "", d->profile ? ", profiling" : "");
    return PL_OK;
}

static void device_destroy(pl_component *c)
{
    cuda_device *d = (cuda_device *)c;
    if (d->stream) {
        cudaStreamSynchronize(d->stream);
        cudaStreamDestroy(d->stream);
        d->stream = NULL;
    }
    if (d->live > 0)
        pl_log_warn("%s: %ld device allocations were never freed", c->name, d->live);
}

static const pl_type cuda_device_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "CudaDevice",
    .help = "An NVIDIA GPU and the stream the scene's device-side work is queued on (device "
            "service for LocalGlobalSolver device=\"cuda\", SparseInverseSolver and the "
            "hyperelastic terms); place it in the root node before the solvers.",
    .size = sizeof(cuda_device),
    .fields = FIELDS,
    .nfields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .ops = {.init = device_init, .destroy = device_destroy},
    .roles = {[PL_ROLE_DEVICE] = &pl_cuda_device_ops},
};

static const pl_type *const types[] = {&cuda_device_type};

PL_PLUGIN_DEFINE(types)
