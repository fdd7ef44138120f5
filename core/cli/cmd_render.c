/* cmd_render.c - `pliant render`: a scene's pictures without a display
 * (EGL), as PNG files and/or an MP4 film, with the viewer's camera and
 * drawing: every K-th step from step S to step N. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "view_common.h"

static const char USAGE[] =
    "usage: pliant render SCENE.xml -n STEPS (--png DIR | --mp4 FILE) [OPTIONS]\n"
    "Draws the scene without a display (EGL: the GPU, else Mesa's software renderer)\n"
    "at steps 0, K, 2K, ... up to STEPS, as pliant view shows it.\n\n"
    "  -n, --steps N          time steps to simulate\n"
    "      --every K          a picture every K steps (default 1)\n"
    "      --from S           no pictures before step S (default 0); the camera is\n"
    "                         framed on the scene at step S\n"
    "      --png DIR          DIR/<scene>_0000.png, ... (frame numbers)\n"
    "      --mp4 FILE         an H.264 film (ffmpeg)\n"
    "      --fps F            film frames per second (default: real time)\n"
    "      --progress S       in a log (stderr not a terminal) a progress line every S\n"
    "                         seconds (default 5; 0 = none)\n"
    VIEW_COMMON_HELP
    "exit codes: 0 ok, 1 internal error, 2 bad input (scene, arguments) or no way to draw\n";

#ifndef PLIANT_HAVE_VIEWER
int cli_render(int argc, char **argv)
{
    for (int k = 1; k < argc && strcmp(argv[k], "--"); ++k)
        if (!strcmp(argv[k], "-h") || !strcmp(argv[k], "--help")) return fputs(USAGE, stdout), 0;
    fprintf(stderr, "pliant render: this pliant was built without the viewer (it needs "
                    "OpenGL, EGL and libpng: make deps, then build again)\n");
    return 2;
}
#else
#include <errno.h>
#include <getopt.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>

#include "app.h"
#include "image.h"
#include "offscreen.h"

typedef struct render_args {
    view_args v;
    int steps, every, from, fps;
    double progress;
    const char *png, *mp4;
} render_args;

enum { OPT_EVERY = 256, OPT_FROM, OPT_PNG, OPT_MP4, OPT_FPS, OPT_PROGRESS };

static int render_option(render_args *a, int c, const char *arg)
{
    switch (c) {
    case 'n': return cli_parse_int("render", "--steps", arg, 0, &a->steps);
    case OPT_EVERY: return cli_parse_int("render", "--every", arg, 1, &a->every);
    case OPT_FROM: return cli_parse_int("render", "--from", arg, 0, &a->from);
    case OPT_FPS: return cli_parse_int("render", "--fps", arg, 1, &a->fps);
    case OPT_PROGRESS: return cli_parse_double("render", "--progress", arg, &a->progress);
    case OPT_PNG: a->png = arg; return 0;
    case OPT_MP4: a->mp4 = arg; return 0;
    }
    int rc = view_common_option(&a->v, "render", c, arg);
    return rc == 1 ? 0 : rc == 2 ? 2 : -1;
}

/* Returns 0, 2 on a bad command line, or -1 when --help was printed. */
static int parse(int argc, char **argv, render_args *a)
{
    static const struct option LONG[] = {
        {"steps", required_argument, 0, 'n'},     {"every", required_argument, 0, OPT_EVERY},
        {"from", required_argument, 0, OPT_FROM}, {"png", required_argument, 0, OPT_PNG},
        {"mp4", required_argument, 0, OPT_MP4},   {"fps", required_argument, 0, OPT_FPS},
        {"progress", required_argument, 0, OPT_PROGRESS}, VIEW_COMMON_LONGOPTS, {0, 0, 0, 0}};
    memset(a, 0, sizeof *a);
    if (view_args_init(&a->v, argc, 640, 480)) return 1;
    a->steps = -1, a->every = 1, a->progress = 5.0;
    opterr = 0;
    int c, rc = 0;
    while (!rc && (c = getopt_long(argc, argv, "n:" VIEW_COMMON_SHORT, LONG, NULL)) != -1) {
        if (c == 'h') return fputs(USAGE, stdout), -1;
        rc = render_option(a, c, optarg);
        if (rc < 0) rc = cli_bad_option("render", argv, optind, optopt);
    }
    if (!rc) rc = view_args_finish(&a->v, "render", argc, argv);
    if (rc) return rc;
    if (a->steps < 0) return cli_usage_error("render", "give the steps (-n N)");
    if (!a->png && !a->mp4)
        return cli_usage_error("render", "nothing to write: give --png DIR or --mp4 FILE");
    if (a->mp4 && (a->v.w % 2 || a->v.h % 2))
        return cli_usage_error("render", "an MP4 needs an even width and height (--size)");
    return 0;
}

