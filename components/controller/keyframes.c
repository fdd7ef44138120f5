/* keyframes.c - Keyframes: drives one RUNTIME field of another component
 * (target="@cable.value") through keyframes, interpolated linearly or held
 * stepwise.  At the start of every step (time t) the controller writes the
 * value at t into the field as text, through the field's own parser, so the
 * target sees exactly what a scene or `pliant --set` would give it.  Only
 * RUNTIME fields may be driven: changing any other field would need the
 * model rebuilt (a refactorisation), which a controller never triggers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "controller.h"
#include "controller/target.h"

enum { INTERP_LINEAR = 0, INTERP_STEP = 1 };

typedef struct keyframes {
    pl_component base;
    char *target;
    pl_doubles times, values;
    int interpolation;
    /* bound at bind */
    pl_component *comp;
    const pl_field *field;
    int k;                   /* values per time */
    double *cur;             /* k scratch values */
    char *text;              /* formatted value */
    size_t text_size;
} keyframes;

static const char *const INTERPOLATIONS[] = {"linear", "step", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD(keyframes, target, "target", PL_F_STRING, NULL,
             "the driven field: @component.field (component path as in links, e.g. "
             "@cable.value or @../finger/cable.value); the field must be RUNTIME",
             PL_FIELD_REQUIRED),
    PL_FIELD(keyframes, times, "times", PL_F_DOUBLES, NULL, "keyframe times [s], increasing",
             PL_FIELD_REQUIRED),
    PL_FIELD(keyframes, values, "values", PL_F_DOUBLES, NULL,
             "keyframe values in the target's unit: one per time, or k per time for a field "
             "of k numbers (a vec3, a list)",
             PL_FIELD_REQUIRED),
    PL_FIELD_ENUM(keyframes, interpolation, "interpolation", INTERPOLATIONS, "linear",
                  "linear: interpolate between keyframes; step: hold each keyframe's values "
                  "until the next",
                  0),
};

void pl_keyframes_eval(const double *times, int ntimes, const double *values, int k, int step,
                       double t, double *out)
{
    if (t <= times[0] || ntimes == 1) {
        memcpy(out, values, (size_t)k * sizeof *out);
        return;
    }
    if (t >= times[ntimes - 1]) {
        memcpy(out, values + (size_t)(ntimes - 1) * k, (size_t)k * sizeof *out);
        return;
    }
    int lo = 0, hi = ntimes - 1; /* times[lo] <= t < times[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (times[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    const double *a = values + (size_t)lo * k, *b = values + (size_t)hi * k;
    double s = step ? 0.0 : (t - times[lo]) / (times[hi] - times[lo]);
    for (int j = 0; j < k; ++j) out[j] = s == 0.0 ? a[j] : a[j] + s * (b[j] - a[j]);
}

static int kf_init(pl_component *c, pl_ctx *ctx)
{
    keyframes *kf = (keyframes *)c;
    int n = kf->times.n;
    if (n < 1) return pl_component_error(c, ctx, PL_EINPUT, "times: expected at least one time");
    for (int i = 0; i < n; ++i)
        if (i > 0 && !(kf->times.v[i] > kf->times.v[i - 1]))
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "times: must increase, but time %d (%g s) follows %g s", i,
                                      kf->times.v[i], kf->times.v[i - 1]);
    if (kf->values.n == 0 || kf->values.n % n)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "values: %d numbers for %d times; expected the same number of "
                                  "values (k >= 1) for every time",
                                  kf->values.n, n);
    kf->k = kf->values.n / n;
    return PL_OK;
}

/* The target's kind must take k numbers per time. */
static int check_count(keyframes *kf, pl_ctx *ctx)
{
    const pl_field *f = kf->field;
    int want = f->type == PL_F_DOUBLE || f->type == PL_F_INT ? 1 : f->type == PL_F_VEC3 ? 3 : -1;
    if (want > 0 && kf->k != want)
        return pl_component_error(&kf->base, ctx, PL_EINPUT,
                                  "values: the target '%s' (%s) takes %d number(s) per time, "
                                  "found %d per time",
                                  f->name, pl_field_type_name(f->type), want, kf->k);
    return PL_OK;
}

/* Writes the value at time t into the target field. */
static int kf_write(keyframes *kf, double t, pl_error *err)
{
    pl_keyframes_eval(kf->times.v, kf->times.n, kf->values.v, kf->k,
                      kf->interpolation == INTERP_STEP, t, kf->cur);
    int integer = kf->field->type == PL_F_INT || kf->field->type == PL_F_INTS;
    size_t w = 0;
    for (int j = 0; j < kf->k; ++j) {
        int n = integer ? snprintf(kf->text + w, kf->text_size - w, "%s%ld", j ? " " : "",
                                   lround(kf->cur[j]))
                        : snprintf(kf->text + w, kf->text_size - w, "%s%.17g", j ? " " : "",
                                   kf->cur[j]);
        if (n < 0 || (size_t)n >= kf->text_size - w)
            return pl_component_fail(&kf->base, err, PL_EINTERNAL, "value text too long");
        w += (size_t)n;
    }
    int rc = pl_field_parse(kf->field, kf->comp, kf->text, err);
    if (rc) {
        char p[160];
        snprintf(err->where, sizeof err->where, "Keyframes %.170s",
                 pl_component_path(&kf->base, p, sizeof p));
    }
    return rc;
}

static int kf_bind(pl_component *c, pl_ctx *ctx)
{
    keyframes *kf = (keyframes *)c;
    int rc = pl_controller_target(c, ctx, "Keyframes", kf->target, &kf->comp, &kf->field);
    if (!rc) rc = check_count(kf, ctx);
    if (rc) return rc;
    free(kf->cur);
    free(kf->text);
    kf->cur = malloc((size_t)kf->k * sizeof *kf->cur);
    kf->text_size = (size_t)kf->k * 32 + 1;
    kf->text = malloc(kf->text_size);
    if (!kf->cur || !kf->text) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    /* the target holds the value of the initial time from the start */
    pl_error err;
    if (kf_write(kf, ctx->data->time, &err) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "target: %s", err.msg);
    return PL_OK;
}

static void kf_destroy(pl_component *c)
{
    keyframes *kf = (keyframes *)c;
    free(kf->cur);
    free(kf->text);
}

static int kf_apply(pl_component *c, pl_ctx *ctx, double t, pl_error *err)
{
    (void)ctx;
    return kf_write((keyframes *)c, t, err);
}

static const pl_controller_ops CONTROLLER = {.version = PL_CONTROLLER_OPS_VERSION,
                                             .apply = kf_apply};

const pl_type pl_keyframes_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "Keyframes",
    .help = "Drives a RUNTIME field of another component (target=\"@cable.value\") through "
            "keyframes (times, values), linearly interpolated or stepwise.",
    .size = sizeof(keyframes),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = kf_init, .bind = kf_bind, .destroy = kf_destroy},
    .roles = {[PL_ROLE_CONTROLLER] = &CONTROLLER},
};
