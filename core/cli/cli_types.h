/* cli_types.h - the registry as `pliant list` and `pliant doc` show it. */
#ifndef PLIANT_CLI_TYPES_H
#define PLIANT_CLI_TYPES_H

#include <pliant/pliant.h>

#include <stddef.h>

/* A registry with the built-ins and every plugin found; NULL on failure
 * (reported on stderr). */
pl_registry *cli_full_registry(void);
/* A registered type and the plugin that registered it ("builtin"). */
typedef struct cli_type {
    const pl_type *t;
    const char *plugin;
} cli_type;
/* The registry's types, built-ins first, then by plugin and name; malloc'ed. */
cli_type *cli_sorted_types(const pl_registry *r);
/* "state, mass" */
void cli_roles_text(const pl_type *t, char *buf, size_t size);
/* "double", or the choices of an enum "a|b|c" */
void cli_field_type_text(const pl_field *f, char *buf, size_t size);

#endif
