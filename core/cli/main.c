/* main.c - `pliant`: run scenes headless, list components, regenerate the
 * component reference, run regression checks.  A thin user of sim.h. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static void usage(FILE *f)
{
    fputs("usage:\n"
          "  pliant run SCENE.xml [-n STEPS] [--out DIR] [--export-every K]\n"
          "             [--timings FILE.json] [--set PATH=VALUE ...] [--quiet]\n"
          "             [--device cpu|auto]  (auto: the GPU when the scene declares no\n"
          "             device and one is usable; default PLIANT_DEVICE, else auto)\n"
          "  pliant list [TYPE]          components and plugins, with their fields\n"
          "  pliant doc [FILE.md]        regenerate the component reference\n"
          "  pliant regress LIST [--update] [--refs DIR]\n"
          "  pliant view SCENE.xml [--play] [--script FILE] ...   the scene live in a window\n"
          "  pliant render SCENE.xml -n STEPS (--png DIR | --mp4 FILE) [--every K] ...\n"
          "                              pictures without a display (--help for more)\n"
          "exit codes: 0 ok, 2 bad input, 1 internal error\n",
          f);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "run")) return cli_run(argc - 2, argv + 2);
    if (!strcmp(cmd, "list")) return cli_list(argc - 2, argv + 2);
    if (!strcmp(cmd, "doc")) return cli_doc(argc - 2, argv + 2);
    if (!strcmp(cmd, "regress")) return cli_regress(argc - 2, argv + 2);
    /* getopt_long wants the command name at argv[0] */
    if (!strcmp(cmd, "view")) return cli_view(argc - 1, argv + 1);
    if (!strcmp(cmd, "render")) return cli_render(argc - 1, argv + 1);
    if (!strcmp(cmd, "-h") || !strcmp(cmd, "--help") || !strcmp(cmd, "help")) {
        usage(stdout);
        return 0;
    }
    fprintf(stderr, "pliant: unknown command '%s'\n", cmd);
    usage(stderr);
    return 2;
}
