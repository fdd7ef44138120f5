/* sim.c - the embedding API: load (parse, override, init, bind, reinit),
 * step, reset, save/restore.  See sim.h. */
#include "pliant/sim.h"
#include "pliant/log.h"
#include "pliant/roles.h"
#include "model_internal.h"
#include "pliant/work_limits.h"
#include "scene.h"
#include "walk.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

struct pl_sim {
    pl_registry *registry;
    int own_registry;
    pl_model model;
    pl_data *data;
    pl_timers *timers;
    char *out_dir;
    int export_every;
    pl_component *loop;      /* the animation loop, or NULL */
    pl_work_limits ceiling;  /* pl_sim_options.max_limits, model.ceiling points here */
    pl_component *implicit_device; /* added by the loader (sim_device.c), or NULL */
    int device_forced;             /* policy "gpu": the cost model does not choose */
    pl_sim_callback callback;
    void *callback_user;
    pl_data *stepping;       /* the data whose step runs the callback, or NULL */
    int frame_timer;
};

/* A step's context: the model read-only. */
static pl_ctx make_ctx(pl_sim *s, pl_data *d, pl_diag *diag)
{
    pl_ctx ctx = {&s->model, d, s->registry, s->timers, diag, NULL};
    return ctx;
}

/* The context of init, bind and reinit: the model may be built. */
static pl_ctx build_ctx(pl_sim *s, pl_data *d, pl_diag *diag)
{
    pl_ctx ctx = {&s->model, d, s->registry, s->timers, diag, &s->model};
    return ctx;
}

/* ---- loading ------------------------------------------------------------ */

static int resolve_links(pl_component *c, void *user)
{
    pl_ctx *ctx = user;
    for (int k = 0; k < c->type->nfields; ++k) {
        const pl_field *f = &c->type->fields[k];
        if (f->type != PL_F_LINK) continue;
        pl_link *l = (pl_link *)((char *)c + f->offset);
        if (!l->path || !l->path[0]) continue;
        l->target = pl_node_resolve(c, l->path);
        if (!l->target)
            pl_component_error(c, ctx, PL_EINPUT,
                               "%s: link '@%s' names no component (names are looked up in this "
                               "node, then its parents; use '@../x' or '@child/x' for others)",
                               f->name, l->path);
    }
    return 0;
}

/* A load-time callback's status is the plugin's word: a failure stops the
 * load even when the callback recorded nothing (then a generic error names
 * the component), and a recorded error stops it even with PL_OK. */
static int honour(pl_component *c, pl_ctx *ctx, const char *what, int rc, int errors_before)
{
    if (rc == PL_OK) return 0;
    if (ctx->diag->nerrors == errors_before)
        pl_component_error(c, ctx, rc == PL_EINPUT ? PL_EINPUT : PL_EINTERNAL,
                           "%s failed (status %d) without saying why", what, rc);
    return 0; /* go on: the user sees every component's errors at once */
}

static int call_init(pl_component *c, void *user)
{
    pl_ctx *ctx = user;
    pl_error err;
    /* the slots of its input fields first: init may look them up */
    if (pl_input_declare(ctx->build, c, &err) != PL_OK) {
        pl_component_error(c, ctx, err.code, "%s", err.msg);
        return 0;
    }
    int before = ctx->diag->nerrors;
    return c->type->ops.init ? honour(c, ctx, "init", c->type->ops.init(c, ctx), before) : 0;
}
static int call_bind(pl_component *c, void *user)
{
    pl_ctx *ctx = user;
    int before = ctx->diag->nerrors;
    return c->type->ops.bind ? honour(c, ctx, "bind", c->type->ops.bind(c, ctx), before) : 0;
}
static int call_reinit(pl_component *c, void *user)
{
    pl_ctx *ctx = user;
    int before = ctx->diag->nerrors;
    return c->type->ops.reinit ? honour(c, ctx, "reinit", c->type->ops.reinit(c, ctx), before) : 0;
}

static int apply_override(pl_sim *s, const char *text, pl_diag *diag)
{
    const char *eq = strchr(text, '=');
    char path[512];
    if (!eq || (size_t)(eq - text) >= sizeof path) {
        return pl_diag_error(diag, PL_EINPUT, "--set", 0, NULL,
                             "'%s': expected PATH=VALUE (e.g. bar/arap.youngModulus=1e6)", text);
    }
    memcpy(path, text, (size_t)(eq - text));
    path[eq - text] = '\0';
    pl_error e;
    if (pl_walk_set(s->model.root, path, eq + 1, &e) != PL_OK) {
        pl_diag_error(diag, e.code, "--set", 0, path, "%s", e.msg);
        return e.code;
    }
    return PL_OK;
}

