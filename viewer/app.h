/* app.h - the viewer's behaviour, apart from any window: a simulation, its
 * scene, the camera, what is drawn, and what keys and the mouse do.  The
 * GLFW window (pliant view) and the scripted tests feed it the same input
 * events; pliant render drives it without input.
 *
 * Keys of the viewer: space play/pause, n one step, r reset, t real time /
 * as fast as possible, w wireframe, c next colour field, f contact forces,
 * v camera back to the start, o overlay, h help, p screenshot, q or Esc
 * quit.  Every other key, and every key with Ctrl held (as in runSofa),
 * goes to the scene (pl_sim_send_event: KeyboardController and
 * controllers).  Mouse: left drag orbits, right or middle drag pans, the
 * wheel zooms, Shift + left drag pulls a vertex with a spring (PickSpring). */
#ifndef PLIANT_VW_APP_H
#define PLIANT_VW_APP_H

#include "camera.h"
#include "render.h"
#include "scene.h"

/* Keys that are neither characters nor pl_event keys. */
enum { VW_KEY_ESCAPE = 0x1B, VW_KEY_SPACE = ' ' };
enum { VW_MOD_SHIFT = 1, VW_MOD_CTRL = 2 };

typedef enum vw_input_kind {
    VW_IN_KEY,      /* key (a character, VW_KEY_*, PL_KEY_*), mods */
    VW_IN_BUTTON,   /* button (0 left, 1 right, 2 middle), pressed, mods, x, y */
    VW_IN_MOVE,     /* x, y */
    VW_IN_SCROLL,   /* y: wheel steps (> 0: away from the user, zoom in) */
    VW_IN_RESIZE    /* x, y: the new width and height */
} vw_input_kind;

typedef struct vw_input {
    vw_input_kind kind;
    int key, mods, button, pressed;
    double x, y;    /* pixels from the top left */
} vw_input;

typedef struct vw_app {
    pl_sim *sim;
    vw_scene scene;
    vw_camera camera, camera0;
    vw_draw_options draw;
    int w, h;
    int playing, realtime, overlay, help, quit;
    double lag;                 /* simulated time owed to the wall clock [s] */
    int buttons[3], mods;
    double mx, my;
    /* the mouse spring */
    char pick_path[256];        /* "root/viewerPick" or "" when the scene cannot have one */
    int picking, pick_vertex, pick_body, pick_local;
    double pick_plane[3];       /* the grabbed point: the drag plane passes through it */
    /* the overlay's timings: per-phase totals at the last frame */
    double *phase_total;
    int nphases;
    long steps_at_frame;
    double ms_per_step[16];
    char phase_text[192];
    double wall_frame_ms;       /* wall time of the last displayed frame */
    char message[192];          /* the last notice (errors, a key sent to the scene) */
    int screenshots, want_screenshot;
} vw_app;

/* The prepare hook of pl_sim_load_file_prepared (user: the vw_app): adds a
 * PickSpring named viewerPick next to the animation loop, and a
 * NonSmoothNewtonContactSolver when the loop has none (the spring is a
 * constraint), so that vertices can be dragged in any scene. */
int vw_app_prepare(pl_node *root, pl_registry *reg, pl_diag *diag, void *app);

/* Reads the scene, frames the camera (or takes the InteractiveCamera). */
int vw_app_init(vw_app *a, pl_sim *sim, int w, int h, pl_error *err);
void vw_app_free(vw_app *a);
/* Handles one input event.  PL_OK, or an error of the simulation. */
int vw_app_input(vw_app *a, const vw_input *in, pl_error *err);
/* Advances the simulation for a displayed frame that took wall_dt seconds:
 * playing in real time, as many steps as simulated time fell behind (at
 * most 100 ms of computing); as fast as possible, steps for about 30 ms. */
int vw_app_advance(vw_app *a, double wall_dt, pl_error *err);
int vw_app_step(vw_app *a, int n, pl_error *err);
int vw_app_reset(vw_app *a, pl_error *err);
/* Puts the camera at the scene's InteractiveCamera, else frames the bodies
 * and obstacles of the frame read last; 'v' comes back to it. */
void vw_app_frame_camera(vw_app *a);
/* Saves pliant_view_NNNN.png when 'p' was pressed (after a draw). */
void vw_app_after_draw(vw_app *a, vw_renderer *r);
/* Reads the frame and draws it with the overlay into the bound framebuffer. */
int vw_app_render(vw_app *a, vw_renderer *r, pl_error *err);

#endif
