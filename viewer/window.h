/* window.h - pliant view's window (GLFW, OpenGL 3.3 core): turns GLFW's
 * key, character, mouse and resize callbacks into vw_app input events. */
#ifndef PLIANT_VW_WINDOW_H
#define PLIANT_VW_WINDOW_H

#include "app.h"

typedef struct vw_window vw_window;

/* Opens a w x h window titled `title` and makes its context current.
 * NULL with err (PL_EINPUT, saying why) when there is no display or no
 * OpenGL 3.3. */
vw_window *vw_window_open(int w, int h, const char *title, pl_error *err);
void vw_window_close(vw_window *win);
/* Events from now on go to app (NULL: none). */
void vw_window_attach(vw_window *win, vw_app *app);
/* Handles pending events; returns the first error an event caused. */
int vw_window_poll(vw_window *win, pl_error *err);
int vw_window_should_close(const vw_window *win);
/* The framebuffer's size in pixels. */
void vw_window_size(const vw_window *win, int *w, int *h);
void vw_window_swap(vw_window *win);

#endif
