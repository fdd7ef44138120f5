/* shape_draw.h - triangles of an analytic shape for the visual role
 * (plugin-internal). */
#ifndef PLIANT_COLLISION_SHAPE_DRAW_H
#define PLIANT_COLLISION_SHAPE_DRAW_H

#include "collision.h"
#include "pliant/pliant.h"

/* Appends the surface of s (as posed) to p.  A plane becomes a square patch
 * of half side `half` [m] around the projection of `around` onto it (both
 * are ignored for the other shapes).  PL_OK or PL_EINTERNAL. */
int coll_shape_draw(const pl_shape *s, const double around[3], double half, pl_draw_part *p);

/* Helpers of the plugin's visual roles (obstacle_draw.c): the centre and
 * the largest extent [m] of the bodies of c's scene (rest positions of
 * every state), and a contacts part of n records (stride bytes apart) whose
 * point and force [N] are the doubles at the given offsets. */
void coll_scene_extent(const pl_component *c, double center[3], double *extent);
int coll_draw_contacts(const pl_component *c, pl_drawing *dw, const void *items, int n,
                       size_t stride, size_t point_at, size_t force_at);

#endif
