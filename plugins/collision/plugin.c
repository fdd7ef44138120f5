/* plugin.c - the collision plugin's entry point: collision models of
 * deformable bodies, analytic and mesh obstacles, and the CollisionPipeline,
 * which emit contact rows for the scene's contact solver.
 * <RequiredPlugin name="collision"/> loads it. */
#include "pliant/plugin.h"

extern const pl_type coll_surface_model_type;
extern const pl_type coll_point_model_type;
extern const pl_type coll_plane_obstacle_type;
extern const pl_type coll_sphere_obstacle_type;
extern const pl_type coll_box_obstacle_type;
extern const pl_type coll_capsule_obstacle_type;
extern const pl_type coll_cylinder_obstacle_type;
extern const pl_type coll_mesh_obstacle_type;
extern const pl_type coll_mapped_model_type;
extern const pl_type coll_pipeline_type;
extern const pl_type coll_shape_tets_type;
extern const pl_type coll_mapped_points_type;

static const pl_type *const types[] = {
    &coll_surface_model_type,   &coll_point_model_type,    &coll_plane_obstacle_type,
    &coll_sphere_obstacle_type, &coll_box_obstacle_type,   &coll_capsule_obstacle_type,
    &coll_cylinder_obstacle_type, &coll_mesh_obstacle_type,  &coll_mapped_model_type,
    &coll_pipeline_type,        &coll_shape_tets_type,       &coll_mapped_points_type,
};

PL_PLUGIN_DEFINE(types)
