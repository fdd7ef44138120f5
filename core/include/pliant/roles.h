/* roles.h - the role interfaces (versioned tables of function pointers).
 *
 * Like sqlite3_module, each table starts with a version so it can grow
 * without breaking plugins built against an older header: a caller checks
 * `ops->version >= N` before using a member added in version N.  NULL
 * members mean "not supported".  Arrays cross as pl_buffer descriptors
 * (host or device, float64 or float32), so the CUDA backend implements the
 * same roles.  Positions, velocities and right-hand sides are n x 3
 * row-major blocks over the vertices of the global system.
 *
 * Members called during a time step take the component const: a step reads
 * the model and writes only the pl_data it is given (slots, and the
 * component's workspace for scratch and per-step results: model.h).  The
 * device service and exporters are the exceptions: a device is a resource
 * (memory, a stream) shared by every data, and exporters write files for
 * the simulation's own data after its steps. */
#ifndef PLIANT_ROLES_H
#define PLIANT_ROLES_H

#include "buffer.h"
#include "component.h"
#include "draw.h"
#include "mesh.h"
#include "model.h"
#include "rows.h"
#include "sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- pl_state: a block of DOFs (MechanicalObject) ----------------------- */
#define PL_STATE_OPS_VERSION 1
typedef struct pl_state_ops {
    int version;
    /* number of vertices */
    int (*count)(const pl_component *c);
    /* current positions / velocities in d (n x 3) [m], [m/s] */
    pl_buffer (*positions)(const pl_component *c, const pl_data *d);
    pl_buffer (*velocities)(const pl_component *c, const pl_data *d);
    /* rest positions (model, n x 3) [m] */
    pl_buffer (*rest_positions)(const pl_component *c);
    /* first vertex of this state in the global system, -1 before assignment */
    int (*offset)(const pl_component *c);
    /* called by the animation loop when it numbers the global system */
    void (*set_offset)(pl_component *c, int offset);
    /* constraint forces on the vertices from the last step, H^T lambda (n x 3)
     * [N]: contact, friction and cable forces (zero without constraints) */
    pl_buffer (*constraint_forces)(const pl_component *c, const pl_data *d);
} pl_state_ops;

/* ---- pl_mass: lumped masses of a state ---------------------------------- */
#define PL_MASS_OPS_VERSION 1
typedef struct pl_mass_ops {
    int version;
    /* the state it weighs */
    pl_component *(*state)(const pl_component *c);
    /* m[0..n-1] += lumped vertex masses [kg] (n = state count) */
    int (*add_vertex_masses)(const pl_component *c, double *m, int n, pl_error *err);
} pl_mass_ops;

/* ---- pl_topology: something that provides a mesh (loaders, generators) -- */
#define PL_TOPOLOGY_OPS_VERSION 1
typedef struct pl_topology_ops {
    int version;
    const pl_mesh *(*mesh)(const pl_component *c);
} pl_topology_ops;

/* ---- pl_prescribed: DOFs whose positions are given, not solved ---------- */
#define PL_PRESCRIBED_OPS_VERSION 1
typedef struct pl_prescribed_ops {
    int version;
    pl_component *(*state)(const pl_component *c);
    /* local vertex indices (in its state); returns the count */
    int (*indices)(const pl_component *c, const int **idx);
    /* positions of those vertices at time t (count x 3) [m] */
    int (*positions_at)(const pl_component *c, const pl_data *d, double t, double *out,
                        pl_error *err);
} pl_prescribed_ops;

/* ---- pl_local_term: a projective term w ||G q - p||^2 (elements, targets) */
#define PL_LOCAL_TERM_OPS_VERSION 2 /* 2: accepts */
#if PL_ABI_TARGET_MINOR >= 4 /* since 5.4; older terms read it as psd != 0 */
/* add_hessian's psd argument: the stiffness without the rotation's derivative */
#define PL_HESSIAN_FIXED_ROTATION 2
#endif

