/* sim.h - the embedding API: load a scene, step it, read and change it.
 * The `pliant` command-line tool is a thin user of these functions.
 *
 *     pl_diag diag; pl_diag_init(&diag);
 *     pl_sim *sim = pl_sim_load_file("scenes/twisting_bar.xml", NULL, &diag);
 *     if (!sim) { pl_diag_print(&diag, stderr); ... }
 *     pl_error err;
 *     pl_sim_step(sim, 100, &err);
 *     char buf[64]; pl_sim_get(sim, "bar/dofs.position", buf, sizeof buf, &err);
 *     pl_sim_free(sim);
 */
#ifndef PLIANT_SIM_H
#define PLIANT_SIM_H

#include "api.h"
#include <stddef.h>
#include "error.h"
#include "model.h"
#include "registry.h"
#include "roles.h"
#include "timer.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pl_sim pl_sim;

/* A callback a program sets to drive the simulation itself: called at the
 * start of every step with the time t [s], before the scene's controllers;
 * it may call pl_sim_set, which (like pl_sim_get) then addresses the data
 * being stepped (pl_sim_step_data's d).  Returning non-zero stops the step
 * with an error. */
typedef int (*pl_sim_callback)(pl_sim *sim, double t, void *user);

typedef struct pl_sim_options {
    pl_registry *registry;    /* NULL: a private one with the built-ins */
    const char *out_dir;      /* directory exporters write into; NULL = as the scene says */
    int export_every;         /* 0 = each exporter's own setting */
    const char *const *overrides; /* "path.field=value" applied before init */
    int noverrides;
    /* NULL: PLIANT_DEVICE, else "auto".  "auto": a scene that declares no
     * device service gets a CudaDevice when the cuda plugin loads, a GPU
     * answers and a cost model predicts its step faster there (components
     * with device="auto" then run on it; the choice and why are logged and
     * in the timings' statistics); "gpu-always": whenever a GPU answers;
     * "cpu": never. */
    const char *device;
    /* 0 (default): <RequiredPlugin> takes plugin names, found on the plugin
     * path; a name with '/' or '..' is an input error.  1: it may also name
     * a shared object by path (loading one runs its code: only for scenes
     * the user trusts; `pliant run --allow-plugin-path`). */
    int allow_plugin_path;
    /* NULL: the scene's WorkLimits (else the defaults) bound its work.
     * Else also these ceilings, which no scene can raise: for a program that
     * runs scenes it does not trust (see work_limits.h). */
    const struct pl_work_limits *max_limits;
} pl_sim_options;

/* Loads and initialises a scene.  On any error returns NULL with every
 * problem in diag (file:line, component path, the closest valid name). */
PL_API pl_sim *pl_sim_load_file(const char *path, const pl_sim_options *opt, pl_diag *diag);
/* Same from XML text; `name` stands for the file name in messages. */
PL_API pl_sim *pl_sim_load_string(const char *xml, const char *name, const pl_sim_options *opt,
                                  pl_diag *diag);
#if PL_ABI_TARGET_MINOR >= 2
/* Called on the parsed scene before it is initialised (after the --set
 * overrides): an interactive program adds its tools there, e.g. the
 * viewer's PickSpring (pl_node_add_component).  Non-zero stops the load;
 * the reason goes to diag. */
typedef int (*pl_sim_prepare)(pl_node *root, pl_registry *reg, pl_diag *diag, void *user);
/* pl_sim_load_file / pl_sim_load_string with a prepare hook (NULL: none),
 * called with `user`.  Since ABI 5.2 (functions rather than members of
 * pl_sim_options, whose layout a program compiled against an older minor
 * fixes). */
PL_API pl_sim *pl_sim_load_file_prepared(const char *path, const pl_sim_options *opt,
                                         pl_sim_prepare prepare, void *user, pl_diag *diag);
PL_API pl_sim *pl_sim_load_string_prepared(const char *xml, const char *name,
                                           const pl_sim_options *opt, pl_sim_prepare prepare,
                                           void *user, pl_diag *diag);
#endif
PL_API void pl_sim_free(pl_sim *sim);

/* Advances nsteps time steps of the scene's dt. */
PL_API int pl_sim_step(pl_sim *sim, int nsteps, pl_error *err);
/* Advances another state over the same model (several states, one model:
 * make them with pl_data_clone(pl_sim_data(sim)) and free them before the
 * sim).  Steps of several data may be interleaved: each evolves exactly as
 * if stepped alone.  Exporters write only the sim's own data. */
PL_API int pl_sim_step_data(pl_sim *sim, pl_data *d, int nsteps, pl_error *err);
/* Flushes exporters (closes .pvd series); called by pl_sim_free too. */
PL_API int pl_sim_finish(pl_sim *sim, pl_error *err);

/* Field access by path "node/sub/component.field" (the root's name may be
 * left out; a component name unique in the scene may stand alone).  An
 * input field (a cable's value, input.h) is set in and read from the sim's
 * data (in a step callback: the data being stepped); any other field is the
 * model's, shared by every data: changing a field that is neither RUNTIME
 * nor an input rebuilds the model (weights, factors). */
PL_API int pl_sim_set(pl_sim *sim, const char *path, const char *value, pl_error *err);
PL_API int pl_sim_get(const pl_sim *sim, const char *path, char *buf, size_t size, pl_error *err);
/* The same for the data d of this sim's model: an input field is set in d
 * only, so that several data can be driven differently.  d NULL sets the
 * model's value of an input field (where new data start from). */
PL_API int pl_sim_set_data(pl_sim *sim, pl_data *d, const char *path, const char *value,
                           pl_error *err);
PL_API int pl_sim_get_data(const pl_sim *sim, const pl_data *d, const char *path, char *buf,
                           size_t size, pl_error *err);
/* Component by path, or NULL. */
PL_API pl_component *pl_sim_component(const pl_sim *sim, const char *path);

PL_API pl_model *pl_sim_model(pl_sim *sim);
PL_API pl_data *pl_sim_data(pl_sim *sim);
PL_API pl_registry *pl_sim_registry(pl_sim *sim);
PL_API pl_timers *pl_sim_timers(pl_sim *sim);
PL_API double pl_sim_time(const pl_sim *sim);

/* Back to the state right after loading (input fields too). */
PL_API int pl_sim_reset(pl_sim *sim);
/* Save/restore the current state to/from a file (binary, exact). */
PL_API int pl_sim_save_state(const pl_sim *sim, const char *path, pl_error *err);
PL_API int pl_sim_restore_state(pl_sim *sim, const char *path, pl_error *err);

/* Installs a per-step callback (NULL removes it). */
PL_API void pl_sim_set_callback(pl_sim *sim, pl_sim_callback fn, void *user);

#if PL_ABI_TARGET_MINOR >= 2
/* Hands an event (a key pressed in a viewer) to every component playing the
 * event role (KeyboardController, Python controllers), in scene order, for
 * the current state.  *used (may be NULL) tells whether one of them used it.
 * Since ABI 5.2. */
PL_API int pl_sim_send_event(pl_sim *sim, const pl_event *ev, int *used, pl_error *err);
#endif

/* Paths of the main files exporters wrote (for "output went to ..."). */
PL_API int pl_sim_outputs(const pl_sim *sim, const char **paths, int max);

#ifdef __cplusplus
}
#endif
#endif
