/* uniform_mass.c - UniformMass: the same mass on every vertex. */
#include <math.h>

#include "pliant/util.h"
#include "mass.h"

typedef struct uniform_mass {
    pl_component base;
    double total_mass, vertex_mass;
    pl_component *state;
} uniform_mass;

static const pl_field FIELDS[] = {
    PL_FIELD(uniform_mass, total_mass, "totalMass", PL_F_DOUBLE, "0",
             "mass of the whole body [kg], shared equally by the vertices (or give vertexMass)", 0),
    PL_FIELD(uniform_mass, vertex_mass, "vertexMass", PL_F_DOUBLE, "0",
             "mass of each vertex [kg] (used when totalMass is 0)", 0),
};

static int um_bind(pl_component *c, pl_ctx *ctx)
{
    uniform_mass *m = (uniform_mass *)c;
    if (m->total_mass < 0 || m->vertex_mass < 0)
        return pl_component_error(c, ctx, PL_EINPUT, "masses must be positive");
    if (m->total_mass == 0 && m->vertex_mass == 0)
        return pl_component_error(c, ctx, PL_EINPUT, "give totalMass [kg] or vertexMass [kg]");
    m->state = pl_util_state(c, ctx, 1);
    return m->state ? PL_OK : PL_EINPUT;
}

static pl_component *um_state(const pl_component *c) { return ((const uniform_mass *)c)->state; }

static int um_add(const pl_component *c, double *mass, int n, pl_error *err)
{
    const uniform_mass *m = (const uniform_mass *)c;
    double each = m->total_mass > 0 ? m->total_mass / n : m->vertex_mass;
    for (int i = 0; i < n; ++i) mass[i] += each;
    return PL_OK;
}

static const pl_mass_ops MASS_OPS = {
    .version = PL_MASS_OPS_VERSION, .state = um_state, .add_vertex_masses = um_add};

const pl_type pl_uniform_mass_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "UniformMass",
    .help = "The same lumped mass on every vertex of the node's MechanicalObject.",
    .size = sizeof(uniform_mass),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.bind = um_bind},
    .roles = {[PL_ROLE_MASS] = &MASS_OPS},
};
