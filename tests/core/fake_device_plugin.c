/* fake_device_plugin.c - a stand-in for the cuda plugin in the loader's
 * tests: built as tests/fake_device/libpliant_cuda.so with a "CudaDevice"
 * type, so that the implicit device (core/src/sim_device.c) can be tested
 * on machines without a GPU.  FAKE_GPU=0 makes it behave as CudaDevice
 * does where no GPU answers: one warning, and the device absent. */
#include <pliant/pliant.h>

#include <stdlib.h>
#include <string.h>

typedef struct fake_device {
    pl_component base;
    int index;
    int absent;
} fake_device;

static const pl_field FIELDS[] = {
    PL_FIELD(fake_device, index, "device", PL_F_INT, "0", "device ordinal", 0),
};

static int fd_init(pl_component *c, pl_ctx *ctx)
{
    const char *gpu = getenv("FAKE_GPU");
    fake_device *d = (fake_device *)c;
    d->absent = gpu && !strcmp(gpu, "0");
    if (d->absent)
        pl_component_warn(c, ctx, "no CUDA device usable here (none found): the scene runs on "
                                  "the CPU");
    return PL_OK;
}

static int fd_flags(const pl_component *c)
{
    return ((const fake_device *)c)->absent ? PL_DEVICE_ABSENT : 0;
}

static const pl_device_ops OPS = {.version = 1, .flags = fd_flags};

static const pl_type FAKE_DEVICE = {
    .abi_version = PL_ABI_VERSION,
    .name = "CudaDevice",
    .help = "test stand-in for the cuda plugin's device",
    .size = sizeof(fake_device),
    .fields = FIELDS,
    .nfields = 1,
    .ops = {.init = fd_init},
    .roles = {[PL_ROLE_DEVICE] = &OPS},
};

static const pl_type *const TYPES[] = {&FAKE_DEVICE};
PL_PLUGIN_DEFINE(TYPES)
