/* builtin.c - registers the built-in components with a registry. */
#include "pliant/registry.h"

#include "constraint/pick.h"
#include "constraint/prescribed.h"
#include "controller/controller.h"
#include "export/export.h"
#include "force/force.h"
#include "loader/loader.h"
#include "mass/mass.h"
#include "solver/solver.h"
#include "state/mechanical_object.h"
#include "visual/visual.h"

extern const pl_type pl_work_limits_type; /* core/src/work_limits.c */

static const pl_type *const BUILTIN[] = {
    &pl_mechanical_object_type,
    &pl_uniform_mass_type,
    &pl_diagonal_mass_type,
    &pl_fixed_constraint_type,
    &pl_prescribed_motion_type,
    &pl_constant_force_field_type,
    &pl_plane_force_field_type,
    &pl_mesh_loader_type,
    &pl_grid_tetrahedra_type,
    &pl_grid_triangles_type,
    &pl_sphere_mesh_type,
    &pl_cylinder_mesh_type,
    &pl_vtk_exporter_type,
    &pl_write_state_type,
    &pl_local_global_solver_type,
    &pl_newton_solver_type,
    &pl_linearized_euler_solver_type,
    &pl_jacobi_solver_type,
    &pl_keyframes_type,
    &pl_keyboard_controller_type,
    &pl_pick_spring_type,
    &pl_interactive_camera_type,
    &pl_work_limits_type,
};

int pl_register_builtin_components(pl_registry *r, pl_error *err)
{
    for (size_t k = 0; k < sizeof BUILTIN / sizeof BUILTIN[0]; ++k) {
        int rc = pl_registry_add(r, BUILTIN[k], err);
        if (rc != PL_OK) return rc;
    }
    return PL_OK;
}
