/* registry.h - component types by name, and plugin loading.
 * An explicit handle: there is no global registry. */
#ifndef PLIANT_REGISTRY_H
#define PLIANT_REGISTRY_H

#include "component.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pl_registry pl_registry;

pl_registry *pl_registry_create(void);
void pl_registry_free(pl_registry *r);   /* also unloads plugins */

/* Adds a type.  Refuses (PL_EINPUT, message in err) a duplicate name or a
 * type compiled for another ABI version. */
int pl_registry_add(pl_registry *r, const pl_type *t, pl_error *err);
const pl_type *pl_registry_find(const pl_registry *r, const char *name);
/* The registered type name closest to `name`, or NULL if none is close. */
const char *pl_registry_suggest(const pl_registry *r, const char *name);
/* The last error pl_registry_add recorded (for plugins whose entry point
 * cannot pass it back). */
const pl_error *pl_registry_last_error(const pl_registry *r);
int pl_registry_count(const pl_registry *r);
const pl_type *pl_registry_type(const pl_registry *r, int i);

/* Directories searched for plugins, in order: those added here, then each
 * entry of PLIANT_PLUGIN_PATH (colon-separated), then the build's plugin
 * folder compiled into libpliant. */
int pl_registry_add_plugin_dir(pl_registry *r, const char *dir);
/* Loads plugin `name` (searched as lib<name>.so / <name>.so in the plugin
 * dirs) or a path to a .so.  Loading an already loaded plugin is a no-op.
 * A plugin built for another ABI version is refused with both versions. */
int pl_registry_load_plugin(pl_registry *r, const char *name_or_path, pl_error *err);
/* Loads every plugin found in the plugin folders (for `pliant list`);
 * failures are recorded in diag and do not stop the others. */
int pl_registry_load_all(pl_registry *r, pl_diag *diag);
int pl_registry_plugin_count(const pl_registry *r);
const char *pl_registry_plugin_name(const pl_registry *r, int i);
const char *pl_registry_plugin_path(const pl_registry *r, int i);

/* Registers the built-in components (libpliant_components). */
int pl_register_builtin_components(pl_registry *r, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
