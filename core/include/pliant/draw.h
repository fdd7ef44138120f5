/* draw.h - what a component shows: the drawing of the visual role.
 *
 * As SOFA's draw(vparams) with its DrawTool, a component that plays
 * PL_ROLE_VISUAL (roles.h) adds parts to a pl_drawing for a state d:
 * rigid surfaces as triangles (obstacles, at their pose at d->time), lines
 * (cable paths) and points with a vector each (contacts and the force on
 * the body).  The viewer renders the parts and VTKExporter writes them next
 * to the bodies, so both show the same scene.  Bodies (states with their
 * topology) are not drawn through this role: their readers use the state
 * and topology roles, which give per-vertex fields too.
 *
 *     pl_draw_part *p = pl_drawing_add(dw, c, PL_DRAW_OBSTACLE);
 *     int first = p ? pl_draw_vertices(p, x, NULL, nverts) : -1;
 *     if (first < 0 || pl_draw_triangles(p, tris, ntris, first)) return PL_EINTERNAL;
 */
#ifndef PLIANT_DRAW_H
#define PLIANT_DRAW_H

#include "api.h"
#include "component.h"

#ifdef __cplusplus
extern "C" {
#endif

#if PL_ABI_TARGET_MINOR >= 2 /* the drawing is new in ABI 5.2 */

typedef enum pl_draw_kind {
    PL_DRAW_OBSTACLE = 0, /* a rigid surface: triangles */
    PL_DRAW_CABLE = 1,    /* lines (cable paths) */
    PL_DRAW_CONTACTS = 2  /* points, each with a vector: the force on the body [N] */
} pl_draw_kind;

typedef struct pl_draw_part {
    const pl_component *owner;
    pl_draw_kind kind;
    int unbounded;    /* a shape without an extent of its own drawn as a finite patch (a
                         plane, sized after the bodies): left out of the scene's bounds */
    int nverts, cap_verts;
    double *x;        /* nverts x 3 [m] */
    double *vec;      /* nverts x 3: a vector per point (0 when none was given) */
    int ntris, cap_tris;
    int *tris;        /* ntris x 3 into x */
    int nlines, cap_lines;
    int *lines;       /* nlines x 2 into x */
} pl_draw_part;

typedef struct pl_drawing {
    pl_draw_part *parts;
    int nparts, cap_parts;
} pl_drawing;

PL_API void pl_drawing_init(pl_drawing *dw);
PL_API void pl_drawing_free(pl_drawing *dw);
/* Empties the drawing but keeps its memory (a viewer redraws every frame). */
PL_API void pl_drawing_clear(pl_drawing *dw);
/* Starts a part owned by c; NULL on allocation failure. */
PL_API pl_draw_part *pl_drawing_add(pl_drawing *dw, const pl_component *c, pl_draw_kind kind);
/* Appends n points (x: n x 3) with their vectors (vec: n x 3, or NULL for
 * zeros); returns the index of the first one, or -1 on allocation failure. */
PL_API int pl_draw_vertices(pl_draw_part *p, const double *x, const double *vec, int n);
/* Appends n triangles (n x 3) / segments (n x 2) whose indices are
 * relative to `base` (the value pl_draw_vertices returned); PL_OK or
 * PL_EINTERNAL (allocation), PL_EINPUT for an index outside the part. */
PL_API int pl_draw_triangles(pl_draw_part *p, const int *tris, int n, int base);
PL_API int pl_draw_lines(pl_draw_part *p, const int *lines, int n, int base);
/* Appends the polyline through n points (n - 1 segments). */
PL_API int pl_draw_polyline(pl_draw_part *p, const double *x, int n);

/* Every component of the subtree of `root` that plays the visual role draws
 * into dw (scene order), for state d.  Stops at the first error. */
struct pl_node;
struct pl_data;
PL_API int pl_drawing_collect(struct pl_node *root, const struct pl_data *d, pl_drawing *dw,
                              pl_error *err);

#endif /* PL_ABI_TARGET_MINOR >= 2 */

#ifdef __cplusplus
}
#endif
#endif
