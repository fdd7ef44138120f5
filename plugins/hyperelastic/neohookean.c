/* neohookean.c - the NeoHookean component: Neo-Hookean elasticity by ADMM-PD (Overby
 * et al. 2017): psi = mu/2 (I1 - d) - mu ln J + lambda/2 (ln J)^2.
 * Tetrahedra or membranes (triangles, plane-stress lambda); the shared
 * machinery is in fem_term.c, the math in hyperelastic_core. */
#include "fem_term.h"

static const pl_field FIELDS[] = {HYPER_FEM_FIELDS};
_Static_assert(sizeof FIELDS / sizeof FIELDS[0] == HYPER_FEM_NFIELDS, "field count");

static int neohookean_init(pl_component *c, pl_ctx *ctx)
{
    return hyper_fem_init(c, ctx, PL_HYPER_NEOHOOKEAN);
}

const pl_type hyper_neohookean_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "NeoHookean",
    .help = "Neo-Hookean elasticity by ADMM-PD (Overby et al. 2017): psi = mu/2 (I1 - d) - mu"
            " ln J + lambda/2 (ln J)^2.",
    .size = sizeof(hyper_fem),
    .workspace_size = sizeof(hyper_term_ws),
    .fields = FIELDS,
    .nfields = HYPER_FEM_NFIELDS,
    .ops = {.init = neohookean_init,
            .bind = hyper_fem_bind,
            .reinit = hyper_fem_reinit,
            .begin_step = hyper_fem_begin_step,
            .end_step = hyper_fem_end_step,
            .destroy = hyper_fem_destroy,
            .workspace_free = hyper_term_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &hyper_fem_local_term_ops},
};
