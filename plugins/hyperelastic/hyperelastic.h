/* hyperelastic.h - the numeric core of the hyperelastic plugin (library
 * hyperelastic_core): Projective Dynamics / ADMM-PD local steps, the energies,
 * gradients and Hessians a Newton reference needs, cloth bending and
 * positional targets.  The components in this folder are thin wrappers.
 *
 * Conventions (see PAPER_NOTES.md items 1-3):
 *  - The global system is SCALAR (n x n): every term has isotropic weights.
 *    Positions, right-hand sides and gradients are n x 3 row-major blocks
 *    over global vertices; a term's local vertex v is global vertex
 *    offset + v.  Hessians are over 3n DOFs, index 3 * vertex + coordinate.
 *  - An element with vertex positions X (3 x k) has the deformation gradient
 *    F = X D (3 x d, row-major), D (k x d, row-major) constant: k = 4, d = 3
 *    for tetrahedra; k = 3, d = 2 for triangles (F maps the rest triangle's
 *    2D frame into 3D).  The element adds h2 * w * D D^T (k x k) to A and its
 *    local step adds h2 * w * (p - u) D^T (3 x k) to the xyz rows of its
 *    vertices.
 *  - ARAP (Projective Dynamics): p = the closest rotation (closest 3 x 2
 *    matrix with orthonormal columns for triangles), w = 2 mu V, no dual;
 *    w/2 ||F - p||^2 is then exactly the ARAP energy mu V ||F - R||^2.
 *  - Corotational and Neo-Hookean (ADMM-PD, Overby et al. 2017): a scaled
 *    dual u (3 x d) per element; p = argmin psi(p) V + w/2 ||p - (F + u)||^2,
 *    then u += F - p.  w = (2 mu + lambda) V: the stiffness of psi at rest
 *    along a uniaxial strain (p-wave modulus).  A w of the order of the
 *    material stiffness makes ADMM converge fastest; much smaller w lets p
 *    drift from F, much larger w slows the dual.  Without u the fixed point
 *    is too soft (PAPER_NOTES.md item 2).
 *  - psi is an energy density [J/m^3] (J/m^2 per unit thickness for
 *    membranes); V is the rest volume (triangle: area * thickness).
 *  - Every element loop is OpenMP-parallel and deterministic: an element
 *    writes its own slot; a gather over vertices in a fixed order sums. */
#ifndef PLIANT_HYPERELASTIC_H
#define PLIANT_HYPERELASTIC_H

#include "pliant/error.h"
#include "pliant/sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- small dense linear algebra (svd.c, sym_eigen.c) -------------------- */
/* (The implementations are svd.h and sym_eigen.h, shared with the GPU.) */

/* Signed SVD of a 3x3 F (row-major): F = U diag(s) V^T with U, V proper
 * rotations (det +1), |s0| >= |s1| >= |s2|, s0, s1 >= 0; s2 < 0 exactly when
 * det F < 0 (the smallest singular value carries the inversion).  One-sided
 * Jacobi (Hestenes): accurate for tiny singular values. */
void hyper_svd3(const double F[9], double U[9], double s[3], double V[9]);
/* SVD of a 3x2 F: F = U diag(s) V^T, U 3x2 with orthonormal columns,
 * s0 >= s1 >= 0, V 2x2 rotation. */
void hyper_svd32(const double F[6], double U[6], double s[2], double V[4]);
/* The same with the Jacobi sweeps started from V0 (a rotation, e.g. the V
 * of a nearby matrix: then fewer sweeps; NULL: the identity, as above). */
void hyper_svd3_from(const double F[9], const double V0[9], double U[9], double s[3], double V[9]);
void hyper_svd32_from(const double F[6], const double V0[4], double U[6], double s[2],
                      double V[4]);
/* Closest proper rotation to F (3x3), also for inverted F. */
void hyper_polar3(const double F[9], double R[9]);
/* Closest 3x2 matrix with orthonormal columns to F (3x2). */
void hyper_polar32(const double F[6], double R[6]);

#define PL_HYPER_SYM_MAX 12
/* Cyclic Jacobi eigen-decomposition of a symmetric n x n A (row-major,
 * n <= PL_HYPER_SYM_MAX): A = Q diag(lambda) Q^T, Q's columns the
 * eigenvectors, lambda ascending.  PL_EINPUT if n is out of range. */
