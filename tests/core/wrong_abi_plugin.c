/* wrong_abi_plugin.c - claims to be built for another ABI version: the
 * host must refuse it without letting it touch the registry. */
#include <pliant/plugin.h>

PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi);
PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi)
{
    (void)reg;
    (void)host_abi;
    return 999;
}