typedef struct renderer_out {
    vw_offscreen *off;
    vw_renderer *r;
    vw_video *video;
    unsigned char *rgb;
    int frames;
} renderer_out;

static int one_frame(render_args *a, vw_app *app, renderer_out *o, pl_error *err)
{
    vw_offscreen_bind(o->off);
    int rc = vw_app_render(app, o->r, err);
    if (rc) return rc;
    vw_offscreen_read(o->off, o->rgb);
    if (a->png) {
        char name[128], path[4096];
        cli_scene_name(a->v.scene, name, sizeof name);
        snprintf(path, sizeof path, "%s/%s_%04d.png", a->png, name, o->frames);
        rc = vw_png_write(path, a->v.w, a->v.h, o->rgb, err);
    }
    if (!rc && o->video) rc = vw_video_frame(o->video, o->rgb, err);
    if (!rc) o->frames++;
    return rc;
}

static int run(render_args *a, vw_app *app, pl_sim *sim, renderer_out *o, pl_error *err)
{
    int rc = PL_OK, step = 0;
    cli_progress prog;
    cli_progress_start(&prog, a->steps, a->v.quiet, a->progress);
    for (; !rc; ++step) {
        /* the camera frames the scene as it is when the pictures begin */
        if (step == a->from && step > 0 && !(rc = vw_scene_update(&app->scene, app->draw.field, err)))
            vw_app_frame_camera(app);
        if (!rc && step >= a->from && step % a->every == 0) rc = one_frame(a, app, o, err);
        if (rc || step == a->steps) break;
        cli_progress_update(&prog, step, pl_sim_time(sim));
        rc = pl_sim_step(sim, 1, err);
    }
    cli_progress_finish(&prog, step, pl_sim_time(sim));
    return rc;
}

static int setup(render_args *a, vw_app *app, pl_sim *sim, renderer_out *o, pl_error *err)
{
    if (a->png && cli_make_dirs(a->png) != 0)
        return pl_error_set(err, PL_EINPUT, a->png, 0, NULL, "cannot make the folder: %s",
                            strerror(errno));
    o->off = vw_offscreen_create(a->v.w, a->v.h, err);
    if (!o->off) return err->code;
    if (!(o->r = vw_renderer_create(err))) return err->code;
    if (!(o->rgb = malloc((size_t)a->v.w * a->v.h * 3)))
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    int rc = vw_app_init(app, sim, a->v.w, a->v.h, err);
    if (rc) return rc;
    app->draw.field = (vw_field)a->v.field;
    app->draw.wireframe = a->v.wireframe;
    app->overlay = a->v.overlay;
    if (a->mp4) {
        int fps = a->fps;
        if (!fps) {
            double dt = pl_node_dt(pl_sim_model(sim)->root) * a->every;
            fps = dt > 0.0 ? (int)(1.0 / dt + 0.5) : 30;
            fps = fps < 1 ? 1 : fps > 60 ? 60 : fps;
        }
        signal(SIGPIPE, SIG_IGN); /* a dead ffmpeg is an error, not a crash */
        if (!(o->video = vw_video_open(a->mp4, a->v.w, a->v.h, fps, err))) return err->code;
    }
    return PL_OK;
}

int cli_render(int argc, char **argv)
{
    render_args a;
    int rc = parse(argc, argv, &a);
    if (rc) {
        view_args_free(&a.v);
        return rc < 0 ? 0 : rc;
    }
    vw_app app;
    memset(&app, 0, sizeof app);
    pl_sim *sim = NULL;
    renderer_out o = {0};
    pl_error err;
    pl_error_clear(&err);
    double t0 = pl_now();
    rc = view_load(&a.v, &app, &sim);
    if (!rc) {
        int code = setup(&a, &app, sim, &o, &err);
        if (!code) code = run(&a, &app, sim, &o, &err);
        int vcode = vw_video_close(o.video, code ? NULL : &err);
        if (!code) code = vcode;
        if (code) {
            char msg[1600];
            fprintf(stderr, "pliant render: %s\n", pl_error_format(&err, msg, sizeof msg));
            rc = code == PL_EINPUT ? 2 : 1;
        } else {
            printf("%s: %d frame%s of %dx%d in %.1f s (%s; %s), %d thread%s", a.v.scene,
                   o.frames, o.frames == 1 ? "" : "s", a.v.w, a.v.h, pl_now() - t0,
                   vw_renderer_gl_name(), vw_offscreen_platform(o.off), a.v.threads,
                   a.v.threads == 1 ? "" : "s");
            if (a.png) printf("; PNG: %s/", a.png);
            if (a.mp4) printf("; MP4: %s", a.mp4);
            printf("\n");
        }
    }
    vw_app_free(&app);
    vw_renderer_free(o.r);
    vw_offscreen_free(o.off);
    free(o.rgb);
    pl_sim_free(sim);
    view_args_free(&a.v);
    return rc;
}
#endif
