/* fault_injector.c - a test plugin (never installed): FaultInjector makes a
 * run go wrong on purpose at a given step, so that the tests of `pliant
 * sweep` and `pliant regress` can show that one bad run is reported while
 * the others complete:
 *   nan    writes NaN into the velocities of its node's state (the solver
 *          then stops the run with its non-finite error),
 *   segv   the process dies of SIGSEGV,  abort  of SIGABRT,
 *   hang   the step never returns (a --timeout ends it),
 *   none   nothing (the grid point that runs normally). */
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include "pliant/pliant.h"

typedef struct fault_injector {
    pl_component base;
    int kind;
    int step;
} fault_injector;

enum { FAULT_NONE, FAULT_NAN, FAULT_SEGV, FAULT_ABORT, FAULT_HANG };
static const char *const KINDS[] = {"none", "nan", "segv", "abort", "hang", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD_ENUM(fault_injector, kind, "kind", KINDS, "none", "what goes wrong", 0),
    PL_FIELD(fault_injector, step, "step", PL_F_INT, "1",
             "the step (0-based) at whose start it goes wrong [count]", 0),
};

static int fault_begin_step(const pl_component *c, pl_ctx *ctx, pl_error *err)
{
    const fault_injector *f = (const fault_injector *)c;
    if (ctx->data->step != f->step) return PL_OK;
    switch (f->kind) {
    case FAULT_NAN: {
        pl_component *state = pl_node_find_role(c->node, PL_ROLE_STATE);
        const pl_state_ops *ops = pl_component_role(state, PL_ROLE_STATE);
        if (!ops) return pl_component_fail(c, err, PL_EINPUT, "needs a state in its node");
        pl_buffer v = ops->velocities(state, ctx->data);
        double *x = pl_buffer_f64(&v);
        for (size_t k = 0; x && k < v.rows * v.cols; ++k) x[k] = NAN;
        return PL_OK;
    }
    case FAULT_SEGV:
        /* the default action: a sanitizer's handler would turn it into exit(1) */
        signal(SIGSEGV, SIG_DFL);
        raise(SIGSEGV);
        break;
    case FAULT_ABORT: abort();
    case FAULT_HANG:
        for (;;) pause();
    default: break;
    }
    return PL_OK;
}

static const pl_type FAULT_TYPE = {
    .abi_version = PL_ABI_VERSION,
    .name = "FaultInjector",
    .help = "test only: makes the run fail at a given step (NaN, crash, hang)",
    .size = sizeof(fault_injector),
    .fields = FIELDS,
    .nfields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .ops = {.begin_step = fault_begin_step},
};

static const pl_type *const TYPES[] = {&FAULT_TYPE};
PL_PLUGIN_DEFINE(TYPES)