static int find_loop(pl_component *c, void *user)
{
    pl_component **loop = user;
    if (!*loop) *loop = c;
    return 0;
}

static int load_tree(pl_sim *s, pl_diag *diag)
{
    pl_node *root = s->model.root;
    pl_ctx ctx = build_ctx(s, NULL, diag);
    if (diag->nerrors) return PL_EINPUT;
    if (pl_model_index_components(&s->model) != PL_OK)
        return pl_diag_error(diag, PL_EINTERNAL, s->model.file, 0, NULL, "out of memory");
    /* links first: init may follow them to components above it in the scene */
    walk_pre(root, resolve_links, &ctx);
    if (diag->nerrors) return pl_diag_status(diag);
    walk_pre(root, call_init, &ctx);
    if (diag->nerrors) return pl_diag_status(diag);
    /* sizes known, nothing on the device yet: the implicit device stays
     * only where the cost model predicts it faster */
    if (pl_sim_device_cost(root, s->implicit_device, s->device_forced, &s->model, s->timers)) {
        s->implicit_device = NULL;
        if (pl_model_index_components(&s->model) != PL_OK)
            return pl_diag_error(diag, PL_EINTERNAL, s->model.file, 0, NULL, "out of memory");
    }
    s->data = pl_data_create(&s->model);
    if (!s->data) return pl_diag_error(diag, PL_EINTERNAL, s->model.file, 0, NULL, "out of memory");
    ctx.data = s->data;
    walk_pre(root, call_bind, &ctx);
    if (diag->nerrors) return pl_diag_status(diag);
    walk_post(root, call_reinit, &ctx);
    s->model.generation++;
    if (diag->nerrors) return pl_diag_status(diag);
    if (pl_node_count_role(root, PL_ROLE_ANIMATION_LOOP) > 1)
        return pl_diag_error(diag, PL_EINPUT, s->model.file, 0, NULL,
                             "the scene has %d animation loops; it needs at most one",
                             pl_node_count_role(root, PL_ROLE_ANIMATION_LOOP));
    pl_node_visit_role(root, PL_ROLE_ANIMATION_LOOP, find_loop, &s->loop);
    s->model.initial = pl_data_clone(s->data);
    if (!s->model.initial)
        return pl_diag_error(diag, PL_EINTERNAL, s->model.file, 0, NULL, "out of memory");
    return PL_OK;
}

static int export_all(pl_sim *s, pl_data *d, int finish, pl_error *err);

/* A time step is the one number of a node that scales everything (dt^2 in
 * every update): above the cap, positions overflow to NaN a step later, so
 * it is refused here as bad input, with the node's file:line. */
static void check_time_steps(const pl_model *m, const pl_node *n, pl_diag *diag)
{
    if (n->has_dt) {
        pl_work_limits lim;
        pl_work_limits_of(m, n, &lim);
        char np[160];
        if (!(n->dt <= lim.max_dt))
            pl_diag_error(diag, PL_EINPUT, n->file, n->line, pl_node_path(n, np, sizeof np),
                          "dt = %g s is above the cap of %g s (it guards against steps that "
                          "overflow; a scene that needs more sets <WorkLimits maxTimeStep=\"...\"/>)",
                          n->dt, lim.max_dt);
    }
    for (int k = 0; k < n->nchildren; ++k) check_time_steps(m, n->children[k], diag);
}

typedef struct prepare_hook {
    pl_sim_prepare fn;
    void *user;
} prepare_hook;

