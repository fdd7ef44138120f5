/* incidence.c - vertex -> slot incidence and the deterministic gather. */
#include <stdlib.h>

#include "incidence.h"

int hyper_incidence_build(int nverts, int nslots, const int *vert, int **vptr, int **vinc)
{
    int *p = calloc((size_t)nverts + 1, sizeof *p);
    int *inc = malloc(((size_t)nslots > 0 ? (size_t)nslots : 1) * sizeof *inc);
    int *next = malloc(((size_t)nverts > 0 ? (size_t)nverts : 1) * sizeof *next);
    if (!p || !inc || !next) {
        free(p);
        free(inc);
        free(next);
        return -1;
    }
    for (int s = 0; s < nslots; ++s) p[vert[s] + 1]++;
    for (int v = 0; v < nverts; ++v) p[v + 1] += p[v];
    for (int v = 0; v < nverts; ++v) next[v] = p[v];
    for (int s = 0; s < nslots; ++s) inc[next[vert[s]]++] = s; /* increasing s per vertex */
    free(next);
    *vptr = p;
    *vinc = inc;
    return 0;
}

void hyper_incidence_gather(int nverts, const int *vptr, const int *vinc, const double *vals,
                            int offset, double *out)
{
#pragma omp parallel for schedule(static)
    for (int v = 0; v < nverts; ++v) {
        double a0 = 0.0, a1 = 0.0, a2 = 0.0;
        for (int k = vptr[v]; k < vptr[v + 1]; ++k) {
            const double *x = vals + 3 * (size_t)vinc[k];
            a0 += x[0];
            a1 += x[1];
            a2 += x[2];
        }
        double *o = out + 3 * ((size_t)offset + v);
        o[0] += a0;
        o[1] += a1;
        o[2] += a2;
    }
}