typedef struct pl_local_term_ops {
    int version;
    /* the state its vertices belong to */
    pl_component *(*state)(const pl_component *c);
    /* adds h2 * w G^T G to the scalar n x n system (global vertex numbering,
     * this term's vertices start at `offset`); called once per factorisation */
    int (*add_matrix)(pl_component *c, int offset, double h2, pl_triplets *A, pl_error *err);
    /* local step: reads q (global n x 3), projects every element in parallel,
     * updates its duals in d, and adds h2 * w G^T (p - u) to rhs (n x 3).
     * Deterministic: element results are gathered in a fixed order. */
    int (*project)(const pl_component *c, pl_data *d, int offset, double h2, const pl_buffer *q,
                   pl_buffer *rhs, pl_error *err);
    /* elastic energy psi(q) [J] at q (global n x 3) */
    double (*energy)(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q);
    /* optional (Newton reference): grad += d psi / dq (n x 3) */
    int (*add_gradient)(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                        pl_buffer *grad, pl_error *err);
    /* optional (Newton reference): H += d2 psi / dq2 over 3n x 3n DOFs (index 3*v+k),
     * each element block projected to positive semi-definite when psd != 0;
     * psd == PL_HESSIAN_FIXED_ROTATION: terms with a per-element rotation
     * (corotational, ARAP) may instead hold it fixed (SOFA's R K0 R^T, PSD),
     * others treat it as 1 */
    int (*add_hessian)(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                       int psd, pl_triplets *H, pl_error *err);
    /* optional: the term changes A when this returns non-zero (refactor) */
    int (*matrix_changed)(const pl_component *c);
    /* version 2, optional: non-zero when project() takes q and rhs in `where`
     * with element type `prec` (NULL: host float64 only).  Asked with
     * prec = PL_F64 | PL_ACCEPTS_GRADIENT: whether add_gradient takes q and
     * grad there (terms written before this question compare prec with
     * PL_F64 and answer 0) */
    int (*accepts)(const pl_component *c, pl_location where, pl_precision prec);
} pl_local_term_ops;

/* Or'ed into accepts()' prec: the question is about add_gradient (a device
 * force residual, LocalGlobalSolver forceTolerance), not project(). */
#define PL_ACCEPTS_GRADIENT 0x100

/* ---- pl_system: what the animation loop shares with solvers -------------- */
typedef struct pl_system {
    int nverts;               /* vertices of all states */
    int nfree;                /* unknowns: vertices not prescribed */
    const int *free_index;    /* per global vertex: index among unknowns, -1 if prescribed */
    const int *free_vertex;   /* per unknown: its global vertex */
    double h;                 /* time step [s] */
    pl_component *global_solver;
    const double *mass;       /* per global vertex: the inertia term's lumped mass [kg]
                               * (h m under LocalGlobalSolver firstOrder: W's scale) */
} pl_system;

