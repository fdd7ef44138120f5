/* pick.h - interaction components: PickSpring (the viewer's mouse drag). */
#ifndef PLIANT_PICK_H
#define PLIANT_PICK_H

#include "pliant/pliant.h"

extern const pl_type pl_pick_spring_type;

#endif
