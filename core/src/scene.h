/* scene.h - private: building the node tree from XML, and freeing it. */
#ifndef PLIANT_SCENE_PRIVATE_H
#define PLIANT_SCENE_PRIVATE_H

#include "pliant/node.h"
#include "pliant/registry.h"

/* flags of pl_scene_build */
enum {
    /* <RequiredPlugin name="/some/libx.so"/> may name a file (the user trusts
     * the scene); otherwise plugins come from the plugin path only */
    PL_SCENE_ALLOW_PLUGIN_PATH = 1
};

/* Parses scene XML (never touching the network or expanding entities) and
 * builds the tree: components created with defaults, attributes parsed,
 * plugins loaded.  Every problem goes to diag with file:line.  Returns the
 * root (possibly partial, to be freed) or NULL. */
pl_node *pl_scene_build(const char *xml, size_t len, const char *file, pl_registry *reg,
                        int flags, pl_diag *diag);
/* Frees a tree: components' destroy callbacks, fields, nodes. */
void pl_scene_free(pl_node *root);
/* Creates a component of type t in node n (defaults applied); NULL on OOM. */
pl_component *pl_scene_new_component(pl_node *n, const pl_type *t, const char *name,
                                     const char *file, int line, pl_diag *diag);

/* Takes c out of n and destroys it (a component that was never used). */
void pl_scene_remove_component(pl_node *n, pl_component *c);
/* Moves c to the front of n's components: initialised first, destroyed last. */
void pl_scene_move_component_first(pl_node *n, pl_component *c);
/* The implicit device (sim_device.c): a CudaDevice added first in the root
 * of a scene that declares no device, when the policy (opt->device, else
 * PLIANT_DEVICE; "auto" by default, "gpu-always": *forced = 1, no cost model) allows it and the cuda plugin loads
 * (NULL otherwise; a bad policy is an error in diag).  _try initialises it
 * and takes it out again when no GPU answers (returns it, or NULL).
 * pl_sim_device_cost, called after every component's init: records the
 * cost model's sizes and predictions in timers (may be NULL) and, when dev
 * (the implicit device, or NULL) is predicted slower than the CPU and not
 * forced (gpu-always), takes it out of the root (returns 1: the caller
 * indexes the components again). */
struct pl_model;
struct pl_sim_options;
pl_component *pl_sim_implicit_device(pl_node *root, pl_registry *reg, struct pl_model *model,
                                     const struct pl_sim_options *opt, int *forced,
                                     pl_diag *diag);
pl_component *pl_sim_implicit_device_try(pl_node *root, pl_component *c, pl_registry *reg,
                                         struct pl_model *model);
struct pl_timers;
int pl_sim_device_cost(pl_node *root, pl_component *dev, int forced, struct pl_model *model,
                       struct pl_timers *timers);

#endif
