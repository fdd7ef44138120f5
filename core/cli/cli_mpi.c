/* cli_mpi.c - the jobs of a sweep or regression list over MPI ranks.
 *
 * Rank 0 hands out jobs as ranks ask for them (dynamic assignment: a rank
 * that finished a short run gets the next one) and runs jobs itself
 * between answering.  Every job runs in a forked child of its rank
 * (cli_jobs.c); the child never calls MPI.  Messages:
 *   worker -> 0, TAG_RESULT: "job end code seconds host\n" + the child's
 *                            report; job -1 means "ready, nothing to report"
 *   0 -> worker, TAG_JOB:    one int, the job to run; -1 = stop.
 * Waiting is done in poll() (for a child) or in short sleeps around
 * MPI_Iprobe (rank 0), never in a spinning MPI call that would take a core
 * from the runs. */
#ifdef PLIANT_HAVE_MPI
#include <mpi.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli_dispatch.h"

enum { TAG_JOB = 1, TAG_RESULT = 2 };

int cli_mpi_init(int *argc, char ***argv, int *rank, int *size)
{
    if (MPI_Init(argc, argv) != MPI_SUCCESS) return -1;
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    return 0;
}

/* This rank's index on its node, and how many ranks of the node may run on
 * the cores it may run on (itself included): they share those cores. */
int cli_mpi_local(int *local_rank, int *sharing)
{
    MPI_Comm node;
    int rank, n;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node))
        return -1;
    MPI_Comm_rank(node, local_rank);
    MPI_Comm_size(node, &n);
    cpu_set_t mine, *all = malloc((size_t)n * sizeof *all);
    if (!all || sched_getaffinity(0, sizeof mine, &mine) != 0) {
        free(all);
        MPI_Comm_free(&node);
        return -1;
    }
    MPI_Allgather(&mine, (int)sizeof mine, MPI_BYTE, all, (int)sizeof mine, MPI_BYTE, node);
    *sharing = 0;
    for (int k = 0; k < n; ++k) {
        cpu_set_t both;
        CPU_AND(&both, &mine, &all[k]);
        if (CPU_COUNT(&both) > 0) ++*sharing;
    }
    free(all);
    MPI_Comm_free(&node);
    return 0;
}

/* Completes a request in short sleeps: a blocking MPI call would spin and
 * take a core from the runs of this node. */
static void wait_quietly(MPI_Request *req)
{
    const struct timespec nap = {0, 2000000}; /* 2 ms */
    int flag = 0;
    while (MPI_Test(req, &flag, MPI_STATUS_IGNORE) == MPI_SUCCESS && !flag) nanosleep(&nap, NULL);
}

static void send_result(const cli_job_result *r)
{
    char head[160];
    const char *text = r ? r->text : "";
    int n = r ? snprintf(head, sizeof head, "%d %d %d %.17g %s\n", r->job, (int)r->end, r->code,
                         r->seconds, r->host[0] ? r->host : "?")
              : snprintf(head, sizeof head, "-1 0 0 0 -\n");
    size_t len = (size_t)n + strlen(text);
    char *msg = malloc(len + 1);
    if (!msg) MPI_Abort(MPI_COMM_WORLD, 1);
    memcpy(msg, head, (size_t)n);
    memcpy(msg + n, text, strlen(text) + 1);
    MPI_Request req;
    MPI_Isend(msg, (int)len, MPI_CHAR, 0, TAG_RESULT, MPI_COMM_WORLD, &req);
    wait_quietly(&req);
    free(msg);
}

/* Receives a worker's message; returns 1 (r filled) for a result, 0 for "ready". */
static int recv_result(const MPI_Status *st, cli_job_result *r)
{
    int len;
    MPI_Get_count(st, MPI_CHAR, &len);
    char *msg = malloc((size_t)len + 1);
    if (!msg) MPI_Abort(MPI_COMM_WORLD, 1);
    MPI_Recv(msg, len, MPI_CHAR, st->MPI_SOURCE, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    msg[len] = '\0';
    memset(r, 0, sizeof *r);
    int end = 0;
    char *nl = strchr(msg, '\n');
    if (sscanf(msg, "%d %d %d %lf %63s", &r->job, &end, &r->code, &r->seconds, r->host) != 5 ||
        !nl || r->job < 0) {
        free(msg);
        return 0;
    }
    r->end = (cli_job_end)end;
    r->rank = st->MPI_SOURCE;
    r->text = strdup(nl + 1);
    free(msg);
    return r->text != NULL;
}

static void run_one(const cli_dispatch *d, int job, const char *gpu, int rank, cli_job_result *r)
{
    cli_job j;
    cli_job_start(&j, job, d->run, d->ctx, d->timeout, gpu);
    while (!cli_job_poll(&j, 1000, r)) {}
    r->rank = rank;
}

static int worker(const cli_dispatch *d, const char *gpu, int rank)
{
    send_result(NULL);
    for (;;) {
        int job;
        MPI_Request req;
        MPI_Irecv(&job, 1, MPI_INT, 0, TAG_JOB, MPI_COMM_WORLD, &req);
        wait_quietly(&req);
        if (job < 0) return 0;
        cli_job_result r;
        run_one(d, job, gpu, rank, &r);
        send_result(&r);
        cli_job_result_free(&r);
    }
}

/* Answers every worker that asked; returns how many were told to stop. */
static int serve(const cli_dispatch *d, int *next)
{
    int stopped = 0, flag;
    MPI_Status st;
    while (MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag, &st) == MPI_SUCCESS &&
           flag) {
        cli_job_result r;
        if (recv_result(&st, &r)) {
            d->done(&r, d->done_ctx);
            cli_job_result_free(&r);
        }
        int job = *next < d->ntodo ? d->todo[(*next)++] : -1;
        if (job < 0) stopped++;
        MPI_Send(&job, 1, MPI_INT, st.MPI_SOURCE, TAG_JOB, MPI_COMM_WORLD);
    }
    return stopped;
}

static int root(const cli_dispatch *d, const char *gpu, int size)
{
    int next = 0, stopped = 0, busy = 0;
    cli_job own;
    const struct timespec nap = {0, 5000000}; /* 5 ms */
    while (stopped < size - 1 || busy || next < d->ntodo) {
        if (!busy && next < d->ntodo) {
            cli_job_start(&own, d->todo[next++], d->run, d->ctx, d->timeout, gpu);
            busy = 1;
        }
        cli_job_result r;
        if (busy && cli_job_poll(&own, 5, &r)) {
            d->done(&r, d->done_ctx);
            cli_job_result_free(&r);
            busy = 0;
        } else if (!busy) {
            nanosleep(&nap, NULL);
        }
        stopped += serve(d, &next);
    }
    return 0;
}

int cli_mpi_run(const cli_dispatch *d, const char *gpu)
{
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    return rank == 0 ? root(d, gpu, size) : worker(d, gpu, rank);
}

void cli_mpi_finish(void)
{
    /* ranks done early wait here for the others' last runs, without spinning */
    MPI_Request req;
    MPI_Ibarrier(MPI_COMM_WORLD, &req);
    wait_quietly(&req);
    MPI_Finalize();
}

const char *cli_mpi_version(void)
{
    static char v[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    MPI_Get_library_version(v, &len);
    char *comma = strchr(v, ',');
    if (comma) *comma = '\0';
    return v;
}
#endif
