/* cli.h - the pliant command-line tool's subcommands. */
#ifndef PLIANT_CLI_H
#define PLIANT_CLI_H

/* Exit codes: 0 ok, 1 internal error, 2 bad input (scene, arguments). */
int cli_run(int argc, char **argv);
int cli_list(int argc, char **argv);
int cli_doc(int argc, char **argv);
int cli_regress(int argc, char **argv);
int cli_view(int argc, char **argv);
int cli_render(int argc, char **argv);

#endif
