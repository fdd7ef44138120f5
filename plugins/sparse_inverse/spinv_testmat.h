/* spinv_testmat.h - SPD test matrices for the sparse inverse tests and
 * benchmark: a Freudenthal (6 tets per cube) box grid and random sparse SPD
 * matrices.  Not part of the solver. */
#ifndef PLIANT_SPINV_TESTMAT_H
#define PLIANT_SPINV_TESTMAT_H

#include "pliant/sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A = M + h2w * G for the tetrahedral grid of nx x ny x nz vertices (unit
 * spacing, 6 tets per cube around its main diagonal): M is the lumped mass
 * (volume / 4 per tet and vertex), G the graph Laplacian of the tet edges,
 * each tet adding its volume to the weight of its 6 edges (the pattern of a
 * sum of w G^T G over tets).  Both triangles, sorted.  PL_EINPUT on sizes
 * below 2, PL_EINTERNAL on allocation failure. */
int spinv_grid_matrix(int nx, int ny, int nz, double h2w, pl_csc *A);

/* A random sparse symmetric, strictly diagonally dominant (so SPD) n x n
 * matrix with about `per_col` off-diagonal pairs per column; both
 * triangles, sorted.  Deterministic for a seed. */
int spinv_random_spd(int n, int per_col, unsigned seed, pl_csc *A);

/* Tets of the grid above: 6 (nx-1)(ny-1)(nz-1) rows of 4 vertex indices
 * (v = i + nx (j + ny k)); malloc'ed, NULL on failure. */
int *spinv_grid_tets(int nx, int ny, int nz, int *ntets);

#ifdef __cplusplus
}
#endif
#endif
