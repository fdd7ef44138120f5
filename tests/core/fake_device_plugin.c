/* fake_device_plugin.c - a stand-in for the cuda plugin in the loader's
 * tests: built as tests/fake_device/libcuda.so with a "CudaDevice" type,
 * so that the implicit device (core/src/sim_device.c) can be tested on
 * machines without a GPU.  FAKE_GPU=0 makes its init fail as CudaDevice's
 * does where no GPU answers. */
#include <pliant/pliant.h>

#include <stdlib.h>
#include <string.h>

typedef struct fake_device {
    pl_component base;
    int index;
} fake_device;

static const pl_field FIELDS[] = {
    PL_FIELD(fake_device, index, "device", PL_F_INT, "0", "device ordinal", 0),
};

static int fd_init(pl_component *c, pl_ctx *ctx)
{
    const char *gpu = getenv("FAKE_GPU");
    if (gpu && !strcmp(gpu, "0"))
        return pl_component_error(c, ctx, PL_EINPUT, "no CUDA device usable here: none found");
    return PL_OK;
}

static const pl_device_ops OPS = {.version = 1};

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
