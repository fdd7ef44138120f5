/* prescribed.h - components that prescribe DOFs (eliminated from the unknowns). */
#ifndef PLIANT_PRESCRIBED_H
#define PLIANT_PRESCRIBED_H

#include "pliant/pliant.h"

extern const pl_type pl_fixed_constraint_type;
extern const pl_type pl_prescribed_motion_type;

#endif
