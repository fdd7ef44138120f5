/* obstacle_types.c - the analytic obstacle components: PlaneObstacle,
 * SphereObstacle, BoxObstacle, CapsuleObstacle and CylinderObstacle.  Each
 * adds its shape's fields to the common ones (obstacle.h) and says how to
 * build its pl_shape; everything else is shared. */
#include <stddef.h>

#include "pliant/util.h"
#include "obstacle.h"

#define COLL_TYPE(var, tag, S, table, init_fn, helptext)                                       \
    const pl_type var = {                                                                       \
        .abi_version = PL_ABI_VERSION,                                                          \
        .name = tag,                                                                            \
        .help = helptext,                                                                       \
        .size = sizeof(S),                                                                      \
        .workspace_size = sizeof(coll_obstacle_ws),                                             \
        .fields = table,                                                                        \
        .nfields = sizeof table / sizeof table[0],                                              \
        .ops = {.init = init_fn,                                                                \
                .bind = coll_obstacle_bind,                                                     \
                .reinit = coll_obstacle_reinit,                                                 \
                .destroy = coll_obstacle_destroy,                                               \
                .get = coll_obstacle_get,                                                       \
                .workspace_free = coll_obstacle_workspace_free},                                \
        .roles = {[PL_ROLE_CONSTRAINT] = &coll_obstacle_constraint_ops,                         \
                  [PL_ROLE_VISUAL] = &coll_obstacle_visual_ops},                                \
    }

/* ---- PlaneObstacle -------------------------------------------------------- */

typedef struct plane_obstacle {
    coll_obstacle ob;
    double point[3], normal[3], rotation[3];
} plane_obstacle;

static const pl_field PLANE_FIELDS[] = {
    COLL_OBSTACLE_FIELDS(plane_obstacle),
    PL_FIELD(plane_obstacle, point, "point", PL_F_VEC3, "0 0 0", "a point of the plane [m]",
             PL_FIELD_RUNTIME),
    PL_FIELD(plane_obstacle, normal, "normal", PL_F_VEC3, "0 1 0",
             "normal pointing out of the solid side (towards the bodies); need not be unit",
             PL_FIELD_RUNTIME),
    PL_FIELD(plane_obstacle, rotation, "rotation", PL_F_VEC3, "0 0 0",
             "rotation applied to the normal [deg about x, then y, then z]", PL_FIELD_RUNTIME),
};

static int plane_shape(const coll_obstacle *o, pl_shape *s, pl_error *err)
{
    const plane_obstacle *p = (const plane_obstacle *)o;
    double R[9], n[3];
    pl_util_rotation_deg(p->rotation, R);
    for (int i = 0; i < 3; ++i)
        n[i] = R[3 * i] * p->normal[0] + R[3 * i + 1] * p->normal[1] + R[3 * i + 2] * p->normal[2];
    return shape_plane(s, p->point, n, err);
}

static int plane_init(pl_component *c, pl_ctx *ctx)
{
    return coll_obstacle_init(c, ctx, plane_shape);
}

COLL_TYPE(coll_plane_obstacle_type, "PlaneObstacle", plane_obstacle, PLANE_FIELDS, plane_init,
          "An infinite plane (half-space) that body points cannot cross; any orientation, may "
          "move (velocity, rotation, keyframes).");

/* ---- SphereObstacle ------------------------------------------------------- */

typedef struct sphere_obstacle {
    coll_obstacle ob;
    double center[3], radius;
} sphere_obstacle;

