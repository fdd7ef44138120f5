/* spinv_test_util.h - references for the sparse inverse tests: CHOLMOD's
 * own (default, supernodal-when-it-likes) factorisation and solves, dense
 * copies, random blocks. */
#ifndef SPINV_TEST_UTIL_H
#define SPINV_TEST_UTIL_H

#include <stddef.h>
#include "pliant/sparse.h"

/* n x k row-major block of values in [-1, 1], deterministic per seed. */
double *spinv_random_block(int n, int k, unsigned seed);
/* x = A^-1 b (n x k row-major) with an independent CHOLMOD factorisation. */
int spinv_ref_solve(const pl_csc *A, const double *b, double *x, int k);
/* ||a - b|| / ||b|| over len values. */
double spinv_rel_diff(const double *a, const double *b, size_t len);
/* Column-major dense copy of A (both triangles as given). */
double *spinv_dense(const pl_csc *A);
/* The lower triangle of A (with the diagonal). */
int spinv_lower(const pl_csc *A, pl_csc *lower);

#endif
