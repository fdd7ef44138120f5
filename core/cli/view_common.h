/* view_common.h - what pliant view and pliant render share: their common
 * options (named as pliant run names them) and loading a scene with the
 * viewer's tools (the mouse spring). */
#ifndef PLIANT_CLI_VIEW_COMMON_H
#define PLIANT_CLI_VIEW_COMMON_H

#include <pliant/pliant.h>

typedef struct view_args {
    const char *scene;
    const char **sets;
    int nsets;
    const char *device;
    char out[1024];      /* exporters' folder (-o; default out/<scene name>) */
    int has_out;
    int threads;         /* -j; 0 = OpenMP's default */
    int w, h;
    int field;           /* vw_field */
    int wireframe, overlay;
    int quiet;
} view_args;

/* getopt_long codes of the shared options without a short letter */
enum { VOPT_DEVICE = 1000, VOPT_SIZE, VOPT_FIELD, VOPT_WIREFRAME, VOPT_NO_OVERLAY };

/* The short letters of the shared options: -s -o -j -q -h. */
#define VIEW_COMMON_SHORT "s:o:j:qh"
#define VIEW_COMMON_LONGOPTS                                                                    \
    {"set", required_argument, 0, 's'}, {"out", required_argument, 0, 'o'},                     \
        {"threads", required_argument, 0, 'j'}, {"quiet", no_argument, 0, 'q'},                 \
        {"help", no_argument, 0, 'h'}, {"device", required_argument, 0, VOPT_DEVICE},           \
        {"size", required_argument, 0, VOPT_SIZE}, {"field", required_argument, 0, VOPT_FIELD}, \
        {"wireframe", no_argument, 0, VOPT_WIREFRAME},                                          \
        {"no-overlay", no_argument, 0, VOPT_NO_OVERLAY}
#define VIEW_COMMON_HELP                                                                        \
    "      --size WxH         picture size in pixels\n"                                        \
    "      --field F          colour the bodies by displacement (default), velocity, force,\n" \
    "                         none\n"                                                          \
    "      --wireframe        edges over the surfaces\n"                                       \
    "      --no-overlay       no text (time, ms per step by phase, contacts)\n"                \
    "  -s, --set PATH=VALUE   change a field before the scene starts (repeatable)\n"           \
    "      --device cpu|auto|gpu-always  as for pliant run (default PLIANT_DEVICE, else auto)\n" \
    "  -o, --out DIR          where the scene's exporters write (default out/<scene name>/)\n" \
    "  -j, --threads N        OpenMP threads (default OMP_NUM_THREADS, else the cores this\n"  \
    "                         process may use; never more than those)\n"                      \
    "  -q, --quiet            only warnings and errors\n"                                      \
    "  -h, --help             this text\n"

/* Defaults (w x h pixels); 0, or 1 when out of memory. */
int view_args_init(view_args *a, int argc, int w, int h);
/* One of the shared options (not -h): 1 when it was one of them, 0 when
 * not, 2 on a bad value (with a message in the style of cli_usage_error). */
int view_common_option(view_args *a, const char *cmd, int opt, const char *arg);
/* After getopt_long: the scene (exactly one), the default output folder,
 * the log level and the threads; 0 or 2. */
int view_args_finish(view_args *a, const char *cmd, int argc, char **argv);
void view_args_free(view_args *a);

struct vw_app;
/* Loads the scene with the viewer's prepare hook into *sim; prints the
 * diagnostics.  0, 2 (bad scene) or 1. */
int view_load(const view_args *a, struct vw_app *app, pl_sim **sim);

#endif
