/* obstacle.h - what the analytic obstacle components share (plugin-internal):
 * the common fields (friction, SOFA's alarmDistance / contactDistance,
 * prescribed motion), the constraint role that turns body points within
 * alarmDistance into contact rows, and the per-step contact records kept in
 * the pl_data slot "contacts" (an array of pl_obstacle_contact). */
#ifndef PLIANT_COLLISION_OBSTACLE_H
#define PLIANT_COLLISION_OBSTACLE_H

#include "collision.h"
#include "pliant/pliant.h"

typedef struct coll_obstacle coll_obstacle;

/* Builds the obstacle's shape at its scene pose from its own fields; errors
 * name the field (PL_EINPUT). */
typedef int (*coll_shape_fn)(const coll_obstacle *o, pl_shape *s, pl_error *err);

struct coll_obstacle {
    pl_component base;
    /* common fields */
    double mu;                 /* Coulomb coefficient */
    double alarm_distance;     /* detection radius [m] */
    double contact_distance;   /* kept gap [m] */
    pl_ints group;    /* collision groups (a list; 0: none) */
    double velocity[3];        /* [m/s] */
    double rotation_axis[3];
    double angular_velocity;   /* [rad/s] */
    pl_doubles rotation_center;/* empty: the shape's centre */
    pl_doubles times;          /* keyframe times [s] */
    pl_doubles translations;   /* keyframe translations [m], 3 per time */
    /* output fields (served from the state by get; never stored) */
    int out_count;
    pl_doubles out_points, out_forces, out_normals;
    /* model */
    coll_shape_fn make_shape;
    pl_component **models;     /* collision models of the scene, scene order */
    int nmodels;
    int slot;                  /* data slot "contacts" */
};

/* Per data (pl_data_workspace): this step's records before they go to the
 * slot. */
typedef struct coll_obstacle_ws {
    pl_obstacle_contact *work;
    int nwork, capwork;
    pl_collision_geometry *geo; /* per model: this step's geometry */
    pl_reach *reach;            /* per model: its motion over the step (impact.c) */
    int nmodels;                /* entries of geo and reach */
} coll_obstacle_ws;

/* Field table entries every obstacle type starts with (S embeds a
 * coll_obstacle named `ob` as its first member). */
#define COLL_OBSTACLE_FIELDS(S)                                                                   \
    PL_FIELD(S, ob.mu, "mu", PL_F_DOUBLE, "0",                                                    \
             "Coulomb friction coefficient of its contacts (a collision model's own mu >= 0 "     \
             "takes precedence)",                                                                 \
             PL_FIELD_RUNTIME),                                                                   \
    PL_FIELD(S, ob.alarm_distance, "alarmDistance", PL_F_DOUBLE, "0.01",                          \
             "detection radius [m]: a body point whose signed distance to the surface is below "  \
             "it gets a contact",                                                                 \
             PL_FIELD_RUNTIME),                                                                   \
    PL_FIELD(S, ob.contact_distance, "contactDistance", PL_F_DOUBLE, "0",                         \
             "gap [m] that contacts keep between body points and the surface (<= "               \
             "alarmDistance)",                                                                    \
             PL_FIELD_RUNTIME),                                                                   \
    PL_FIELD(S, ob.group, "group", PL_F_INTS, "0",                                                \
             "collision groups (a list: \"1 2\"; 0: none): models that share one do not touch " \
             "this obstacle",                                                                     \
             PL_FIELD_RUNTIME),                                                                   \
    PL_FIELD(S, ob.velocity, "velocity", PL_F_VEC3, "0 0 0",                                      \
             "constant translation velocity [m/s]", PL_FIELD_RUNTIME),                            \
    PL_FIELD(S, ob.rotation_axis, "rotationAxis", PL_F_VEC3, "0 0 0",                             \
             "direction of the axis it spins about (with angularVelocity)", PL_FIELD_RUNTIME),    \
    PL_FIELD(S, ob.angular_velocity, "angularVelocity", PL_F_DOUBLE, "0",                         \
             "spin rate [rad/s], right-handed about rotationAxis", PL_FIELD_RUNTIME),             \
    PL_FIELD(S, ob.rotation_center, "rotationCenter", PL_F_DOUBLES, NULL,                         \
             "a point of the spin axis [m] at t = 0 (x y z; default: the obstacle's centre); it " \
             "travels with the translation",                                                      \
             PL_FIELD_RUNTIME),                                                                   \
    PL_FIELD(S, ob.times, "times", PL_F_DOUBLES, NULL,                                            \
             "keyframe times [s], strictly increasing", PL_FIELD_RUNTIME),                        \
    PL_FIELD(S, ob.translations, "translations", PL_F_DOUBLES, NULL,                              \
             "keyframe translations [m] from the scene pose, x y z per time (linear in between, " \
             "held before the first and after the last)",                                         \
             PL_FIELD_RUNTIME),                                                                   \
    PL_FIELD(S, ob.out_count, "contactCount", PL_F_INT, "0",                                     \
             "contacts of the last step", PL_FIELD_OUTPUT),                                       \
    PL_FIELD(S, ob.out_points, "contactPoints", PL_F_DOUBLES, NULL,                               \
             "closest surface points of the last step's contacts [m], x y z each",                \
             PL_FIELD_OUTPUT),                                                                    \
    PL_FIELD(S, ob.out_normals, "contactNormals", PL_F_DOUBLES, NULL,                             \
             "outward unit normals of the last step's contacts, x y z each", PL_FIELD_OUTPUT),    \
    PL_FIELD(S, ob.out_forces, "contactForces", PL_F_DOUBLES, NULL,                               \
             "forces on the body of the last step's contacts [N], x y z each", PL_FIELD_OUTPUT)

/* Lifecycle shared by the obstacle types; each type's init sets make_shape
 * and calls coll_obstacle_init. */
int coll_obstacle_init(pl_component *c, pl_ctx *ctx, coll_shape_fn make_shape);
int coll_obstacle_bind(pl_component *c, pl_ctx *ctx);
int coll_obstacle_reinit(pl_component *c, pl_ctx *ctx);
void coll_obstacle_destroy(pl_component *c);
void coll_obstacle_workspace_free(const pl_component *c, void *ws);
int coll_obstacle_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                      size_t size);
extern const pl_constraint_ops coll_obstacle_constraint_ops;

/* The obstacle's shape posed at time t [s] (its fields as they are now). */
int coll_obstacle_pose(const coll_obstacle *o, double t, pl_shape *s, pl_error *err);
extern const pl_visual_ops coll_obstacle_visual_ops;

/* The contacts an obstacle recorded in d during the last step (count; *items
 * points into d, valid until the next step). */
int coll_obstacle_contacts(const pl_component *c, const pl_data *d,
                           const pl_obstacle_contact **items);

#endif
