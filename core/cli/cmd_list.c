/* cmd_list.c - `pliant list` and `pliant doc`: the component reference,
 * generated from the registry's field tables. */
#include <pliant/pliant.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char *ROLE_NAMES[PL_ROLE_COUNT] = {
    "state", "mass", "topology", "local term", "global solver", "constraint",
    "contact solver", "collision model", "detector", "exporter", "controller",
    "prescribed DOFs", "animation loop", "device", "visual", "event"};

static pl_registry *full_registry(void)
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
    const pl_type *x = *(const pl_type *const *)a, *y = *(const pl_type *const *)b;
    int c = strcmp(x->plugin, y->plugin);
    if (c) return !strcmp(x->plugin, "builtin") ? -1 : !strcmp(y->plugin, "builtin") ? 1 : c;
    return strcmp(x->name, y->name);
}

static const pl_type **sorted_types(const pl_registry *r)
{
    int n = pl_registry_count(r);
    const pl_type **t = malloc((size_t)(n ? n : 1) * sizeof *t);
    if (!t) return NULL;
    for (int k = 0; k < n; ++k) t[k] = pl_registry_type(r, k);
    qsort(t, (size_t)n, sizeof *t, cmp_types);
    return t;
}

static void roles_text(const pl_type *t, char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; k < PL_ROLE_COUNT; ++k)
        if (t->roles[k] && n < size)
            n += (size_t)snprintf(buf + n, size - n, "%s%s", n ? ", " : "", ROLE_NAMES[k]);
}

static void field_type_text(const pl_field *f, char *buf, size_t size)
{
    if (f->type != PL_F_ENUM || !f->choices) {
        snprintf(buf, size, "%s", pl_field_type_name(f->type));
        return;
    }
    size_t n = 0;
    for (int k = 0; f->choices[k] && n < size; ++k)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", k ? "|" : "", f->choices[k]);
}

static void print_type(const pl_type *t, FILE *f)
{
    char roles[256], ty[256];
    roles_text(t, roles, sizeof roles);
    fprintf(f, "%s  (%s)%s%s\n  %s\n", t->name, t->plugin, roles[0] ? "  roles: " : "", roles,
            t->help ? t->help : "");
    for (int k = 0; k < t->nfields; ++k) {
        const pl_field *fd = &t->fields[k];
        field_type_text(fd, ty, sizeof ty);
        fprintf(f, "    %-20s %-18s %s%s%s%s%s%s\n", fd->name, ty, fd->help ? fd->help : "",
                fd->def && fd->def[0] ? " (default " : "", fd->def && fd->def[0] ? fd->def : "",
                fd->def && fd->def[0] ? ")" : "", (fd->flags & PL_FIELD_REQUIRED) ? " [required]" : "",
                (fd->flags & PL_FIELD_OUTPUT) ? " [output]" : "");
    }
}

int cli_list(int argc, char **argv)
{
    pl_registry *r = full_registry();
    if (!r) return 1;
    const pl_type **types = sorted_types(r);
    int n = pl_registry_count(r), found = 0;
    for (int k = 0; types && k < n; ++k) {
        if (argc > 0 && strcmp(types[k]->name, argv[0])) continue;
        print_type(types[k], stdout);
        found++;
    }
    if (argc == 0) {
        printf("\nplugins:\n");
        for (int k = 0; k < pl_registry_plugin_count(r); ++k)
            printf("  %-16s %s\n", pl_registry_plugin_name(r, k), pl_registry_plugin_path(r, k));
    } else if (!found) {
        const char *s = pl_registry_suggest(r, argv[0]);
        fprintf(stderr, "pliant list: no component '%s'%s%s%s\n", argv[0], s ? " (did you mean " : "",
                s ? s : "", s ? "?)" : "");
    }
    free(types);
    pl_registry_free(r);
    return (argc > 0 && !found) ? 2 : 0;
}

static void doc_type(const pl_type *t, FILE *f)
{
    char roles[256], ty[256];
    roles_text(t, roles, sizeof roles);
    fprintf(f, "### %s\n\n%s\n\nPlugin: `%s`.%s%s%s\n\n", t->name, t->help ? t->help : "",
            t->plugin, roles[0] ? " Roles: " : "", roles, roles[0] ? "." : "");
    if (t->nfields == 0) return;
    fprintf(f, "| field | type | default | description |\n| --- | --- | --- | --- |\n");
    for (int k = 0; k < t->nfields; ++k) {
        const pl_field *fd = &t->fields[k];
        field_type_text(fd, ty, sizeof ty);
        fprintf(f, "| `%s`%s | %s | %s | %s%s%s |\n", fd->name,
                fd->alias ? "" : "", ty, fd->def && fd->def[0] ? fd->def : "",
                fd->help ? fd->help : "", (fd->flags & PL_FIELD_REQUIRED) ? " **Required.**" : "",
                (fd->flags & PL_FIELD_OUTPUT) ? " *Output.*" : "");
    }
    fputc('\n', f);
}

int cli_doc(int argc, char **argv)
{
    const char *path = argc > 0 ? argv[0] : "docs/components.md";
    pl_registry *r = full_registry();
    if (!r) return 1;
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "pliant doc: cannot write %s\n", path);
        pl_registry_free(r);
        return 2;
    }
    const pl_type **types = sorted_types(r);
    fprintf(f, "# Component reference\n\nGenerated by `pliant doc` from the registry's field "
               "tables; do not edit by hand.\nUnits are SI unless a field says otherwise.\n\n");
    const char *group = "";
    for (int k = 0; types && k < pl_registry_count(r); ++k) {
        if (strcmp(group, types[k]->plugin)) {
            group = types[k]->plugin;
            if (!strcmp(group, "builtin"))
                fprintf(f, "## Built-in components\n\n");
            else
                fprintf(f, "## Plugin `%s`\n\nLoad with `<RequiredPlugin name=\"%s\"/>`.\n\n",
                        group, group);
        }
        doc_type(types[k], f);
    }
    free(types);
    int rc = fclose(f) != 0;
    pl_registry_free(r);
    if (!rc) printf("wrote %s\n", path);
    return rc ? 1 : 0;
}
