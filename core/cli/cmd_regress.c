/* cmd_regress.c - `pliant regress LIST`: SOFA-style state regression. */
#include <stdio.h>

#include "cli.h"

int cli_regress(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "pliant regress: being written\n");
    return 1;
}
