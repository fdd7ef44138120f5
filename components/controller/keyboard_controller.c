/* keyboard_controller.c - KeyboardController: keys change an input field
 * of another component (target="@cable.value" keys="+ -" step="0.001"),
 * as SoftRobots' keyboard controllers do in runSofa.
 *
 * It plays the event role: a key press of the first key adds `step` to the
 * target's value, the second key subtracts it, clamped to [min, max].  From
 * the first press on it also plays the controller role: it writes its value
 * into the target at the start of every step, so placed after a Keyframes
 * on the same target (scene order) it takes over from the keyframes when a
 * person starts pressing keys; until then it changes nothing.  Like every
 * controller it writes the target's value in the data (pl_input_set,
 * input.h), never the model.  Whether it has taken over and its value are
 * state too (the pl_data slot "value"): reset and restore bring them back
 * with the rest of the scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "controller/controller.h"
#include "controller/target.h"

typedef struct keyboard_controller {
    pl_component base;
    char *target;
    char *keys;
    double step;
    pl_doubles min, max;
    /* bound */
    pl_component *comp;
    const pl_field *field;
    int key[2];                /* increase, decrease */
    int slot;                  /* 2 doubles: taken over (0/1), value */
} keyboard_controller;

static const pl_field FIELDS[] = {
    PL_FIELD(keyboard_controller, target, "target", PL_F_STRING, NULL,
             "the driven field: @component.field (e.g. @cable.value); an input field of one "
             "number or a list (a list gets one number)",
             PL_FIELD_REQUIRED),
    PL_FIELD(keyboard_controller, keys, "keys", PL_F_STRING, "+ -",
             "the key that increases and the key that decreases the value: characters, or up, "
             "down, left, right, pageup, pagedown",
             0),
    PL_FIELD(keyboard_controller, step, "step", PL_F_DOUBLE, NULL,
             "change per key press, in the target's unit", PL_FIELD_REQUIRED | PL_FIELD_RUNTIME),
    PL_FIELD(keyboard_controller, min, "min", PL_F_DOUBLES, NULL,
             "lowest value (one number, empty = none)", PL_FIELD_RUNTIME),
    PL_FIELD(keyboard_controller, max, "max", PL_F_DOUBLES, NULL,
             "highest value (one number, empty = none)", PL_FIELD_RUNTIME),
};

static const struct {
    const char *name;
    int key;
} KEY_NAMES[] = {{"up", PL_KEY_UP},           {"down", PL_KEY_DOWN},
                 {"left", PL_KEY_LEFT},       {"right", PL_KEY_RIGHT},
                 {"pageup", PL_KEY_PAGE_UP}, {"pagedown", PL_KEY_PAGE_DOWN}};

/* A key token: one character, or a name; -1 if neither. */
static int parse_key(const char *tok, size_t len)
{
    if (len == 1) return (unsigned char)tok[0];
    for (size_t k = 0; k < sizeof KEY_NAMES / sizeof KEY_NAMES[0]; ++k)
        if (strlen(KEY_NAMES[k].name) == len && !strncmp(tok, KEY_NAMES[k].name, len))
            return KEY_NAMES[k].key;
    return -1;
}

static int parse_keys(keyboard_controller *kc, pl_ctx *ctx)
{
    const char *s = kc->keys ? kc->keys : "";
    int n = 0;
    while (*s) {
        while (*s == ' ') s++;
        if (!*s) break;
        size_t len = strcspn(s, " ");
        int key = parse_key(s, len);
        if (key < 0 || n == 2)
            return pl_component_error(&kc->base, ctx, PL_EINPUT,
                                      "keys: expected two keys, increase then decrease (single "
                                      "characters or up, down, left, right, pageup, pagedown), "
                                      "got '%s'", kc->keys ? kc->keys : "");
        kc->key[n++] = key;
        s += len;
    }
    if (n != 2 || kc->key[0] == kc->key[1])
        return pl_component_error(&kc->base, ctx, PL_EINPUT,
                                  "keys: expected two different keys (increase decrease), got "
                                  "'%s'", kc->keys ? kc->keys : "");
    return PL_OK;
}

