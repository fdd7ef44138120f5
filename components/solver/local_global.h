/* local_global.h - the LocalGlobalSolver's model and per-data workspace,
 * shared by its CPU path (local_global_solver.c) and its device path
 * (local_global_device.c).  Internal to libpliant's solver folder. */
#ifndef PLIANT_LOCAL_GLOBAL_H
#define PLIANT_LOCAL_GLOBAL_H

#include "dynamics.h"
#include "force_residual.h"

/* The model's device copies (built at reinit through the scene's device
 * service, pl_device_ops); dev == NULL: the loop runs on the CPU. */
typedef struct lg_device {
    pl_component *dev;
    const pl_device_ops *ops;
    double *mass;              /* n */
    int *free_vertex;          /* nfree */
    pl_csr A_fp;               /* rows of A_fp (nfree x n), device arrays */
    int fp_nnz;                /* its entries (0: nothing prescribed) */
    pl_csr A_f;                /* [A_ff A_fp] (nfree x n): forceTolerance only */
    int *term_branch;          /* nterms (host): the device branch of each local term's
                                  project (its state's), NULL: all on the main stream */
    int nbranch;               /* the branches used (states; 0 without term_branch) */
    /* the step's start and end on the device (local_global_device_state.c) */
    int on_device;             /* the model allows the states to go up and down, with
                                  q_t, sn and q on the device only */
    double *gravity;           /* n x 3 */
    int npres;                 /* prescribed vertices, each once (the last component's) */
    int *pres_host, *pres_map; /* npres: their vertices, on the host and on the device */
} lg_device;

/* One data's device vectors (float64, n x 3 unless said) and graph, in the
 * workspace; made through the device they name. */
typedef struct lg_device_ws {
    pl_component *dev;         /* NULL: none made */
    const pl_device_ops *ops;
    int flags;                 /* PL_DEVICE_GRAPHS / PL_DEVICE_PROFILE */
    double *q, *sn, *rhs;
    double *b_free, *q_free;   /* nfree x 3 */
    double *change;            /* 1: largest position change of an iteration; the first
                                  of `scalars` doubles (residual, grad follow) */
    size_t scalars;
    pl_device_loop *loop;      /* 1: the device loop's state (device ops version 3) */
    double *grad, *t, *residual; /* forceTolerance: gradient (n x 3), rhs_f - A_f* q
                                  * (nfree x 3), the force residual (1); grad and
                                  * residual inside change's block */
    void *graph[2];            /* one iteration captured (PL_DEVICE_GRAPHS), or the device
                                  loop over it (PL_DEVICE_LOOPS): [0] for steps
                                  without rows, [1] with the contact iterate */
    unsigned char graph_loop[2]; /* graph[k] is a device loop (else one iteration) */
    unsigned long graph_epoch; /* the contact solver's graph_epoch at graph[1]'s capture */
    long captures;             /* graphs captured for this data (stat "device graph captures") */
    int nrows;                 /* constraint rows of the step being taken */
    double *pinned_q, *pinned_sn; /* the host vectors page-locked (NULL: not) */
    int prepared;              /* the global solver's device W path was prepared */
    /* on_device (local_global_device_state.c): the states' positions and
     * velocities (n x 3), q_t, the prescribed positions (npres x 3), a
     * non-finite flag (device int); the states' slots page-locked */
    double *x, *v, *q_t, *pres;
    int *bad;
    void **slot_tried;         /* 2 nstates + 1: the states' slots met, up to a NULL */
    unsigned char *slot_pinned; /* for each of them: 1 if page-locked */
} lg_device_ws;

/* The workspace (pl_data_workspace): what a step of one data writes. */
typedef struct lg_ws {
    int ready;                 /* w allocated for the model */
    pl_dyn_work w;
    pl_rows rows;              /* the step's constraint rows */
    pl_force_residual res;     /* its scratch (force_residual.c) */
    lg_device_ws gpu;
} lg_ws;

typedef struct local_global_solver {
    pl_component base;
    int iterations;
    double tolerance;
    double force_tolerance;    /* [N]: stop once the force residual is below it (0: not used) */
    int compute_residual;      /* field: 0 auto, 1 on, 2 off */
    int report_residual;       /* the force residual of each step is recorded */
    int initial_guess;         /* 0 prediction sn, 1 inertia q_t + h v_t */
    double damping;
    int first_order;           /* SOFA's firstOrder (dynamics.h) */
    double rayleigh_stiffness; /* rS [s]: damping force -rS L v */
    int compute_energy;
    pl_link solver_link;
    pl_link contact_link;
    int device;                /* 0 cpu, 1 cuda, 2 auto */
    /* model */
    pl_dynamics dyn;
    pl_component *solver;
    pl_component *contact;     /* contact solver, or NULL */
    pl_component **constraints;
    int nconstraints;
    int ready;
    int t_local, t_global, t_assembly, t_residual;
    int t_rows;                /* "Rows": every constraint's build_rows (Detection inside) */
    int t_queue;               /* "Device queue": the host queueing the step's iterations */
    int t_wait;                /* "Device wait": the host blocked on the step's positions */
    lg_device gpu;
} local_global_solver;

