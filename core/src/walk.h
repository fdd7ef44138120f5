/* walk.h - private: tree traversals and field access by path. */
#ifndef PLIANT_WALK_PRIVATE_H
#define PLIANT_WALK_PRIVATE_H

#include "pliant/model.h"
#include "pliant/node.h"

/* Every component, node by node, pre-order (a node's components in scene
 * order before its children) or post-order (children first).  Stops when fn
 * returns non-zero and returns that value. */
int walk_pre(pl_node *n, pl_component_visit fn, void *user);
int walk_post(pl_node *n, pl_component_visit fn, void *user);

/* The component named by `path` ("root/bar/dofs", "bar/dofs" or a name
 * unique in the scene).  On failure returns NULL with a message in err. */
pl_component *pl_walk_component(pl_node *root, const char *path, pl_error *err);

/* walk_suggest.c: the closest existing names, for "did you mean".  The node
 * path one (whole path corrected segment by segment) and the anywhere one
 * (a component name, with its node path when the name is not unique) write
 * into buf and return 1 when there is one; the other returns a name or NULL. */
int pl_walk_suggest_node(pl_node *root, const char *path, char *buf, size_t size);
const char *pl_walk_suggest_component(const pl_node *n, const char *name);
int pl_walk_suggest_anywhere(pl_node *root, const char *name, char *buf, size_t size);

/* Sets "component.field" (or "node.dt", "node.gravity") from text, in the
 * component (the model). */
int pl_walk_set(pl_node *root, const char *path, const char *value, pl_error *err);
/* Same, but an input field goes into d (when d is not NULL); *runtime tells
 * whether the field may change without a rebuild. */
int pl_walk_set_runtime(pl_node *root, pl_data *d, const char *path, const char *value,
                        int *runtime, pl_error *err);
/* Formats the current value of "component.field" (state-backed values and
 * input fields come from d). */
int pl_walk_get(pl_node *root, const pl_data *d, const char *path, char *buf, size_t size,
                pl_error *err);

#endif
