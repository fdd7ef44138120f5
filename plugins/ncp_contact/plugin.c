/* plugin.c - the ncp_contact plugin's entry point: the non-smooth Newton
 * contact solver of the paper's Section 5 (Algorithm 4).
 * <RequiredPlugin name="ncp_contact"/> loads it. */
#include "pliant/plugin.h"

extern const pl_type pl_ncp_contact_solver_type;

static const pl_type *const types[] = {&pl_ncp_contact_solver_type};

PL_PLUGIN_DEFINE(types)
