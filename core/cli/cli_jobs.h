/* cli_jobs.h - one run of a sweep or a regression list in a child process:
 * a crash, a hang or an exit() of the run ends the child, not the command,
 * which reports it and goes on with the other runs. */
#ifndef PLIANT_CLI_JOBS_H
#define PLIANT_CLI_JOBS_H

#include <stdio.h>
#include <sys/types.h>

/* Runs job number `job` in the child; writes its report (text) to `out` and
 * returns the child's exit code. */
typedef int (*cli_job_fn)(int job, void *ctx, FILE *out);

typedef enum cli_job_end {
    CLI_JOB_EXITED,     /* code = exit code */
    CLI_JOB_SIGNALLED,  /* code = signal number */
    CLI_JOB_TIMED_OUT,  /* killed after the time limit */
    CLI_JOB_NOT_STARTED /* fork failed */
} cli_job_end;

typedef struct cli_job_result {
    int job;
    cli_job_end end;
    int code;
    double seconds;     /* wall time of the child */
    char *text;         /* its report (malloc'ed, NUL-terminated) */
    int rank;           /* the MPI rank that ran it (0 when serial) */
    char host[64];
} cli_job_result;

typedef struct cli_job {
    pid_t pid;
    int fd;             /* read end of the report pipe; -1 once at EOF */
    int job;
    double t0, timeout; /* [pl_now], [s]; timeout 0 = none */
    char *buf;
    size_t len, cap;
} cli_job;

/* Forks the child.  gpu: if not NULL, the child's CUDA_VISIBLE_DEVICES.
 * Returns 0, or -1 with res-worthy failure (then cli_job_poll reports
 * CLI_JOB_NOT_STARTED). */
int cli_job_start(cli_job *j, int job, cli_job_fn fn, void *ctx, double timeout, const char *gpu);
/* Waits at most wait_ms for the child.  Returns 1 when it has ended (res
 * filled; res->text then belongs to the caller), 0 while it runs. */
int cli_job_poll(cli_job *j, int wait_ms, cli_job_result *res);
void cli_job_result_free(cli_job_result *r);

/* The value of a report line "KEY VALUE" ("ms", "rec 2", ...) into buf, or
 * NULL when the report has no such line. */
const char *cli_report_get(const char *report, const char *key, char *buf, size_t size);

/* "ended with exit code 1", "crashed: SIGSEGV (Segmentation fault)",
 * "timed out after 5 s" */
void cli_job_describe(const cli_job_result *r, double timeout, char *buf, size_t size);

#endif