/* After the dynamics are set up and A_ff factored: resolves `device`
 * (auto: cuda when a device service is found in this node or above and
 * every part of the loop can run there) and copies the model's arrays to
 * it.  Errors (device="cuda" with a part that cannot run there) are
 * recorded against the solver in ctx. */
int pl_lg_device_setup(local_global_solver *s, pl_ctx *ctx);
/* Frees the model's device copies; call before pl_dynamics_free. */
void pl_lg_device_free(local_global_solver *s);
/* Makes a workspace's device vectors (once per workspace). */
int pl_lg_device_ws_alloc(const local_global_solver *s, lg_ws *ws, pl_error *err);
/* Frees them (and the graph). */
void pl_lg_device_ws_free(lg_ws *ws);
/* One time step with the iterations on the device. */
int pl_lg_device_step(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx, pl_error *err);
/* `bytes` of device memory, unless *rc already holds an error; on failure
 * NULL and the error code in *rc (a chain of allocations checked once). */
void *pl_lg_dalloc(pl_component *dev, const pl_device_ops *ops, size_t bytes, int *rc,
                   pl_error *err);
/* y[f] = x[map[f]] - (A q)[f], f < m (A NULL: none): the service's
 * gather_sub_csr (version 3), else gather_rows and sub_csr. */
int pl_lg_device_gather_sub(const lg_device_ws *g, int m, const int *map, const double *x,
                            const pl_csr *A, const double *q, double *y, pl_error *err);
/* One iteration queued on the device (profile: sync and time each phase). */
int pl_lg_device_iteration(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx,
                           int profile, pl_error *err);
/* local_global_device_loop.c: the graphs kept from earlier steps dropped
 * where they went stale (flags: the device's now); then the step's
 * iterations, as one device loop or one at a time: *done iterations,
 * *residual the last force residual (left as it is without forceTolerance). */
int pl_lg_device_graphs_begin_step(const local_global_solver *s, lg_device_ws *g, int flags,
                                   pl_error *err);
int pl_lg_device_iterate(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx, double scale,
                         int *done, double *residual, pl_error *err);
/* forceTolerance on the device (local_global_device_residual.c): why it
 * cannot run there appended to why (nothing when it can or is 0); the
 * model's A_f* up; its per-data vectors; the residual of the iterate g->q
 * queued into g->residual. */
int pl_lg_csc_rows(const pl_csc *const *M, const int *const *cols, int nm, int nrows, int ncols,
                   pl_csr *R);
void pl_lg_device_residual_refusals(const local_global_solver *s, char *why, size_t size);
int pl_lg_device_residual_setup(local_global_solver *s, pl_error *err);
void pl_lg_device_residual_free(lg_device *g);
int pl_lg_device_residual_ws_alloc(const local_global_solver *s, lg_device_ws *g, pl_error *err);
void pl_lg_device_residual_ws_free(lg_device_ws *g);
int pl_lg_device_residual_queue(const local_global_solver *s, lg_device_ws *g, pl_ctx *ctx,
                                pl_error *err);
/* local_global_device_state.c: a step's start and end on the device, for
 * steps whose vectors the host needs for nothing else (no rows, no host
 * residual, energy, tolerance or Rayleigh damping; device ops version 6).
 * setup at reinit sets gpu.on_device (the model allows it) and uploads the
 * model's part; state_now says whether this step may (run-time fields); ws_alloc
 * and ws_free the data's; begin uploads the states and queues q_t, sn and
 * q (the host has written the prescribed vertices into w->q); end queues
 * the states' new values, copies them into the data (the wait) and fails
 * naming a vertex whose position is not finite. */
int pl_lg_device_state_setup(local_global_solver *s, pl_error *err);
int pl_lg_device_state_now(const local_global_solver *s);
void pl_lg_device_state_free(lg_device *g);
int pl_lg_device_state_ws_alloc(const local_global_solver *s, lg_device_ws *g, pl_error *err);
void pl_lg_device_state_ws_free(lg_device_ws *g);
int pl_lg_device_state_begin(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx,
                             pl_error *err);
int pl_lg_device_state_end(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx, double damping,
                           pl_error *err);
/* The step's constraint rows and the contact solver's begin (host, q_t):
 * the number of rows, or minus an error code.  local_global_solver.c. */
int pl_lg_begin_constraints(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx,
                            pl_error *err);
/* The multipliers to the state (constraint forces) and to their emitters. */
void pl_lg_end_constraints(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx);
/* The force residual [N] at the workspace's iterate with the contact
 * solver's multipliers of this data (cs NULL: none).  local_global_solver.c. */
int pl_lg_residual(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx,
                   const pl_contact_solver_ops *cs, double *out, pl_error *err);
/* Its record in the timings, with the iterations done. */
void pl_lg_record_residual(const local_global_solver *s, pl_ctx *ctx, double residual,
                           int iterations);

#endif
