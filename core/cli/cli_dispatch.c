/* cli_dispatch.c - jobs one after the other, or over MPI ranks (cli_mpi.c). */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_dispatch.h"

static int g_rank = 0, g_size = 1, g_mpi = 0, g_sharing = 1;

/* The launchers' environment: Open MPI's mpirun, PMI (MPICH, Slurm's srun
 * --mpi=pmi2) and PMIx (srun --mpi=pmix).  Returns 1 when started by one;
 * size and rank are -1 where it does not say. */
static int launched(int *size, int *rank)
{
    const char *s = getenv("OMPI_COMM_WORLD_SIZE"), *r = getenv("OMPI_COMM_WORLD_RANK");
    if (!s) s = getenv("PMI_SIZE"), r = getenv("PMI_RANK");
    if (!r) r = getenv("PMIX_RANK");
    *size = s ? atoi(s) : -1;
    *rank = r ? atoi(r) : -1;
    return s || r;
}

#ifdef PLIANT_HAVE_MPI
static char g_gpu[64];       /* CUDA_VISIBLE_DEVICES for this rank's runs; "" = as is */

/* GPUs of this node: CUDA_VISIBLE_DEVICES's list where set (a launcher or
 * Slurm's gres may have narrowed it), else the NVIDIA driver's count. */
static int gpu_list(char ids[][16], int max)
{
    const char *env = getenv("CUDA_VISIBLE_DEVICES");
    int n = 0;
    if (env) {
        char copy[256], *save = NULL;
        snprintf(copy, sizeof copy, "%s", env);
        for (char *t = strtok_r(copy, ",", &save); t && n < max; t = strtok_r(NULL, ",", &save))
            snprintf(ids[n++], sizeof ids[0], "%s", t);
        return n;
    }
    DIR *d = opendir("/proc/driver/nvidia/gpus");
    struct dirent *e;
    while (d && (e = readdir(d)) && n < max)
        if (e->d_name[0] != '.') snprintf(ids[n], sizeof ids[0], "%d", n), n++;
    if (d) closedir(d);
    return n;
}
#endif

int cli_dispatch_init(const char *cmd, int *argc, char ***argv)
{
    int size, rank;
    if (!launched(&size, &rank)) return 0;
#ifdef PLIANT_HAVE_MPI
    (void)size, (void)rank;
    if (cli_mpi_init(argc, argv, &g_rank, &g_size) != 0) {
        fprintf(stderr, "pliant %s: cannot join the MPI job (MPI_Init failed)\n", cmd);
        return 2;
    }
    g_mpi = 1;
    int local = 0;
    if (cli_mpi_local(&local, &g_sharing) != 0) g_sharing = 1;
    char ids[64][16];
    int ngpu = g_size > 1 ? gpu_list(ids, 64) : 0;
    if (ngpu > 0) snprintf(g_gpu, sizeof g_gpu, "%s", ids[local % ngpu]);
    return 0;
#else
    (void)argc, (void)argv;
    if (size > 1 || rank > 0) {
        fprintf(stderr,
                "pliant %s: started by mpirun/srun as one of several processes (%d), but this "
                "pliant was built without MPI, so each process would run everything. Install "
                "MPI (libopenmpi-dev) and rebuild, or run it without mpirun (it then runs the "
                "runs one after the other).\n",
                cmd, size);
        return 2;
    }
    return 0;
#endif
}

int cli_dispatch_rank(void) { return g_rank; }
int cli_dispatch_size(void) { return g_size; }

int cli_dispatch_default_threads(void)
{
    if (g_sharing <= 1 || getenv("OMP_NUM_THREADS")) return 0;
    int n = cli_cpu_count() / g_sharing;
    return n > 0 ? n : 1;
}

static int run_serial(const cli_dispatch *d)
{
    for (int k = 0; k < d->ntodo; ++k) {
        cli_job j;
        cli_job_result r;
        cli_job_start(&j, d->todo[k], d->run, d->ctx, d->timeout, NULL);
        while (!cli_job_poll(&j, 1000, &r)) {}
        d->done(&r, d->done_ctx);
        cli_job_result_free(&r);
    }
    return 0;
}

int cli_dispatch_run(const cli_dispatch *d)
{
#ifdef PLIANT_HAVE_MPI
    if (g_mpi && g_size > 1) return cli_mpi_run(d, g_gpu[0] ? g_gpu : NULL);
#endif
    return run_serial(d);
}

int cli_dispatch_finish(int rc)
{
#ifdef PLIANT_HAVE_MPI
    if (g_mpi) cli_mpi_finish();
#endif
    g_mpi = 0;
    return rc;
}

const char *cli_dispatch_build_info(void)
{
#ifdef PLIANT_HAVE_MPI
    static char buf[160];
    snprintf(buf, sizeof buf, "with MPI: %s", cli_mpi_version());
    return buf;
#else
    return "without MPI";
#endif
}

void cli_dispatch_where(const cli_job_result *r, char *buf, size_t size)
{
    if (g_size > 1)
        snprintf(buf, size, "rank %d of %d, host %s", r->rank, g_size, r->host);
    else
        snprintf(buf, size, "host %s", r->host);
}
