/* laplace_beltrami_bending.c - the LaplaceBeltramiBending component.
 * Laplace-Beltrami cloth bending (Bouaziz et al. 2014): per vertex, keeps the rest mean-
 * curvature magnitude.
 * Shared machinery in bending_term.c, the math in hyperelastic_core. */
#include "bending_term.h"

static const pl_field FIELDS[] = {HYPER_BENDING_FIELDS};
_Static_assert(sizeof FIELDS / sizeof FIELDS[0] == HYPER_BENDING_NFIELDS, "field count");

static int laplace_beltrami_bending_init(pl_component *c, pl_ctx *ctx)
{
    return hyper_bending_init(c, ctx, HYPER_BENDING_LAPLACE_BELTRAMI);
}

const pl_type hyper_laplace_beltrami_bending_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "LaplaceBeltramiBending",
    .help = "Laplace-Beltrami cloth bending (Bouaziz et al. 2014): per vertex, keeps the rest"
            " mean-curvature magnitude.",
    .size = sizeof(hyper_bending),
    .workspace_size = sizeof(hyper_term_ws),
    .fields = FIELDS,
    .nfields = HYPER_BENDING_NFIELDS,
    .ops = {.init = laplace_beltrami_bending_init,
            .bind = hyper_bending_bind,
            .reinit = hyper_bending_reinit,
            .destroy = hyper_bending_destroy,
            .workspace_free = hyper_term_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &hyper_bending_local_term_ops},
};
