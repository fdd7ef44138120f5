/* app.c - the viewer's input handling and stepping (app.h). */
#include "app.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image.h"
#include "vw_math.h"

int vw_app_init(vw_app *a, pl_sim *sim, int w, int h, pl_error *err)
{
    char pick[sizeof a->pick_path];
    memcpy(pick, a->pick_path, sizeof pick); /* set by vw_app_prepare during the load */
    memset(a, 0, sizeof *a);
    memcpy(a->pick_path, pick, sizeof pick);
    a->sim = sim;
    a->w = w, a->h = h;
    a->realtime = 1;
    a->overlay = 1;
    a->draw.field = VW_FIELD_DISPLACEMENT;
    a->draw.contacts = 1;
    a->pick_vertex = -1;
    int rc = vw_scene_init(&a->scene, sim, err);
    if (!rc) rc = vw_scene_update(&a->scene, a->draw.field, err);
    if (rc) return rc;
    vw_app_frame_camera(a);
    a->steps_at_frame = pl_sim_data(sim)->step;
    return PL_OK;
}

void vw_app_free(vw_app *a)
{
    vw_scene_free(&a->scene);
    free(a->phase_total);
    a->phase_total = NULL;
}

int vw_app_step(vw_app *a, int n, pl_error *err)
{
    return pl_sim_step(a->sim, n, err);
}

int vw_app_reset(vw_app *a, pl_error *err)
{
    if (pl_sim_reset(a->sim) != PL_OK)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "reset failed");
    vw_scene_reset_scale(&a->scene);
    a->lag = 0.0;
    a->steps_at_frame = pl_sim_data(a->sim)->step;
    snprintf(a->message, sizeof a->message, "reset to t = 0");
    return PL_OK;
}

int vw_app_advance(vw_app *a, double wall_dt, pl_error *err)
{
    if (!a->playing) return PL_OK;
    double dt = pl_node_dt(pl_sim_model(a->sim)->root), t0 = pl_now();
    if (a->realtime) {
        a->lag += wall_dt;
        if (a->lag > 0.25) a->lag = 0.25; /* slower than real time: no catching up */
        int rc = PL_OK;
        while (!rc && a->lag >= dt && pl_now() - t0 < 0.1) {
            rc = pl_sim_step(a->sim, 1, err);
            a->lag -= dt;
        }
        return rc;
    }
    int rc = pl_sim_step(a->sim, 1, err);
    while (!rc && pl_now() - t0 < 0.03) rc = pl_sim_step(a->sim, 1, err);
    return rc;
}

/* ---- keys ---------------------------------------------------------------- */

static void screenshot(vw_app *a, vw_renderer *r)
{
    (void)r;
    unsigned char *rgb = malloc((size_t)a->w * a->h * 3);
    char name[64];
    pl_error e;
    snprintf(name, sizeof name, "pliant_view_%04d.png", a->screenshots++);
    if (!rgb) return;
    vw_read_pixels(a->w, a->h, rgb);
    if (vw_png_write(name, a->w, a->h, rgb, &e) == PL_OK)
        snprintf(a->message, sizeof a->message, "saved %s", name);
    else
        snprintf(a->message, sizeof a->message, "%.180s", e.msg);
    free(rgb);
}

/* Sends a key to the scene's event components. */
static int key_to_scene(vw_app *a, int key, pl_error *err)
{
    pl_event ev = {PL_EVENT_KEY_PRESSED, key};
    int used = 0;
    int rc = pl_sim_send_event(a->sim, &ev, &used, err);
    if (rc) return rc;
    if (key >= 32 && key < 127)
        snprintf(a->message, sizeof a->message, "key '%c' %s", key,
                 used ? "sent to the scene" : "(no component of the scene uses it)");
    else
        snprintf(a->message, sizeof a->message, "key %d %s", key,
                 used ? "sent to the scene" : "(no component of the scene uses it)");
    return PL_OK;
}

static int viewer_key(vw_app *a, int key, pl_error *err, int *handled)
{
    *handled = 1;
    switch (key) {
    case ' ': a->playing = !a->playing, a->lag = 0.0; break;
    case 'n': a->playing = 0; return vw_app_step(a, 1, err);
    case 'r': return vw_app_reset(a, err);
    case 't': a->realtime = !a->realtime, a->lag = 0.0; break;
    case 'w': a->draw.wireframe = !a->draw.wireframe; break;
    case 'c':
        a->draw.field = (vw_field)((a->draw.field + 1) % VW_FIELD_COUNT);
        vw_scene_reset_scale(&a->scene);
        break;
    case 'f': a->draw.contacts = !a->draw.contacts; break;
    case 'v': a->camera = a->camera0; break;
    case 'o': a->overlay = !a->overlay; break;
    case 'h': a->help = !a->help; break;
    case 'p': a->want_screenshot = 1; break; /* taken after the next draw */
    case 'q':
    case VW_KEY_ESCAPE: a->quit = 1; break;
    default: *handled = 0;
    }
    return PL_OK;
}

