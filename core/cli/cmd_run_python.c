/* cmd_run_python.c - `pliant run script.py`: a SofaPython3-style script
 * (createScene(rootNode)) runs in the Python package, as runSofa would run
 * it: the CLI hands its arguments to `python3 -m pliant run` (python/pliant/
 * __main__.py; docs/python.md).  PLIANT_PYTHON names another interpreter. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

/* Imports the package's runner, or says how to install it (exit 2). */
static const char BOOT[] =
    "import sys\n"
    "try:\n"
    "    import pliant.__main__ as m\n"
    "except ImportError as e:\n"
    "    sys.stderr.write('pliant run: %s is a Python script; running it needs the Python "
    "package pliant (%s). Install it from the source tree: python3 -m venv venv && "
    ". venv/bin/activate && pip install . (docs/python.md)\\n' % (sys.argv[2], e))\n"
    "    sys.exit(2)\n"
    "sys.exit(m.main(sys.argv[1:]))\n";

int cli_is_python_script(int argc, char **argv)
{
    for (int k = 1; k < argc; ++k) {
        size_t n = strlen(argv[k]);
        if (argv[k][0] != '-' && n > 3 && strcmp(argv[k] + n - 3, ".py") == 0) return 1;
    }
    return 0;
}

int cli_run_python(int argc, char **argv)
{
    const char *py = getenv("PLIANT_PYTHON");
    if (!py || !*py) py = "python3";
    /* python3 -c BOOT run <the run command's arguments> */
    char **args = calloc((size_t)argc + 4, sizeof *args);
    if (!args) return 1;
    args[0] = (char *)py;
    args[1] = "-c";
    args[2] = (char *)BOOT;
    args[3] = "run";
    for (int k = 1; k < argc; ++k) args[3 + k] = argv[k];
    fflush(stdout);
    execvp(py, args);
    fprintf(stderr,
            "pliant run: %s is a Python script; running it needs Python 3 (%s: %s) and the "
            "package pliant (pip install . in the source tree, docs/python.md)\n",
            argv[argc - 1], py, strerror(errno));
    free(args);
    return 2;
}
