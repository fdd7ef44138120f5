/* plugin.c - the hyperelastic plugin's entry point: PD / ADMM-PD local
 * terms (ARAP, Corotational, NeoHookean), cloth bending and position
 * targets.  <RequiredPlugin name="hyperelastic"/> loads it. */
#include "pliant/plugin.h"

extern const pl_type hyper_arap_type;
extern const pl_type hyper_corotational_type;
extern const pl_type hyper_neohookean_type;
extern const pl_type hyper_isometric_bending_type;
extern const pl_type hyper_laplace_beltrami_bending_type;
extern const pl_type hyper_position_target_type;

static const pl_type *const types[] = {
    &hyper_arap_type,
    &hyper_corotational_type,
    &hyper_neohookean_type,
    &hyper_isometric_bending_type,
    &hyper_laplace_beltrami_bending_type,
    &hyper_position_target_type,
};

PL_PLUGIN_DEFINE(types)
