/* app_render.c - a frame of the viewer: the scene read from the state, drawn,
 * and the overlay (time, ms per step by phase, contacts, colour scale). */
#include "app.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Insertion sort (a handful of phases): Frame first, then slowest first. */
static void sort_phases(pl_timers *t, int *order, double *ms, int m)
{
    for (int i = 1; i < m; ++i)
        for (int j = i; j > 0; --j) {
            int frame = !strcmp(pl_timers_name(t, order[j]), "Frame");
            if (!frame && ms[j] <= ms[j - 1]) break;
            int o = order[j];
            double v = ms[j];
            order[j] = order[j - 1], ms[j] = ms[j - 1];
            order[j - 1] = o, ms[j - 1] = v;
        }
}

/* Per-phase milliseconds per step since the previous frame, as text. */
static void update_timings(vw_app *a)
{
    pl_timers *t = pl_sim_timers(a->sim);
    int n = pl_timers_count(t);
    long step = pl_sim_data(a->sim)->step, steps = step - a->steps_at_frame;
    if (n > a->nphases) {
        double *p = realloc(a->phase_total, (size_t)n * sizeof *p);
        if (!p) return;
        for (int k = a->nphases; k < n; ++k) p[k] = 0.0;
        a->phase_total = p, a->nphases = n;
    }
    if (steps <= 0) {
        if (step < a->steps_at_frame) a->steps_at_frame = step; /* after a reset */
        return;
    }
    /* Frame first, then the other phases, slowest first, at most 6 */
    int order[64], m = 0;
    double ms[64];
    for (int k = 0; k < n && m < 64; ++k) {
        double total = pl_timers_total_ms(t, k);
        ms[m] = (total - a->phase_total[k]) / steps;
        a->phase_total[k] = total;
        if (ms[m] > 0.0) order[m] = k, m++;
    }
    sort_phases(t, order, ms, m);
    size_t w = 0;
    a->phase_text[0] = '\0';
    for (int k = 0; k < m && k < 6 && w < sizeof a->phase_text; ++k) {
        int len = snprintf(a->phase_text + w, sizeof a->phase_text - w, "%s%s %.2f", w ? "  " : "",
                           pl_timers_name(t, order[k]), ms[k]);
        if (len > 0) w += (size_t)len;
    }
    a->steps_at_frame = step;
}

static const char *const HELP[] = {
    "space play/pause   n step   r reset   t real time/fast",
    "w wireframe   c colour field   f contact forces   o overlay",
    "v camera back   p screenshot   h help   q quit",
    "left drag orbit   right drag pan   wheel zoom",
    "shift+left drag: pull a vertex   other keys (or ctrl+key): the scene",
};

static void overlay(vw_app *a, vw_renderer *r)
{
    char l0[160], l1[220], l2[160];
    const pl_data *d = pl_sim_data(a->sim);
    const char *state = a->playing ? (a->realtime ? "playing, real time" : "playing, fast")
                                   : "paused";
    snprintf(l0, sizeof l0, "t = %.3f s   step %ld   %s   draw %.1f ms", d->time, d->step, state,
             a->wall_frame_ms);
    snprintf(l1, sizeof l1, "ms/step: %s", a->phase_text[0] ? a->phase_text : "-");
    if (a->draw.field == VW_FIELD_NONE)
        snprintf(l2, sizeof l2, "contacts %d   colour: none", a->scene.ncontacts);
    else
        snprintf(l2, sizeof l2, "contacts %d   colour: %s 0 .. %.3g %s", a->scene.ncontacts,
                 vw_field_name(a->draw.field), a->scene.field_max, vw_field_unit(a->draw.field));
    const char *lines[4] = {l0, l1, l2, a->message};
    int scale = a->h >= 700 ? 2 : 1;
    vw_renderer_text(r, a->w, a->h, lines, a->message[0] ? 4 : 3, 0, scale);
    if (a->help) vw_renderer_text(r, a->w, a->h, HELP, 5, 1, scale);
}

int vw_app_render(vw_app *a, vw_renderer *r, pl_error *err)
{
    double t0 = pl_now();
    int rc = vw_scene_update(&a->scene, a->draw.field, err);
    if (rc) return rc;
    a->draw.pick = a->picking;
    if (a->picking) {
        const double *x = &a->scene.bodies[a->pick_body].x[3 * a->pick_local];
        memcpy(a->draw.pick_from, x, sizeof a->draw.pick_from);
        vw_camera_unproject_at(&a->camera, a->w, a->h, a->mx, a->my, a->pick_plane,
                               a->draw.pick_to);
    }
    vw_renderer_draw(r, &a->scene, &a->camera, &a->draw, a->w, a->h);
    update_timings(a);
    if (a->overlay) overlay(a, r);
    a->wall_frame_ms = 1e3 * (pl_now() - t0);
    return PL_OK;
}
