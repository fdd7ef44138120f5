/* cli_threads.c - OpenMP that behaves on a shared machine.
 *
 * libgomp's default wait policy spins at every barrier.  When the cores are
 * busy with other work, a spinning thread keeps a core from the descheduled
 * thread it waits for, and a step measured 201-314 ms instead of 9 ms on a
 * busy 2-core machine.  OMP_WAIT_POLICY=PASSIVE makes waiting threads sleep;
 * libgomp reads it once, when it is loaded (before main), so the only way
 * for a program to set it for itself is to run again with it set. */
#include <omp.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "cli.h"

void cli_threads_prepare(char **argv)
{
    if (getenv("OMP_WAIT_POLICY")) return; /* the user's choice, or already re-executed */
    if (setenv("OMP_WAIT_POLICY", "PASSIVE", 1) != 0) return;
    execv("/proc/self/exe", argv);
    /* no /proc: run on with libgomp's default (slower on busy cores, same results) */
    fprintf(stderr, "pliant: note: could not restart with OMP_WAIT_POLICY=PASSIVE; set it "
                    "yourself if other programs share these cores\n");
}

int cli_cpu_count(void)
{
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0) {
        int n = CPU_COUNT(&set);
        if (n > 0) return n;
    }
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

int cli_threads_set(int requested)
{
    int cores = cli_cpu_count();
    int n = requested > 0 ? requested : omp_get_max_threads();
    if (n > cores) {
        /* more threads than cores only adds waiting at every barrier */
        if (requested > 0 || getenv("OMP_NUM_THREADS"))
            fprintf(stderr, "pliant: %d threads asked for, this process may use %d core%s: "
                            "using %d\n", n, cores, cores == 1 ? "" : "s", cores);
        n = cores;
    }
    if (n < 1) n = 1;
    omp_set_num_threads(n);
    return n;
}
