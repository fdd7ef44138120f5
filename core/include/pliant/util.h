/* util.h - small helpers for writing components: finding partners by role,
 * selecting vertices by boxes, rotations.  Part of the SDK (implemented in
 * libpliant), so plugins built out of tree can use them too. */
#ifndef PLIANT_UTIL_H
#define PLIANT_UTIL_H

#include "pliant.h"

/* The topology a component uses: its link if set (must play the topology
 * role), else the first topology component of its node, else NULL. */
const pl_mesh *pl_util_topology(const pl_component *c, const pl_link *src, pl_ctx *ctx,
                                int required);
/* The state of c's node (first PL_ROLE_STATE component), or NULL with an
 * error recorded when required. */
pl_component *pl_util_state(const pl_component *c, pl_ctx *ctx, int required);
/* Rest positions and count of a state. */
const double *pl_util_rest(const pl_component *state, int *n);

/* Vertices of x (n x 3) inside any of the boxes (6 numbers each:
 * xmin ymin zmin xmax ymax zmax) plus the explicit indices; sorted, unique.
 * Returns the count (>= 0) or -1 on allocation failure; *out is malloc'ed. */
int pl_util_select(const double *x, int n, const pl_doubles *boxes, const pl_ints *indices,
                   int **out);
/* The usual selection of a component: checks the boxes (6 numbers each, min
 * <= max) and that every index is within the state's rest positions, then
 * selects.  Errors are recorded against c.  Returns the count or -1. */
int pl_util_select_checked(const pl_component *c, pl_ctx *ctx, const pl_component *state,
                           const pl_doubles *boxes, const pl_ints *indices, int **out);
/* Checks a box list has a multiple of 6 numbers with min <= max. */
int pl_util_check_boxes(const pl_component *c, pl_ctx *ctx, const char *field,
                        const pl_doubles *boxes);

/* Rotation matrix (row-major 3x3) from degrees about x, then y, then z. */
void pl_util_rotation_deg(const double deg[3], double R[9]);
/* Rotation about a unit axis by angle [rad] (Rodrigues). */
void pl_util_axis_angle(const double axis[3], double angle, double R[9]);

#endif