int hyper_sym_eigen(int n, const double *A, double *lambda, double *Q);
/* Replaces A (symmetric n x n) by its projection on the PSD cone (negative
 * eigenvalues set to zero). */
int hyper_project_psd(int n, double *A);

/* ---- element geometry (element_geometry.c) ------------------------------ */

/* x: the 4 rest vertices (4 x 3).  D (4 x 3) with F = X D; volume > 0 (the
 * absolute value: a negatively oriented rest tet still has F = I at rest).
 * PL_EINPUT if the tetrahedron is degenerate. */
int hyper_tet_shape(const double x[12], double D[12], double *volume);
/* x: the 3 rest vertices (3 x 3).  D (3 x 2) with F = X D mapping the rest
 * frame (t1 along edge 01, t2 in-plane) to 3D; at rest F = [t1 t2].
 * PL_EINPUT if the triangle is degenerate. */
int hyper_tri_shape(const double x[9], double D[6], double *area);

/* ---- material laws (material_law.c, material_hessian.c, local_solve.c) -- */
/* (The laws on the singular values and the local solve are material_law.h
 * and local_solve.h, shared with the GPU.) */

typedef enum pl_hyper_material {
    PL_HYPER_ARAP = 0,          /* psi = mu ||F - R||^2 */
    PL_HYPER_COROTATIONAL = 1,  /* psi = mu ||F - R||^2 + lambda/2 tr(R^T F - I)^2 */
    PL_HYPER_NEOHOOKEAN = 2     /* psi = mu/2 (I1 - d) - mu ln J + lambda/2 (ln J)^2 */
} pl_hyper_material;

/* A material law on F (3 x d).  d = 3: volumetric; d = 2: membrane (J = s0 s1,
 * I1 = s0^2 + s1^2, R = the closest 3x2 matrix with orthonormal columns). */
typedef struct pl_hyper_law {
    pl_hyper_material material;
    int d;          /* 3 (tetrahedra) or 2 (triangles) */
    double mu;      /* [Pa] */
    double lambda;  /* [Pa]; ignored by ARAP */
} pl_hyper_law;

/* Lame parameters from Young's modulus E [Pa] and Poisson's ratio nu:
 * mu = E/(2(1+nu)), lambda = E nu/((1+nu)(1-2nu)).  membrane != 0 returns
 * the plane-stress lambda* = 2 mu lambda/(lambda + 2 mu) (= E nu/(1-nu^2)),
 * which makes a 2D law's uniaxial stiffness E.  PL_EINPUT unless E > 0 and
 * -1 < nu < 0.5. */
int hyper_lame(double E, double nu, int membrane, double *mu, double *lambda, pl_error *err);
/* The PD weight per unit volume: 2 mu (ARAP), 2 mu + lambda (ADMM-PD). */
double hyper_law_weight(const pl_hyper_law *m);
/* Energy density psi(F); +INFINITY for Neo-Hookean when J <= 0. */
double hyper_psi(const pl_hyper_law *m, const double *F);
/* First Piola-Kirchhoff stress P = dpsi/dF (3 x d). */
void hyper_piola(const pl_hyper_law *m, const double *F, double *P);
/* dP/dF as a (3d x 3d) row-major matrix over vec(F) (index a*d + b for
 * F_ab).  psd != 0: projected to PSD (exactly: the Hessian is block-diagonal
 * in the singular frame; each block's eigenvalues are clamped at zero). */
void pl_hyper_dPdF(const pl_hyper_law *m, const double *F, int psd, double *H);
/* Local step on z (3 x d).  ARAP: p = closest rotation to z.  Otherwise:
 * p = argmin psi(p) + what/2 ||p - z||^2 (what = w / V), solved on the
 * singular values of z by Newton with backtracking (s > 0 kept for
 * Neo-Hookean).  Returns the Newton iterations (>= 0), or -1 if it did not
 * reach its tolerance (p is then the last iterate) or z is not finite. */
int hyper_local_solve(const pl_hyper_law *m, double what, const double *z, double *p);
/* The doubles of an element's warm start: its last solve's d singular
 * values (warm[0] > 0: set), then its d x d right singular vectors V. */
#define HM_WARM_LEN(d) ((d) + (d) * (d))
/* The same, started from warm (HM_WARM_LEN(d) values: the element's
 * previous solve, used when warm[0] > 0; NULL: cold): the SVD's Jacobi
 * sweeps from its V, the Newton on the singular values from its s; leaves
 * its own there, adding its line-search halvings to *halvings (not NULL). */
