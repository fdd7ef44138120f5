/* ncp_cuda.h - the kernels of the contact solver's device path (CUDA
 * builds): the rows' products (ncp_cuda_rows.cu) and the constraint update
 * of Algorithm 4 split into phases around its W products (ncp_cuda_step.cu,
 * the phases' code in ncp_cuda_phases.cuh) or in one kernel
 * (ncp_cuda_fused.cu).
 *
 * Every function queues work on `stream` and returns the launch's
 * cudaError_t as an int (0: queued); nothing waits, so a whole iteration
 * can be captured in a CUDA graph.  Pointers are device pointers.  The
 * kernels read the step's rows (sizes and arrays) from a device copy of
 * pl_ncp_cuda_rows, and their grids are sized by a capacity of rows
 * (mcap >= m): a graph captured once stays valid for later steps with
 * other rows as long as that descriptor's address, the capacity and the
 * work vectors stay (contact_device.c counts the changes).  The
 * phases are single-block kernels (rows and contacts of one step are few;
 * their reductions are then deterministic): they call the CPU's own NCP
 * functions, residual parts and projections (ncp_functions.h,
 * ncp_residual.h, ncp_project.h, compiled as CUDA) and replay ncp_step.c,
 * cr.c and ncp_linesearch.c with the same formulas, the CPU files being the
 * reference.  Host decisions of the CPU code that depend on
 * values become device flags: CR's stop (done) freezes its updates, the
 * clamped rows' product always runs (zero when no row is clamped), the line
 * search evaluates its trials in one kernel and takes the first that
 * decreases the residual. */
#ifndef PLIANT_NCP_CUDA_H
#define PLIANT_NCP_CUDA_H

