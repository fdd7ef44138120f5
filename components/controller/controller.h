/* controller.h - built-in controllers (PL_ROLE_CONTROLLER): components that
 * drive a RUNTIME field of another component over time. */
#ifndef PLIANT_CONTROLLER_H
#define PLIANT_CONTROLLER_H

#include "pliant/pliant.h"

extern const pl_type pl_keyframes_type;
extern const pl_type pl_keyboard_controller_type;

/* Keyframe interpolation: k values per time (times increasing, ntimes >= 1,
 * values ntimes x k).  Before the first time the first values hold, after
 * the last time the last ones; in between linear interpolation, or the
 * values of the last keyframe at or before t when step != 0. */
void pl_keyframes_eval(const double *times, int ntimes, const double *values, int k, int step,
                       double t, double *out);

#endif
