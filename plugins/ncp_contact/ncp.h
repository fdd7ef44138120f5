/* ncp.h - the numerical core of the ncp_contact plugin: non-smooth Newton on
 * NCP functions (Fischer-Burmeister or minimum map) with the non-smooth
 * indicators Omega split out of the Jacobian (paper Section 5, Appendices
 * A-B, PAPER_NOTES items 5-12).  No scene code here: plain arrays in, plain
 * arrays out, so the same functions serve the plugin and the tests.
 *
 * Units and scaling.  Everything inside is written at the POSITION level:
 *   - normal, bilateral and bounded rows: delta = H q - d [m];
 *   - friction rows: y = h * dot(delta_f) = H_f (q - q_t) - h d_f [m]
 *     (Appendix A, end);
 *   - lambda [N]; the system solved for dlambda is
 *       (h^2 Omega W Omega + Et) dlambda = rhs,      Et = h^2 E (PAPER_NOTES 6)
 *     i.e. Et = diag(E_b, E_n, h E_f); its solution is exactly the paper's
 *     h^-2 (Omega W Omega + E)^-1 (h_vec - J A^-1 g).  DERIVATION.md derives
 *     rhs from `eq: non-smooth newton problem matrix form`, and the one
 *     change: bounded rows held at a bound keep their force (S below).
 * The complementarity scaling r follows the paper (Section 5.4): r = h^2 D_jj
 * for normal and bounded rows [m/N], r = h * mean(D_f1f1, D_f2f2) for BOTH
 * friction rows of a contact [m/(N s)], D = W (Delassus variant) or
 * H M^-1 H^T (mass variant).  Internally friction uses rho = h r [m/N]. */
#ifndef PLIANT_NCP_H
#define PLIANT_NCP_H

#include "pliant/error.h"
#include "pliant/rows.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- rows ---------------------------------------------------------------- */

/* The per-row data the solver reads (a view: no copies, arrays owned by the
 * caller).  Same conventions as pl_rows: friction rows point (pair) to their
 * normal row; at most two friction rows per normal row. */
typedef struct pl_ncp_rows {
    int m;                      /* rows */
    const pl_row_kind *kind;    /* m */
    const int *pair;            /* m: friction -> its normal row (others ignored) */
    const double *mu;           /* m: friction coefficient, read on normal rows (NULL = 0) */
    const double *compliance;   /* m: E_b [m/N] of bilateral rows (NULL = 0) */
    const double *lo, *hi;      /* m: bounds of bounded rows [N] (NULL = -inf / +inf) */
} pl_ncp_rows;

/* The view of a pl_rows (valid while r is not modified). */
static inline pl_ncp_rows ncp_rows_view(const pl_rows *r)
{
    pl_ncp_rows v = {r->n, r->kind, r->pair, r->mu, r->compliance, r->lo, r->hi};
    return v;
}

/* ---- the W operator ------------------------------------------------------ */

/* y = W x for the m x m Delassus operator; returns PL_OK or an error code. */
typedef int (*pl_ncp_apply_fn)(void *user, const double *x, double *y);

/* W explicit (dense, row-major m x m, symmetric) or matrix-free (apply). */
typedef struct pl_ncp_operator {
    int m;
    const double *dense;        /* m x m, or NULL to use apply */
    pl_ncp_apply_fn apply;      /* used when dense is NULL */
    void *user;                 /* passed to apply */
    const double *diag;         /* m: W_jj, for ncp_scaling (Delassus variant);
                                   the step itself does not read it */
} pl_ncp_operator;

/* y = W x. */
int ncp_operator_apply(const pl_ncp_operator *W, const double *x, double *y);

/* ---- conjugate residual -------------------------------------------------- */

/* Solves A x = b for a symmetric A given as products y = A x (op).  x holds
 * the initial guess on entry.  Stops when ||b - A x|| <= rtol ||b|| or after
 * max_iter products (a nonzero guess costs one more).  work: 4 n doubles.  iters / relres (may be NULL) get
 * the iterations done and ||b - A x|| / ||b||.  Not converging within
 * max_iter is not an error (the caller decides); a breakdown or a non-finite
 * value is (PL_EINTERNAL). */