static int check_limits(const keyboard_controller *kc, pl_error *err)
{
    const pl_component *c = &kc->base;
    if (!isfinite(kc->step) || kc->step <= 0.0)
        return pl_component_fail(c, err, PL_EINPUT, "step must be > 0, got %g", kc->step);
    if (kc->min.n > 1 || kc->max.n > 1)
        return pl_component_fail(c, err, PL_EINPUT, "min and max take one number each");
    if (kc->min.n && kc->max.n && !(kc->min.v[0] <= kc->max.v[0]))
        return pl_component_fail(c, err, PL_EINPUT, "min (%g) exceeds max (%g)", kc->min.v[0],
                                 kc->max.v[0]);
    return PL_OK;
}

static int kc_init(pl_component *c, pl_ctx *ctx)
{
    keyboard_controller *kc = (keyboard_controller *)c;
    pl_error err;
    if (check_limits(kc, &err) != PL_OK) return pl_component_error(c, ctx, PL_EINPUT, "%s", err.msg);
    int rc = parse_keys(kc, ctx);
    if (rc) return rc;
    kc->slot = pl_model_add_slot(ctx->build, c, "value", 2 * sizeof(double));
    return kc->slot < 0 ? pl_component_error(c, ctx, PL_EINTERNAL, "out of memory") : PL_OK;
}

static int kc_bind(pl_component *c, pl_ctx *ctx)
{
    keyboard_controller *kc = (keyboard_controller *)c;
    int rc = pl_controller_target(c, ctx, "KeyboardController", kc->target, &kc->comp, &kc->field);
    if (!rc && kc->field->type == PL_F_VEC3)
        rc = pl_component_error(c, ctx, PL_EINPUT, "target: '%s' is a vec3; KeyboardController "
                                "drives one number", kc->field->name);
    return rc;
}

/* Writes v into the target's input in d. */
static int write_target(const keyboard_controller *kc, pl_data *d, double v, pl_error *err)
{
    int rc = pl_input_set(d, kc->comp, kc->field, &v, 1, err);
    if (rc) {
        char p[160];
        snprintf(err->where, sizeof err->where, "KeyboardController %.150s",
                 pl_component_path(&kc->base, p, sizeof p));
    }
    return rc;
}

/* The target's current first number in d (0 when it has none). */
static double read_target(const keyboard_controller *kc, const pl_data *d)
{
    char text[256];
    if (pl_input_format(d, kc->comp, kc->field, text, sizeof text) != PL_OK) return 0.0;
    char *end;
    double v = strtod(text, &end);
    return end == text || !isfinite(v) ? 0.0 : v;
}

static int kc_handle(const pl_component *c, pl_ctx *ctx, const pl_event *ev, int *used,
                     pl_error *err)
{
    const keyboard_controller *kc = (const keyboard_controller *)c;
    if (ev->kind != PL_EVENT_KEY_PRESSED || (ev->key != kc->key[0] && ev->key != kc->key[1]))
        return PL_OK;
    int rc = check_limits(kc, err);
    if (rc) return rc;
    double *s = pl_data_slot(ctx->data, kc->slot);
    double v = s[0] != 0.0 ? s[1] : read_target(kc, ctx->data);
    v += ev->key == kc->key[0] ? kc->step : -kc->step;
    if (kc->min.n && v < kc->min.v[0]) v = kc->min.v[0];
    if (kc->max.n && v > kc->max.v[0]) v = kc->max.v[0];
    s[0] = 1.0;
    s[1] = v;
    *used = 1;
    return write_target(kc, ctx->data, v, err);
}

static int kc_apply(const pl_component *c, pl_ctx *ctx, double t, pl_error *err)
{
    (void)t;
    const keyboard_controller *kc = (const keyboard_controller *)c;
    const double *s = pl_data_slot(ctx->data, kc->slot);
    return s[0] != 0.0 ? write_target(kc, ctx->data, s[1], err) : PL_OK;
}

static const pl_controller_ops CONTROLLER = {.version = PL_CONTROLLER_OPS_VERSION,
                                             .apply = kc_apply};
static const pl_event_ops EVENT = {.version = PL_EVENT_OPS_VERSION, .handle = kc_handle};

const pl_type pl_keyboard_controller_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "KeyboardController",
    .help = "Keys pressed in the viewer change an input field of another component "
            "(target=\"@cable.value\" keys=\"+ -\" step min max); after a Keyframes on the same "
            "target it takes over at the first key press.",
    .size = sizeof(keyboard_controller),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = kc_init, .bind = kc_bind},
    .roles = {[PL_ROLE_CONTROLLER] = &CONTROLLER, [PL_ROLE_EVENT] = &EVENT},
};
