/* dynamics.h - what every implicit-Euler solver of a scene shares: the
 * global numbering of the states below it, lumped masses, gravity,
 * prescribed DOFs (eliminated from the unknowns), the local terms, the
 * constant system A = M + h^2 sum w G^T G split into free and prescribed
 * blocks, and the incremental potential
 *     E(q) = 1/(2 h^2) ||M^1/2 (q - sn)||^2 + sum psi(q),
 *     sn = q_t + h v_t + h^2 g
 * (the paper's eq. "implicit euler") that both the local-global loop and
 * the Newton reference minimise. */
#ifndef PLIANT_DYNAMICS_H
#define PLIANT_DYNAMICS_H

#include "pliant/pliant.h"

typedef struct pl_dynamics {
    double h;                 /* time step [s] */
    int n;                    /* vertices of all states */
    int nstates;
    pl_component **states;
    int nterms;
    pl_component **terms;     /* local terms (elements, targets) */
    int *term_offset;         /* first global vertex of each term's state */
    int nprescribed;
    pl_component **prescribed;
    double *mass;             /* n [kg] */
    double *gravity;          /* n x 3 [m/s^2], from each state's node */
    int nfree;
    int *free_index;          /* n: index among unknowns or -1 */
    int *free_vertex;         /* nfree: global vertex */
    pl_csc A_ff;              /* nfree x nfree, both triangles */
    pl_csc A_fp;              /* nfree x n, only prescribed columns non-empty */
    pl_system sys;
    /* per-step work (n x 3 unless said) */
    double *q, *q_t, *v_t, *sn, *rhs, *qp;
    double *b_free, *q_free;  /* nfree x 3 */
} pl_dynamics;

/* Collects the states, masses, prescribed DOFs and local terms of the
 * subtree of `owner`'s node, numbers the vertices and (if with_matrix)
 * assembles A_ff and A_fp.  Errors are recorded against owner in ctx. */
int pl_dynamics_setup(pl_dynamics *d, pl_component *owner, pl_ctx *ctx, double h,
                      int with_matrix);
void pl_dynamics_free(pl_dynamics *d);

/* q_t, v_t <- the states in data. */
void pl_dynamics_gather(pl_dynamics *d, const pl_data *data);
/* sn <- q_t + h v_t + h^2 g. */
void pl_dynamics_predict(pl_dynamics *d);
/* Writes the prescribed vertices' positions at time t into q (n x 3). */
int pl_dynamics_prescribe(pl_dynamics *d, const pl_data *data, double t, double *q,
                          pl_error *err);
/* The states in data <- positions q and velocities (q - q_t)/h / (1 + h c),
 * c = damping [1/s]. */
void pl_dynamics_scatter(pl_dynamics *d, pl_data *data, const double *q, double damping);
/* Writes every state's constraint forces H^T lambda [N] (zero when rows
 * is NULL or empty). */
void pl_dynamics_store_forces(pl_dynamics *d, pl_data *data, const pl_rows *rows,
                              const double *lambda);
/* The incremental potential E(q) [J] at q (n x 3). */
double pl_dynamics_energy(const pl_dynamics *d, const pl_data *data, const double *q);
/* Length of the bounding-box diagonal of n points (1 if they coincide):
 * the scale of tolerances on positions. */
double pl_dynamics_bbox_diagonal(const double *q, int n);
/* b_free <- rhs restricted to the unknowns minus A_fp qp. */
void pl_dynamics_reduce_rhs(pl_dynamics *d, const double *rhs, const double *qp);

#endif
