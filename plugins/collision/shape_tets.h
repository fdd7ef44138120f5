/* shape_tets.h - the ImplicitTetrahedra generator's internals (plugin-
 * internal): its fields, the shape's inside test and signed distance, and
 * the snapping of the boundary vertices onto the surface. */
#ifndef PLIANT_COLLISION_SHAPE_TETS_H
#define PLIANT_COLLISION_SHAPE_TETS_H

#include "pliant/pliant.h"
#include "pliant/util.h"

typedef struct shape_tets {
    pl_component base;
    pl_mesh mesh; /* right after base: the topology role reads it */
    pl_doubles ellipsoids, capsules, boxes, clip;
    double cell;
    int smooth;
    double rotation[3], translation[3];
} shape_tets;

/* Whether p is inside the union (and the clip box). */
int coll_shape_inside(const shape_tets *s, const double p[3]);
/* Signed distance-like field of the shape [m]: negative inside, 0 on the
 * surface, distance-like near it (exact for capsules and boxes, scaled for
 * ellipsoids); union = min, clip = max. */
double coll_shape_field(const shape_tets *s, const double p[3]);
/* Signed volume of tetrahedron t of the vertex array v. */
double coll_tet_volume(const double *v, const int *t);
/* Moves the boundary vertices (flags per vertex) of m onto the zero level of
 * the field by a few Newton steps, at most 0.45 cellSize each, then pulls
 * back the vertices of any tetrahedron that became flat or inverted.
 * PL_OK or PL_EINTERNAL. */
int coll_shape_snap(const shape_tets *s, pl_mesh *m, const unsigned char *boundary);

#endif
