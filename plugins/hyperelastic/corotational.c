/* corotational.c - the Corotational component: corotational elasticity by ADMM-PD
 * (Overby et al. 2017): psi = mu |F - R|^2 + lambda/2 tr(R^T F - I)^2.
 * Tetrahedra or membranes (triangles, plane-stress lambda); the shared
 * machinery is in fem_term.c, the math in hyperelastic_core. */
#include "fem_term.h"

static const pl_field FIELDS[] = {
    HYPER_FEM_FIELDS,
    PL_FIELD_ENUM(hyper_fem, rotation, "rotation", hyper_fem_rotation_choices, "polar",
                  "each element's rotation R: polar (the polar decomposition of F; forces are "
                  "the energy's gradient) or edges (SOFA's 'large' method: a frame on the "
                  "element's edges, linear elasticity in it; no energy, so only "
                  "LinearizedEulerSolver uses it, with SOFA's stiffness R K0 R^T)",
                  0),
};
_Static_assert(sizeof FIELDS / sizeof FIELDS[0] == HYPER_FEM_NFIELDS + 1, "field count");

static int corotational_init(pl_component *c, pl_ctx *ctx)
{
    return hyper_fem_init(c, ctx, PL_HYPER_COROTATIONAL);
}

const pl_type hyper_corotational_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "Corotational",
    .help = "Corotational elasticity by ADMM-PD (Overby et al. 2017): psi = mu |F - R|^2 + "
            "lambda/2 tr(R^T F - I)^2.",
    .size = sizeof(hyper_fem),
    .workspace_size = sizeof(hyper_term_ws),
    .fields = FIELDS,
    .nfields = HYPER_FEM_NFIELDS + 1,
    .ops = {.init = corotational_init,
            .bind = hyper_fem_bind,
            .reinit = hyper_fem_reinit,
            .begin_step = hyper_fem_begin_step,
            .end_step = hyper_fem_end_step,
            .destroy = hyper_fem_destroy,
            .workspace_free = hyper_term_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &hyper_fem_local_term_ops},
};