static pl_sim *load(const char *xml, size_t len, const char *file, const pl_sim_options *opt,
                    const prepare_hook *hook, pl_diag *diag)
{
    pl_sim *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->registry = opt && opt->registry ? opt->registry : NULL;
    s->timers = pl_timers_create();
    s->model.file = strdup(file);
    if (!s->timers || !s->model.file) goto fail;
    if (!s->registry) {
        pl_error e;
        s->registry = pl_registry_create();
        s->own_registry = 1;
        if (!s->registry || pl_register_builtin_components(s->registry, &e) != PL_OK) {
            pl_diag_error(diag, PL_EINTERNAL, file, 0, NULL, "cannot register components");
            goto fail;
        }
    }
    if (opt && opt->out_dir && !(s->out_dir = strdup(opt->out_dir))) goto fail;
    if (opt && opt->max_limits) {
        s->ceiling = *opt->max_limits;
        s->model.ceiling = &s->ceiling;
    }
    s->export_every = opt ? opt->export_every : 0;
    int flags = opt && opt->allow_plugin_path ? PL_SCENE_ALLOW_PLUGIN_PATH : 0;
    s->model.root = pl_scene_build(xml, len, file, s->registry, flags, diag);
    if (!s->model.root || diag->nerrors) goto fail;
    pl_component *dev = pl_sim_implicit_device(s->model.root, s->registry, &s->model, opt,
                                               &s->device_forced, diag);
    for (int k = 0; opt && k < opt->noverrides; ++k) apply_override(s, opt->overrides[k], diag);
    check_time_steps(&s->model, s->model.root, diag);
    if (diag->nerrors) goto fail;
    s->implicit_device = pl_sim_implicit_device_try(s->model.root, dev, s->registry, &s->model);
    if (hook->fn && hook->fn(s->model.root, s->registry, diag, hook->user)) {
        if (!diag->nerrors)
            pl_diag_error(diag, PL_EINPUT, file, 0, NULL, "the program's prepare step failed");
        goto fail;
    }
    if (load_tree(s, diag) != PL_OK) goto fail;
    s->frame_timer = pl_timer_id(s->timers, "Frame");
    pl_timer_watch(s->timers, s->frame_timer); /* spikes: the host's or the work's */
    pl_error e;
    if (export_all(s, s->data, 0, &e) != PL_OK) {
        pl_diag_add(diag, &e);
        goto fail;
    }
    return s;
fail:
    pl_sim_free(s);
    return NULL;
}

pl_sim *pl_sim_load_string_prepared(const char *xml, const char *name,
                                    const pl_sim_options *opt, pl_sim_prepare prepare,
                                    void *user, pl_diag *diag)
{
    prepare_hook hook = {prepare, user};
    return load(xml, strlen(xml), name ? name : "<string>", opt, &hook, diag);
}

pl_sim *pl_sim_load_string(const char *xml, const char *name, const pl_sim_options *opt,
                           pl_diag *diag)
{
    return pl_sim_load_string_prepared(xml, name, opt, NULL, NULL, diag);
}

pl_sim *pl_sim_load_file(const char *path, const pl_sim_options *opt, pl_diag *diag)
{
    return pl_sim_load_file_prepared(path, opt, NULL, NULL, diag);
}

pl_sim *pl_sim_load_file_prepared(const char *path, const pl_sim_options *opt,
                                  pl_sim_prepare prepare, void *user, pl_diag *diag)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        pl_diag_error(diag, PL_EINPUT, path, 0, NULL, "cannot open the scene: %s",
                      strerror(errno));
        return NULL;
    }
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || st.st_size > (1 << 30)) {
        fclose(f);
        pl_diag_error(diag, PL_EINPUT, path, 0, NULL, "cannot read the scene (too large?)");
        return NULL;
    }
    size_t len = (size_t)st.st_size;
    char *buf = malloc(len + 1);
    if (!buf || fread(buf, 1, len, f) != len) {
        free(buf);
        fclose(f);
        pl_diag_error(diag, PL_EINPUT, path, 0, NULL, "cannot read the scene");
        return NULL;
    }
    buf[len] = '\0';
    fclose(f);
    prepare_hook hook = {prepare, user};
    pl_sim *s = load(buf, len, path, opt, &hook, diag);
    free(buf);
    return s;
}

void pl_sim_free(pl_sim *s)
{
    if (!s) return;
    if (s->data && s->model.root) pl_sim_finish(s, NULL);
    /* the data first: their workspaces are freed by the components */
    pl_data_free(s->model.initial);
    pl_data_free(s->data);
    pl_scene_free(s->model.root);
    for (int k = 0; k < s->model.nslots; ++k) free(s->model.slots[k].name);
    free(s->model.slots);
    free(s->model.components);
    free(s->model.file);
    if (s->own_registry) pl_registry_free(s->registry);
    pl_timers_free(s->timers);
    free(s->out_dir);
    free(s);
}

/* ---- stepping ----------------------------------------------------------- */

typedef struct step_walk {
    pl_ctx ctx;
    pl_error *err;
    int rc;
    double t;
    const pl_export_info *info;
    int finish;
} step_walk;

/* A step-time callback's status: a failure without a message in err gets
 * a generic one naming the component. */
