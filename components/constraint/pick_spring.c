/* pick_spring.c - PickSpring: a stiff spring from one vertex to a point,
 * the mouse spring of an interactive viewer (runSofa's pick-and-drag).
 *
 * It plays the constraint role: while `vertex` names a vertex (a global
 * index, as the animation loop numbers the vertices of all states), every
 * step gets three bilateral rows, one per axis, H q - d + E lambda = 0 with
 * d the target and compliance E = 1 / stiffness.  So lambda = k (target - x)
 * is the spring force, solved implicitly with the rest of the constrained
 * step: a stiff spring cannot make the step unstable, as an explicit force
 * would.  The viewer adds one to the animation loop's node of the scene it
 * shows (its prepare hook, pl_sim_load_file_prepared) and sets vertex and
 * target through the embedding API (pl_sim_set) while the mouse drags: all
 * three fields are input fields, whose values live in the data (input.h), so a drag
 * changes the state being shown and never rebuilds the model. */
#include <math.h>

#include "constraint/pick.h"

typedef struct pick_spring {
    pl_component base;
    int vertex;
    double target[3];
    double stiffness;
} pick_spring;

static const pl_field FIELDS[] = {
    PL_FIELD(pick_spring, vertex, "vertex", PL_F_INT, "-1",
             "picked vertex, a global index over all states in scene order (-1: none, the "
             "spring is off)",
             PL_FIELD_INPUT),
    PL_FIELD(pick_spring, target, "target", PL_F_VEC3, "0 0 0",
             "point the vertex is pulled to [m]", PL_FIELD_INPUT),
    PL_FIELD(pick_spring, stiffness, "stiffness", PL_F_DOUBLE, "1000",
             "spring stiffness [N/m] (the rows' compliance is its inverse)", PL_FIELD_INPUT),
};

static int ps_build_rows(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                         const pl_buffer *q, pl_rows *rows, pl_error *err)
{
    (void)q;
    const pick_spring *p = (const pick_spring *)c;
    int vertex = pl_input_int(ctx->data, c, &p->vertex);
    const double *target = pl_input_vec3(ctx->data, c, p->target);
    double stiffness = pl_input_double(ctx->data, c, &p->stiffness);
    if (vertex < 0) return PL_OK;
    if (vertex >= sys->nverts)
        return pl_component_fail(c, err, PL_EINPUT, "vertex %d: the scene has %d vertices",
                                 vertex, sys->nverts);
    if (!isfinite(stiffness) || stiffness <= 0.0)
        return pl_component_fail(c, err, PL_EINPUT, "stiffness must be > 0 [N/m], got %g",
                                 stiffness);
    for (int k = 0; k < 3; ++k)
        if (!isfinite(target[k]))
            return pl_component_fail(c, err, PL_EINPUT, "target is not finite");
    for (int k = 0; k < 3; ++k) {
        int r = pl_rows_begin(rows, PL_ROW_BILATERAL, c);
        double dir[3] = {0.0, 0.0, 0.0};
        dir[k] = 1.0;
        if (r < 0 || pl_rows_add(rows, vertex, dir[0], dir[1], dir[2]) != PL_OK)
            return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        rows->d[r] = target[k];
        rows->compliance[r] = 1.0 / stiffness;
    }
    return PL_OK;
}

static const pl_constraint_ops CONSTRAINT = {.version = PL_CONSTRAINT_OPS_VERSION,
                                             .build_rows = ps_build_rows};

const pl_type pl_pick_spring_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "PickSpring",
    .help = "A stiff spring pulling one vertex to a point, solved with the constraints "
            "(the viewer's mouse drag); needs a contact solver.",
    .size = sizeof(pick_spring),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .roles = {[PL_ROLE_CONSTRAINT] = &CONSTRAINT},
};