/* ---- pl_global_solver: A^-1 for the constant system ---------------------- */
#define PL_GLOBAL_SOLVER_OPS_VERSION 4 /* 2: accepts; 3: delassus_device; 4: solve_from, approximate */
typedef struct pl_global_solver_ops {
    int version;
    /* factors the scalar SPD matrix A (n x n over the unknowns, both triangles
     * or the lower one given); logs sizes and times into timers */
    int (*factor)(pl_component *c, const pl_csc *A, struct pl_timers *timers, pl_error *err);
    /* x = A^-1 b on an n x k row-major block; x may equal b.  Like the
     * members below, called during steps: the factor is only read (scratch
     * the solver needs within one call may be its own, overwritten by every
     * call: steps of several data interleave, they do not run concurrently) */
    int (*solve)(const pl_component *c, const pl_buffer *b, pl_buffer *x, pl_error *err);
    /* Y = S P H^T for scalar rows H (m x n, CSR over the unknowns): W = Y^T Y
     * is then H A^-1 H^T.  Y is returned as CSC (n x m) in the solver's own
     * (permuted) row space, owned by the caller. */
    int (*apply_inverse_to_rows)(const pl_component *c, const pl_csr *H, pl_csc *Y, pl_error *err);
    /* diag[i] = [A^-1]_ii (column norms of S), n values */
    int (*inverse_diagonal)(const pl_component *c, double *diag, pl_error *err);
    /* number of unknowns factored (0 before factor) */
    int (*size)(const pl_component *c);
    /* version 2, optional: non-zero when solve() takes n x 3 blocks in `where`
     * with element type `prec` (NULL: host float64 only) */
    int (*accepts)(const pl_component *c, pl_location where, pl_precision prec);
    /* version 3, optional (NULL: not on this solver's device): W = H A^-1 H^T
     * (m x m, float64, dense, symmetric) built on the device into the device
     * array W (queued on the solver's stream), for scalar rows H as in
     * apply_inverse_to_rows with 3m rows (coordinate k of row j is row
     * k m + j); its diagonal into the host array diag (returns when it is
     * written).  PL_EINPUT when the solver is not on a device.  W NULL:
     * the diagonal alone (a matrix-free W's scaling); an entry the solver
     * cannot make there is NaN, for the caller to make otherwise.  m = 0
     * (H, W and diag NULL) only prepares: the one-time setup of the first
     * call (library handles, kernels loaded on first use) done ahead, so that
     * the step of the first contact carries none of it. */
    int (*delassus_device)(const pl_component *c, const pl_csr *H, int m, double *W, double *diag,
                           pl_error *err);
    /* version 4, optional (NULL: callers use solve): the global step of an
     * iterative solver, from the current iterate.  On entry x holds the guess
     * (the iterate q^k over the unknowns, n x k), on return the new iterate;
     * `iteration` is k, 0 on the first call of a time step (an acceleration
     * restarts there).  b and x are distinct host float64 blocks.  What the
     * solver carries from one iteration to the next (an acceleration's
     * previous iterate) may be its own: several data's steps interleave a
     * whole step at a time, and iteration 0 starts it again. */
    int (*solve_from)(pl_component *c, const pl_buffer *b, pl_buffer *x, int iteration,
                      pl_error *err);
    /* version 4, optional (NULL: exact): non-zero when the solver only
     * approximates A^-1 b (JacobiSolver: one sweep per call).  Constraint rows
     * need W = H A^-1 H^T: LocalGlobalSolver refuses such a solver in a scene
     * with constraint components. */
    int (*approximate)(const pl_component *c);
} pl_global_solver_ops;

/* ---- pl_constraint: emits rows of H once per step ------------------------ */
#define PL_CONSTRAINT_OPS_VERSION 1
typedef struct pl_constraint_ops {
    int version;
    /* appends this step's rows; q = positions at the start of the step (n x 3) */
    int (*build_rows)(const pl_component *c, pl_ctx *ctx, const pl_system *sys, const pl_buffer *q,
                      pl_rows *rows, pl_error *err);
    /* receives the step's multipliers of its rows (first .. first+count-1) [N] */
    void (*accept_multipliers)(const pl_component *c, pl_data *d, const pl_rows *rows,
                               const double *lambda, int first, int count);
} pl_constraint_ops;

/* ---- pl_contact_solver: the constrained global step (Algorithm 4) -------- */
#define PL_CONTACT_SOLVER_OPS_VERSION 3 /* 2: multipliers of a data; 3: graph_epoch */
typedef struct pl_contact_solver_ops {
    int version;
    /* once per step: rows are final; builds W (explicit or matrix-free) and
     * the complementarity scaling; warm-starts lambda.  q_t: positions at the
     * start of the step. */
    int (*begin)(const pl_component *c, pl_ctx *ctx, const pl_system *sys, const pl_rows *rows,
                 const pl_buffer *q_t, pl_error *err);
    /* one local-global iteration's constraint part: from q^k (all vertices,
     * n x 3) and the elastic right-hand side b^k over the unknowns (nfree x 3,
     * prescribed contributions -A_fp q_p already in), updates lambda and
     * writes the unknowns q^{k+1} = A^-1 (b^k + h^2 J^T lambda) (nfree x 3);
     * rows on prescribed vertices contribute to H q but get no correction */
    int (*iterate)(const pl_component *c, pl_ctx *ctx, const pl_system *sys, const pl_buffer *q_k,
                   const pl_buffer *b, pl_buffer *q_next, pl_error *err);
    /* the multipliers of the last iteration of d's step (one per row) [N],
     * kept in d (its workspace) */
    const double *(*multipliers)(const pl_component *c, pl_data *d, int *count);
    /* version 3, optional (NULL: a graph holding iterate() on device
     * buffers is good for one step only): a number that changes whenever a
     * graph captured around iterate() on device buffers in an earlier step
     * of d would no longer replay this step's rows; valid after the step's
     * first iterate().  An animation loop keeps its graph while it stays. */
    unsigned long (*graph_epoch)(const pl_component *c, pl_data *d);
} pl_contact_solver_ops;

