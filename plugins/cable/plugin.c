/* plugin.c - the cable plugin's entry point: SoftRobots' actuators,
 * CableConstraint (cable-driven soft robots) and SurfacePressureConstraint
 * (pneumatic cavities).  <RequiredPlugin name="cable"/> loads it. */
#include "pliant/plugin.h"

extern const pl_type pl_cable_constraint_type;
extern const pl_type pl_surface_pressure_type;

static const pl_type *const cable_types[] = {&pl_cable_constraint_type,
                                             &pl_surface_pressure_type};
PL_PLUGIN_DEFINE(cable_types)
