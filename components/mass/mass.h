/* mass.h - lumped mass components. */
#ifndef PLIANT_MASS_H
#define PLIANT_MASS_H

#include "pliant/pliant.h"

extern const pl_type pl_uniform_mass_type;
extern const pl_type pl_diagonal_mass_type;

#endif
