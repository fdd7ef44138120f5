/* component.h - components and their type descriptors.
 *
 * A component is a C struct whose first member is a pl_component.  Its
 * pl_type (one static instance per component type) says how big it is,
 * which fields it has, how its life goes (the lifecycle vtable) and which
 * roles it plays (role vtables, see roles.h).  Solvers find what they need
 * by role, never by type name. */
#ifndef PLIANT_COMPONENT_H
#define PLIANT_COMPONENT_H

#include "api.h"
#include <stddef.h>
#include "error.h"
#include "field.h"

#ifdef __cplusplus
extern "C" {
#endif

struct pl_node;
struct pl_model;
struct pl_data;
struct pl_registry;
struct pl_timers;

/* Roles a component can play; each maps to a vtable type in roles.h. */
typedef enum pl_role {
    PL_ROLE_STATE,           /* pl_state_ops */
    PL_ROLE_MASS,            /* pl_mass_ops */
    PL_ROLE_TOPOLOGY,        /* pl_topology_ops: provides a mesh */
    PL_ROLE_LOCAL_TERM,      /* pl_local_term_ops */
    PL_ROLE_GLOBAL_SOLVER,   /* pl_global_solver_ops */
    PL_ROLE_CONSTRAINT,      /* pl_constraint_ops */
    PL_ROLE_CONTACT_SOLVER,  /* pl_contact_solver_ops */
    PL_ROLE_COLLISION_MODEL, /* pl_collision_model_ops */
    PL_ROLE_EXPORTER,        /* pl_exporter_ops */
    PL_ROLE_CONTROLLER,      /* pl_controller_ops */
    PL_ROLE_PRESCRIBED,      /* pl_prescribed_ops: fixed or moving DOFs */
    PL_ROLE_ANIMATION_LOOP,  /* pl_animation_loop_ops: advances one step */
    PL_ROLE_DEVICE,          /* pl_device_ops: device memory, copies, a stream (CudaDevice) */
#if PL_ABI_TARGET_MINOR >= 2
    PL_ROLE_VISUAL,          /* pl_visual_ops: draws obstacles, cables, contacts (draw.h); 5.2 */
    PL_ROLE_EVENT,           /* pl_event_ops: key events from an interactive program; 5.2 */
#endif
    PL_ROLE_COUNT            /* roles defined so far */
} pl_role;

/* Room in pl_type.roles: a role added later takes a free slot, so the
 * layout of pl_type does not change and older plugins stay loadable (their
 * tables hold NULL there: role not played). */
#define PL_ROLE_MAX 24

/* What a lifecycle or role callback is given.  The model is const: a step
 * reads it and writes only the data (its slots and the component's
 * workspace, model.h).  While the model is being built (init, bind, reinit)
 * `build` is the same model, writable: declare state slots through it. */
typedef struct pl_ctx {
    const struct pl_model *model;
    struct pl_data *data;        /* the state being initialised or stepped */
    struct pl_registry *registry;
    struct pl_timers *timers;
    pl_diag *diag;               /* where load-time errors and warnings go */
    struct pl_model *build;      /* init, bind, reinit only: the model; NULL during a step */
} pl_ctx;

typedef struct pl_component pl_component;

/* Lifecycle, called by the core in this order (every callback optional):
 *   init       after fields are parsed: check fields, load files, declare
 *              state slots (pl_model_add_slot(ctx->build, ...)).  Pre-order
 *              over the tree.
 *   bind       resolve links and find partners by role.  Pre-order.
 *   reinit     (re)build derived model data (weights, factors); called after
 *              bind and again after a field changes at run time, so it must
 *              not touch the state.  Post-order: a solver at the root sees
 *              its children ready.  Initial state values are written in
 *              init or bind (ctx->data is then the initial state).
 *   begin_step / end_step   around each time step.  Like every callback
 *              that runs during a step (the role members that take a const
 *              component), they write only ctx->data: its slots, and the
 *              component's workspace for per-step scratch and results.
 *   destroy    free what init/bind/reinit allocated (fields are freed by
 *              the core).
 *   workspace_free  free what the component allocated inside one of its
 *              workspaces (pl_data_workspace, model.h); the core frees the
 *              workspace itself.  Called when the data is freed or the
 *              model rebuilt, while the components are alive.
 * A callback returns PL_OK or an error code with the error recorded in
 * ctx->diag (load time) or err (step time). */
typedef struct pl_lifecycle {
    int (*init)(pl_component *c, pl_ctx *ctx);
    int (*bind)(pl_component *c, pl_ctx *ctx);
    int (*reinit)(pl_component *c, pl_ctx *ctx);
    int (*begin_step)(const pl_component *c, pl_ctx *ctx, pl_error *err);
    int (*end_step)(const pl_component *c, pl_ctx *ctx, pl_error *err);
    void (*destroy)(pl_component *c);
    /* optional: the current value of a field backed by the state or
     * computed (positions, outputs such as cableLength) as text; return
     * PL_EINPUT if `field` is not one it serves (the stored value is used) */
    int (*get)(const pl_component *c, const struct pl_data *d, const char *field, char *buf,
               size_t size);
    void (*workspace_free)(const pl_component *c, void *ws);
} pl_lifecycle;

/* A component type: one static, constant instance per type, registered as
 * is (the registry keeps the pointer: a component's c->type is the address
 * of the type's definition, so `c->type == &my_type` identifies it).
 * Members a later minor ABI version adds go at the end and are read only
 * from types whose abi_version has them (see plugin.h). */
typedef struct pl_type {
    int abi_version;            /* PL_ABI_VERSION the type was compiled with */
    const char *name;           /* XML tag, e.g. "MechanicalObject" */
    const char *help;           /* one-line description */
    size_t size;                /* sizeof the component struct (the model) */
    size_t workspace_size;      /* bytes of its per-data workspace (0: none), see model.h */
    const pl_field *fields;     /* field table */
    int nfields;
    const void *roles[PL_ROLE_MAX]; /* role vtables; NULL = role not played */
    pl_lifecycle ops;
} pl_type;

struct pl_component {
    const pl_type *type;
    char *name;                 /* unique within its node */
    struct pl_node *node;
    char *file;                 /* scene file it came from */
    int line;                   /* its line in that file */
};

/* Role vtable of c, or NULL if c does not play that role. */
static inline const void *pl_component_role(const pl_component *c, pl_role r)
{
    return (c && c->type) ? c->type->roles[r] : NULL;
}

/* "global solver", "contact solver", ...: a role's name for messages. */
PL_API const char *pl_role_name(int role);
/* "root/bar/dofs": node path plus component name, for messages. */
PL_API const char *pl_component_path(const pl_component *c, char *buf, size_t size);
/* Field descriptor by name (or alias), or NULL. */
PL_API const pl_field *pl_component_field(const pl_component *c, const char *name);

/* Records a load-time error about c (its file, line and path). Returns code. */
PL_API int pl_component_error(const pl_component *c, pl_ctx *ctx, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
PL_API void pl_component_warn(const pl_component *c, pl_ctx *ctx, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Fills err about c at step time. Returns code. */
PL_API int pl_component_fail(const pl_component *c, pl_error *err, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#ifdef __cplusplus
}
#endif
#endif