int ncp_cr(int n, pl_ncp_apply_fn op, void *user, const double *b, double *x,
              int max_iter, double rtol, double *work, int *iters, double *relres,
              pl_error *err);

/* ---- NCP functions (one row or one contact) ------------------------------ */

typedef enum pl_ncp_function { PL_NCP_FB = 0, PL_NCP_MINMAP = 1 } pl_ncp_function;

/* Normal row (Signorini, 0 <= delta perp lambda >= 0), position level.
 * phi [m], omega = dphi/ddelta (the split indicator Omega_jj), e = dphi/dlambda
 * [m/N].  FB uses s = sqrt(delta^2 + (r lambda)^2 + eps^2), eps [m]: at
 * delta = lambda = 0 it gives omega = 1, e = r (finite), even with eps = 0. */
void ncp_eval_normal(pl_ncp_function fn, double delta, double lambda, double r, double eps,
                   double *phi, double *omega, double *e);

/* Coulomb friction of one contact with nt (1 or 2) tangent rows, position
 * level: y = h dot(delta_f) [m], lf [N], normal multiplier ln [N], rho = h r_f
 * [m/N].  Writes the contact's shared omega (1 when mu ln > 0, else 0), the
 * compliance e [m/N] (= h E_f of Appendix B, times the nt x nt identity) and
 * phi = omega y + e lf [m] (nt values).  Norms are 2-norms over the tangent
 * rows.  FB: Appendix B's formula inside the cone (rewritten without
 * cancellation; e = 0 at stick, also when lf = 0 = y), (s - b)/(mu ln) on and
 * outside the cone where Appendix B's denominator can vanish or change sign;
 * both agree on the cone.  Inactive (mu ln <= 0): omega = 0, e = rho, so the
 * step sets lf to 0. */
void ncp_eval_friction(pl_ncp_function fn, int nt, const double *y, const double *lf, double ln,
                     double mu, double rho, double *phi, double *omega, double *e);

/* Bounded row, lambda in [lo, hi] (box complementarity: delta = 0 inside,
 * delta >= 0 at lo, delta <= 0 at hi), min-map form
 * phi = r lambda - mid(r lo, r lambda - delta, r hi) [m]. */
void ncp_eval_bounded(double delta, double lambda, double lo, double hi, double r,
                    double *phi, double *omega, double *e);

/* Bilateral row with compliance E_b [m/N]: phi = delta + E_b lambda, omega = 1, e = E_b. */
void ncp_eval_bilateral(double delta, double lambda, double compliance,
                      double *phi, double *omega, double *e);

/* ---- one constraint update of Algorithm 4 -------------------------------- */

typedef struct pl_ncp_params {
    pl_ncp_function fn;         /* NCP function of normal and friction rows */
    double h;                   /* time step [s] (1 for a plain fc3d problem) */
    double fb_eps;              /* FB regularisation [m] (default 1e-12) */
    int cr_max_iter;            /* CR cap (<= 0: 2 m + 10) */
    double cr_rtol;             /* CR relative tolerance (default 1e-10) */
    int full_force;             /* 0 (default): the paper's correction with J^T lambda, S = Omega
                                   (1 on bounded rows); 1: H^T lambda on every row, S = 1, the
                                   Newton step of the unsymmetric system made symmetric by
                                   Omega^-1 (DERIVATION.md section 7) */
    int cr_jacobi;              /* 1 (default): CR solves the symmetrically diagonal-scaled
                                   system D^-1/2 A D^-1/2 (D = diag A, from W->diag); 0: A as
                                   it is.  The friction compliance e spans many decades
                                   (a contact that barely touches has e >> h^2 W_jj), and
                                   unscaled CR then hardly reduces the residual in 10
                                   iterations (docs/contact.md, "CR scaling") */
} pl_ncp_params;

void ncp_params_default(pl_ncp_params *p);

