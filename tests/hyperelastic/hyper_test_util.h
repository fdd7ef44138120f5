/* hyper_test_util.h - helpers shared by the hyperelastic tests: a
 * deterministic random generator, small meshes, dense linear algebra. */
#ifndef PLIANT_HYPER_TEST_UTIL_H
#define PLIANT_HYPER_TEST_UTIL_H

#include "pliant/sparse.h"

/* Uniform in [-1, 1) from a 64-bit LCG (deterministic across platforms). */
double ht_rand(unsigned long long *state);
/* A random proper rotation (3x3 row-major). */
void ht_random_rotation(unsigned long long *state, double R[9]);

/* Regular grid of nx x ny x nz vertices with spacing h, 6 positively
 * oriented tetrahedra per cell.  Returns the vertex count; *verts and *tets
 * are malloc'd (free them). */
int ht_tet_grid(int nx, int ny, int nz, double h, double **verts, int **tets, int *ntets);
/* Flat nx x ny grid in the xy-plane (z = 0), spacing h, 2 triangles per cell. */
int ht_tri_grid(int nx, int ny, double h, double **verts, int **tris, int *ntris);

/* Dense n x n (row-major) += the triplets (duplicates summed). */
void ht_triplets_to_dense(const pl_triplets *t, double *A, int n);
/* In-place Cholesky A = L L^T (lower triangle); 0 on success, -1 if not SPD. */
int ht_cholesky(int n, double *A);
/* Solves L L^T x = b for k right-hand sides (b: n x k row-major, in place). */
void ht_cholesky_solve(int n, const double *L, int k, double *b);

#endif
