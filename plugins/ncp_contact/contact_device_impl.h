/* contact_device_impl.h - the state of the contact solver's device path,
 * shared by its files (contact_device.c: the step's upload, the iterate
 * and the multipliers' way back; contact_device_update.c: a constrained
 * iteration's kernels).  Internal to contact_device*.c. */
#ifndef PLIANT_NCP_CONTACT_DEVICE_IMPL_H
#define PLIANT_NCP_CONTACT_DEVICE_IMPL_H

#include "contact_device.h"
#include "ncp_cuda.h"

/* What a CUDA graph captured around iterate() keeps of this path: device
 * addresses, the capacities that size its grids and copies, and the
 * parameters passed by value.  While it stays the same, a graph captured in
 * an earlier step replays this step's rows (their sizes and arrays are read
 * from the device descriptor at in_dev); a change bumps epoch. */
typedef struct graph_key {
    const void *in_dev, *work, *W, *X, *q_free, *corr, *U;
    int mcap, nallcap, nfree, active, jacobian, explicit_w, fused, dense, one, grid;
    pl_ncp_cuda_params P;
} graph_key;

struct pl_ncpc_device {
    const pl_component *owner;
    pl_component *dev;
    const pl_device_ops *ops;
    struct CUstream_st *stream;
    int stale, ran;
    int fetched;            /* the host copies below hold this step's last iteration */
    /* the step's inputs: one device arena, filled from one page-locked
     * staging buffer */
    void *in_dev, *in_host;
    size_t in_cap, in_host_cap;
    /* work vectors (20 x m doubles + m ints), W, nfree x 3 blocks */
    void *work;
    size_t work_cap;
    double *W;
    size_t W_cap;
    double *X, *q_free, *corr;
    size_t f_cap;
    /* the dense correction: U_j = A^-1 H_j^T, dense_max blocks of nfree x 3
     * (its address changes with nfree only: a captured graph reads it) */
    double *U;
    size_t U_cap;
    int dense_max;          /* PLIANT_NCP_DENSE_CORR: the most rows, 0 off */
    int dense;              /* this step's: 0 < m <= dense_max, unknowns */
    pl_ncp_cuda_scalars *sc;
    double *series;
    /* page-locked host copy of the series' first series_guess iterations,
     * queued before fetch's wait (one wait a step where the step iterated
     * no more than the guess: the largest count so far, at least 64) */
    double *h_series;
    int series_guess;
    /* page-locked host copies of lambda (m), lambda_all (nall), scalars */
    double *h_lambda, *h_lambda_all;
    size_t h_cap, h_all_cap, h_series_cap;
    pl_ncp_cuda_scalars *h_sc;
    pl_ncp_cuda_rows R;     /* host copy; the device copy is at in_dev */
    pl_ncp_cuda_vecs V;
    pl_ncp_cuda_params P;
    int explicit_w, jacobian;
    int fused_env;          /* PLIANT_NCP_FUSED_CR=1: the constraint update in one kernel */
    int fused;              /* this step's: fused_env, W explicit, mcap <= NCP_CUDA_FUSED_MAX_ROWS */
    int fused_warp;         /* PLIANT_NCP_FUSED_WARP: few rows by one warp (ncp_cuda.h) */
    int fused_narrow;       /* PLIANT_NCP_FUSED_NARROW: few rows by a block of 128 or 256 */
    int scatter_warp;       /* PLIANT_NCP_SCATTER_WARP: H^T x a warp an unknown */
    int phase_pairs;        /* PLIANT_NCP_PHASE_PAIRS: two phases a launch where no product
                               comes between them (contact_device_update.c) */
    int update_graph_env;   /* PLIANT_NCP_UPDATE_GRAPH (on unless 0): see update_graph */
    /* the phase kernels' constraint update with W explicit, recorded at
     * update_epoch and replayed where an iteration runs eagerly (a step's
     * first: contact_device_update.c); NULL: none yet */
    void *update_graph;
    unsigned long update_epoch;
    int one_env;            /* PLIANT_NCP_ONE_KERNEL (on unless 0): see `one` */
    int one;                /* this step's: fused by the warp, dense: ncp_cuda_iterate_few */
    int grid_min;           /* PLIANT_NCP_GRID_MIN: the least capacity of rows whose phases
                               run over many blocks (ncp_cuda_grid.cu) */
    int grid;               /* this step's: not fused, mcap >= grid_min */
    double *part;           /* NCP_CUDA_GRID_PART doubles on the device (V.part) */
    int mcap, nallcap;      /* capacities of rows and of all rows (doubled) */
    graph_key key;
    unsigned long epoch;
};

/* err set for the device path's component (code 0: PL_EINTERNAL) / with a
 * CUDA error's text; both return the code set. */
int ncpc_device_fail(const pl_ncpc_device *g, pl_error *err, int code, const char *what);
int ncpc_device_cuda_fail(const pl_ncpc_device *g, pl_error *err, int e, const char *what);
/* With the device's profile flag: start timer id, or wait and stop it. */
int ncpc_device_lap(pl_ncpc_device *g, pl_ctx *ctx, int profile, int id, int start, pl_error *err);
/* A constrained iteration after q_free = A^-1 b (contact_device_update.c):
 * the row values at q_k and q_free, the step's stick start (its first
 * iterate), the constraint update and q_next = q_free + h^2 A^-1 H^T (S
 * lambda); queued on the stream, one launch for few rows (`one`). */
int ncpc_device_constrained(pl_ncpc_device *g, const pl_ncpc_device_step *st, pl_ctx *ctx,
                            const pl_system *sys, const pl_buffer *q_k, pl_buffer *q_next,
                            int profile, pl_error *err);

#endif