#ifdef __cplusplus
extern "C" {
#endif

struct CUstream_st;

/* A step's active rows on the device (see pl_ncpc_rows), plus the
 * contact table of pl_ncp_work and the transpose of the free entries. */
typedef struct pl_ncp_cuda_rows {
    int m, nc, nall, nfree;
    const int *kind;        /* m (pl_row_kind) */
    const int *contact;     /* nc x 3: normal row, friction rows (-1 if absent) */
    const int *full;        /* m: index among all rows */
    const int *fstart, *fcol; /* free entries (m + 1, per entry) */
    const double *fcoef;    /* 3 per free entry */
    const int *pstart, *pvert; /* entries on prescribed vertices */
    const double *pcoef;
    const int *tptr;        /* nfree + 1: unknown -> its free entries ... */
    const int *tent;        /* ... in increasing entry order */
    const int *erow;        /* per free entry: its row */
    const double *offset, *mu, *compliance, *lo, *hi, *r; /* m */
    const double *wdiag;    /* m: W_jj (CR's Jacobi scaling) */
    const int *fvert;       /* nfree: the free vertices (jacobian correction), or NULL */
} pl_ncp_cuda_rows;

/* Device scalars of one iteration (and error flags of the step). */
typedef struct pl_ncp_cuda_scalars {
    double bnorm, rnorm, rAr, phin;
    int done, its, error, iter; /* error: 1 CR rhs, 2 CR residual, 3 line search residual not finite */
} pl_ncp_cuda_scalars;

/* The work vectors (m unless said). */
typedef struct pl_ncp_cuda_vecs {
    double *lambda, *dlambda, *delta, *delta_free, *omega, *e, *phi, *rhs, *tmp, *tmp2;
    double *scale, *clamped, *op_omega, *op_e, *force, *ls0, *ls1;
    double *cr_r, *cr_p, *cr_Ar, *cr_Ap;
    double *cr_s;           /* CR's scaling D^-1/2 (1 without cr_jacobi) */
    int *is_clamped;
    double *lambda_all;     /* nall */
    double *series;         /* series_cap x 4: phi norm, CR products, CR residual, step length */
    int series_cap;
    pl_ncp_cuda_scalars *sc;
    double *part;           /* NCP_CUDA_GRID_PART: the grid kernels' partial sums */
} pl_ncp_cuda_vecs;

typedef struct pl_ncp_cuda_params {
    int fn;                 /* pl_ncp_function */
    double h, fb_eps, cr_rtol, damping;
    int cr_max_iter, full_force, project, line_search, cr_jacobi;
} pl_ncp_cuda_params;

/* ---- rows (ncp_cuda_rows.cu) ------------------------------------------- */
/* R: the device copy of the rows; mcap >= R->m sizes the grids over rows,
 * nfree (= R->nfree) the grids over unknowns. */
/* delta_j = H_j [x; q_p] - offset_j (x: nfree x 3, q: all vertices); with
 * use_fvert, x is ignored and the free part reads q at R->fvert too. */
int ncp_cuda_delta(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap, const double *x,
                   const double *q, int use_fvert, double *delta);
/* Both at once, as the two ncp_cuda_delta calls of a jacobian iteration:
 * delta at q (use_fvert) and delta_free at x (the same sums, one launch). */
int ncp_cuda_delta2(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap, const double *x,
                    const double *q, double *delta, double *delta_free);
/* X (nfree x 3) = alpha H_free^T x (per unknown, entries in row order);
 * warp: a warp an unknown (its entries loaded at once), else a thread (the
 * same sums). */
int ncp_cuda_scatter(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int nfree,
                     const double *x, double alpha, double *X, int warp);
/* force = scale .* lambda (PL_NCP_PHASE_LAMBDA) and X = alpha H_free^T
 * force (ncp_cuda_scatter) in one launch, the same values. */
int ncp_cuda_scatter_scaled(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                            int nfree, const double *scale, const double *lambda, double alpha,
                            double *force, double *X, int warp);
/* y_j = H_j,free X. */
int ncp_cuda_gather(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap, const double *X,
                    double *y);
/* y = W x, W dense m x m row-major, m = R->m (summed as ncp_cuda_dense.cuh
 * says: K threads a row, a warp for many rows). */
int ncp_cuda_dense(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap, const double *W,
                   const double *x, double *y);
/* out[i] = a[i] + b[i], i < n. */
int ncp_cuda_add(struct CUstream_st *st, long n, const double *a, const double *b, double *out);
/* Whether work queued on st is being recorded into a graph (not run). */
int ncp_cuda_capturing(struct CUstream_st *st);
/* sc reset for a new step: error 0, iter 0. */
int ncp_cuda_reset(struct CUstream_st *st, pl_ncp_cuda_scalars *sc);

/* ---- the constraint update (ncp_cuda_step.cu) -------------------------- */
typedef enum pl_ncp_cuda_phase {
    PL_NCP_PHASE_LIN = 0,   /* delta = ls0 = delta_free + h^2 tmp2 (tmp2 = W lambda) */
    PL_NCP_PHASE_A,         /* phi, omega, e; S, clamped rows; tmp = S lambda; max |phi| */
    PL_NCP_PHASE_B,         /* rhs (tmp2 = W S lambda); clamped dlambda; tmp = S clamped */
    PL_NCP_PHASE_C,         /* rhs -= h^2 Omega W (S clamped); CR's operator, its Jacobi
                               scaling and start; tmp = ox */
    PL_NCP_PHASE_D,         /* CR: Ar from tmp2, p = r, Ap = Ar */
    PL_NCP_PHASE_E,         /* CR: x, r update, stop test; tmp = ox */
    PL_NCP_PHASE_F,         /* CR: Ar from tmp2, beta, p, Ap */
    PL_NCP_PHASE_G,         /* dlambda = cr_s dlambda + clamped */
    PL_NCP_PHASE_LAMBDA,    /* force = S lambda */
    PL_NCP_PHASE_LS0,       /* ls0 = delta_free + h^2 tmp2 (jacobian correction) */
    PL_NCP_PHASE_DLAMBDA,   /* force = S dlambda */
    PL_NCP_PHASE_UPDATE     /* line search (tmp2 = W S dlambda) or alpha 1, lambda update,
                               projection, lambda_all, series */
} pl_ncp_cuda_phase;

/* Queues one phase (a single-block kernel); R: the device copy. */
int ncp_cuda_phase_run(struct CUstream_st *st, pl_ncp_cuda_phase phase,
                          const pl_ncp_cuda_rows *R, const pl_ncp_cuda_vecs *V,
                          const pl_ncp_cuda_params *P, int last);
/* Two phases with no product between them in one launch (phase, then
 * phase2 after a block barrier): the results of the two launches. */
int ncp_cuda_phase_run2(struct CUstream_st *st, pl_ncp_cuda_phase phase, int last,
                        pl_ncp_cuda_phase phase2, int last2, const pl_ncp_cuda_rows *R,
                        const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P);

/* The whole constraint update (contact_device.c's constraint_update: the
 * phases above and the products y = W x between them, CR's loop included)
 * in one single-block kernel, W explicit (m x m, m = R->m): the same
 * arithmetic as those phases and ncp_cuda_dense queued one by one (bitwise
 * the same results), without their launches; reductions take one barrier
 * each.  jacobian: the correction's kind (no linearisation).  For few
 * rows, one block doing each product: NCP_CUDA_FUSED_MAX_ROWS.  With warp
 * = 2, at most NCP_CUDA_WARP_MAX_ROWS rows (the kernel reads the step's m)
 * are done by the block's first warp alone, one row a lane, with warp
 * barriers and shuffles only, on copies of the step's rows, W and work
 * vectors in shared memory; warp = 1: that warp on the arrays in place;
 * 0: the whole block for few rows too.  mcap > 0 (>= R->m): a block of 128
 * or 256 threads where the capacity fits it, else (or mcap = 0) 512.  The
 * same sums in all of them. */
#define NCP_CUDA_FUSED_MAX_ROWS 256
#define NCP_CUDA_WARP_MAX_ROWS 32
int ncp_cuda_update_fused(struct CUstream_st *st, const pl_ncp_cuda_rows *R,
                          const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P, const double *W,
                          int jacobian, int warp, int mcap);
/* ---- the phases over many blocks (ncp_cuda_grid.cu) ------------------- */
/* For many rows, the phases above over a grid of ncp_cuda_grid_blocks(mcap)
 * blocks, a kernel ending wherever a reduction (or a contact's read of rows
 * other blocks write) is needed, the partial sums in V->part
 * (NCP_CUDA_GRID_PART doubles).  The phases' results up to the order of
 * their sums (fixed by the grid: deterministic); sc->phin is written by
 * the update (the series), not by A. */
#define NCP_CUDA_GRID_MAX_BLOCKS 512
#define NCP_CUDA_GRID_PART (10 * NCP_CUDA_GRID_MAX_BLOCKS + 2)
int ncp_cuda_grid_blocks(int mcap);
/* [LIN (lin),] A. */
int ncp_cuda_grid_a(struct CUstream_st *st, int lin, const pl_ncp_cuda_rows *R, int mcap,
                    const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P);
/* B, or the one-assignment phases p then q (q = -1: none): LIN, G, LAMBDA,
 * LS0, DLAMBDA. */
int ncp_cuda_grid_rows(struct CUstream_st *st, pl_ncp_cuda_phase p, int q,
                       const pl_ncp_cuda_rows *R, int mcap, const pl_ncp_cuda_vecs *V,
                       const pl_ncp_cuda_params *P);
/* C. */
int ncp_cuda_grid_c(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                    const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P);
/* CR's D and E_1 (first) or F_t and E_t+1 (last: as for phase E). */
int ncp_cuda_cr_grid(struct CUstream_st *st, int first, int last, const pl_ncp_cuda_rows *R,
                     int mcap, const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P);
/* UPDATE (with or without the line search, as P says). */
int ncp_cuda_grid_update(struct CUstream_st *st, const pl_ncp_cuda_rows *R, int mcap,
                         const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P);

/* A few rows' whole constrained iteration in one launch (W explicit, the
 * dense correction's U made, R->m <= NCP_CUDA_WARP_MAX_ROWS rows): the
 * row values as ncp_cuda_delta2 (jacobian: delta at q, delta_free at
 * q_free) or ncp_cuda_delta (delta_free at q_free), the update as
 * ncp_cuda_update_fused with warp = 2, then the correction as
 * ncp_cuda_correct_dense (ncp_cuda_correct.h) into q_next: the same values
 * as those three queued in turn, bitwise, less two launches (each part's
 * device code is theirs).  More rows are correct too (the block's update),
 * though the host does not choose it then. */
int ncp_cuda_iterate_few(struct CUstream_st *st, const pl_ncp_cuda_rows *R,
                         const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P, const double *W,
                         int jacobian, const double *q_free, const double *q, int nfree,
                         double h2, const double *U, double *q_next);

#ifdef __cplusplus
}
#endif
#endif
