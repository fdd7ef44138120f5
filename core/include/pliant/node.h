/* node.h - the scene tree.  A node holds components and child nodes; its
 * context values (dt, gravity) are inherited by the nodes below it unless a
 * node sets its own. */
#ifndef PLIANT_NODE_H
#define PLIANT_NODE_H

#include "api.h"
#include "component.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pl_node {
    char *name;
    struct pl_node *parent;
    struct pl_node **children;
    int nchildren, cap_children;
    pl_component **components;  /* in scene order */
    int ncomponents, cap_components;
    char *file;
    int line;
    /* context as written on this node; has_* says whether it was given */
    double dt;
    double gravity[3];
    int has_dt, has_gravity;
} pl_node;

/* Inherited context: the nearest ancestor (or self) that sets the value.
 * Defaults when no node sets them: dt 0.01 s, gravity (0, -9.81, 0) m/s^2. */
PL_API double pl_node_dt(const pl_node *n);
PL_API void pl_node_gravity(const pl_node *n, double g[3]);

/* "root/bar" */
PL_API const char *pl_node_path(const pl_node *n, char *buf, size_t size);

/* First component playing `role` in node n itself, or NULL. */
PL_API pl_component *pl_node_find_role(const pl_node *n, pl_role role);
/* Same, searching n then its ancestors (SOFA's context lookup). */
PL_API pl_component *pl_node_find_role_up(const pl_node *n, pl_role role);

/* Calls fn on every component of the subtree playing `role` (pre-order, scene
 * order).  Stops and returns fn's value when it is non-zero. */
typedef int (*pl_component_visit)(pl_component *c, void *user);
PL_API int pl_node_visit_role(pl_node *n, pl_role role, pl_component_visit fn, void *user);
/* Number of components of the subtree playing `role`. */
PL_API int pl_node_count_role(const pl_node *n, pl_role role);

/* Resolves a link path from component `from`: "name" (same node, then up the
 * tree), "../name", "child/name", "/abs/path/name" or "[-1]" (the previous
 * component of the same node).  Returns NULL if not found. */
PL_API pl_component *pl_node_resolve(const pl_component *from, const char *path);

#if PL_ABI_TARGET_MINOR >= 2
/* Adds a component of the registered type `type` at the end of n, with its
 * defaults (name NULL: SOFA's default name, the type's with a lower-case
 * initial).  For programs that add tools to a parsed scene before it is
 * initialised (the prepare hook of pl_sim_load_file_prepared); set fields
 * with pl_field_parse.  NULL with the reason in diag (unknown type, name
 * taken, out of memory).  Since ABI 5.2. */
struct pl_registry;
PL_API pl_component *pl_node_add_component(pl_node *n, const struct pl_registry *reg,
                                           const char *type, const char *name, pl_diag *diag);
#endif

#ifdef __cplusplus
}
#endif
#endif
