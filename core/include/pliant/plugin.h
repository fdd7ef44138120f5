/* plugin.h - what a plugin .so exports.
 *
 * Exactly one entry point:
 *
 *     int pl_plugin_register(pl_registry *reg, int host_abi);
 *
 * It returns the ABI version the plugin was compiled with (PL_ABI_VERSION).
 * When host_abi differs it must return at once without touching the
 * registry; the host then refuses the plugin, naming both versions.  When
 * they match it registers its types with pl_registry_add and returns
 * PL_ABI_VERSION (or a negative value if a registration failed).
 * PL_PLUGIN_DEFINE writes that boilerplate:
 *
 *     static const pl_type *const types[] = {&arap_type, &neohookean_type};
 *     PL_PLUGIN_DEFINE(types)
 */
#ifndef PLIANT_PLUGIN_H
#define PLIANT_PLUGIN_H

#include "registry.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped whenever a public struct layout or a role table changes
 * incompatibly.  Plugins of another version are refused. */
#define PL_ABI_VERSION 4 /* 2: PL_ROLE_DEVICE (pl_type.roles grew); 3: collision groups as sets;
                            4: PL_ROLE_VISUAL, PL_ROLE_EVENT */

#define PL_PLUGIN_ENTRY_NAME "pl_plugin_register"
typedef int (*pl_plugin_entry)(pl_registry *reg, int host_abi);

#if defined(__GNUC__)
#define PL_EXPORT __attribute__((visibility("default")))
#else
#define PL_EXPORT
#endif

#define PL_PLUGIN_DEFINE(types_array)                                              \
    PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi);              \
    PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi)               \
    {                                                                              \
        if (host_abi != PL_ABI_VERSION) return PL_ABI_VERSION;                     \
        for (size_t k_ = 0; k_ < sizeof(types_array) / sizeof(types_array[0]); ++k_) { \
            pl_error e_;                                                           \
            if (pl_registry_add(reg, types_array[k_], &e_) != PL_OK) return -1;    \
        }                                                                          \
        return PL_ABI_VERSION;                                                     \
    }

#ifdef __cplusplus
}
#endif
#endif
