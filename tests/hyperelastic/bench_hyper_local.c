/* bench_hyper_local.c - times the local step (hyper_elements_project) of
 * ARAP, corotational and Neo-Hookean tetrahedra and membranes.  Not a test:
 *   build-<dir>/bin/bench_hyper_local [n (grid vertices per axis, default 30)] [reps]
 * Prints ms per local step and ns per element for the current OMP_NUM_THREADS. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hyper_test_util.h"
#include "hyperelastic.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void bench(const char *label, pl_hyper_material mat, int k, const int *cells, int ncells,
                  const double *rest, int nv, int reps)
{
    pl_hyper_elements el;
    double E = 1e6, nu = 0.45;
    if (hyper_elements_build(&el, mat, k, cells, ncells, rest, nv, &E, 1, &nu, 1, 1e-3, NULL)) {
        fprintf(stderr, "build failed\n");
        exit(1);
    }
    unsigned long long st = 1;
    double *q = malloc(sizeof(double) * 3 * nv), *rhs = calloc((size_t)3 * nv, sizeof(double));
    for (int i = 0; i < 3 * nv; ++i) q[i] = 1.1 * rest[i] + 0.002 * ht_rand(&st);
    int nd = hyper_elements_dual_size(&el);
    double *u = calloc((size_t)ncells * (nd ? nd : 1), sizeof(double));
    hyper_prox_stats stats = {0};
    double *work = malloc(sizeof(double) * hyper_elements_work_size(&el));
    hyper_elements_project(&el, 0, 1e-4, q, nd ? u : NULL, NULL, work, rhs, &stats, NULL); /* warm up */
    double t0 = now();
    for (int r = 0; r < reps; ++r)
        hyper_elements_project(&el, 0, 1e-4, q, nd ? u : NULL, NULL, work, rhs, &stats, NULL);
    double dt = (now() - t0) / reps;
    printf("%-26s %8d elements  %8.3f ms/step  %7.1f ns/element  (max Newton its %d)\n", label,
           ncells, 1e3 * dt, 1e9 * dt / ncells, stats.max_iterations);
    free(q);
    free(rhs);
    free(u);
    free(work);
    hyper_elements_free(&el);
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 30, reps = argc > 2 ? atoi(argv[2]) : 10;
    printf("threads: %d\n", omp_get_max_threads());
    double *v;
    int *t, nt;
    int nv = ht_tet_grid(n, n, n, 0.01, &v, &t, &nt);
    bench("ARAP tetrahedra", PL_HYPER_ARAP, 4, t, nt, v, nv, reps);
    bench("corotational tetrahedra", PL_HYPER_COROTATIONAL, 4, t, nt, v, nv, reps);
    bench("Neo-Hookean tetrahedra", PL_HYPER_NEOHOOKEAN, 4, t, nt, v, nv, reps);
    free(v);
    free(t);
    nv = ht_tri_grid(8 * n, 8 * n, 0.01, &v, &t, &nt);
    bench("ARAP triangles", PL_HYPER_ARAP, 3, t, nt, v, nv, reps);
    bench("corotational triangles", PL_HYPER_COROTATIONAL, 3, t, nt, v, nv, reps);
    bench("Neo-Hookean triangles", PL_HYPER_NEOHOOKEAN, 3, t, nt, v, nv, reps);
    free(v);
    free(t);
    return 0;
}
