/* offscreen.h - an OpenGL context without a display (EGL) and a
 * framebuffer to draw into: pliant render and the render tests.  EGL
 * picks a GPU when its driver offers one (EGL device platform), else
 * Mesa's software rasterizer (surfaceless platform, llvmpipe). */
#ifndef PLIANT_VW_OFFSCREEN_H
#define PLIANT_VW_OFFSCREEN_H

#include <pliant/error.h>

typedef struct vw_offscreen vw_offscreen;

/* Creates the context and a w x h framebuffer (4x multisampled), makes
 * them current.  NULL with err (PL_EINPUT: no usable EGL/OpenGL 3.3). */
vw_offscreen *vw_offscreen_create(int w, int h, pl_error *err);
void vw_offscreen_free(vw_offscreen *o);
/* Binds the framebuffer for drawing. */
void vw_offscreen_bind(vw_offscreen *o);
/* Resolves the samples and reads the picture (RGB, top row first). */
void vw_offscreen_read(vw_offscreen *o, unsigned char *rgb);
/* Which EGL display was used ("EGL device 0", "Mesa surfaceless"). */
const char *vw_offscreen_platform(const vw_offscreen *o);

#endif