static int step_status(step_walk *w, pl_component *c, const char *what, int rc)
{
    if (rc != PL_OK && w->err->code == PL_OK)
        pl_component_fail(c, w->err, rc == PL_EINPUT ? PL_EINPUT : PL_EINTERNAL,
                          "%s failed (status %d) without saying why", what, rc);
    return (w->rc = rc == PL_OK ? PL_OK : w->err->code);
}

static int call_begin(pl_component *c, void *user)
{
    step_walk *w = user;
    if (!c->type->ops.begin_step) return 0;
    return step_status(w, c, "begin_step", c->type->ops.begin_step(c, &w->ctx, w->err));
}
static int call_end(pl_component *c, void *user)
{
    step_walk *w = user;
    if (!c->type->ops.end_step) return 0;
    return step_status(w, c, "end_step", c->type->ops.end_step(c, &w->ctx, w->err));
}
static int call_controller(pl_component *c, void *user)
{
    step_walk *w = user;
    const pl_controller_ops *ops = pl_component_role(c, PL_ROLE_CONTROLLER);
    return ops->apply ? step_status(w, c, "apply", ops->apply(c, &w->ctx, w->t, w->err)) : 0;
}
static int call_exporter(pl_component *c, void *user)
{
    step_walk *w = user;
    const pl_exporter_ops *ops = pl_component_role(c, PL_ROLE_EXPORTER);
    if (w->finish)
        return ops->finish ? step_status(w, c, "finish", ops->finish(c, &w->ctx, w->info, w->err)) : 0;
    return ops->write ? step_status(w, c, "write", ops->write(c, &w->ctx, w->info, w->err)) : 0;
}

static int export_all(pl_sim *s, pl_data *d, int finish, pl_error *err)
{
    pl_error_clear(err);
    pl_export_info info = {s->out_dir, s->export_every, d->step, d->time};
    step_walk w = {make_ctx(s, d, NULL), err, 0, d->time, &info, finish};
    pl_node_visit_role(s->model.root, PL_ROLE_EXPORTER, call_exporter, &w);
    return w.rc;
}

static int step_once(pl_sim *s, pl_data *d, pl_error *err)
{
    double dt = pl_node_dt(s->model.root);
    step_walk w = {make_ctx(s, d, NULL), err, 0, d->time, NULL, 0};
    pl_error_clear(err);
    pl_timer_start(s->timers, s->frame_timer);
    s->stepping = d; /* pl_sim_set/get in the callback address this data */
    int cb = s->callback ? s->callback(s, d->time, s->callback_user) : 0;
    s->stepping = NULL;
    if (cb != 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "callback",
                            "the embedding program's step callback failed at t = %g s", d->time);
    if (walk_pre(s->model.root, call_begin, &w)) return w.rc;
    if (pl_node_visit_role(s->model.root, PL_ROLE_CONTROLLER, call_controller, &w)) return w.rc;
    if (s->loop) {
        const pl_animation_loop_ops *ops = pl_component_role(s->loop, PL_ROLE_ANIMATION_LOOP);
        int rc = step_status(&w, s->loop, "step", ops->step(s->loop, &w.ctx, dt, err));
        if (rc) return rc;
    }
    d->time += dt;
    d->step++;
    if (walk_pre(s->model.root, call_end, &w)) return w.rc;
    pl_timer_stop(s->timers, s->frame_timer);
    pl_timers_end_frame(s->timers);
    /* exporters write the sim's own data: another data would mix its frames in */
    return d == s->data ? export_all(s, d, 0, err) : PL_OK;
}

int pl_sim_step_data(pl_sim *s, pl_data *d, int nsteps, pl_error *err)
{
    pl_error local;
    if (!err) err = &local;
    pl_error_clear(err);
    if (d->model != &s->model)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "this state belongs to another model");
    for (int k = 0; k < nsteps; ++k) {
        int rc = step_once(s, d, err);
        if (rc) return rc;
    }
    return PL_OK;
}

int pl_sim_step(pl_sim *s, int nsteps, pl_error *err)
{
    return pl_sim_step_data(s, s->data, nsteps, err);
}

int pl_sim_finish(pl_sim *s, pl_error *err)
{
    pl_error local;
    return export_all(s, s->data, 1, err ? err : &local);
}

/* ---- access ------------------------------------------------------------- */

