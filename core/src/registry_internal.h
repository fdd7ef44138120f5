/* registry_internal.h - private: the registry's struct, shared by
 * registry.c (types) and plugins.c (plugin files). */
#ifndef PLIANT_REGISTRY_INTERNAL_H
#define PLIANT_REGISTRY_INTERNAL_H

#include "pliant/plugin.h"
#include "pliant/registry.h"

#include <stdio.h>

typedef struct plugin {
    char *name;
    char *path;
    void *handle;
} plugin;

typedef struct type_entry {
    const pl_type *type;  /* the registrant's own definition */
    const char *plugin;   /* a plugins[].name, or "builtin" */
} type_entry;

struct pl_registry {
    type_entry *types;
    int ntypes, cap_types;
    plugin *plugins;
    int nplugins, cap_plugins;
    char **dirs;
    int ndirs;
    const char *loading;  /* plugin being registered, recorded with its types */
    pl_error last;
};

/* "4.1", or the single number of versions before 4.0 ("3": below 1000). */
static inline const char *abi_text(int v, char *buf, size_t size)
{
    if (v < 1000)
        snprintf(buf, size, "%d", v);
    else
        snprintf(buf, size, "%d.%d", PL_ABI_MAJOR_OF(v), PL_ABI_MINOR_OF(v));
    return buf;
}

#endif
