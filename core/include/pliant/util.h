/* util.h - small helpers for writing components: finding partners by role,
 * selecting vertices by boxes, rotations.  Part of the SDK (implemented in
 * libpliant), so plugins built out of tree can use them too. */
#ifndef PLIANT_UTIL_H
#define PLIANT_UTIL_H

#include "api.h"
#include "pliant.h"

/* The topology a component uses: its link if set (must play the topology
 * role), else the first topology component of its node, else NULL. */
PL_API const pl_mesh *pl_util_topology(const pl_component *c, const pl_link *src, pl_ctx *ctx,
                                       int required);
/* The state of c's node (first PL_ROLE_STATE component), or NULL with an
 * error recorded when required. */
PL_API pl_component *pl_util_state(const pl_component *c, pl_ctx *ctx, int required);
/* Rest positions and count of a state. */
PL_API const double *pl_util_rest(const pl_component *state, int *n);

/* Vertices of x (n x 3) inside any of the boxes (6 numbers each:
 * xmin ymin zmin xmax ymax zmax) plus the explicit indices; sorted, unique.
 * Returns the count (>= 0) or -1 on allocation failure; *out is malloc'ed. */
PL_API int pl_util_select(const double *x, int n, const pl_doubles *boxes, const pl_ints *indices,
                          int **out);
/* The usual selection of a component: checks the boxes (6 numbers each, min
 * <= max) and that every index is within the state's rest positions, then
 * selects.  Errors are recorded against c.  Returns the count or -1. */
PL_API int pl_util_select_checked(const pl_component *c, pl_ctx *ctx, const pl_component *state,
                                  const pl_doubles *boxes, const pl_ints *indices, int **out);
/* Checks a box list has a multiple of 6 numbers with min <= max. */
PL_API int pl_util_check_boxes(const pl_component *c, pl_ctx *ctx, const char *field,
                               const pl_doubles *boxes);

#if PL_ABI_TARGET_MINOR >= 1
/* The device service (PL_ROLE_DEVICE) in c's node or above that has a
 * device: NULL when there is none, or when it reports PL_DEVICE_ABSENT (no
 * GPU here, or a build without CUDA).  Since ABI 5.1 (4.1 before 5.0). */
PL_API pl_component *pl_util_device(const pl_component *c);

/* A file named in a scene: absolute as is; otherwise relative to the scene
 * file's folder, then the working directory, then each folder of
 * PLIANT_DATA_PATH.  Returns 0 and the path in out, or -1 with the places
 * tried in `tried` (for the message).  Since ABI 5.1 (4.1 before 5.0). */
PL_API int pl_util_data_file(const char *scene_file, const char *name, char *out, size_t size,
                             char *tried, size_t tried_size);
#endif

/* Rotation matrix (row-major 3x3) from degrees about x, then y, then z. */
PL_API void pl_util_rotation_deg(const double deg[3], double R[9]);
/* Rotation about a unit axis by angle [rad] (Rodrigues). */
PL_API void pl_util_axis_angle(const double axis[3], double angle, double R[9]);

#endif