/* Per time step: the contact table and all scratch arrays, for fixed rows. */
typedef struct pl_ncp_work {
    pl_ncp_rows rows;           /* the view given at creation */
    int m, nc;                  /* rows, contacts (normal rows) */
    int *contact;               /* nc x 3: normal row, friction rows (-1 if absent) */
    int *contact_of;            /* m: contact of a normal/friction row, else -1 */
    double *omega;              /* m: Omega_jj of the last step */
    double *scale;              /* m: S_jj of the last step: the scale of lambda in the
                                   correction (Omega_jj; 1 on bounded rows) */
    double *clamped;            /* m: dlambda of clamped rows (Omega 0, S 1) */
    int *is_clamped;            /* m: 1 on clamped rows of the last step */
    double *op_omega, *op_e;    /* m: the diagonals CR's operator uses */
    double *cr_scale;           /* m: CR's diagonal scaling D^-1/2 (1 without cr_jacobi) */
    double *e;                  /* m: Et_jj = h^2 E_jj of the last step [m/N] */
    double *phi;                /* m: position-level NCP values at (delta^k, lambda^k) [m] */
    double *rhs;                /* m: right-hand side of the last step [m] */
    double *tmp, *tmp2;         /* m */
    double *cr;                 /* 4 m: CR scratch */
} pl_ncp_work;

/* Validates the rows (kinds, pairs, mu >= 0, lo <= hi, E_b >= 0) and builds
 * the work; *out = NULL on error. */
int ncp_work_create(const pl_ncp_rows *rows, pl_ncp_work **out, pl_error *err);
void ncp_work_destroy(pl_ncp_work *w);

/* The complementarity scaling r (paper units, see top) from a diagonal D
 * (W_jj for the Delassus variant, (H M^-1 H^T)_jj for the mass variant);
 * bilateral rows get h^2 D_jj (unused).  D must be > 0 on NCP rows. */
int ncp_scaling(const pl_ncp_work *w, const double *diag, double h, double *r, pl_error *err);

typedef struct pl_ncp_step_info {
    int cr_iters;               /* CR products */
    double cr_relres;           /* CR final relative residual (of the scaled system) */
    double phi_norm;            /* max_j |phi_j| at (delta^k, lambda^k) [m] */
} pl_ncp_step_info;

/* One constraint update (the "solve constraint linear system" line of
 * Algorithms 3-4) at iterate k.
 *   delta:      m, constraint values at q^k (delta_b, delta_n, y_f) [m]
 *   delta_free: m, the same with q_free = A^-1 b^k instead of q^k, SAME
 *               offsets (d, and H_f q_t + h d_f for friction) [m]
 *   lambda:     m, lambda^k [N]
 *   r:          m, from ncp_scaling (once per time step)
 * Outputs dlambda (m) [N] and force_scale S (m, may be NULL; also
 * w->scale): Omega_jj (the paper's J = Omega H), but 1 on bounded rows;
 * 1 on every row with par->full_force.
 * The caller then sets lambda^{k+1} = lambda^k + dlambda and
 *   q^{k+1} = A^-1 (b^k + h^2 H^T (S .* lambda^{k+1}))
 *           = q_free + h^2 A^-1 H^T (S .* lambda^{k+1}),
 * with the S of this same step (at a solution S .* lambda = lambda). */
int ncp_step(pl_ncp_work *w, const pl_ncp_params *par, const pl_ncp_operator *W,
                const double *r, const double *delta, const double *delta_free,
                const double *lambda, double *dlambda, double *force_scale,
                pl_ncp_step_info *info, pl_error *err);

/* Projects lambda (m) onto the admissible set: lambda_n >= 0, |lambda_f| <=
 * mu lambda_n per contact (scaling the tangent rows), lo <= lambda <= hi on
 * bounded rows.  Returns the number of rows or contacts changed.  A
 * solution is a fixed point; the plugin applies it after each update. */
int ncp_project(const pl_ncp_work *w, double *lambda);

