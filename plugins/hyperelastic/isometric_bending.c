/* isometric_bending.c - the IsometricBending component.
 * Quadratic isometric cloth bending (Bergou et al. 2006): a 4-vertex cotangent stencil per
 * interior edge; flat rest state.
 * Shared machinery in bending_term.c, the math in hyperelastic_core. */
#include "bending_term.h"

static const pl_field FIELDS[] = {HYPER_BENDING_FIELDS};
_Static_assert(sizeof FIELDS / sizeof FIELDS[0] == HYPER_BENDING_NFIELDS, "field count");

static int isometric_bending_init(pl_component *c, pl_ctx *ctx)
{
    return hyper_bending_init(c, ctx, HYPER_BENDING_ISOMETRIC);
}

const pl_type hyper_isometric_bending_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "IsometricBending",
    .help = "Quadratic isometric cloth bending (Bergou et al. 2006): a 4-vertex cotangent "
            "stencil per interior edge; flat rest state.",
    .size = sizeof(hyper_bending),
    .workspace_size = sizeof(hyper_term_ws),
    .fields = FIELDS,
    .nfields = HYPER_BENDING_NFIELDS,
    .ops = {.init = isometric_bending_init,
            .bind = hyper_bending_bind,
            .reinit = hyper_bending_reinit,
            .destroy = hyper_bending_destroy,
            .workspace_free = hyper_term_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &hyper_bending_local_term_ops},
};