int pl_sim_set_data(pl_sim *s, pl_data *d, const char *path, const char *value, pl_error *err)
{
    int runtime = 0;
    pl_error local;
    if (!err) err = &local;
    if (d && d->model != &s->model)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "this state belongs to another model");
    int rc = pl_walk_set_runtime(s->model.root, d, path, value, &runtime, err);
    if (rc != PL_OK || runtime) return rc;
    /* a model field changed: rebuild derived data (weights, factors); every
     * data's workspaces are remade when next used */
    pl_diag diag;
    pl_diag_init(&diag);
    pl_ctx ctx = build_ctx(s, s->data, &diag);
    walk_post(s->model.root, call_reinit, &ctx);
    s->model.generation++;
    rc = pl_diag_status(&diag);
    if (rc != PL_OK && diag.count) *err = diag.items[0];
    pl_diag_free(&diag);
    return rc;
}

int pl_sim_set(pl_sim *s, const char *path, const char *value, pl_error *err)
{
    return pl_sim_set_data(s, s->stepping ? s->stepping : s->data, path, value, err);
}

int pl_sim_get_data(const pl_sim *s, const pl_data *d, const char *path, char *buf, size_t size,
                    pl_error *err)
{
    if (d->model != &s->model)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "this state belongs to another model");
    return pl_walk_get(s->model.root, d, path, buf, size, err);
}

int pl_sim_get(const pl_sim *s, const char *path, char *buf, size_t size, pl_error *err)
{
    return pl_walk_get(s->model.root, s->stepping ? s->stepping : s->data, path, buf, size, err);
}

pl_component *pl_sim_component(const pl_sim *s, const char *path)
{
    return pl_walk_component(s->model.root, path, NULL);
}

pl_model *pl_sim_model(pl_sim *s) { return &s->model; }
pl_data *pl_sim_data(pl_sim *s) { return s->data; }
pl_registry *pl_sim_registry(pl_sim *s) { return s->registry; }
pl_timers *pl_sim_timers(pl_sim *s) { return s->timers; }
double pl_sim_time(const pl_sim *s) { return s->data->time; }

int pl_sim_reset(pl_sim *s)
{
    return pl_data_copy(s->data, s->model.initial) ? PL_EINTERNAL : PL_OK;
}

int pl_sim_save_state(const pl_sim *s, const char *path, pl_error *err)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot write: %s", strerror(errno));
    int rc = pl_data_save(s->data, f, err);
    if (fclose(f) != 0 && rc == PL_OK)
        rc = pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "cannot write the state file");
    return rc;
}

int pl_sim_restore_state(pl_sim *s, const char *path, pl_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot open: %s", strerror(errno));
    int rc = pl_data_load(s->data, f, err);
    if (rc != PL_OK) snprintf(err->file, sizeof err->file, "%s", path);
    fclose(f);
    return rc;
}

void pl_sim_set_callback(pl_sim *s, pl_sim_callback fn, void *user)
{
    s->callback = fn;
    s->callback_user = user;
}

typedef struct event_walk {
    pl_ctx ctx;
    const pl_event *ev;
    pl_error *err;
    int used, rc;
} event_walk;

static int call_event(pl_component *c, void *user)
{
    event_walk *w = user;
    const pl_event_ops *ops = pl_component_role(c, PL_ROLE_EVENT);
    if (!ops || ops->version < 1 || !ops->handle) return 0;
    int used = 0;
    w->rc = ops->handle(c, &w->ctx, w->ev, &used, w->err);
    if (used) w->used = 1;
    return w->rc;
}

int pl_sim_send_event(pl_sim *s, const pl_event *ev, int *used, pl_error *err)
{
    pl_error local;
    if (!err) err = &local;
    pl_error_clear(err);
    event_walk w = {make_ctx(s, s->data, NULL), ev, err, 0, PL_OK};
    pl_node_visit_role(s->model.root, PL_ROLE_EVENT, call_event, &w);
    if (used) *used = w.used;
    return w.rc;
}

typedef struct outputs_walk {
    const char **paths;
    int n, max;
} outputs_walk;

static int collect_output(pl_component *c, void *user)
{
    outputs_walk *w = user;
    const pl_exporter_ops *ops = pl_component_role(c, PL_ROLE_EXPORTER);
    const char *p = ops->output_path ? ops->output_path(c) : NULL;
    if (p && w->n < w->max) w->paths[w->n++] = p;
    return 0;
}

int pl_sim_outputs(const pl_sim *s, const char **paths, int max)
{
    outputs_walk w = {paths, 0, max};
    pl_node_visit_role(s->model.root, PL_ROLE_EXPORTER, collect_output, &w);
    return w.n;
}
