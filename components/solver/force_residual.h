/* force_residual.h - how far an implicit-Euler step is from equilibrium, in
 * newtons (issue 14 item 4).  The step solves
 *     M (q - sn) / h^2 + grad psi(q) - H^T lambda = 0
 * over the free vertices (sn = q_t + h v_t + h^2 g; H^T lambda the
 * constraint forces); the residual of vertex i is the left-hand side's
 * 3-vector r_i = m_i (q_i - sn_i) / h^2 - f_int,i(q) - (H^T lambda)_i with
 * f_int = -grad psi (the local terms' add_gradient, as the Newton reference
 * uses), and the step's residual is max_i |r_i| over free vertices.  A
 * position-based tolerance cannot say that a still-looking body is in
 * equilibrium: a finger moving 1e-8 m/s carried 0.14 N of unbalanced force.
 * LocalGlobalSolver's firstOrder and rayleighStiffness (dynamics.h) change
 * the inertia term to M (q - q_t) / h - M g and add the damping force
 * rS L (q - q_t) / h. */
#ifndef PLIANT_FORCE_RESIDUAL_H
#define PLIANT_FORCE_RESIDUAL_H

#include "dynamics.h"

/* Per-data scratch (in the solver's workspace), made on first use. */
typedef struct pl_force_residual {
    int n;
    double *f;                /* n x 3 */
} pl_force_residual;

/* At load: every local term of d has a gradient, else a load error against
 * owner naming the term. */
int pl_force_residual_check(const pl_dynamics *d, pl_component *owner, pl_ctx *ctx);
/* Whether every local term of d has a gradient (computeResidual="auto"
 * then reports the residual; a term of a plugin without one leaves it out). */
int pl_force_residual_possible(const pl_dynamics *d);
void pl_force_residual_free(pl_force_residual *r);

/* *out = max over free vertices of |r_i| [N] at positions q (n x 3, all
 * vertices) of the step whose prediction is w->sn, with the constraint
 * forces H^T lambda of rows and lambda (rows->n values; both NULL: no
 * constraint force). */
int pl_force_residual_eval(pl_force_residual *r, const pl_dynamics *d, const pl_dyn_work *w,
                           const pl_data *data, const double *q, const pl_rows *rows,
                           const double *lambda, double *out, pl_error *err);

#endif
