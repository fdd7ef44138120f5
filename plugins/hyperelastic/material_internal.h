/* material_internal.h - isotropic laws as functions of the singular values
 * on the CPU, for any law (internal to the hyperelastic core).
 * material_law.c defines them over the shared material_law.h and svd.h;
 * material_hessian.c builds on them. */
#ifndef PLIANT_HYPER_MATERIAL_INTERNAL_H
#define PLIANT_HYPER_MATERIAL_INTERNAL_H

#include "hyperelastic.h"

/* SVD of F (3 x d) with a FULL 3x3 U (for d = 2 its third column is
 * u0 x u1, the normal of the deformed membrane), s[d], V (d x d). */
void hyper_svd(int d, const double *F, double *U, double *s, double *V);

/* psi_hat(s) and, when g / H are not NULL, its gradient g[d] and Hessian
 * H (d x d).  Returns 0, or -1 outside the law's domain (Neo-Hookean with
 * some s <= 0), where psi is +INFINITY and g, H are left unset. */
int hyper_sv_eval(const pl_hyper_law *m, const double *s, double *psi, double *g, double *H);

/* For a pair i < j of singular values: c = (g_i - g_j) / (s_i - s_j) and
 * t = (g_i + g_j) / (s_i + s_j), in forms that stay finite when s_i = s_j.
 * j == d (membranes only) stands for the out-of-plane direction, a zero
 * singular value with zero gradient: c = t = g_i / s_i. */
void hyper_sv_pair(const pl_hyper_law *m, const double *s, const double *g, int i, int j,
                   double *c, double *t);

#endif
