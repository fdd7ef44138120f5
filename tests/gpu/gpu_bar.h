/* gpu_bar.h - the twisting bar's system for the GPU check and benchmark,
 * built with the CPU plugin cores: a 1 m x 0.25 m x 0.25 m bar of nx x ny
 * x nz vertices (6 tets per cube), rho 1000 kg/m^3, E 1e9 Pa, nu 0.45,
 * h = 0.01 s (the paper's Table 3 row); A = M + h^2 sum w D D^T with the
 * ARAP weights, every vertex free, factored by the sparse inverse. */
#ifndef PLIANT_TESTS_GPU_BAR_H
#define PLIANT_TESTS_GPU_BAR_H

#include "hyperelastic.h"
#include "sparse_inverse.h"

typedef struct gpu_bar {
    int nx, ny, nz, n, ntets;
    double h;
    double *rest;               /* n x 3 */
    double *mass;               /* n lumped masses [kg] */
    pl_hyper_elements el[3];    /* ARAP, corotational, Neo-Hookean */
    pl_sparse_inverse *spinv;   /* factored A (sparse mode) */
} gpu_bar;

int gpu_bar_build(gpu_bar *b, int nx, int ny, int nz, pl_error *err);
void gpu_bar_free(gpu_bar *b);
/* q (n x 3): the rest bar twisted about its axis by `turns` * 2 pi over its
 * length, plus a uniform random offset of +-noise [m] per coordinate. */
void gpu_bar_twist(const gpu_bar *b, double turns, double noise, unsigned seed, double *q);
/* b (n x 3) = M q + h^2 sum w (p - u) D^T of the ARAP local step at q:
 * the right-hand side of a global step (u = 0). */
int gpu_bar_rhs(gpu_bar *b, const double *q, double *rhs, pl_error *err);
/* Uniform pseudo-random numbers in [-0.5, 0.5) (xorshift, reproducible). */
double gpu_rand(unsigned *state);
/* ||a - b|| / ||b|| over m values. */
double gpu_rel_diff(const double *a, const double *b, size_t m);

#endif
