/* cmd_view.c - `pliant view`: the scene live in a window (GLFW), with the
 * keys and mouse of viewer/app.h; --script feeds the same input from a
 * file (tests, demonstrations). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "view_common.h"

static const char USAGE[] =
    "usage: pliant view SCENE.xml [OPTIONS]\n"
    "Runs the scene live in a window.  Keys: space play/pause, n step, r reset,\n"
    "t real time/fast, w wireframe, c colour field, f contact forces, v camera,\n"
    "o overlay, p screenshot, h help, q quit; other keys (or Ctrl+key) go to the\n"
    "scene (KeyboardController).  Mouse: left orbit, right pan, wheel zoom,\n"
    "Shift+left drag pulls a vertex.\n\n"
    "      --play             start playing (default: paused)\n"
    "      --fast             as fast as possible instead of real time\n"
    "      --script FILE      input from a file (step, key, drag, screenshot, print, quit)\n"
    VIEW_COMMON_HELP
    "exit codes: 0 ok, 1 internal error, 2 bad input (scene, arguments) or no display\n";

#if !defined(PLIANT_HAVE_VIEWER) || !defined(PLIANT_HAVE_GLFW)
int cli_view(int argc, char **argv)
{
    for (int k = 1; k < argc && strcmp(argv[k], "--"); ++k)
        if (!strcmp(argv[k], "-h") || !strcmp(argv[k], "--help")) return fputs(USAGE, stdout), 0;
    fprintf(stderr, "pliant view: this pliant was built without a window library (it needs "
                    "GLFW, OpenGL, EGL and libpng: make deps, then build again); pliant render "
                    "draws without a display when EGL is there\n");
    return 2;
}
#else
#include <getopt.h>
#include <stdlib.h>

#include "app.h"
#include "image.h"
#include "script.h"
#include "window.h"

typedef struct cmd_args {
    view_args v;
    const char *script;
    int play, fast;
} cmd_args;

enum { OPT_SCRIPT = 256, OPT_PLAY, OPT_FAST };

/* Returns 0, 2 on a bad command line, or -1 when --help was printed. */
static int parse(int argc, char **argv, cmd_args *a)
{
    static const struct option LONG[] = {{"script", required_argument, 0, OPT_SCRIPT},
                                         {"play", no_argument, 0, OPT_PLAY},
                                         {"fast", no_argument, 0, OPT_FAST},
                                         VIEW_COMMON_LONGOPTS,
                                         {0, 0, 0, 0}};
    memset(a, 0, sizeof *a);
    if (view_args_init(&a->v, argc, 1024, 768)) return 1;
    opterr = 0;
    int c, rc = 0;
    while (!rc && (c = getopt_long(argc, argv, VIEW_COMMON_SHORT, LONG, NULL)) != -1) {
        switch (c) {
        case OPT_SCRIPT: a->script = optarg; break;
        case OPT_PLAY: a->play = 1; break;
        case OPT_FAST: a->fast = 1; break;
        case 'h': fputs(USAGE, stdout); return -1;
        default:
            rc = view_common_option(&a->v, "view", c, optarg);
            rc = rc == 1 ? 0 : rc == 2 ? 2 : cli_bad_option("view", argv, optind, optopt);
        }
    }
    return rc ? rc : view_args_finish(&a->v, "view", argc, argv);
}

typedef struct shot_ctx {
    vw_app *app;
    vw_renderer *r;
} shot_ctx;

/* The script's screenshot: draws the frame again and saves it. */
static int shot(void *user, const char *file, pl_error *err)
{
    shot_ctx *s = user;
    int rc = vw_app_render(s->app, s->r, err);
    unsigned char *rgb = rc ? NULL : malloc((size_t)s->app->w * s->app->h * 3);
    if (rc) return rc;
    if (!rgb) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    vw_read_pixels(s->app->w, s->app->h, rgb);
    rc = vw_png_write(file, s->app->w, s->app->h, rgb, err);
    free(rgb);
    return rc;
}

static int loop(cmd_args *a, vw_window *win, vw_app *app, vw_renderer *r, vw_script *script,
                pl_error *err)
{
    double last = pl_now();
    shot_ctx sc = {app, r};
    int rc = PL_OK, done = 0;
    while (!rc && !done && !vw_window_should_close(win)) {
        rc = vw_window_poll(win, err);
        double now = pl_now();
        if (!rc && script)
            rc = vw_script_next(script, app, shot, &sc, &done, err);
        else if (!rc)
            rc = vw_app_advance(app, now - last, err);
        last = now;
        vw_window_size(win, &app->w, &app->h);
        if (!rc) rc = vw_app_render(app, r, err);
        if (!rc) vw_app_after_draw(app, r);
        vw_window_swap(win);
    }
    (void)a;
    return rc;
}

static int run(cmd_args *a, pl_sim *sim, vw_app *app, pl_error *err)
{
    vw_script script, *sp = NULL;
    if (a->script) {
        if (vw_script_load(&script, a->script, err) != PL_OK) return vw_script_free(&script), err->code;
        sp = &script;
    }
    char title[300];
    snprintf(title, sizeof title, "pliant view: %s", a->v.scene);
    vw_window *win = vw_window_open(a->v.w, a->v.h, title, err);
    vw_renderer *r = win ? vw_renderer_create(err) : NULL;
    int rc = r ? PL_OK : err->code;
    if (!rc) {
        int w, h;
        vw_window_size(win, &w, &h);
        rc = vw_app_init(app, sim, w, h, err);
    }
    if (!rc) {
        app->draw.field = (vw_field)a->v.field;
        app->draw.wireframe = a->v.wireframe;
        app->overlay = a->v.overlay;
        app->playing = a->play && !a->script;
        app->realtime = !a->fast;
        if (!a->v.quiet) printf("pliant view: %s (%s)\n", a->v.scene, vw_renderer_gl_name());
        vw_window_attach(win, app);
        rc = loop(a, win, app, r, sp, err);
        vw_window_attach(win, NULL);
    }
    vw_renderer_free(r);
    vw_window_close(win);
    if (sp) vw_script_free(sp);
    return rc;
}

int cli_view(int argc, char **argv)
{
    cmd_args a;
    int rc = parse(argc, argv, &a);
    if (rc) {
        view_args_free(&a.v);
        return rc < 0 ? 0 : rc;
    }
    vw_app app;
    memset(&app, 0, sizeof app);
    pl_sim *sim = NULL;
    rc = view_load(&a.v, &app, &sim);
    if (!rc) {
        pl_error err;
        pl_error_clear(&err);
        int code = run(&a, sim, &app, &err);
        if (code) {
            char msg[1600];
            fprintf(stderr, "pliant view: %s\n", pl_error_format(&err, msg, sizeof msg));
            rc = code == PL_EINPUT ? 2 : 1;
        }
    }
    vw_app_free(&app);
    pl_sim_free(sim);
    view_args_free(&a.v);
    return rc;
}
#endif