static const pl_field SPHERE_FIELDS[] = {
    COLL_OBSTACLE_FIELDS(sphere_obstacle),
    PL_FIELD(sphere_obstacle, center, "center", PL_F_VEC3, "0 0 0", "centre [m]",
             PL_FIELD_RUNTIME),
    PL_FIELD(sphere_obstacle, radius, "radius", PL_F_DOUBLE, NULL, "radius [m]",
             PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
};

static int sphere_shape(const coll_obstacle *o, pl_shape *s, pl_error *err)
{
    const sphere_obstacle *p = (const sphere_obstacle *)o;
    return shape_sphere(s, p->center, p->radius, err);
}

static int sphere_init(pl_component *c, pl_ctx *ctx)
{
    return coll_obstacle_init(c, ctx, sphere_shape);
}

COLL_TYPE(coll_sphere_obstacle_type, "SphereObstacle", sphere_obstacle, SPHERE_FIELDS,
          sphere_init, "A rigid ball that body points cannot enter; may move.");

/* ---- BoxObstacle ---------------------------------------------------------- */

typedef struct box_obstacle {
    coll_obstacle ob;
    double center[3], half[3], rotation[3];
} box_obstacle;

static const pl_field BOX_FIELDS[] = {
    COLL_OBSTACLE_FIELDS(box_obstacle),
    PL_FIELD(box_obstacle, center, "center", PL_F_VEC3, "0 0 0", "centre [m]", PL_FIELD_RUNTIME),
    PL_FIELD(box_obstacle, half, "halfExtents", PL_F_VEC3, NULL,
             "half the side lengths along the box's own x, y, z [m]",
             PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
    PL_FIELD(box_obstacle, rotation, "rotation", PL_F_VEC3, "0 0 0",
             "orientation [deg about x, then y, then z]", PL_FIELD_RUNTIME),
};

static int box_shape(const coll_obstacle *o, pl_shape *s, pl_error *err)
{
    const box_obstacle *p = (const box_obstacle *)o;
    double R[9];
    pl_util_rotation_deg(p->rotation, R);
    return shape_box(s, p->center, p->half, R, err);
}

static int box_init(pl_component *c, pl_ctx *ctx)
{
    return coll_obstacle_init(c, ctx, box_shape);
}

COLL_TYPE(coll_box_obstacle_type, "BoxObstacle", box_obstacle, BOX_FIELDS, box_init,
          "A rigid oriented box that body points cannot enter; may move.");

/* ---- CapsuleObstacle ------------------------------------------------------ */

typedef struct capsule_obstacle {
    coll_obstacle ob;
    double start[3], end[3], radius;
} capsule_obstacle;

static const pl_field CAPSULE_FIELDS[] = {
    COLL_OBSTACLE_FIELDS(capsule_obstacle),
    PL_FIELD(capsule_obstacle, start, "start", PL_F_VEC3, NULL, "one end of the axis segment [m]",
             PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
    PL_FIELD(capsule_obstacle, end, "end", PL_F_VEC3, NULL, "the other end of the segment [m]",
             PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
    PL_FIELD(capsule_obstacle, radius, "radius", PL_F_DOUBLE, NULL, "radius [m]",
             PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
};

static int capsule_shape(const coll_obstacle *o, pl_shape *s, pl_error *err)
{
    const capsule_obstacle *p = (const capsule_obstacle *)o;
    return shape_capsule(s, p->start, p->end, p->radius, err);
}

static int capsule_init(pl_component *c, pl_ctx *ctx)
{
    return coll_obstacle_init(c, ctx, capsule_shape);
}

COLL_TYPE(coll_capsule_obstacle_type, "CapsuleObstacle", capsule_obstacle, CAPSULE_FIELDS,
          capsule_init,
          "A rigid capsule (a segment swept by a ball: a cylinder with rounded ends); may move.");

/* ---- CylinderObstacle ----------------------------------------------------- */

typedef struct cylinder_obstacle {
    coll_obstacle ob;
    double center[3], axis[3], radius, length;
} cylinder_obstacle;

static const pl_field CYLINDER_FIELDS[] = {
    COLL_OBSTACLE_FIELDS(cylinder_obstacle),
    PL_FIELD(cylinder_obstacle, center, "center", PL_F_VEC3, "0 0 0", "centre [m]",
             PL_FIELD_RUNTIME),
    PL_FIELD(cylinder_obstacle, axis, "axis", PL_F_VEC3, "0 1 0",
             "direction of the cylinder's axis (need not be unit)", PL_FIELD_RUNTIME),
    PL_FIELD(cylinder_obstacle, radius, "radius", PL_F_DOUBLE, NULL, "radius [m]",
             PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
    PL_FIELD(cylinder_obstacle, length, "length", PL_F_DOUBLE, NULL,
             "length along the axis, cap to cap [m]", PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
};

static int cylinder_shape(const coll_obstacle *o, pl_shape *s, pl_error *err)
{
    const cylinder_obstacle *p = (const cylinder_obstacle *)o;
    return shape_cylinder(s, p->center, p->axis, p->radius, p->length, err);
}

static int cylinder_init(pl_component *c, pl_ctx *ctx)
{
    return coll_obstacle_init(c, ctx, cylinder_shape);
}

COLL_TYPE(coll_cylinder_obstacle_type, "CylinderObstacle", cylinder_obstacle, CYLINDER_FIELDS,
          cylinder_init,
          "A rigid cylinder with flat caps; may move (e.g. spin about its own axis: rotationAxis "
          "= axis, rotationCenter = center).");
