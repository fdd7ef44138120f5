/* view_common.c - options and loading shared by pliant view and render. */
#ifdef PLIANT_HAVE_VIEWER
#include "view_common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"

void view_args_init(view_args *a, int argc, int w, int h)
{
    memset(a, 0, sizeof *a);
    a->sets = calloc((size_t)argc + 1, sizeof *a->sets);
    a->w = w, a->h = h;
    a->field = VW_FIELD_DISPLACEMENT;
    a->overlay = 1;
}

void view_args_free(view_args *a)
{
    free(a->sets);
    free((char *)a->out);
    a->sets = NULL;
    a->out = NULL;
}

int view_common_option(view_args *a, const char *cmd, int opt, const char *arg)
{
    switch (opt) {
    case VOPT_SET: a->sets[a->nsets++] = arg; return 1;
    case VOPT_DEVICE:
        if (strcmp(arg, "cpu") && strcmp(arg, "auto")) {
            fprintf(stderr, "pliant %s: --device expects cpu or auto, got '%s'\n", cmd, arg);
            return 2;
        }
        a->device = arg;
        return 1;
    case VOPT_OUT:
        free((char *)a->out);
        a->out = strdup(arg);
        return 1;
    case VOPT_SIZE:
        if (sscanf(arg, "%dx%d", &a->w, &a->h) != 2 || a->w < 16 || a->h < 16 || a->w > 8192 ||
            a->h > 8192) {
            fprintf(stderr, "pliant %s: --size expects WxH between 16 and 8192 (e.g. 640x480), "
                            "got '%s'\n", cmd, arg);
            return 2;
        }
        return 1;
    case VOPT_FIELD:
        if ((a->field = vw_field_parse(arg)) < 0) {
            fprintf(stderr, "pliant %s: --field expects displacement, velocity, force or none, "
                            "got '%s'\n", cmd, arg);
            return 2;
        }
        return 1;
    case VOPT_WIREFRAME: a->wireframe = 1; return 1;
    case VOPT_NO_OVERLAY: a->overlay = 0; return 1;
    case VOPT_QUIET: a->quiet = 1; return 1;
    }
    return 0;
}

int view_args_finish(view_args *a, const char *cmd)
{
    if (!a->sets) return 1;
    if (!a->scene) {
        fprintf(stderr, "pliant %s: no scene given (pliant %s SCENE.xml; --help)\n", cmd, cmd);
        return 2;
    }
    if (!a->out) {
        /* out/<scene file name without .xml> */
        const char *b = strrchr(a->scene, '/');
        b = b ? b + 1 : a->scene;
        size_t n = strlen(b);
        if (n > 4 && !strcmp(b + n - 4, ".xml")) n -= 4;
        char *o = malloc(n + 5);
        if (!o) return 1;
        snprintf(o, n + 5, "out/%.*s", (int)n, b);
        a->out = o;
    }
    if (a->quiet) pl_log_set_level(PL_LOG_WARN);
    return 0;
}

int view_load(const view_args *a, vw_app *app, pl_sim **sim)
{
    pl_sim_options opt = {.out_dir = a->out, .overrides = a->sets, .noverrides = a->nsets,
                          .device = a->device, .prepare = vw_app_prepare, .prepare_user = app};
    pl_diag diag;
    pl_diag_init(&diag);
    *sim = pl_sim_load_file(a->scene, &opt, &diag);
    if (!a->quiet || !*sim) pl_diag_print(&diag, stderr);
    int status = pl_diag_status(&diag);
    if (!*sim)
        fprintf(stderr, "pliant: %s: %d error%s; the scene was not loaded\n", a->scene,
                diag.nerrors, diag.nerrors == 1 ? "" : "s");
    pl_diag_free(&diag);
    return *sim ? 0 : status == PL_EINTERNAL ? 1 : 2;
}
#endif
