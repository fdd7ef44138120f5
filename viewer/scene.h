/* scene.h - what the viewer draws, read from a loaded simulation through
 * the public API only: the bodies (every state, its positions and the
 * surface of its topology: the boundary of its tetrahedra, or its
 * triangles), a per-vertex field to colour them by, and the drawing of the
 * visual components (obstacles, cables, contacts: pliant/draw.h).  Read
 * once per displayed frame: on the GPU path this is where positions come
 * back to the host. */
#ifndef PLIANT_VW_SCENE_H
#define PLIANT_VW_SCENE_H

#include <pliant/pliant.h>

typedef enum vw_field {
    VW_FIELD_NONE = 0,     /* one colour */
    VW_FIELD_DISPLACEMENT, /* |x - rest| [m] */
    VW_FIELD_VELOCITY,     /* |v| [m/s] */
    VW_FIELD_FORCE,        /* |constraint force| [N] */
    VW_FIELD_COUNT
} vw_field;

/* Name and unit of a field ("displacement", "m"). */
const char *vw_field_name(vw_field f);
const char *vw_field_unit(vw_field f);
/* The field named s, or -1. */
int vw_field_parse(const char *s);

typedef struct vw_body {
    pl_component *state;
    int n;               /* vertices */
    int *tris, ntris;    /* surface triangles into the vertices (0: points only) */
    double *x;           /* n x 3: positions of the frame [m] */
    double *value;       /* n: the field of the frame */
} vw_body;

typedef struct vw_scene {
    pl_sim *sim;
    vw_body *bodies;
    int nbodies;
    pl_drawing drawing;  /* obstacles, cables, contacts of the frame */
    double lo[3], hi[3]; /* bounds of bodies and obstacles in the frame */
    double field_max;    /* largest field value since the last reset (colour scale) */
    int ncontacts;       /* contact points in the frame */
} vw_scene;

/* Finds the bodies of a loaded simulation.  PL_OK, or an error with err. */
int vw_scene_init(vw_scene *s, pl_sim *sim, pl_error *err);
void vw_scene_free(vw_scene *s);
/* Reads the frame: positions, field values, drawing, bounds. */
int vw_scene_update(vw_scene *s, vw_field field, pl_error *err);
/* Forget the colour scale (after a reset or a field change). */
void vw_scene_reset_scale(vw_scene *s);

/* The nearest body triangle the ray (o, unit d) hits: its body, the vertex
 * of the triangle nearest to the hit point and the hit point.  0 if none. */
int vw_scene_pick(const vw_scene *s, const double o[3], const double d[3], int *body, int *vertex,
                  double hit[3]);
/* Global index of vertex v of body b (-1 when the loop has not numbered it). */
int vw_scene_global_vertex(const vw_scene *s, int b, int v);
/* Mean of the vertices of body b. */
void vw_scene_centroid(const vw_scene *s, int b, double c[3]);

/* ParaView's "cool to warm" colour map at s in [0, 1]. */
void vw_colormap(double s, float rgb[3]);

#endif
