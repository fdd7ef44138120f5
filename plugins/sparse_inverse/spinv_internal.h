/* spinv_internal.h - the sparse inverse solver's private state, shared by
 * its source files (factor, inverse, subtrees, apply, rows). */
#ifndef PLIANT_SPINV_INTERNAL_H
#define PLIANT_SPINV_INTERNAL_H

#include <cholmod.h>
#include "sparse_inverse.h"

struct pl_sparse_inverse {
    pl_spinv_options opt;
    int nthreads;             /* resolved thread count (>= 1) */
    int n;                    /* 0 before factor */
    cholmod_common cc;
    int cc_started;
    cholmod_factor *L;        /* simplicial LL^T of P A P^T */
    int *perm;                /* n: perm[k] = original index of k */
    int *pinv;                /* n: pinv[i] = permuted index of i */
    int *parent;              /* n: etree in the permuted space */
    int *first;               /* n: first descendant */
    pl_spinv_profile S;       /* sparse mode only */
    pl_spinv_runs ST;         /* sparse mode only */
    int nchunks;              /* row ranges for the products */
    int *S_bounds, *ST_bounds;/* nchunks + 1 each */
    double *work_a, *work_b;  /* n x k blocks for solve */
    size_t work_cap;          /* doubles in each work block */
    cholmod_dense *B, *X, *Y, *E; /* direct-mode workspaces of cholmod_solve2 */
    pl_spinv_stats stats;
};

/* Below this many multiply-adds a loop runs on the calling thread: waking
 * a team costs more than it saves there (the cable finger's S^T S b, 20k:
 * its global phase took 0.74 ms a frame on 2 threads against 0.28 ms on
 * one; docs/benchmarks.md, "Small solves on one thread"). */
#define SPINV_SERIAL_WORK 32768.0

/* The threads for a loop of `work` multiply-adds. */
static inline int spinv_threads_for(const struct pl_sparse_inverse *s, double work)
{
    return work < SPINV_SERIAL_WORK ? 1 : s->nthreads;
}

/* Releases everything factor built (keeps options and CHOLMOD's common). */
void spinv_clear(pl_sparse_inverse *s);

/* Column j of L^-1 on the ancestor path of j: out[t] = S(path_t, j), the
 * path ascending from j.  w (n doubles) must be zero and is left zero.
 * Returns the path length. */
int spinv_path_column(const cholmod_factor *L, const int *parent, int j, double *w,
                         double *out);

/* The elimination tree cut into top nodes (descending: parents first) and
 * subtree roots (heaviest first); subtree r is the range first[r]..r. */
typedef struct pl_spinv_split {
    int *top, ntop;
    int *roots, nroots;
} pl_spinv_split;

/* Splits so that each subtree carries at most 1/target of the work
 * (work[k] per node), with at most 4 target subtrees unless the forest has
 * more trees.  PL_EINTERNAL on allocation failure. */
int spinv_subtrees(int n, const int *parent, const double *work, int target,
                      pl_spinv_split *split);
void spinv_split_free(pl_spinv_split *split);

/* Computes S and S^T (sparse mode) from s->L, s->parent, s->first. */
int spinv_build_inverse(pl_sparse_inverse *s, pl_error *err);

/* Ensures s->work_a/b hold n * k doubles. */
int spinv_reserve_work(pl_sparse_inverse *s, int k, pl_error *err);

#endif
