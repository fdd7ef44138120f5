/* test_plugin.c - a plugin for the core tests: "TestMover", an animation
 * loop that moves every state by its velocity (x += v dt) and counts steps
 * in its own state slot, so save/restore/reset can be checked exactly; its
 * acceleration is an input field (per pl_data).  It also keeps a per-data
 * workspace: the number of steps that workspace saw, so the tests can see
 * when the core made, kept or remade it. */
#include <pliant/pliant.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct test_mover {
    pl_component base;
    double accel[3];
    int slot;
} test_mover;

typedef struct test_mover_ws {
    long steps;       /* steps this workspace saw */
    double *buffer;   /* something to free: a leak shows under ASan */
} test_mover_ws;

static long workspaces_freed;

static const pl_field FIELDS[] = {
    PL_FIELD(test_mover, accel, "acceleration", PL_F_VEC3, "0 0 0",
             "acceleration added to the velocities [m/s^2]", PL_FIELD_INPUT),
};

static int tm_init(pl_component *c, pl_ctx *ctx)
{
    test_mover *m = (test_mover *)c;
    m->slot = pl_model_add_slot(ctx->build, c, "count", sizeof(long));
    return m->slot < 0 ? PL_EINTERNAL : PL_OK;
}

typedef struct move_args {
    pl_data *d;
    double dt;
    const double *a;
} move_args;

static int move_state(pl_component *s, void *user)
{
    move_args *m = user;
    const pl_state_ops *ops = pl_component_role(s, PL_ROLE_STATE);
    pl_buffer x = ops->positions(s, m->d), v = ops->velocities(s, m->d);
    double *px = pl_buffer_f64(&x), *pv = pl_buffer_f64(&v);
    for (size_t i = 0; i < x.rows; ++i)
        for (int k = 0; k < 3; ++k) {
            /* a non-linear update so that round-off is visible if a state is restored wrong */
            pv[3 * i + k] += m->dt * m->a[k] - 0.01 * pv[3 * i + k] * pv[3 * i + k] * m->dt;
            px[3 * i + k] += m->dt * pv[3 * i + k];
        }
    return 0;
}

static int tm_step(const pl_component *c, pl_ctx *ctx, double dt, pl_error *err)
{
    const test_mover *tm = (const test_mover *)c;
    pl_node *root = c->node;
    while (root->parent) root = root->parent;
    test_mover_ws *w = pl_data_workspace(ctx->data, c);
    if (!w || (!w->buffer && !(w->buffer = calloc(16, sizeof *w->buffer))))
        return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    w->steps++;
    move_args args = {ctx->data, dt, pl_input_vec3(ctx->data, c, tm->accel)};
    pl_node_visit_role(root, PL_ROLE_STATE, move_state, &args);
    (*(long *)pl_data_slot(ctx->data, tm->slot))++;
    return PL_OK;
}

static void tm_workspace_free(const pl_component *c, void *ws)
{
    (void)c;
    free(((test_mover_ws *)ws)->buffer);
    workspaces_freed++;
}

/* "count": the step slot; "wsSteps": the steps the data's workspace saw
 * (-1 when it has none yet); "wsFreed": workspaces freed so far. */
static int tm_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                  size_t size)
{
    const test_mover *tm = (const test_mover *)c;
    if (!strcmp(field, "wsFreed")) {
        snprintf(buf, size, "%ld", workspaces_freed);
        return PL_OK;
    }
    if (!strcmp(field, "wsSteps")) {
        /* peeks without making one: the workspace array is the core's */
        long steps = -1;
        const pl_model *m = d->model;
        for (int k = 0; d->workspaces && k < m->ncomponents; ++k)
            if (m->components[k] == c && d->workspaces[k] && d->ws_generation == m->generation)
                steps = ((const test_mover_ws *)d->workspaces[k])->steps;
        snprintf(buf, size, "%ld", steps);
        return PL_OK;
    }
    if (strcmp(field, "count")) return PL_EINPUT;
    snprintf(buf, size, "%ld", *(const long *)pl_data_slot(d, tm->slot));
    return PL_OK;
}

static const pl_animation_loop_ops LOOP = {.version = PL_ANIMATION_LOOP_OPS_VERSION,
                                           .step = tm_step};

static const pl_type TEST_MOVER = {
    .abi_version = PL_ABI_VERSION,
    .name = "TestMover",
    .help = "test loop: x += v dt for every state",
    .size = sizeof(test_mover),
    .workspace_size = sizeof(test_mover_ws),
    .fields = FIELDS,
    .nfields = 1,
    .ops = {.init = tm_init, .get = tm_get, .workspace_free = tm_workspace_free},
    .roles = {[PL_ROLE_ANIMATION_LOOP] = &LOOP},
};

static const pl_type *const TYPES[] = {&TEST_MOVER};
PL_PLUGIN_DEFINE(TYPES)
