/* work_limits.c - WorkLimits: the caps on what a scene may ask for (see
 * pliant/work_limits.h), and their lookup by the components they bound. */
#include <stdio.h>
#include <string.h>

#include "pliant/component.h"
#include "pliant/field.h"
#include "pliant/node.h"
#include "pliant/plugin.h"
#include "pliant/work_limits.h"

typedef struct work_limits {
    pl_component base;
    double max_elements, max_iterations, max_steps, max_record_mb, max_dt;
} work_limits;

static const pl_field FIELDS[] = {
    PL_FIELD(work_limits, max_elements, "maxElements", PL_F_DOUBLE, "1e7",
             "most tetrahedra + triangles one mesh loader or generator may make (subdivision "
             "included) [count]", 0),
    PL_FIELD(work_limits, max_iterations, "maxIterations", PL_F_DOUBLE, "1e5",
             "most iterations per time step a solver may be asked for [count]", 0),
    PL_FIELD(work_limits, max_steps, "maxSteps", PL_F_DOUBLE, "1e7",
             "most time steps of a regression entry (pliant regress) [count]", 0),
    PL_FIELD(work_limits, max_record_mb, "maxRecordMB", PL_F_DOUBLE, "2048",
             "most memory the recorded states of a regression entry may take [MB]", 0),
    PL_FIELD(work_limits, max_dt, "maxTimeStep", PL_F_DOUBLE, "1",
             "largest time step dt a node may set [s]", 0),
};

static int wl_init(pl_component *c, pl_ctx *ctx)
{
    const work_limits *w = (const work_limits *)c;
    const double v[] = {w->max_elements, w->max_iterations, w->max_steps, w->max_record_mb,
                        w->max_dt};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k)
        if (!(v[k] > 0) || (k < 3 && v[k] > 9.2e18))
            return pl_component_error(c, ctx, PL_EINPUT, "%s must be positive, got %g",
                                      FIELDS[k].name, v[k]);
    return PL_OK;
}

/* The caps of the nearest WorkLimits in n or above (out unchanged if none). */
static void scene_limits(const pl_node *n, pl_work_limits *out)
{
    for (; n; n = n->parent)
        for (int k = 0; k < n->ncomponents; ++k) {
            const pl_component *c = n->components[k];
            /* the registry holds a copy of the type: recognise it by its init */
            if (c->type->ops.init != wl_init) continue;
            const work_limits *w = (const work_limits *)c;
            /* only sane values count (init reports the others) */
            if (w->max_elements > 0 && w->max_elements < 9.2e18)
                out->max_elements = (long long)w->max_elements;
            if (w->max_iterations > 0 && w->max_iterations < 9.2e18)
                out->max_iterations = (long long)w->max_iterations;
            if (w->max_steps > 0 && w->max_steps < 9.2e18)
                out->max_steps = (long long)w->max_steps;
            if (w->max_record_mb > 0) out->max_record_mb = w->max_record_mb;
            if (w->max_dt > 0) out->max_dt = w->max_dt;
            return;
        }
}

#define MIN(a, b) ((a) < (b) ? (a) : (b))

void pl_work_limits_of(const pl_model *m, const pl_node *n, pl_work_limits *out)
{
    *out = (pl_work_limits){PL_LIMIT_ELEMENTS, PL_LIMIT_ITERATIONS, PL_LIMIT_STEPS,
                            PL_LIMIT_RECORD_MB, PL_LIMIT_TIME_STEP};
    scene_limits(n, out);
    const pl_work_limits *c = m ? m->ceiling : NULL;
    if (!c) return;
    out->max_elements = MIN(out->max_elements, c->max_elements);
    out->max_iterations = MIN(out->max_iterations, c->max_iterations);
    out->max_steps = MIN(out->max_steps, c->max_steps);
    out->max_record_mb = MIN(out->max_record_mb, c->max_record_mb);
    out->max_dt = MIN(out->max_dt, c->max_dt);
}

int pl_work_limit_check(const pl_component *c, pl_ctx *ctx, double amount, long long cap,
                        const char *what, const char *limit_field)
{
    if (amount <= (double)cap) return PL_OK;
    return pl_component_error(c, ctx, PL_EINPUT,
                              "%s would be %.6g, above the cap of %lld (it guards against "
                              "runs that never end or exhaust memory; a scene that needs more "
                              "sets <WorkLimits %s=\"...\"/>)",
                              what, amount, cap, limit_field);
}

const pl_type pl_work_limits_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "WorkLimits",
    .help = "Caps on the work the scene may ask for (mesh sizes, iterations, steps, dt), for "
            "this node and the nodes below it; the defaults apply where there is none.",
    .size = sizeof(work_limits),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = wl_init},
};