/* ---- pl_collision_model: geometry that collides -------------------------- */
typedef struct pl_collision_geometry {
    int nverts;
    const double *x;          /* nverts x 3 current positions [m] */
    const double *v;          /* nverts x 3 velocities [m/s] (NULL = static) */
    const int *map_vertex;    /* nverts x 4 global vertices each point follows (-1 unused) */
    const double *map_weight; /* nverts x 4 barycentric weights */
    int ntris;
    const int *tris;          /* ntris x 3 into x */
    int nedges;
    const int *edges;         /* nedges x 2 into x */
    int is_obstacle;          /* no DOFs: moves by prescription only */
    double mu;                /* friction coefficient */
    unsigned groups;          /* collision groups, bit k - 1 for group k (1..32): two models
                                 sharing a group never collide (0: none) */
} pl_collision_geometry;

#define PL_COLLISION_MODEL_OPS_VERSION 1
typedef struct pl_collision_model_ops {
    int version;
    /* the geometry at the positions q (global n x 3); the arrays it points to
     * live in ctx->data (the model's own, or the component's workspace) */
    int (*update)(const pl_component *c, pl_ctx *ctx, const pl_buffer *q,
                  pl_collision_geometry *out, pl_error *err);
} pl_collision_model_ops;

/* ---- pl_exporter: writes frames ------------------------------------------ */
typedef struct pl_export_info {
    const char *out_dir;      /* directory for outputs (created if missing); NULL = as the scene says */
    int every;                /* export every k-th step (0 = the exporter's own setting) */
    long step;                /* steps taken so far */
    double time;              /* simulated time [s] */
} pl_export_info;

#define PL_EXPORTER_OPS_VERSION 1
typedef struct pl_exporter_ops {
    int version;
    /* called after loading (step 0) and after every step; decides itself
     * whether this step is one to write */
    int (*write)(pl_component *c, pl_ctx *ctx, const pl_export_info *info, pl_error *err);
    /* called once at the end of a run: close series files (.pvd) */
    int (*finish)(pl_component *c, pl_ctx *ctx, const pl_export_info *info, pl_error *err);
    /* the main file written (for "output went to ..."), or NULL */
    const char *(*output_path)(const pl_component *c);
} pl_exporter_ops;

/* ---- pl_controller: drives fields over time ------------------------------ */
#define PL_CONTROLLER_OPS_VERSION 1
typedef struct pl_controller_ops {
    int version;
    /* sets the driven values for time t (start of the step being taken):
     * input fields of ctx->data (pl_input_set, input.h) */
    int (*apply)(const pl_component *c, pl_ctx *ctx, double t, pl_error *err);
} pl_controller_ops;

/* ---- pl_animation_loop: advances the state by one step ------------------- */
#define PL_ANIMATION_LOOP_OPS_VERSION 1
typedef struct pl_animation_loop_ops {
    int version;
    int (*step)(const pl_component *c, pl_ctx *ctx, double dt, pl_error *err);
} pl_animation_loop_ops;

/* ---- pl_device: a compute device, its memory and its stream -------------- */
/* Device memory is addressed by plain pointers (inside pl_buffer descriptors
 * with location PL_DEVICE).  Every member queues its work on the device's
 * current stream (its one main stream unless a branch is open: version 5),
 * in call order, and returns without waiting unless it says so; other
 * components queue their own kernels on stream(), asked for at each call.
 * The vector kernels work on float64 n x 3 row-major blocks (a row = a
 * vertex's xyz). */
