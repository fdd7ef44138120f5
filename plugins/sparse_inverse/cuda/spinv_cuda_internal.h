/* spinv_cuda_internal.h - the CUDA backend's private state, shared by its
 * .cu files (CUDA C++ only). */
#ifndef PLIANT_SPINV_CUDA_INTERNAL_H
#define PLIANT_SPINV_CUDA_INTERNAL_H

#include <cuda_runtime.h>

#include "spinv_cuda.h"
#include "spinv_cuda_layout.h"

/* Sets err from a failed CUDA call; returns PL_EINTERNAL. */
int spinv_cuda_fail(pl_error *err, cudaError_t e, const char *what);
#define SPINV_CK(call, what)                                       \
    do {                                                           \
        cudaError_t ck_e_ = (call);                                \
        if (ck_e_ != cudaSuccess) return spinv_cuda_fail(err, ck_e_, what); \
    } while (0)

struct spinv_delassus; /* spinv_cuda_delassus.cu: cuBLAS handle and buffers, made on first use */
extern "C" void spinv_delassus_destroy(struct spinv_delassus *d);

struct pl_spinv_cuda {
    int n, npad;
    pl_precision prec;
    /* sizes of the layout (the host arrays are freed after upload) */
    int nitems_S, nitems_ST, nparts_S, nparts_ST, ntiles, vc, tile;
    int group, item_blocks;          /* rows per ROWS item at most, blocks per ROWS item */
    int64_t nval;
    /* device arrays */
    int *perm;                       /* n */
    int *parent;                     /* n: the etree in the permuted numbering (-1: root) */
    void *val;                       /* nval padded values */
    pl_spinv_cuda_rowmeta *meta;     /* n */
    pl_spinv_cuda_item *items_S, *items_ST;
    int *short_rows;
    pl_spinv_cuda_tilerow *rowlist;
    void *a;                         /* npad x 3: P b */
    void *y4;                        /* n x 4: S P b (4th column unused) */
    void *part_S, *part_ST;          /* partial sums of split rows and tiles */
    int *cnt_S, *cnt_ST;             /* arrival counters (reset by the last warp) */
    int small;                       /* the single-block solve (spinv_cuda_small.cu) */
    size_t small_shmem;              /* its shared memory, bytes */
    double *hb, *hx;                 /* n x 3 float64 staging for solve_host */
    struct spinv_delassus *dl;       /* spinv_cuda_delassus's state */
    /* the last solve's buffers, for run_stage */
    const void *last_b;
    void *last_x;
    pl_precision last_io;
    double bytes_device, bytes_step;
};

/* A step's rows on the device (pl_spinv_cuda_rows' arrays, uploaded). */
typedef struct pl_spinv_cuda_drows {
    int m, nu;
    const int *pos, *rp, *ru;
    const double *rx;
    int nl;             /* rows of more than 64 entries (spinv_cuda_delassus.cu) */
    const int *longr;   /* their indices, ascending */
} pl_spinv_cuda_drows;

/* diag[j] = W_jj = sum_k |S P h_kj|^2 for the m rows of A (spinv_cuda_wdiag.cu),
 * queued on st; m = 0 only loads the kernel. */
int spinv_cuda_launch_wdiag(pl_spinv_cuda *g, const pl_spinv_cuda_drows *A, double *diag,
                            cudaStream_t st, pl_error *err);

/* Kernel launches (spinv_cuda_kernels.cu); io: element type of b / x. */
int spinv_cuda_launch_permute(pl_spinv_cuda *g, const void *b, pl_precision io, const int *perm,
                              cudaStream_t st, pl_error *err);
int spinv_cuda_launch_S(pl_spinv_cuda *g, cudaStream_t st, pl_error *err);
int spinv_cuda_launch_ST(pl_spinv_cuda *g, void *x, pl_precision io, const int *perm,
                         cudaStream_t st, pl_error *err);
/* The single-block solve (spinv_cuda_small.cu; when: spinv_cuda_small_fits). */
/* Decides g->small at create (and lets the kernels use their shared memory). */
int spinv_cuda_small_setup(pl_spinv_cuda *g, pl_error *err);
/* x = A^-1 b in one launch (g->small set). */
int spinv_cuda_launch_small(pl_spinv_cuda *g, const void *b, void *x, pl_precision io,
                            cudaStream_t st, pl_error *err);
/* y4 (n x 4) <- x (n x 3) and y (n x 3) <- y4, in the object's precision. */
int spinv_cuda_launch_to4(pl_spinv_cuda *g, const void *x, cudaStream_t st, pl_error *err);
int spinv_cuda_launch_from4(pl_spinv_cuda *g, void *y, cudaStream_t st, pl_error *err);

#endif
