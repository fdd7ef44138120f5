/* contact_device.h - the device path of NonSmoothNewtonContactSolver (CUDA
 * builds; contact_device.c, kernels in ncp_cuda.h).
 *
 * begin() stays on the CPU (rows, W explicit or the matrix-free diagonal,
 * the scaling, the warm start: the "Schur" phase).  The first iterate() of
 * the step on device buffers uploads all of it at once (one copy of a
 * packed, page-locked staging buffer, plus W when explicit); every
 * iterate() then only queues work on the device's stream: q_free = A^-1 b,
 * the row values, the constraint update (ncp_cuda_step.cu, W products
 * dense or as scatter / device solve / gather) and the correction
 * q^{k+1} = q_free + h^2 A^-1 H^T (S lambda) (for few rows one product with
 * U = A^-1 H^T, made at the upload: ncp_cuda_correct.h; with the fused update of few
 * rows too, all three in one launch: ncp_cuda_iterate_few), and asynchronous copies of
 * lambda into page-locked host memory.  Nothing waits for the device, so
 * the animation loop can capture an iteration as a CUDA graph, and keep it
 * for later steps: the kernels read the rows from the device descriptor
 * the upload put first, their grids and copies are sized by a capacity
 * of rows, and ncpc_device_epoch says when a graph went stale; the loop's
 * copy of q at the end of the step is the one synchronisation, after which
 * the multipliers are on the host.  Internal to the plugin. */
#ifndef PLIANT_NCP_CONTACT_DEVICE_H
#define PLIANT_NCP_CONTACT_DEVICE_H

#include "contact.h"
#include "pliant/timer.h"

typedef struct pl_ncpc_device pl_ncpc_device;

/* What the solver's step hands the device path (views, owned by it). */
typedef struct pl_ncpc_device_step {
    const pl_ncpc_rows *rows;
    const pl_ncpc_delassus *D;  /* W (explicit) or nothing (matrix-free) */
    const pl_ncp_work *work;    /* the contact table */
    const double *r;            /* m: complementarity scaling */
    const double *lambda;       /* m: warm start */
    const double *lambda_all;   /* nall */
    int nall;
    double h;
    int fn, cr_iterations, full_force, project, line_search, record, cr_jacobi;
    double cr_tolerance, damping, fb_eps;
    /* timer ids (used with the device's profile flag) */
    int t_global, t_assembly, t_solve, t_corr, t_cglobal;
    /* stickStart, at the step's first iterate only (NULL otherwise): given
     * the row values at q_free (m, host), it updates the host multipliers
     * `lambda` (this struct's) and returns how many rows it set (>= 0), or
     * minus an error code; they then go up before the constraint update. */
    int (*stick)(void *user, const double *delta_free, pl_error *err);
    void *stick_user;
} pl_ncpc_device_step;

/* The device path of contact solver c, on the device service found in its
 * node or above; NULL with err set when there is none. */
pl_ncpc_device *ncpc_device_create(const pl_component *c, pl_error *err);
void ncpc_device_destroy(pl_ncpc_device *g);
/* The device array for an explicit W of m rows (grown as needed), for
 * the global solver to build W into; NULL with err set on failure. */
double *ncpc_device_w(pl_ncpc_device *g, int m, pl_error *err);
/* A new step began (its data goes up at the next iterate). */
void ncpc_device_begin(pl_ncpc_device *g);
/* One iteration on device buffers (q_k: n x 3; b, q_next: nfree x 3). */
int ncpc_device_iterate(pl_ncpc_device *g, const pl_ncpc_device_step *st, pl_ctx *ctx,
                           const pl_system *sys, const pl_buffer *q_k, const pl_buffer *b,
                           pl_buffer *q_next, pl_error *err);
/* Whether an iterate ran on the device since the last begin. */
int ncpc_device_ran(const pl_ncpc_device *g);
/* The multipliers of the step's last iteration (m and nall values, host),
 * copied from the device at the first call after the iterations (a wait);
 * NULL with err set when the device failed. */
const double *ncpc_device_lambda(pl_ncpc_device *g, pl_error *err);
const double *ncpc_device_lambda_all(pl_ncpc_device *g, pl_error *err);
/* A number that changes whenever a CUDA graph captured around iterate()
 * in an earlier step would no longer fit this step (device buffers moved,
 * capacities grew, rows appeared or vanished, parameters changed); the
 * step's data went up with its first iterate.  0 for NULL. */
unsigned long ncpc_device_epoch(const pl_ncpc_device *g);
/* End of the step: device errors of the step (CR or residual not finite)
 * and, with record, the per-iteration series pushed into timers. */
int ncpc_device_end_step(pl_ncpc_device *g, pl_timers *timers, int record, pl_error *err);

#endif