#if PL_ABI_TARGET_MINOR >= 10
#include "device_loop.h"
/* 2: residual_max; 3: loop, gather_sub_csr; 4: scale_rows_zero, residual_max_csr;
 * 5: branch; 6: step_begin, step_end */
#define PL_DEVICE_OPS_VERSION 6
#elif PL_ABI_TARGET_MINOR >= 8
#include "device_loop.h"
/* 2: residual_max; 3: loop, gather_sub_csr; 4: scale_rows_zero, residual_max_csr;
 * 5: branch */
#define PL_DEVICE_OPS_VERSION 5
#elif PL_ABI_TARGET_MINOR >= 6
#include "device_loop.h"
/* 2: residual_max; 3: loop, gather_sub_csr; 4: scale_rows_zero, residual_max_csr */
#define PL_DEVICE_OPS_VERSION 4
#elif PL_ABI_TARGET_MINOR >= 5
#include "device_loop.h"
#define PL_DEVICE_OPS_VERSION 3 /* 2: residual_max; 3: loop, gather_sub_csr */
#elif PL_ABI_TARGET_MINOR >= 4
#define PL_DEVICE_OPS_VERSION 2 /* 2: residual_max */
#else
#define PL_DEVICE_OPS_VERSION 1
#endif
enum {
    PL_DEVICE_GRAPHS = 1, /* callers should capture repeated work (an iteration) as a graph */
    PL_DEVICE_PROFILE = 2, /* callers should sync after each phase so host timers see device time */
    PL_DEVICE_LOOPS = 8    /* since ABI 5.5: loop (version 3) keeps a whole loop on the device */
};
#if PL_ABI_TARGET_MINOR >= 1
/* Since ABI 5.1 (4.1 before 5.0): the service has no device behind it (no GPU answers, or
 * a build without CUDA): callers stay on the host, as without a service
 * (pl_util_device skips it). */