int hyper_local_solve_warm(const pl_hyper_law *m, double what, const double *z, double *p,
                           double *warm, int *halvings);

/* What the local steps did, summed over element-calls (hyper_elements_project
 * adds to it; the FEM terms publish it per step, fem_term.c). */
#define HYPER_PROX_HIST 13 /* bins: 0 .. 11 Newton iterations, then >= 12 */
typedef struct hyper_prox_stats {
    long long solves;                /* element-calls of the local step */
    long long newton;                /* Newton iterations, summed */
    long long halvings;              /* line-search halvings, summed */
    long long capped;                /* solves that stopped before their tolerance */
    long long hist[HYPER_PROX_HIST]; /* solves by Newton iterations (capped ones not binned) */
    int max_iterations;              /* the largest count of one solve */
} hyper_prox_stats;

/* ---- element sets: one FEM term's elements (elements.c, elements_step.c) */

typedef struct pl_hyper_elements {
    pl_hyper_material material;
    int k;              /* vertices per element: 4 or 3 */
    int d;              /* columns of F: 3 or 2 */
    int n;              /* elements */
    int nverts;         /* vertices of the term's state */
    int *verts;         /* n x k local vertex indices */
    double *D;          /* n x (k*d): each a k x d row-major shape matrix */
    double *volume;     /* n rest volumes [m^3] (triangles: area * thickness) */
    double *mu, *lambda;/* n Lame parameters [Pa] (lambda plane-stress for triangles) */
    double *w;          /* n PD weights [N m] = weight_scale * hyper_law_weight * volume */
    double weight_scale;/* the ADMM-PD penalty's scale (admmWeight; 1 by default, ARAP: 1) */
    int *vptr, *vinc;   /* vertex -> (element*k + corner) incidence, for gathers */
    int edge_rotation;  /* 1: SOFA's 'large' rotation from the edges (edge_rotation.c) */
} pl_hyper_elements;

/* SOFA's 'large' corotational method (edge_rotation.c), tetrahedra: the
 * rotation from a frame on the element's edges (D: its 4 x 3 shape matrix),
 * the first Piola stress of linear elasticity in that frame, and its
 * stiffness with the rotation held fixed (9 x 9, dP_ab / dF_cd at
 * (3a + b, 3c + d)). */
void hyper_edge_rotation(const double *F, const double *D, double *R);
void hyper_edge_piola(const pl_hyper_law *m, const double *F, const double *D, double *P);
void hyper_edge_dPdF(const pl_hyper_law *m, const double *F, const double *D, double *H);

/* Builds the element set.  elems: nelem x k local vertex indices (k = 4
 * tetrahedra, 3 triangles); rest: nverts x 3 rest positions.  E, nu: one
 * value (count 1) or one per element (count nelem).  thickness [m] scales
 * triangle areas into volumes (ignored for tetrahedra).  On error (bad index,
 * degenerate element, bad material) e is left empty and err says which
 * element. */
int hyper_elements_build(pl_hyper_elements *e, pl_hyper_material material, int k,
                            const int *elems, int nelem, const double *rest, int nverts,
                            const double *E, int nE, const double *nu, int nnu,
                            double thickness, pl_error *err);
void hyper_elements_free(pl_hyper_elements *e);
/* The law of element i. */
pl_hyper_law hyper_elements_law(const pl_hyper_elements *e, int i);
/* Doubles per element in the dual (3 * d; 0 for ARAP, which has none). */
int hyper_elements_dual_size(const pl_hyper_elements *e);
/* A += h2 * w D D^T, scalar, at global vertices offset + v (full matrix,
 * both triangles). */
int hyper_elements_add_matrix(const pl_hyper_elements *e, int offset, double h2,
                                 pl_triplets *A, pl_error *err);
/* Doubles of scratch the local step needs (n x 3k). */
size_t hyper_elements_work_size(const pl_hyper_elements *e);
/* The local step: q global positions (>= offset + nverts rows, x 3); dual
 * n x dual_size (NULL for ARAP; ADMM duals updated in place); work: the
 * caller's scratch of hyper_elements_work_size doubles (the element set
 * is only read, so several states may project with it at once); adds
 * h2 * w (p - u) D^T into rhs (global n x 3).  warm (n x HM_WARM_LEN(d),
 * or NULL): each element's prox starts from its row when set (row[0] > 0)
 * and leaves its solution there (zeros: cold).  If stats != NULL, this call's counts
 * are added to it.  PL_EINTERNAL if q gives a non-finite F. */
