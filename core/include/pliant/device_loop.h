/* device_loop.h - the stopping rule of an iteration loop kept on a device
 * (pl_device_ops.loop, device ops version 3, ABI 5.5).
 *
 * A solver that iterates until a position change and a force residual are
 * small (the LocalGlobalSolver's tolerance and forceTolerance) would read
 * those numbers back after every iteration to decide whether to go on: a
 * host wait per iteration.  Instead the decision is taken on the device by
 * pl_device_loop_rule, on a pl_device_loop in device memory that the
 * solver fills once per step and reads back once at its end.  The rule is
 * written here once (PL_HD: C and CUDA, hostdevice.h) so that the CUDA
 * service's kernel, host fakes and any host fallback apply the same
 * arithmetic; it is the CPU loop's rule (local_global_solver.c), in the
 * same order of operations. */
#ifndef PLIANT_DEVICE_LOOP_H
#define PLIANT_DEVICE_LOOP_H

#include <math.h>

#include "hostdevice.h"

/* Plain data, the same layout in C and CUDA.  The solver sets every field
 * before the loop; the rule updates done, nonfinite, converged, residual. */
typedef struct pl_device_loop {
    int done;               /* iterations counted so far (each rule call adds one) */
    int iterations;         /* the most iterations: the loop stops once done reaches it */
    int nonfinite;          /* 0, or the iteration (1-based) whose change was not finite */
    int converged;          /* 1 once the tolerances stopped the loop */
    double tolerance;       /* > 0: converged needs change < tolerance * scale */
    double scale;           /* the tolerance's length scale (bounding-box diagonal) [m] */
    double force_tolerance; /* > 0: converged needs residual < force_tolerance [N] */
    double residual;        /* the last residual read (force_tolerance > 0), else as set */
} pl_device_loop;

/* Counts the iteration that just ran and says whether to run another (1)
 * or stop (0).  change: the iteration's largest position change (+inf when
 * a new position is not finite; NULL: none, allowed only without
 * tolerance); residual: its force residual, read only when
 * force_tolerance > 0.  A change that is not finite stops the loop and is
 * recorded in nonfinite (the caller fails the step, as the CPU does at
 * that iteration). */
PL_HD int pl_device_loop_rule(pl_device_loop *s, const double *change, const double *residual)
{
    double ch = change ? *change : 0.0;
    s->done += 1;
    if (s->force_tolerance > 0) s->residual = *residual;
    if (!isfinite(ch)) {
        s->nonfinite = s->done;
        return 0;
    }
    if ((s->tolerance > 0 || s->force_tolerance > 0) &&
        (s->tolerance <= 0 || ch < s->tolerance * s->scale) &&
        (s->force_tolerance <= 0 || s->residual < s->force_tolerance)) {
        s->converged = 1;
        return 0;
    }
    return s->done < s->iterations;
}

#endif