#define PL_DEVICE_ABSENT 4
#endif
typedef struct pl_device_ops {
    int version;
    /* PL_DEVICE_* flags the scene asked for */
    int (*flags)(const pl_component *c);
    /* the native stream (cudaStream_t for CUDA) */
    void *(*stream)(const pl_component *c);
    /* `bytes` of device memory (NULL with err set on failure) */
    void *(*alloc)(pl_component *c, size_t bytes, pl_error *err);
    /* frees device memory from alloc (NULL: nothing) */
    void (*free)(pl_component *c, void *p);
    /* sets `bytes` bytes at device address p to zero */
    int (*zero)(pl_component *c, void *p, size_t bytes, pl_error *err);
    /* copies `bytes` bytes between host and device memory (returns after the
     * copy when `to` is PL_HOST) */
    int (*copy)(pl_component *c, void *dst, pl_location to, const void *src, pl_location from,
                size_t bytes, pl_error *err);
    /* page-locks host memory until unpin (faster, asynchronous copies) */
    int (*pin)(pl_component *c, void *host, size_t bytes, pl_error *err);
    /* undoes pin */
    void (*unpin)(pl_component *c, void *host);
    /* waits for all queued work; reports errors of earlier asynchronous work */
    int (*sync)(pl_component *c, pl_error *err);
    /* y[i] = s[i] x[i] for rows i < n (rhs = M sn) */
    int (*scale_rows)(pl_component *c, int n, const double *s, const double *x, double *y,
                      pl_error *err);
    /* y[f] = x[map[f]] for rows f < m (all vertices -> unknowns) */
    int (*gather_rows)(pl_component *c, int m, const int *map, const double *x, double *y,
                       pl_error *err);
    /* x[map[f]] = y[f] for rows f < m; *change (device) = max(*change, the
     * largest |change| of a coordinate), +inf if a value is not finite */
    int (*scatter_rows)(pl_component *c, int m, const int *map, const double *y, double *x,
                        double *change, pl_error *err);
    /* y -= A x, A a CSR whose p, j, x are device arrays (one thread per row: deterministic) */
    int (*sub_csr)(pl_component *c, const pl_csr *A, const double *x, double *y, pl_error *err);
    /* starts recording the work queued next on the stream (recorded, not run) */
    int (*capture_begin)(pl_component *c, pl_error *err);
    /* stops recording: *graph = the recorded work, ready to replay */
    int (*capture_end)(pl_component *c, void **graph, pl_error *err);
    /* queues the recorded work again (same buffers, same scalars) */
    int (*replay)(pl_component *c, void *graph, pl_error *err);
    /* frees a graph from capture_end (NULL: nothing) */
    void (*graph_free)(pl_component *c, void *graph);
#if PL_ABI_TARGET_MINOR >= 4
    /* version 2: *out (device) = max(*out, the largest |r_f| over rows f < m)
     * with r_f = s[v] (x[v] - y[v]) / h2 + g[v] + t[f] / h2, v = map[f] (t
     * NULL: no t term), +inf if one is not finite: a force residual
     * (force_residual.h), evaluated in that order */
    int (*residual_max)(pl_component *c, int m, const int *map, const double *s, double h2,
                        const double *x, const double *y, const double *g, const double *t,
                        double *out, pl_error *err);
#endif
#if PL_ABI_TARGET_MINOR >= 5
    /* version 3, optional (NULL, or flags() without PL_DEVICE_LOOPS: not
     * here; callers then queue or replay one iteration at a time).  Queues
     *     while (pl_device_loop_rule(state, change, residual)) body(arg);
     * (device_loop.h) on the stream without a host wait: the rule runs first,
     * for the iteration queued just before the call.  state (a
     * pl_device_loop), change and residual are device addresses; the rule
     * reads them on the device.  body queues one iteration's work on the
     * stream (kernels, device-to-device copies and memsets; no host copy, no
     * sync).  *graph caches the loop: when NULL, body is called once and
     * recorded with the rule into a new graph left in *graph (freed by
     * graph_free); when not, that graph is replayed and body is not called
     * (the same buffers and scalars: what changes from step to step lives in
     * device memory, such as *state).  A device that records nothing may
     * leave *graph NULL and call body once per iteration.  The caller reads
     * *state back afterwards (done, converged, nonfinite, residual). */
    int (*loop)(pl_component *c, int (*body)(void *arg, pl_error *err), void *arg,
                pl_device_loop *state, const double *change, const double *residual,
                void **graph, pl_error *err);
    /* version 3: y[f] = x[map[f]] - (A q)[f] for rows f < m (A: m rows, a CSR
     * of device arrays, NULL: none), in one launch: gather_rows then sub_csr,
     * with their arithmetic in their order (bitwise the same) */
    int (*gather_sub_csr)(pl_component *c, int m, const int *map, const double *x,
                          const pl_csr *A, const double *q, double *y, pl_error *err);
#endif
#if PL_ABI_TARGET_MINOR >= 6
    /* version 4, optional (NULL: callers use the version 1-3 members).
     * scale_rows and zero (`bytes` bytes at z) in one launch: y[i] = s[i]
     * x[i] for rows i < n, as scale_rows */
    int (*scale_rows_zero)(pl_component *c, int n, const double *s, const double *x, double *y,
                           void *z, size_t bytes, pl_error *err);
    /* version 4, optional: residual_max whose t term is gather_sub_csr's
     * y, in one launch: *out = max(*out, the largest |r_f| over f < m),
     * r_f = s[v] (x[v] - y[v]) / h2 + g[v] + t_f / h2 with v = map[f] and
     * t_f = b[v] - (A x)[f] (A: m rows in global columns, a CSR of device
     * arrays), each in its member's order (bitwise the same values) */
    int (*residual_max_csr)(pl_component *c, int m, const int *map, const double *s, double h2,
                            const double *x, const double *y, const double *g, const double *b,
                            const pl_csr *A, double *out, pl_error *err);
#endif
#if PL_ABI_TARGET_MINOR >= 8
    /* version 5, optional (NULL: one stream).  branch(c, k), k = 1 ..
     * PL_DEVICE_BRANCHES: the work queued next (on stream(), which now
     * returns branch k's stream, and by the members above) starts after all
     * work queued before on the main stream, and may run beside the other
     * branches' work.  branch(c, 0): back on the main stream, whose next work
     * waits for the work of every branch opened since the last branch(c, 0).
     * Inside a capture (capture_begin, loop) they become the graph's
     * parallel edges.  The caller gives branches work on disjoint memory
     * (the local terms of different states: local_global_device.c) and
     * closes them with branch(c, 0) before it captures, replays, copies to
     * the host or waits. */
    int (*branch)(pl_component *c, int k, pl_error *err);
#endif
#if PL_ABI_TARGET_MINOR >= 10
    /* version 6, optional (NULL: the caller does both on the host): a time
     * step's start and end on the device, for a step whose vectors the host
     * needs for nothing else (components/solver/local_global_device_state.c).
     * step_begin, for i < n3 (x, v: the states' positions and velocities,
     * g: gravity, all n x 3):
     *     q_t[i] = x[i];
     *     sn[i] = first_order ? x[i] + h g[i] : x[i] + h v[i] + h^2 g[i];
     *     q[i] = guess ? x[i] + hv v[i] : sn[i];
     * with pl_dynamics_begin's operations in its order and no contraction
     * into fused multiply-adds: the host's values, bitwise. */
    int (*step_begin)(pl_component *c, int n3, double h, int first_order, int guess, double hv,
                      const double *x, const double *v, const double *g, double *q_t,
                      double *sn, double *q, pl_error *err);
    /* version 6, optional: for i < n3, v[i] = scale (q[i] - q_t[i]) / h and
     * x[i] = q[i] (pl_dynamics_scatter's operations, bitwise); *bad (a device
     * int) = 1 where a q[i] is not finite, else left as it is. */
    int (*step_end)(pl_component *c, int n3, double h, double scale, const double *q,
                    const double *q_t, double *x, double *v, int *bad, pl_error *err);
#endif
} pl_device_ops;
#if PL_ABI_TARGET_MINOR >= 8
#define PL_DEVICE_BRANCHES 8
#endif

