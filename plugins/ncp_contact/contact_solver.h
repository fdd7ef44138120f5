/* contact_solver.h - the NonSmoothNewtonContactSolver component's struct,
 * shared by contact_solver.c (fields, begin / iterate / multipliers) and
 * contact_solver_step.c (the choice and build of W, statistics, the hand-off
 * to the device path).  Internal to the plugin. */
#ifndef PLIANT_NCP_CONTACT_SOLVER_H
#define PLIANT_NCP_CONTACT_SOLVER_H

#include <float.h>

#include "contact.h"
#include "pliant/timer.h"
#ifdef PLIANT_HAVE_CUDA
#include "contact_device.h"
#endif

typedef struct ncp_contact_solver {
    pl_component base;
    /* fields */
    int ncp;                  /* pl_ncp_function */
    int cr_iterations;
    double cr_tolerance;
    int cr_scaling;           /* 0 jacobi, 1 none */
    int preconditioner;       /* 0 delassus, 1 mass */
    int delassus;             /* 0 auto, 1 explicit, 2 matrix-free */
    double max_explicit_mb;
    double max_explicit_work; /* maxExplicitWork: W's exact build work against a step's matrix-free products */
    int warm_start;
    double damping;
    double fb_eps;
    int record;
    int correction;           /* 0 jacobian (paper), 1 multiplier */
    int project;
    int line_search;
    int device;               /* field: 0 cpu, 1 auto (follow the animation loop) */
    int stick_start;
    /* model */
    int slot;                 /* pl_data slot of the warm-start records */
} ncp_contact_solver;

/* CR's relative tolerance: crTolerance, at least 4 machine epsilons.  A
 * residual at round-off cannot be reduced, and further products only move
 * the solution by round-off: for the cable finger's one row CR's first
 * product leaves |r| ~ 1e-16 |b|, and without the floor it often ran
 * its nine more (the device's update 24.9 instead of 18.2 us on the H100;
 * docs/benchmarks.md, "The local step's Newton in fewer divisions"). */
static inline double ncpc_cr_rtol(const ncp_contact_solver *s)
{
    const double floor_ = 4.0 * DBL_EPSILON;
    return s->cr_tolerance > floor_ ? s->cr_tolerance : floor_;
}

/* Per data (pl_data_workspace): the step being taken, and what the step
 * needs from the model but computes on first use. */
typedef struct ncpc_ws {
    /* [A^-1]_ii of the factor (the workspace is remade when the model is) */
    double *inv_diag;
    int inv_diag_n, inv_diag_ok;
    /* the step */
    int active;               /* begin ran for the step being taken */
    int first_iteration;      /* the next iterate is the step's first */
    int nall, nfree;
    double h;
    pl_ncpc_rows rows;
    pl_ncpc_delassus D;
    pl_ncp_work *work;
    pl_ncpc_key *keys;
    double *r, *diag_mass, *lambda, *dlambda, *scale, *delta, *delta_free, *force, *ls0, *ls1;
    double *q_free, *corr;    /* nfree x 3 */
    double *lambda_all;       /* nall: the multipliers handed back */
    size_t cap_m, cap_f3, cap_all; /* capacities of the arrays above (grow-only) */
    int t_global, t_schur, t_assembly, t_solve, t_corr, t_cglobal;
#ifdef PLIANT_HAVE_CUDA
    pl_ncpc_device *gpu;      /* the device path, made on the first device iterate */
#endif
} ncpc_ws;

enum { W_AUTO = 0, W_EXPLICIT = 1, W_MATRIX_FREE = 2 };

/* W explicit or matrix-free for the step's rows (see the delassus field). */
int ncpc_build_delassus(const ncp_contact_solver *s, ncpc_ws *w, pl_ctx *ctx,
                           const pl_system *sys, pl_error *err);
/* contacts max, constraint rows max, W memory into the timers' statistics. */
void ncpc_statistics(const ncpc_ws *w, pl_timers *t);
/* iterate() on device buffers: contact_device.c in CUDA builds, an error otherwise. */
int ncpc_iterate_device(const ncp_contact_solver *s, ncpc_ws *w, pl_ctx *ctx,
                           const pl_system *sys, const pl_buffer *q_k, const pl_buffer *b,
                           pl_buffer *q_next, pl_error *err);

#endif
