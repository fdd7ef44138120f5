/* cuda_device.c - CudaDevice: selects a GPU and creates the stream every
 * device-side component of the scene queues its work on (PL_ROLE_DEVICE);
 * the plugin's entry point.  Components find it with pl_util_device(c),
 * so it belongs in the root node (or an ancestor of the bodies), before the
 * solvers that use it: a node's components are destroyed in reverse order,
 * and its users free their device memory through it.  This file is the
 * same in every build, so that a scene declaring a CudaDevice loads
 * everywhere (a build without CUDA runs it on the CPU, with a warning). */
#include "cuda_device.h"

#include <stdlib.h>

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

static int device_init(pl_component *c, pl_ctx *ctx)
{
    cuda_device *d = (cuda_device *)c;
    if (!d->live && !(d->live = calloc(1, sizeof *d->live)))
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    return cuda_device_open(d, ctx);
}

static void device_destroy(pl_component *c)
{
    cuda_device *d = (cuda_device *)c;
    cuda_device_close(d);
    if (d->live && *d->live > 0)
        pl_log_warn("%s: %ld device allocations were never freed", c->name, *d->live);
    free(d->live);
    d->live = NULL;
}

static const pl_type cuda_device_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "CudaDevice",
    .help = "An NVIDIA GPU and the stream the scene's device-side work is queued on (device "
            "service for LocalGlobalSolver device=\"cuda\", SparseInverseSolver and the "
            "hyperelastic terms); place it in the root node before the solvers.  Where no GPU "
            "answers, or in a build without CUDA, the scene runs on the CPU (one warning).",
    .size = sizeof(cuda_device),
    .fields = FIELDS,
    .nfields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .ops = {.init = device_init, .destroy = device_destroy},
    .roles = {[PL_ROLE_DEVICE] = &pl_cuda_device_ops},
};

static const pl_type *const types[] = {&cuda_device_type};

PL_PLUGIN_DEFINE(types)