int hyper_elements_project(const pl_hyper_elements *e, int offset, double h2, const double *q,
                              double *dual, double *warm, double *work, double *rhs,
                              hyper_prox_stats *stats, pl_error *err);
/* The same with over-relaxed ADMM (Boyd et al. 2011, 3.4.3; ADMM materials
 * only): prev (n x dual_size, or NULL) receives each element's prox
 * solution p; when alpha != 1, the step uses alpha G q + (1 - alpha) prev
 * in place of G q (prev must then hold the previous call's p: alpha = 1 on
 * a step's first iteration). */
int hyper_elements_project_relaxed(const pl_hyper_elements *e, int offset, double h2,
                                   const double *q, double *dual, double *warm, double alpha,
                                   double *prev, double *work, double *rhs,
                                   hyper_prox_stats *stats, pl_error *err);
/* Elastic energy sum psi(F_e) V_e [J] (+INFINITY if a Neo-Hookean element is
 * inverted).  Summed in element order. */
double hyper_elements_energy(const pl_hyper_elements *e, int offset, const double *q);
/* grad (global n x 3) += d energy / dq. */
int hyper_elements_add_gradient(const pl_hyper_elements *e, int offset, const double *q,
                                   double *grad, pl_error *err);
/* H (3n x 3n, index 3*vertex + coordinate) += d2 energy / dq2.  psd != 0:
 * each element's dP/dF is projected to PSD (pl_hyper_dPdF), so each 3k x 3k
 * block V G^T (dP/dF) G is PSD too.  Every entry of every block is appended
 * (a constant pattern). */
int hyper_elements_add_hessian(const pl_hyper_elements *e, int offset, const double *q,
                                  int psd, pl_triplets *H, pl_error *err);

/* ---- stencil terms: bending and targets (stencils.c, bending.c) --------- */

/* Terms w/2 ||g_r x - p_r||^2 with g_r a constant scalar row over a few
 * vertices (applied to x, y and z alike) and p_r a 3-vector:
 *  FIXED      p_r is given by the caller (NULL: zero).  Isometric bending
 *             (p = 0 for a flat rest state) and position targets.
 *  KEEP_NORM  p_r = |g_r x_rest| (g_r x) / |g_r x|: Laplace-Beltrami
 *             bending keeps each vertex's rest mean-curvature magnitude
 *             (Bouaziz et al. 2014); energy w/2 (|g_r x| - |g_r x_rest|)^2. */
typedef enum pl_hyper_stencil_kind {
    PL_HYPER_STENCIL_FIXED = 0,
    PL_HYPER_STENCIL_KEEP_NORM = 1
} pl_hyper_stencil_kind;

typedef struct pl_hyper_stencils {
    pl_hyper_stencil_kind kind;
    int n;              /* stencils (rows) */
    int nverts;         /* vertices of the term's state */
    int *ptr;           /* n + 1: row r holds entries ptr[r] .. ptr[r+1]-1 */
    int *vert;          /* local vertex of each entry */
    double *coef;       /* coefficient of each entry */
    double *w;          /* n weights */
    double *rest;       /* KEEP_NORM: n x 3 values g_r x_rest (else NULL) */
    int *vptr, *vinc;   /* vertex -> entry incidence, for gathers */
} pl_hyper_stencils;

/* Isometric bending (Bergou et al. 2006): one stencil per interior edge (two
 * triangles), g = K, the 4-vertex cotangent stencil (edge x0 x1, opposite
 * x2, x3), w = stiffness * 3 / (A0 + A1): energy stiffness/2 * 3/(A0+A1) *
 * ||K x||^2 (~ |e|^2 theta^2 per edge, as Discrete Shells), zero for any
 * flat affine image of a flat rest state.  Its scale depends on the mesh:
 * relative to the plate energy stiffness/2 * integral kappa^2 of a cylinder,
 * 1.5x on equilateral meshes, ~2.85x on a right-triangle grid bent across
 * one edge family (measured, test_hyper_bending).  Edges with more than two
 * triangles are skipped and counted in *nskipped (may be NULL).  stiffness
 * [N m]. */
int hyper_isometric_bending_build(pl_hyper_stencils *s, const int *tris, int ntris,
                                     const double *rest, int nverts, double stiffness,
                                     int *nskipped, pl_error *err);