typedef struct pl_ncp_line_info {
    double alpha;               /* the step length taken */
    double merit0, merit;       /* residual norm2 before and after [m] */
    int trials;                 /* residual evaluations */
    int decreased;              /* 1 when alpha gave a sufficient decrease */
} pl_ncp_line_info;

/* Backtracking on ncp_residual_eval's norm2 along a Newton direction
 * with affine constraint values: delta(alpha) = delta0 + alpha ddelta,
 * lambda(alpha) = lambda + alpha dlambda.  Halves alpha (at most
 * max_halvings times) until norm2(alpha) <= (1 - 1e-4 alpha) norm2(0);
 * when no length decreases it, alpha = 1.  Uses w->tmp and w->tmp2. */
int ncp_line_search(pl_ncp_work *w, const double *r, double h, const double *delta0,
                       const double *ddelta, const double *lambda, const double *dlambda,
                       int max_halvings, pl_ncp_line_info *info, pl_error *err);

typedef struct pl_ncp_residual {
    double bilateral;           /* max |delta + E_b lambda| [m] */
    double normal;              /* max |min(delta_n, r lambda_n)| [m]: normal complementarity */
    double cone;                /* max (|lambda_f| - mu lambda_n)^+ [N]: cone feasibility */
    double friction;            /* max |rho lf - P_disk(rho mu ln+)(rho lf - y)| [m]: maximal
                                   dissipation (stick: y = 0 inside the cone; slide: lf on the
                                   cone boundary, opposite to y) */
    double bounded;             /* max |r lambda - mid(r lo, r lambda - delta, r hi)| [m] */
    double total;               /* max(bilateral, normal, rho * cone, friction, bounded) [m] */
    double norm2;               /* the 2-norm of the same per-row (per-contact) values [m] */
} pl_ncp_residual;

/* The residual of (delta, lambda) for the rows of w with scaling r (paper
 * units as from ncp_scaling; h converts friction r to rho = h r). */
int ncp_residual_eval(const pl_ncp_work *w, const double *r, double h, const double *delta,
                         const double *lambda, pl_ncp_residual *res, pl_error *err);

/* ---- standalone 3D frictional contact (Siconos' fc3d convention) --------- */

/* nc contacts, rows 3i (normal), 3i+1, 3i+2 (tangents); W (3nc x 3nc,
 * row-major, SPD), q, mu (nc).  Finds r, u = W r + q with 0 <= u_n perp
 * r_n >= 0, |r_t| <= mu r_n, maximal dissipation.  The same machinery as
 * the plugin: ncp_step with h = 1 and the Delassus scaling. */
typedef struct pl_ncp_solve_opts {
    pl_ncp_function fn;
    int max_iter;               /* Newton iterations (default 500: friction converges linearly) */
    double tol;                 /* on residual.total / max(|q|_inf, tiny) (default 1e-12) */
    int cr_max_iter;            /* (<= 0: 2 m + 10) */
    double cr_rtol;             /* (default 1e-12) */
} pl_ncp_solve_opts;

typedef struct pl_ncp_solve_info {
    int iters;                  /* Newton iterations done */
    int cr_iters;               /* CR products, all iterations */
    double residual;            /* final residual.total / max(|q|_inf, tiny) */
    int converged;              /* residual <= tol */
} pl_ncp_solve_info;

void ncp_solve_opts_default(pl_ncp_solve_opts *o);

/* reaction: initial guess on entry (zeros are fine), solution on exit; u (3 nc) out.
 * Not converging is reported in info (status PL_OK); bad input is PL_EINPUT. */
int ncp_solve_fc3d(int nc, const double *W, const double *q, const double *mu,
                      double *reaction, double *u, const pl_ncp_solve_opts *opts,
                      pl_ncp_solve_info *info, pl_error *err);

/* The Signorini-Coulomb residual of an fc3d pair (reaction, u), u = W r + q
 * given; scaling W_nn (normal) and the mean tangent diagonal (friction), i.e.
 * ncp_scaling with h = 1. */
int ncp_residual_fc3d(int nc, const double *W, const double *mu, const double *reaction,
                         const double *u, pl_ncp_residual *res, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
