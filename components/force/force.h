/* force.h - external loads. */
#ifndef PLIANT_FORCE_H
#define PLIANT_FORCE_H

#include "pliant/pliant.h"

extern const pl_type pl_constant_force_field_type;
extern const pl_type pl_plane_force_field_type;

#endif
