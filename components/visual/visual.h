/* visual.h - components only viewers read (the simulation ignores them). */
#ifndef PLIANT_VISUAL_H
#define PLIANT_VISUAL_H

#include "pliant/pliant.h"

extern const pl_type pl_interactive_camera_type;

#endif
