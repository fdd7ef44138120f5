/* cli_dispatch.h - runs a list of jobs (the runs of a sweep, the scenes of
 * a regression list), each in a forked child: one after the other, or
 * spread over the ranks of an MPI job (`mpirun -n N pliant ...`), where
 * rank 0 hands out runs as ranks become free and gathers the results.
 *
 * Every rank builds the same job list from the same command line; rank 0
 * alone decides which jobs run (todo), receives every result (done) and
 * writes the tables. */
#ifndef PLIANT_CLI_DISPATCH_H
#define PLIANT_CLI_DISPATCH_H

#include "cli_jobs.h"

typedef struct cli_dispatch {
    const char *cmd;          /* "sweep", "regress": for messages */
    const int *todo;          /* rank 0: the jobs to run, in order */
    int ntodo;
    cli_job_fn run;           /* what a child does for job k (every rank) */
    void *ctx;                /* run's argument */
    double timeout;           /* per job [s]; 0 = none */
    /* rank 0: called for each job as it ends, in any order */
    void (*done)(const cli_job_result *r, void *done_ctx);
    void *done_ctx;
} cli_dispatch;

/* Joins the MPI job when the process was started by an MPI launcher
 * (mpirun, srun); else runs alone.  A build without MPI started as one of
 * several processes says so and returns 2.  Returns 0 or 2. */
int cli_dispatch_init(const char *cmd, int *argc, char ***argv);
int cli_dispatch_rank(void);
int cli_dispatch_size(void);
/* Threads for each run when the user set none (--threads, OMP_NUM_THREADS):
 * the cores of this process shared among the ranks on its node that may run
 * on the same cores; 0 = OpenMP's default. */
int cli_dispatch_default_threads(void);
/* Runs d's jobs; returns when all have ended (rank 0 has had every done()). */
int cli_dispatch_run(const cli_dispatch *d);
/* Leaves the MPI job; returns rc. */
int cli_dispatch_finish(int rc);
/* "with MPI (Open MPI v4.1.4, ...)" or "without MPI", for --version. */
const char *cli_dispatch_build_info(void);
/* Where a run went wrong, for messages: "rank 1 of 2, host h" or "host h". */
void cli_dispatch_where(const cli_job_result *r, char *buf, size_t size);

/* cli_mpi.c (MPI builds only) */
int cli_mpi_init(int *argc, char ***argv, int *rank, int *size);
int cli_mpi_local(int *local_rank, int *sharing);
int cli_mpi_run(const cli_dispatch *d, const char *gpu);
void cli_mpi_finish(void);
const char *cli_mpi_version(void);

#endif
