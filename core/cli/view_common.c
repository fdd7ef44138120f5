/* view_common.c - options and loading shared by pliant view and render. */
#ifdef PLIANT_HAVE_VIEWER
#include "view_common.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "cli.h"

int view_args_init(view_args *a, int argc, int w, int h)
{
    memset(a, 0, sizeof *a);
    a->sets = calloc((size_t)argc + 1, sizeof *a->sets);
    a->w = w, a->h = h;
    a->field = VW_FIELD_DISPLACEMENT;
    a->overlay = 1;
    return a->sets ? 0 : 1;
}

void view_args_free(view_args *a)
{
    free(a->sets);
    a->sets = NULL;
}

int view_common_option(view_args *a, const char *cmd, int opt, const char *arg)
{
    switch (opt) {
    case 's': a->sets[a->nsets++] = arg; return 1;
    case 'o':
        if (strlen(arg) >= sizeof a->out)
            return cli_usage_error(cmd, "--out: the folder name is too long");
        snprintf(a->out, sizeof a->out, "%s", arg);
        a->has_out = 1;
        return 1;
    case 'j': return cli_parse_int(cmd, "--threads", arg, 1, &a->threads) ? 2 : 1;
    case 'q': a->quiet = 1; return 1;
    case VOPT_DEVICE:
        if (strcmp(arg, "cpu") && strcmp(arg, "auto") && strcmp(arg, "gpu-always"))
            return cli_usage_error(cmd, "--device expects cpu, auto or gpu-always, got '%s'", arg);
        a->device = arg;
        return 1;
    case VOPT_SIZE:
        if (sscanf(arg, "%dx%d", &a->w, &a->h) != 2 || a->w < 16 || a->h < 16 || a->w > 8192 ||
            a->h > 8192)
            return cli_usage_error(cmd, "--size expects WxH between 16 and 8192 (e.g. 640x480), "
                                        "got '%s'", arg);
        return 1;
    case VOPT_FIELD:
        if ((a->field = vw_field_parse(arg)) < 0)
            return cli_usage_error(cmd, "--field expects displacement, velocity, force or none, "
                                        "got '%s'", arg);
        return 1;
    case VOPT_WIREFRAME: a->wireframe = 1; return 1;
    case VOPT_NO_OVERLAY: a->overlay = 0; return 1;
    }
    return 0;
}

int view_args_finish(view_args *a, const char *cmd, int argc, char **argv)
{
    if (optind >= argc) return cli_usage_error(cmd, "no scene given (pliant %s SCENE.xml)", cmd);
    if (optind + 1 < argc)
        return cli_usage_error(cmd, "more than one scene given ('%s', '%s')", argv[optind],
                               argv[optind + 1]);
    a->scene = argv[optind];
    if (!a->has_out) {
        char name[256];
        cli_scene_name(a->scene, name, sizeof name);
        snprintf(a->out, sizeof a->out, "out/%s", name);
    }
    if (a->quiet) pl_log_set_level(PL_LOG_WARN);
    a->threads = cli_threads_set(a->threads);
    return 0;
}

int view_load(const view_args *a, vw_app *app, pl_sim **sim)
{
    pl_sim_options opt = {.out_dir = a->out, .overrides = a->sets, .noverrides = a->nsets,
                          .device = a->device};
    pl_diag diag;
    pl_diag_init(&diag);
    *sim = pl_sim_load_file_prepared(a->scene, &opt, vw_app_prepare, app, &diag);
    if (!a->quiet || !*sim) pl_diag_print(&diag, stderr);
    int status = pl_diag_status(&diag);
    if (!*sim)
        fprintf(stderr, "pliant: %s: %d error%s; the scene was not loaded\n", a->scene,
                diag.nerrors, diag.nerrors == 1 ? "" : "s");
    pl_diag_free(&diag);
    return *sim ? 0 : status == PL_EINTERNAL ? 1 : 2;
}
#endif
