/* sweep.h - `pliant sweep`: a scene run over the grid of --set values.
 *
 *   OUT/sweep.txt          what was asked (scene, steps, --set, --record):
 *                          a later call with the same OUT must ask the same
 *   OUT/run_NNNN/          one run: the scene's outputs, log.txt (its
 *                          messages) and, once it completed, result.txt
 *   OUT/sweep.csv, .md     one row per run: values, recorded outputs,
 *                          steps, ms/step, status
 * Runs are numbered over the grid with the last --set varying fastest. */
#ifndef PLIANT_CLI_SWEEP_H
#define PLIANT_CLI_SWEEP_H

#include <stdio.h>

typedef struct sweep_axis {
    char *path;          /* "bar/arap.youngModulus" */
    char *spec;          /* as given: "1e5:1e6:3", "a,b", "v" */
    char **values;       /* each exactly as --set gets it */
    int n;
} sweep_axis;

typedef struct sweep {
    const char *scene;
    char out[1024];
    int steps;
    sweep_axis *axes;
    int naxes;
    const char **records;
    int nrecords;
    const char *device;
    int quiet;
    int nruns;
    int rank;            /* this process's MPI rank (0 when alone), for result.txt */
} sweep;

/* sweep_grid.c */
/* Adds "--set PATH=SPEC"; returns 0 or prints and returns 2. */
int sweep_add_axis(sweep *s, const char *arg);
/* The number of runs (the product of the axes' lengths); 0 when too many. */
int sweep_count(const sweep *s);
/* The value of axis a in run r. */
const char *sweep_value(const sweep *s, int run, int a);
void sweep_free(sweep *s);

/* sweep_run.c: the children's work */
/* cli_job_fn: run r, outputs in OUT/run_NNNN; writes its report (also
 * result.txt once complete): "status ok|error", "steps N", "ms X",
 * "set K VALUE", "rec K VALUE", "msg TEXT". */
int sweep_run_job(int run, void *s, FILE *out);
/* cli_job_fn: loads the scene with run r's values, outputs in a temporary
 * folder, and checks every --record path; exit 0 or 2 (messages on stderr). */
int sweep_check_job(int run, void *s, FILE *out);
void sweep_run_dir(const sweep *s, int run, char *buf, size_t size);

/* sweep_table.c */
/* OUT/sweep.txt: writes it, or checks that it says the same; 0 or 2. */
int sweep_spec_check(const sweep *s);
/* The report of a run that completed before (result.txt), or NULL. */
char *sweep_completed(const sweep *s, int run);
/* Writes OUT/sweep.csv and OUT/sweep.md from the runs' reports and status
 * texts ("ok", "crashed: SIGSEGV ..."); returns 0 or 1. */
int sweep_write_tables(const sweep *s, char *const *reports, char *const *status);

#endif
