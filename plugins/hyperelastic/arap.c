/* arap.c - the ARAP component: As-rigid-as-possible elasticity (Projective Dynamics):
 * each element is projected on the closest rotation; w = 2 mu V.
 * Tetrahedra or membranes (triangles, plane-stress lambda); the shared
 * machinery is in fem_term.c, the math in hyperelastic_core. */
#include "fem_term.h"

static const pl_field FIELDS[] = {HYPER_FEM_FIELDS};
_Static_assert(sizeof FIELDS / sizeof FIELDS[0] == HYPER_FEM_NFIELDS, "field count");

static int arap_init(pl_component *c, pl_ctx *ctx)
{
    return hyper_fem_init(c, ctx, PL_HYPER_ARAP);
}

const pl_type hyper_arap_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "ARAP",
    .help = "As-rigid-as-possible elasticity (Projective Dynamics): each element is projected"
            " on the closest rotation; w = 2 mu V.",
    .size = sizeof(hyper_fem),
    .workspace_size = sizeof(hyper_term_ws),
    .fields = FIELDS,
    .nfields = HYPER_FEM_NFIELDS,
    .ops = {.init = arap_init,
            .bind = hyper_fem_bind,
            .reinit = hyper_fem_reinit,
            .begin_step = hyper_fem_begin_step,
            .end_step = hyper_fem_end_step,
            .destroy = hyper_fem_destroy,
            .workspace_free = hyper_term_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &hyper_fem_local_term_ops},
};
