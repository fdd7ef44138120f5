/* work_limits.h - caps on the work a scene may ask for.
 *
 * A scene is data, and a typo or a hostile file must not make the program
 * run for ever or allocate gigabytes: a subdivision of 30 rounds, a solver
 * of 2e9 iterations, a regression of INT_MAX steps.  Whatever can be that
 * large is estimated before it starts and refused above a cap, with the
 * file and line of what asked for it.  The caps are generous (the largest
 * scene of scenes/ is far below each); a scene that truly needs more says
 * so with a WorkLimits component in its root or in the node concerned:
 *
 *     <WorkLimits name="limits" maxElements="5e7"/>
 *
 * (and `pliant run --set limits.maxElements=1e8` changes it from outside).
 * The table of caps is in docs/scene-format.md. */
#ifndef PLIANT_WORK_LIMITS_H
#define PLIANT_WORK_LIMITS_H

#include "component.h"
#include "model.h"
#include "node.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The defaults, documented in docs/scene-format.md. */
#define PL_LIMIT_ELEMENTS 10000000LL   /* tetrahedra + triangles of one mesh */
#define PL_LIMIT_ITERATIONS 100000LL   /* iterations per time step of one solver */
#define PL_LIMIT_STEPS 10000000LL      /* time steps of one regression entry */
#define PL_LIMIT_RECORD_MB 2048.0      /* states a regression entry keeps [MB] */
#define PL_LIMIT_TIME_STEP 1.0         /* dt [s] */

typedef struct pl_work_limits {
    long long max_elements;
    long long max_iterations;
    long long max_steps;
    double max_record_mb;
    double max_dt;
} pl_work_limits;

/* The limits in force in node n: those of the nearest WorkLimits component
 * in n or its ancestors, else the defaults; then no more than the model's
 * ceiling (pl_sim_options.max_limits) where it has one.  m and n may be
 * NULL. */
PL_API void pl_work_limits_of(const pl_model *m, const pl_node *n, pl_work_limits *out);

/* Refuses `amount` of `what` above `cap` for component c: PL_OK, or
 * PL_EINPUT reported at c's file:line naming the field that raises it. */
PL_API int pl_work_limit_check(const pl_component *c, pl_ctx *ctx, double amount, long long cap,
                               const char *what, const char *limit_field);

#ifdef __cplusplus
}
#endif
#endif
