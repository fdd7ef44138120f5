/* dynamics.h - what every implicit-Euler solver of a scene shares: the
 * global numbering of the states below it, lumped masses, gravity,
 * prescribed DOFs (eliminated from the unknowns), the local terms, the
 * constant system A = M + h^2 sum w G^T G split into free and prescribed
 * blocks, and the incremental potential
 *     E(q) = 1/(2 h^2) ||M^1/2 (q - sn)||^2 + sum psi(q),
 *     sn = q_t + h v_t + h^2 g
 * (the paper's eq. "implicit euler") that both the local-global loop and
 * the Newton reference minimise.
 *
 * LocalGlobalSolver's scheme options (pl_dyn_scheme) keep A constant:
 *  - first order (SOFA's firstOrder: M (q - q_t) / h = f(q), no velocity
 *    carried): E(q) = 1/(2h) |q - q_t|_M^2 + psi(q) - f_ext.q; times h^2 that
 *    is the second-order form with the inertia mass h m_i and sn = q_t + h g;
 *  - Rayleigh stiffness damping rS, with the rest matrix L = sum w G^T G for
 *    SOFA's tangent K: the dissipation potential (rS/(2h)) (q - q_t)^T L
 *    (q - q_t); A = M' + (h^2 + h rS) L and the right-hand side gains
 *    h rS L q_t, folded into sn (sn += h rS M'^-1 L q_t), so that the
 *    iterations (CPU and device) are unchanged. */
#ifndef PLIANT_DYNAMICS_H
#define PLIANT_DYNAMICS_H

#include "pliant/pliant.h"

/* The time-stepping scheme (zero: second-order implicit Euler, undamped). */
typedef struct pl_dyn_scheme {
    int first_order;          /* SOFA's firstOrder: no velocity carried */
    double rayleigh_stiffness; /* rS [s]: damping force -rS L v */
} pl_dyn_scheme;

typedef struct pl_dynamics {
    double h;                 /* time step [s] */
    pl_dyn_scheme scheme;
    int n;                    /* vertices of all states */
    int nstates;
    pl_component **states;
    int nterms;
    pl_component **terms;     /* local terms (elements, targets) */
    int *term_offset;         /* first global vertex of each term's state */
    int nprescribed;
    pl_component **prescribed;
    double *mass;             /* n [kg] */
    double *inertia;          /* n: the inertia term's mass, m_i (h m_i first order) */
    pl_csc L;                 /* n x n, sum w G^T G (only with rayleigh_stiffness > 0) */
    double *gravity;          /* n x 3 [m/s^2], from each state's node */
    int nfree;
    int *free_index;          /* n: index among unknowns or -1 */
    int *free_vertex;         /* nfree: global vertex */
    pl_csc A_ff;              /* nfree x nfree, both triangles */
    pl_csc A_fp;              /* nfree x n, only prescribed columns non-empty */
    pl_system sys;
} pl_dynamics;

/* A step's vectors, per pl_data (in the solver's workspace): n x 3 unless
 * said. */
typedef struct pl_dyn_work {
    double *q, *q_t, *v_t, *sn, *rhs, *qp;
    double *b_free, *q_free;  /* nfree x 3 */
} pl_dyn_work;

/* Collects the states, masses, prescribed DOFs and local terms of the
 * subtree of `owner`'s node, numbers the vertices and (if with_matrix)
 * assembles A_ff and A_fp for the scheme (NULL: second order, undamped;
 * only with_matrix honours one).  Errors are recorded against owner in ctx. */
int pl_dynamics_setup(pl_dynamics *d, pl_component *owner, pl_ctx *ctx, double h,
                      int with_matrix, const pl_dyn_scheme *scheme);
void pl_dynamics_free(pl_dynamics *d);

/* Allocates w's vectors for d (zeroed); PL_OK or PL_EINTERNAL. */
int pl_dyn_work_alloc(pl_dyn_work *w, const pl_dynamics *d);
void pl_dyn_work_free(pl_dyn_work *w);

/* q_t, v_t <- the states in data. */
void pl_dynamics_gather(const pl_dynamics *d, pl_dyn_work *w, const pl_data *data);
/* out (n x 3) <- q_t + h v_t + h^2 g (first order: q_t + h g): where the
 * body goes without internal forces, the iterations' natural start. */
void pl_dynamics_motion(const pl_dynamics *d, const pl_dyn_work *w, double *out);
/* sn <- q_t + h v_t + h^2 g (first order: q_t + h g), plus
 * h rS M'^-1 L q_t with Rayleigh stiffness damping. */
void pl_dynamics_predict(const pl_dynamics *d, pl_dyn_work *w);
/* A step's start in one pass over the states: pl_dynamics_gather, then
 * pl_dynamics_predict, then the first iterate q^0 (initialGuess): guess 0
 * the motion, i.e. the prediction sn (the paper) without the damping's term
 * (with Rayleigh stiffness sn also carries h rS M'^-1 L q_t, which is no
 * position: L q_t is not zero at rest), guess 1 q_t + h v_t (first order:
 * q_t), where a supported body at rest already is.  The values are those of
 * the separate passes, bitwise.  One pass instead of four over n x 3 arrays: on the
 * device path, where the host does little else, they cost about 0.1 ms of
 * a 20k-vertex step (docs/benchmarks.md, session 17). */
void pl_dynamics_begin(const pl_dynamics *d, pl_dyn_work *w, const pl_data *data, int guess);
/* out (n x 3) += scale L q; nothing without L (no Rayleigh stiffness). */
void pl_dynamics_add_Lq(const pl_dynamics *d, const double *q, double scale, double *out);
/* The first vertex of state s in the system, or -1 when s is not one of
 * its states. */
int pl_dynamics_state_offset(const pl_dynamics *d, const pl_component *s);
/* Writes the prescribed vertices' positions at time t into q (n x 3). */
int pl_dynamics_prescribe(const pl_dynamics *d, pl_dyn_work *w, const pl_data *data, double t,
                          double *q, pl_error *err);
/* The states in data <- positions q and velocities (q - q_t)/h / (1 + h c),
 * c = damping [1/s]. */
void pl_dynamics_scatter(const pl_dynamics *d, const pl_dyn_work *w, pl_data *data,
                         const double *q, double damping);
/* Writes every state's constraint forces H^T lambda [N] (zero when rows
 * is NULL or empty); uses w->rhs as scratch. */
void pl_dynamics_store_forces(const pl_dynamics *d, pl_dyn_work *w, pl_data *data,
                              const pl_rows *rows, const double *lambda);
/* The incremental potential E(q) [J] at q (n x 3), around w->sn (with
 * Rayleigh stiffness damping: up to a constant of the step, the damping's
 * part of sn and (rS/(2h)) q^T L q standing for the dissipation potential). */
double pl_dynamics_energy(const pl_dynamics *d, const pl_dyn_work *w, const pl_data *data,
                          const double *q);
/* Length of the bounding-box diagonal of n points (1 if they coincide):
 * the scale of tolerances on positions. */
double pl_dynamics_bbox_diagonal(const double *q, int n);
/* w->b_free <- rhs restricted to the unknowns minus A_fp qp. */
void pl_dynamics_reduce_rhs(const pl_dynamics *d, pl_dyn_work *w, const double *rhs,
                            const double *qp);

#endif
