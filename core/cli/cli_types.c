/* cli_types.c - the registry as `pliant list` and `pliant doc` show it:
 * every type (built-ins, then plugins), their roles and field types. */
#include <pliant/pliant.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_types.h"

pl_registry *cli_full_registry(void)
{
    pl_error err;
    pl_diag diag;
    pl_registry *r = pl_registry_create();
    if (!r || pl_register_builtin_components(r, &err) != PL_OK) {
        fprintf(stderr, "pliant: cannot register the built-in components\n");
        pl_registry_free(r);
        return NULL;
    }
    pl_diag_init(&diag);
    pl_registry_load_all(r, &diag);
    pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    return r;
}

static int cmp_types(const void *a, const void *b)
{
    const cli_type *x = a, *y = b;
    int c = strcmp(x->plugin, y->plugin);
    if (c) return !strcmp(x->plugin, "builtin") ? -1 : !strcmp(y->plugin, "builtin") ? 1 : c;
    return strcmp(x->t->name, y->t->name);
}

cli_type *cli_sorted_types(const pl_registry *r)
{
    int n = pl_registry_count(r);
    cli_type *t = malloc((size_t)(n ? n : 1) * sizeof *t);
    if (!t) return NULL;
    for (int k = 0; k < n; ++k) {
        t[k].t = pl_registry_type(r, k);
        t[k].plugin = pl_registry_type_plugin(r, t[k].t);
    }
    qsort(t, (size_t)n, sizeof *t, cmp_types);
    return t;
}

void cli_roles_text(const pl_type *t, char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; k < PL_ROLE_COUNT; ++k)
        if (t->roles[k] && n < size)
            n += (size_t)snprintf(buf + n, size - n, "%s%s", n ? ", " : "", pl_role_name(k));
}

void cli_field_type_text(const pl_field *f, char *buf, size_t size)
{
    if (f->type != PL_F_ENUM || !f->choices) {
        snprintf(buf, size, "%s", pl_field_type_name(f->type));
        return;
    }
    size_t n = 0;
    for (int k = 0; f->choices[k] && n < size; ++k)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", k ? "|" : "", f->choices[k]);
}

