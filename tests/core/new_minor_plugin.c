/* new_minor_plugin.c - claims to be built for a newer minor ABI version
 * than the host's: as PL_PLUGIN_DEFINE does, it declines to register with
 * an older host, which must refuse it naming both versions. */
#include <pliant/plugin.h>

#define NEWER PL_ABI(PL_ABI_MAJOR, PL_ABI_MINOR + 1)

PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi);
PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi)
{
    (void)reg;
    if (!PL_ABI_COMPATIBLE(host_abi, NEWER)) return NEWER;
    return -1; /* a host this new would have to exist first */
}
