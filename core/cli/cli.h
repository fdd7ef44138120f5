/* cli.h - the pliant command-line tool: its commands (one per cmd_*.c) and
 * the small helpers they share. */
#ifndef PLIANT_CLI_H
#define PLIANT_CLI_H

#include <stddef.h>
#include <stdio.h>

/* Exit codes: 0 ok, 1 internal error (or a failed regression), 2 bad input
 * (scene, arguments). */
int cli_run(int argc, char **argv);
/* pliant run script.py: hands the arguments to python3 -m pliant run (cmd_run_python.c). */
int cli_is_python_script(int argc, char **argv);
int cli_run_python(int argc, char **argv);
int cli_list(int argc, char **argv);
int cli_doc(int argc, char **argv);
int cli_regress(int argc, char **argv);
int cli_sweep(int argc, char **argv);
int cli_view(int argc, char **argv);
int cli_render(int argc, char **argv);

/* ---- cli_common.c: arguments, names, temporary folders ---- */

/* Prints "pliant CMD: message" and a pointer to --help; returns 2. */
int cli_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The message for getopt_long's '?' (unknown option or missing value). */
int cli_bad_option(const char *cmd, char **argv, int optind_now, int optopt_now);
/* Parses a whole non-negative integer >= min; returns 0 or prints and returns 2. */
int cli_parse_int(const char *cmd, const char *opt, const char *s, int min, int *out);
/* Parses a whole number >= 0 (seconds, etc.); same return convention. */
int cli_parse_double(const char *cmd, const char *opt, const char *s, double *out);
/* "dir/name.xml" -> "name" (the scene name used for default output folders). */
void cli_scene_name(const char *path, char *buf, size_t size);
/* Creates $TMPDIR/pliant_<tag>_XXXXXX (TMPDIR defaults to /tmp); returns a
 * malloc'ed path or NULL. */
char *cli_tmpdir_create(const char *tag);
/* mkdir -p; returns 0 when the folder exists afterwards. */
int cli_make_dirs(const char *path);
/* Removes a folder and everything in it; returns 0 on success. */
int cli_remove_tree(const char *path);

/* ---- cli_threads.c: OpenMP on a shared machine ---- */

/* Re-executes the program with OMP_WAIT_POLICY=PASSIVE unless the user set
 * the variable (libgomp reads it only when it loads, before main). */
void cli_threads_prepare(char **argv);
/* Cores this process may run on (its affinity mask). */
int cli_cpu_count(void);
/* Sets the OpenMP team size: `requested` threads (0 = OpenMP's default,
 * i.e. OMP_NUM_THREADS or the cores), never more than cli_cpu_count(). */
int cli_threads_set(int requested);

/* ---- cli_progress.c: a bar on a terminal, a line every few s in a log ---- */

typedef struct cli_progress {
    int total;
    int tty;           /* draw a bar (stderr is a terminal) */
    double every;      /* seconds between log lines; 0 = none */
    double t0, last;   /* start and last report [pl_now] */
} cli_progress;

void cli_progress_start(cli_progress *p, int total, int quiet, double every);
/* Reports frame `done` at simulated time t [s] when it is time to. */
void cli_progress_update(cli_progress *p, int done, double t);
void cli_progress_finish(cli_progress *p, int done, double t);

#endif