/* Laplace-Beltrami bending: one stencil per vertex used by a triangle,
 * g = (cotangent Laplacian row) / A_i (A_i barycentric area), w = stiffness *
 * A_i, KEEP_NORM: energy stiffness/2 sum_i A_i (|Lx|_i - |Lx_rest|_i)^2, the
 * integral of stiffness/2 (2H)^2 for a flat rest state (a cylinder of radius
 * r: |Lx|_i = 1/r within 1% at interior vertices).  Boundary vertices of a
 * flat rest state would feel no bending (their row sees the boundary's
 * in-plane term): their rows are corrected to annihilate affine functions of
 * the rest one-ring and calibrated to 2H on a paraboloid, with rest value 0
 * (bending_boundary.c).  No Gaussian-curvature term: like a plate with
 * nu = 1, a soft membrane can relax by anticlastic curvature. */
int hyper_laplace_beltrami_build(pl_hyper_stencils *s, const int *tris, int ntris,
                                    const double *rest, int nverts, double stiffness,
                                    pl_error *err);
/* Position targets: stencil r = vertex idx[r] with coefficient 1, w =
 * stiffness [N/m]; energy stiffness/2 ||x_a - t_a||^2 (FIXED, targets given
 * to project/energy). */
int hyper_point_targets_build(pl_hyper_stencils *s, const int *idx, int n, int nverts,
                                 double stiffness, pl_error *err);
void hyper_stencils_free(pl_hyper_stencils *s);
/* A += h2 * w g g^T (scalar, global vertices offset + v). */
int hyper_stencils_add_matrix(const pl_hyper_stencils *s, int offset, double h2,
                                 pl_triplets *A, pl_error *err);
/* Doubles of scratch project needs (3 per entry). */
size_t hyper_stencils_work_size(const pl_hyper_stencils *s);
/* rhs += h2 * w g^T p (p from targets, n x 3, for FIXED; NULL = zero);
 * work: the caller's scratch of hyper_stencils_work_size doubles. */
int hyper_stencils_project(const pl_hyper_stencils *s, int offset, double h2, const double *q,
                              const double *targets, double *work, double *rhs, pl_error *err);
double hyper_stencils_energy(const pl_hyper_stencils *s, int offset, const double *q,
                                const double *targets);
int hyper_stencils_add_gradient(const pl_hyper_stencils *s, int offset, const double *q,
                                   const double *targets, double *grad, pl_error *err);
/* H += w g g^T (x) M: M = I for FIXED; for KEEP_NORM the Hessian of
 * (|y| - r)^2 / 2, clamped to PSD when psd != 0. */
int hyper_stencils_add_hessian(const pl_hyper_stencils *s, int offset, const double *q,
                                  int psd, pl_triplets *H, pl_error *err);

/* ---- target motion (target_motion.c) ------------------------------------ */

typedef enum pl_hyper_motion_kind {
    PL_HYPER_MOTION_NONE = 0,      /* t(t) = base */
    PL_HYPER_MOTION_VELOCITY = 1,  /* t(t) = base + velocity t */
    PL_HYPER_MOTION_ROTATION = 2,  /* base rotated about (center, axis) by angular_velocity t */
    PL_HYPER_MOTION_KEYFRAMES = 3  /* linear interpolation of keyframes, clamped outside */
} pl_hyper_motion_kind;

typedef struct pl_hyper_motion {
    pl_hyper_motion_kind kind;
    double velocity[3];         /* [m/s] */
    double center[3];           /* [m] a point of the rotation axis */
    double axis[3];             /* direction of the axis (normalised here) */
    double angular_velocity;    /* [rad/s], right-handed about axis */
    const double *times;        /* keyframe times [s], increasing */
    int ntimes;
    /* keyframe values: 3 * ntimes (one offset added to every base point) or
     * 3 * ntimes * npoints (positions of every point at every time) */
    const double *values;
    int nvalues;
} pl_hyper_motion;

/* Checks the motion for npoints points (axis non-zero, times increasing,
 * values of a valid size); PL_EINPUT with a message otherwise. */
int hyper_motion_check(const pl_hyper_motion *m, int npoints, pl_error *err);
/* out (npoints x 3) = the targets at time t from base (npoints x 3). */
void hyper_motion_eval(const pl_hyper_motion *m, int npoints, const double *base, double t,
                          double *out);

#ifdef __cplusplus
}
#endif
#endif
