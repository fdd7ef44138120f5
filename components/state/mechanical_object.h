/* mechanical_object.h - MechanicalObject: the DOFs of one body. */
#ifndef PLIANT_MECHANICAL_OBJECT_H
#define PLIANT_MECHANICAL_OBJECT_H

#include "pliant/pliant.h"

extern const pl_type pl_mechanical_object_type;

#endif
