/* stencils_internal.h - building pl_hyper_stencils (internal). */
#ifndef PLIANT_HYPER_STENCILS_INTERNAL_H
#define PLIANT_HYPER_STENCILS_INTERNAL_H

#include "hyperelastic.h"

/* Allocates n rows with nnz entries in total (ptr, vert, coef, w; rest for
 * KEEP_NORM; work).  Returns 0 or -1 (s is then freed). */
int hyper_stencils_alloc(pl_hyper_stencils *s, pl_hyper_stencil_kind kind, int n, int nnz,
                         int nverts);
/* After ptr/vert/coef/w are filled: the incidence for gathers and, for
 * KEEP_NORM, rest = g x_rest.  Returns 0 or -1 (s is then freed). */
int hyper_stencils_finish(pl_hyper_stencils *s, const double *rest_positions);

/* Laplace-Beltrami rows of boundary vertices (boundary[v] != 0) whose rest
 * one-ring is flat: corrected to measure curvature (bending_boundary.c).
 * Call after hyper_stencils_finish.  Returns 0 or -1 (out of memory). */
int hyper_lb_fix_flat_boundary(pl_hyper_stencils *s, const double *rest,
                               const unsigned char *boundary);

#endif
