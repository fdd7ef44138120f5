/* force_residual.h - how far an implicit-Euler step is from equilibrium, in
 * newtons (issue 14 item 4).  The step solves
 *     M (q - sn) / h^2 + grad psi(q) - H^T lambda = 0
 * over the free vertices (sn = q_t + h v_t + h^2 g; H^T lambda the
 * constraint forces); the residual of vertex i is the left-hand side's
 * 3-vector r_i = m_i (q_i - sn_i) / h^2 - f_int,i(q) - (H^T lambda)_i with
 * f_int = -grad psi (the local terms' add_gradient, as the Newton reference
 * uses), and the step's residual is max_i |r_i| over free vertices.  A
 * position-based tolerance cannot say that a still-looking body is in
 * equilibrium: a finger moving 1e-8 m/s carried 0.14 N of unbalanced force. */
#ifndef PLIANT_FORCE_RESIDUAL_H
#define PLIANT_FORCE_RESIDUAL_H

#include "dynamics.h"

typedef struct pl_force_residual {
    int n;
    double *f;                /* n x 3 scratch */
} pl_force_residual;

/* Checks that every local term of d has a gradient (else a load error
 * against owner naming the term) and allocates the scratch. */
int pl_force_residual_init(pl_force_residual *r, const pl_dynamics *d, pl_component *owner,
                           pl_ctx *ctx);
void pl_force_residual_free(pl_force_residual *r);

/* *out = max over free vertices of |r_i| [N] at positions q (n x 3, all
 * vertices), with the constraint forces H^T lambda of rows and lambda
 * (rows->n values; both NULL: no constraint force). */
int pl_force_residual_eval(pl_force_residual *r, const pl_dynamics *d, const pl_data *data,
                           const double *q, const pl_rows *rows, const double *lambda, double *out,
                           pl_error *err);

#endif
