/* old_minor_plugin.c - a plugin built for the previous minor ABI version
 * (CMake compiles it with PL_ABI_TARGET_MINOR=0, so the SDK headers leave
 * out what 5.1 added): the host, of a newer minor, must load and run it.
 * "OldMinorCounter" is a controller (role table version 1) that counts the
 * steps in a state slot. */
#include <pliant/pliant.h>

#include <stdio.h>
#include <string.h>

#if PL_ABI_TARGET_MINOR != 0 || PL_ABI_VERSION != PL_ABI(PL_ABI_MAJOR, 0)
#error "this test plugin must be built for minor version 0"
#endif
#ifdef PL_DEVICE_ABSENT
#error "5.1's additions must be left out of a 5.0 build"
#endif

typedef struct counter {
    pl_component base;
    int slot;
} counter;

static int oc_init(pl_component *c, pl_ctx *ctx)
{
    counter *k = (counter *)c;
    k->slot = pl_model_add_slot(ctx->build, c, "count", sizeof(long));
    return k->slot < 0 ? pl_component_error(c, ctx, PL_EINTERNAL, "out of memory") : PL_OK;
}

static int oc_apply(const pl_component *c, pl_ctx *ctx, double t, pl_error *err)
{
    (*(long *)pl_data_slot(ctx->data, ((const counter *)c)->slot))++;
    return PL_OK;
}

static int oc_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                  size_t size)
{
    if (strcmp(field, "count")) return PL_EINPUT;
    snprintf(buf, size, "%ld", *(const long *)pl_data_slot(d, ((const counter *)c)->slot));
    return PL_OK;
}

static const pl_field FIELDS[] = {
    PL_FIELD(counter, slot, "count", PL_F_INT, NULL, "steps taken [count]", PL_FIELD_OUTPUT),
};

static const pl_controller_ops CONTROLLER = {.version = 1, .apply = oc_apply};

static const pl_type OLD_MINOR_COUNTER = {
    .abi_version = PL_ABI_VERSION,
    .name = "OldMinorCounter",
    .help = "test controller built for ABI 5.0: counts steps",
    .size = sizeof(counter),
    .fields = FIELDS,
    .nfields = 1,
    .ops = {.init = oc_init, .get = oc_get},
    .roles = {[PL_ROLE_CONTROLLER] = &CONTROLLER},
};

static const pl_type *const TYPES[] = {&OLD_MINOR_COUNTER};
PL_PLUGIN_DEFINE(TYPES)
