/* ctor_plugin.c - a valid plugin (no types) whose constructor leaves a mark:
 * it shows whether a scene could make the program map a file and run its
 * code (PL_CTOR_PLUGIN_RAN is set on dlopen, before any check). */
#include <stdlib.h>

#include <pliant/pliant.h>

__attribute__((constructor)) static void leave_mark(void) { setenv("PL_CTOR_PLUGIN_RAN", "1", 1); }

PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi);
PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi)
{
    (void)reg;
    (void)host_abi;
    return PL_ABI_VERSION;
}
