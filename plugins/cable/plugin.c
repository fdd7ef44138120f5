/* plugin.c - the cable plugin's entry point: CableConstraint (cable-driven
 * soft robots).  <RequiredPlugin name="cable"/> loads it. */
#include "pliant/plugin.h"

extern const pl_type pl_cable_constraint_type;

static const pl_type *const cable_types[] = {&pl_cable_constraint_type};
PL_PLUGIN_DEFINE(cable_types)
