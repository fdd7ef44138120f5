/* cmd_list.c - `pliant list [TYPE]`: the components and plugins this build
 * finds, with their fields, from the registry's field tables. */
#include <pliant/pliant.h>

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_types.h"

static const char USAGE[] =
    "usage: pliant list [TYPE]\n"
    "Lists every component type (built-in and from the plugins found) with its roles and\n"
    "fields, then the plugins and where they were loaded from; with TYPE, that type only.\n\n"
    "  -h, --help   this text\n"
    "exit codes: 0 ok, 2 no such type (the closest name is suggested)\n";

static void print_type(const cli_type *e, FILE *f)
{
    const pl_type *t = e->t;
    char roles[256], ty[256];
    cli_roles_text(t, roles, sizeof roles);
    fprintf(f, "%s  (%s)%s%s\n  %s\n", t->name, e->plugin, roles[0] ? "  roles: " : "", roles,
            t->help ? t->help : "");
    for (int k = 0; k < t->nfields; ++k) {
        const pl_field *fd = &t->fields[k];
        cli_field_type_text(fd, ty, sizeof ty);
        fprintf(f, "    %-20s %-18s %s%s%s%s%s%s%s\n", fd->name, ty, fd->help ? fd->help : "",
                fd->def && fd->def[0] ? " (default " : "", fd->def && fd->def[0] ? fd->def : "",
                fd->def && fd->def[0] ? ")" : "", (fd->flags & PL_FIELD_REQUIRED) ? " [required]" : "",
                (fd->flags & PL_FIELD_OUTPUT) ? " [output]" : "",
                (fd->flags & PL_FIELD_INPUT) ? " [input]" : "");
    }
}

int cli_list(int argc, char **argv)
{
    static const struct option opts[] = {{"help", no_argument, NULL, 'h'}, {0, 0, 0, 0}};
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        if (c == 'h') return fputs(USAGE, stdout), 0;
        return cli_bad_option("list", argv, optind, optopt);
    }
    if (argc - optind > 1) return cli_usage_error("list", "give at most one TYPE");
    const char *only = optind < argc ? argv[optind] : NULL;
    pl_registry *r = cli_full_registry();
    if (!r) return 1;
    cli_type *types = cli_sorted_types(r);
    int n = pl_registry_count(r), found = 0;
    for (int k = 0; types && k < n; ++k) {
        if (only && strcmp(types[k].t->name, only)) continue;
        print_type(&types[k], stdout);
        found++;
    }
    if (!only) {
        printf("\nplugins:\n");
        for (int k = 0; k < pl_registry_plugin_count(r); ++k)
            printf("  %-16s %s\n", pl_registry_plugin_name(r, k), pl_registry_plugin_path(r, k));
    } else if (!found) {
        const char *s = pl_registry_suggest(r, only);
        fprintf(stderr, "pliant list: no component '%s'%s%s%s\n", only, s ? " (did you mean " : "",
                s ? s : "", s ? "?)" : "");
    }
    free(types);
    pl_registry_free(r);
    return (only && !found) ? 2 : 0;
}
