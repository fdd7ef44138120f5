/* render.h - draws a vw_scene with OpenGL 3.3 (core profile) into the
 * framebuffer that is bound: the window's (pliant view) or an off-screen
 * one (pliant render), so both make the same pictures.  Needs a current GL
 * context for every call. */
#ifndef PLIANT_VW_RENDER_H
#define PLIANT_VW_RENDER_H

#include "camera.h"
#include "scene.h"

typedef struct vw_draw_options {
    vw_field field;       /* colours the bodies by it (VW_FIELD_NONE: one colour) */
    int wireframe;        /* edges over the surfaces */
    int contacts;         /* contact points and force arrows */
    int pick;             /* a pick spring is drawn from pick_from to pick_to */
    double pick_from[3], pick_to[3];
} vw_draw_options;

typedef struct vw_renderer vw_renderer;

/* Compiles the shaders, makes the buffers and the font texture.  NULL with
 * err set when the context lacks OpenGL 3.3. */
vw_renderer *vw_renderer_create(pl_error *err);
void vw_renderer_free(vw_renderer *r);
/* The GL_RENDERER and GL_VERSION strings ("llvmpipe ...", "4.5 ..."). */
const char *vw_renderer_gl_name(void);

/* The background colour (the tests compare pixels against it). */
extern const float VW_BACKGROUND[3];

/* Clears and draws the scene for a w x h viewport. */
void vw_renderer_draw(vw_renderer *r, const vw_scene *s, const vw_camera *c,
                      const vw_draw_options *o, int w, int h);
/* Draws lines of text in a box at the top left (corner 0) or bottom left
 * (corner 1) of the viewport, `scale` screen pixels per font pixel. */
void vw_renderer_text(vw_renderer *r, int w, int h, const char *const *lines, int n, int corner,
                      int scale);
/* Reads the bound framebuffer's w x h pixels as RGB, top row first. */
void vw_read_pixels(int w, int h, unsigned char *rgb);

#endif
