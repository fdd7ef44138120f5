/* scene.h - private: building the node tree from XML, and freeing it. */
#ifndef PLIANT_SCENE_PRIVATE_H
#define PLIANT_SCENE_PRIVATE_H

#include "pliant/node.h"
#include "pliant/registry.h"

/* Parses scene XML (never touching the network or expanding entities) and
 * builds the tree: components created with defaults, attributes parsed,
 * plugins loaded.  Every problem goes to diag with file:line.  Returns the
 * root (possibly partial, to be freed) or NULL. */
pl_node *pl_scene_build(const char *xml, size_t len, const char *file, pl_registry *reg,
                        pl_diag *diag);
/* Frees a tree: components' destroy callbacks, fields, nodes. */
void pl_scene_free(pl_node *root);
/* Creates a component of type t in node n (defaults applied); NULL on OOM. */
pl_component *pl_scene_new_component(pl_node *n, const pl_type *t, const char *name,
                                     const char *file, int line, pl_diag *diag);

#endif
