/* view_common.h - what pliant view and pliant render share: their common
 * options and loading a scene with the viewer's tools (the mouse spring). */
#ifndef PLIANT_CLI_VIEW_COMMON_H
#define PLIANT_CLI_VIEW_COMMON_H

#include <pliant/pliant.h>

typedef struct view_args {
    const char *scene;
    const char **sets;
    int nsets;
    const char *device;
    const char *out;     /* exporters' folder (default out/<scene name>) */
    int w, h;
    int field;           /* vw_field */
    int wireframe, overlay;
    int quiet;
} view_args;

/* Parses the options shared by both commands (returns 1 when the option
 * was one of them, 0 when not, 2 on a bad value, with a message). */
int view_common_option(view_args *a, const char *cmd, int opt, const char *arg);
/* Defaults, then checks the scene was given; 0 or 2. */
void view_args_init(view_args *a, int argc, int w, int h);
int view_args_finish(view_args *a, const char *cmd);
void view_args_free(view_args *a);

struct vw_app;
/* Loads the scene with the viewer's prepare hook into *sim; prints the
 * diagnostics.  0, 2 (bad scene) or 1. */
int view_load(const view_args *a, struct vw_app *app, pl_sim **sim);

/* getopt_long codes of the shared options */
enum { VOPT_SET = 1000, VOPT_DEVICE, VOPT_OUT, VOPT_SIZE, VOPT_FIELD, VOPT_WIREFRAME,
       VOPT_NO_OVERLAY, VOPT_QUIET };
#define VIEW_COMMON_LONGOPTS                                                                    \
    {"set", required_argument, 0, VOPT_SET}, {"device", required_argument, 0, VOPT_DEVICE},     \
        {"out", required_argument, 0, VOPT_OUT}, {"size", required_argument, 0, VOPT_SIZE},     \
        {"field", required_argument, 0, VOPT_FIELD},                                            \
        {"wireframe", no_argument, 0, VOPT_WIREFRAME},                                          \
        {"no-overlay", no_argument, 0, VOPT_NO_OVERLAY}, {"quiet", no_argument, 0, VOPT_QUIET}
#define VIEW_COMMON_HELP                                                                        \
    "  --size WxH          picture size in pixels\n"                                           \
    "  --field F           colour the bodies by displacement (default), velocity, force, none\n" \
    "  --wireframe         edges over the surfaces\n"                                           \
    "  --no-overlay        no text (time, ms per step by phase, contacts)\n"                    \
    "  --set PATH=VALUE    change a field before the scene starts (repeatable)\n"              \
    "  --device cpu|auto   auto: the GPU when one is usable (default PLIANT_DEVICE, else auto)\n" \
    "  --out DIR           where the scene's exporters write (default out/<scene name>)\n"     \
    "  --quiet             warnings and errors only\n"

#endif
