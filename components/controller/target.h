/* target.h - the field a controller drives: "@component.field". */
#ifndef PLIANT_CONTROLLER_TARGET_H
#define PLIANT_CONTROLLER_TARGET_H

#include "pliant/pliant.h"

/* Splits "@path.field" (`text`), finds the component from c (links'
 * lookup rules) and its field, which must be an input field (its value
 * lives in each pl_data: input.h) of numbers (double, int, vec3 or a list).  `what` names the controller type in
 * messages.  PL_OK, or PL_EINPUT recorded against c. */
int pl_controller_target(pl_component *c, pl_ctx *ctx, const char *what, const char *text,
                         pl_component **comp, const pl_field **field);

#endif