/* ---- the mouse spring ---------------------------------------------------- */

static int set_pick(vw_app *a, const char *field, const char *value, pl_error *err)
{
    char path[300];
    snprintf(path, sizeof path, "%s.%s", a->pick_path, field);
    return pl_sim_set(a->sim, path, value, err);
}

static int pick_start(vw_app *a, pl_error *err)
{
    double o[3], d[3], hit[3];
    int body, v;
    if (!a->pick_path[0]) {
        snprintf(a->message, sizeof a->message,
                 "no mouse spring in this scene (it needs a LocalGlobalSolver and the "
                 "ncp_contact plugin)");
        return PL_OK;
    }
    vw_camera_ray(&a->camera, a->w, a->h, a->mx, a->my, o, d);
    if (!vw_scene_pick(&a->scene, o, d, &body, &v, hit)) return PL_OK;
    int g = vw_scene_global_vertex(&a->scene, body, v);
    if (g < 0) return PL_OK;
    char text[96];
    memcpy(a->pick_plane, hit, sizeof hit);
    const double *x = &a->scene.bodies[body].x[3 * v];
    snprintf(text, sizeof text, "%.17g %.17g %.17g", x[0], x[1], x[2]);
    int rc = set_pick(a, "target", text, err);
    snprintf(text, sizeof text, "%d", g);
    if (!rc) rc = set_pick(a, "vertex", text, err);
    if (rc) return rc;
    a->picking = 1;
    a->pick_body = body, a->pick_local = v, a->pick_vertex = g;
    snprintf(a->message, sizeof a->message, "dragging vertex %d of %s", v,
             a->scene.bodies[body].state->node->name);
    return PL_OK;
}

static int pick_move(vw_app *a, pl_error *err)
{
    double p[3];
    char text[96];
    vw_camera_unproject_at(&a->camera, a->w, a->h, a->mx, a->my, a->pick_plane, p);
    snprintf(text, sizeof text, "%.17g %.17g %.17g", p[0], p[1], p[2]);
    return set_pick(a, "target", text, err);
}

static int pick_stop(vw_app *a, pl_error *err)
{
    a->picking = 0;
    a->pick_vertex = -1;
    return set_pick(a, "vertex", "-1", err);
}

/* ---- input --------------------------------------------------------------- */

static int mouse_button(vw_app *a, const vw_input *in, pl_error *err)
{
    a->mx = in->x, a->my = in->y;
    if (in->button < 0 || in->button > 2) return PL_OK;
    a->buttons[in->button] = in->pressed;
    a->mods = in->mods;
    if (in->button == 0 && in->pressed && (in->mods & VW_MOD_SHIFT)) return pick_start(a, err);
    if (in->button == 0 && !in->pressed && a->picking) return pick_stop(a, err);
    return PL_OK;
}

static int mouse_move(vw_app *a, const vw_input *in, pl_error *err)
{
    double dx = in->x - a->mx, dy = in->y - a->my;
    a->mx = in->x, a->my = in->y;
    if (a->picking) return pick_move(a, err);
    if (a->buttons[0]) vw_camera_orbit(&a->camera, dx, dy);
    if (a->buttons[1] || a->buttons[2]) vw_camera_pan(&a->camera, dx, dy, a->h);
    return PL_OK;
}

int vw_app_input(vw_app *a, const vw_input *in, pl_error *err)
{
    switch (in->kind) {
    case VW_IN_KEY: {
        int handled = 0;
        if (!(in->mods & VW_MOD_CTRL)) {
            int rc = viewer_key(a, in->key, err, &handled);
            if (rc || handled) return rc;
        }
        return key_to_scene(a, in->key, err);
    }
    case VW_IN_BUTTON: return mouse_button(a, in, err);
    case VW_IN_MOVE: return mouse_move(a, in, err);
    case VW_IN_SCROLL: vw_camera_zoom(&a->camera, pow(1.1, in->y)); return PL_OK;
    case VW_IN_RESIZE:
        a->w = (int)in->x, a->h = (int)in->y;
        return PL_OK;
    }
    return PL_OK;
}

/* Called by vw_app_render after drawing: a pending 'p'. */
void vw_app_after_draw(vw_app *a, vw_renderer *r)
{
    if (a->want_screenshot) {
        a->want_screenshot = 0;
        screenshot(a, r);
    }
}
