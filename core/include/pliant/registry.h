/* registry.h - component types by name, and plugin loading.
 * An explicit handle: there is no global registry. */
#ifndef PLIANT_REGISTRY_H
#define PLIANT_REGISTRY_H

#include "component.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pl_registry pl_registry;

PL_API pl_registry *pl_registry_create(void);
PL_API void pl_registry_free(pl_registry *r);   /* also unloads plugins */

/* Adds a type (the pointer is kept: t must outlive the registry, as a
 * plugin's static types do).  Refuses (PL_EINPUT, message in err) a
 * duplicate name, a type built for an ABI this host cannot run, and a role
 * table of a version this host does not know. */
PL_API int pl_registry_add(pl_registry *r, const pl_type *t, pl_error *err);
PL_API const pl_type *pl_registry_find(const pl_registry *r, const char *name);
/* The registered type name closest to `name`, or NULL if none is close. */
PL_API const char *pl_registry_suggest(const pl_registry *r, const char *name);
/* The last error pl_registry_add recorded (for plugins whose entry point
 * cannot pass it back). */
PL_API const pl_error *pl_registry_last_error(const pl_registry *r);
PL_API int pl_registry_count(const pl_registry *r);
PL_API const pl_type *pl_registry_type(const pl_registry *r, int i);
/* The plugin that registered t ("builtin" for libpliant's own), or NULL if
 * t is not registered here. */
PL_API const char *pl_registry_type_plugin(const pl_registry *r, const pl_type *t);

/* Plugin files are named libpliant_<name>.so.  Folders searched for them,
 * in order: those added here, then each entry of PLIANT_PLUGIN_PATH
 * (colon-separated), then libpliant's own plugin folder, found relative to
 * the library itself: <its folder>/pliant/plugins in an install,
 * <its folder>/../plugins in a build tree. */
PL_API int pl_registry_add_plugin_dir(pl_registry *r, const char *dir);
/* libpliant's own plugin folder (see above) into buf; PL_OK, or PL_EINPUT
 * when neither folder exists (buf then holds the installed one). */
PL_API int pl_registry_default_plugin_dir(char *buf, size_t size);
/* Loads plugin `name` (libpliant_<name>.so in the plugin folders) or a path
 * to a .so.  Loading an already loaded plugin is a no-op.  A plugin built
 * for an ABI this host cannot run is refused naming both versions. */
PL_API int pl_registry_load_plugin(pl_registry *r, const char *name_or_path, pl_error *err);
/* Loads every plugin found in the plugin folders (for `pliant list`);
 * failures are errors in diag and do not stop the others; a folder that is
 * missing or holds no plugin is a warning in diag. */
PL_API int pl_registry_load_all(pl_registry *r, pl_diag *diag);
#if PL_ABI_TARGET_MINOR >= 4 /* since 5.4 */
/* The plugin of r's plugin folders that provides `type` (found by loading
 * them all into a scratch registry; r is unchanged): 1 and its name in buf,
 * or 0.  For the error on an unknown type: which plugin to require. */
PL_API int pl_registry_plugin_providing(const pl_registry *r, const char *type, char *buf,
                                        size_t size);
#endif
PL_API int pl_registry_plugin_count(const pl_registry *r);
PL_API const char *pl_registry_plugin_name(const pl_registry *r, int i);
PL_API const char *pl_registry_plugin_path(const pl_registry *r, int i);

/* Registers the built-in components (libpliant_components). */
PL_API int pl_register_builtin_components(pl_registry *r, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