#if PL_ABI_TARGET_MINOR >= 2
/* ---- pl_visual: what a component shows (viewer, exporters); ABI 5.2 ---- */
#define PL_VISUAL_OPS_VERSION 1
typedef struct pl_visual_ops {
    int version;
    /* adds what c shows in state d (at time d->time: obstacles at their pose
     * then, cables through their current points, the last step's contacts
     * with their forces) as parts of dw (draw.h) */
    int (*draw)(const pl_component *c, const pl_data *d, pl_drawing *dw, pl_error *err);
} pl_visual_ops;

/* ---- pl_event: input from an interactive program; ABI 5.2 --------------- */
typedef enum pl_event_kind {
    PL_EVENT_KEY_PRESSED = 0,  /* SOFA's KeypressedEvent */
    PL_EVENT_KEY_RELEASED = 1  /* SOFA's KeyreleasedEvent */
} pl_event_kind;

/* Keys: a printable character as itself ('+', 'a'), or one of these. */
enum {
    PL_KEY_UP = 0x101,
    PL_KEY_DOWN,
    PL_KEY_LEFT,
    PL_KEY_RIGHT,
    PL_KEY_PAGE_UP,
    PL_KEY_PAGE_DOWN
};

typedef struct pl_event {
    pl_event_kind kind;
    int key;
} pl_event;

#define PL_EVENT_OPS_VERSION 1
typedef struct pl_event_ops {
    int version;
    /* handles an event between two steps; ctx->data is the state shown, the
     * only thing it may change (its slots, input fields: input.h), as in a
     * step.  Sets *used when the event meant something to c (others still
     * get it). */
    int (*handle)(const pl_component *c, pl_ctx *ctx, const pl_event *ev, int *used,
                  pl_error *err);
} pl_event_ops;
#endif

#ifdef __cplusplus
}
#endif
#endif
