/* main.c - `pliant`: run scenes headless, list components, regenerate the
 * component reference, run regression checks and parameter sweeps.  A thin
 * user of sim.h; each command lives in its own cmd_*.c. */
#include <pliant/pliant.h>

#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "cli_dispatch.h"

#ifndef PLIANT_VERSION_STRING
#define PLIANT_VERSION_STRING "?"
#endif

typedef struct command {
    const char *name;
    int (*fn)(int argc, char **argv);
    const char *summary;
} command;

static const command COMMANDS[] = {
    {"run", cli_run, "run a scene headless, write its outputs"},
    {"list", cli_list, "components and plugins, with their fields"},
    {"doc", cli_doc, "the component reference in Markdown"},
    {"regress", cli_regress, "run a regression list against stored references"},
    {"sweep", cli_sweep, "run a scene over a grid of field values, tabulate outputs"},
    {"view", cli_view, "the scene live in a window (play, step, keys, mouse)"},
    {"render", cli_render, "pictures without a display: PNG frames or an MP4"},
};
#define NCOMMANDS ((int)(sizeof COMMANDS / sizeof COMMANDS[0]))

static void usage(FILE *f)
{
    fputs("usage: pliant COMMAND [OPTIONS]   (pliant COMMAND --help for its options)\n\n"
          "commands:\n", f);
    for (int k = 0; k < NCOMMANDS; ++k)
        fprintf(f, "  %-9s %s\n", COMMANDS[k].name, COMMANDS[k].summary);
    fputs("\noptions: -h, --help   this text;  -V, --version   version and build\n"
          "exit codes: 0 ok, 1 internal error or failed check, 2 bad input\n", f);
}

static void version(void)
{
    printf("pliant %s (plugin ABI %d.%d, %s)\n", PLIANT_VERSION_STRING, PL_ABI_MAJOR, PL_ABI_MINOR,
           cli_dispatch_build_info());
}

int main(int argc, char **argv)
{
    cli_threads_prepare(argv);
    static const struct option opts[] = {
        {"help", no_argument, NULL, 'h'}, {"version", no_argument, NULL, 'V'}, {0, 0, 0, 0}};
    opterr = 0;
    int c;
    /* '+': stop at the command, whose options are its own */
    while ((c = getopt_long(argc, argv, "+hV", opts, NULL)) != -1) {
        if (c == 'h') return usage(stdout), 0;
        if (c == 'V') return version(), 0;
        fprintf(stderr, "pliant: unknown option '%s'\n", argv[optind - 1]);
        usage(stderr);
        return 2;
    }
    if (optind >= argc) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[optind];
    if (!strcmp(cmd, "help")) {
        if (optind + 1 >= argc) return usage(stdout), 0;
        cmd = argv[optind + 1];
        for (int k = 0; k < NCOMMANDS; ++k)
            if (!strcmp(cmd, COMMANDS[k].name)) {
                char *help_argv[] = {argv[optind + 1], "--help", NULL};
                optind = 0;
                return COMMANDS[k].fn(2, help_argv);
            }
    }
    for (int k = 0; k < NCOMMANDS; ++k)
        if (!strcmp(cmd, COMMANDS[k].name)) {
            int first = optind;
            optind = 0; /* the command parses from its own argv[0] */
            return COMMANDS[k].fn(argc - first, argv + first);
        }
    fprintf(stderr, "pliant: unknown command '%s'\n", cmd);
    usage(stderr);
    return 2;
}
