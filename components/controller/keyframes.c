/* keyframes.c - Keyframes: drives one input field of another component
 * (target="@cable.value") through keyframes, interpolated linearly or held
 * stepwise.  At the start of every step (time t) the controller writes the
 * numbers at t into the data being stepped (pl_input_set: integer fields
 * take them rounded, as their parser would), so two data of one model
 * follow their own times.  Only input fields may be driven: their value
 * lives in the data, while any other field is the model's, which a step
 * never writes (input.h). */
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
} keyframes;

/* Per data: the k values of the step. */
typedef struct keyframes_ws {
    double *cur;
} keyframes_ws;

static const char *const INTERPOLATIONS[] = {"linear", "step", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD(keyframes, target, "target", PL_F_STRING, NULL,
             "the driven field: @component.field (component path as in links, e.g. "
             "@cable.value or @../finger/cable.value); the field must be an input field, whose "
             "value lives in each simulation's state",
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

/* Writes the values at time t into the target's input in d. */
static int kf_write(const keyframes *kf, pl_data *d, double t, pl_error *err)
{
    keyframes_ws *w = pl_data_workspace(d, &kf->base);
    if (!w || (!w->cur && !(w->cur = malloc((size_t)kf->k * sizeof *w->cur))))
        return pl_component_fail(&kf->base, err, PL_EINTERNAL, "out of memory");
    pl_keyframes_eval(kf->times.v, kf->times.n, kf->values.v, kf->k,
                      kf->interpolation == INTERP_STEP, t, w->cur);
    int rc = pl_input_set(d, kf->comp, kf->field, w->cur, kf->k, err);
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
    /* the target holds the value of the initial time from the start */
    pl_error err;
    if (kf_write(kf, ctx->data, ctx->data->time, &err) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "target: %s", err.msg);
    return PL_OK;
}

static void kf_workspace_free(const pl_component *c, void *ws)
{
    (void)c;
    free(((keyframes_ws *)ws)->cur);
}

static int kf_apply(const pl_component *c, pl_ctx *ctx, double t, pl_error *err)
{
    return kf_write((const keyframes *)c, ctx->data, t, err);
}

static const pl_controller_ops CONTROLLER = {.version = PL_CONTROLLER_OPS_VERSION,
                                             .apply = kf_apply};

const pl_type pl_keyframes_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "Keyframes",
    .help = "Drives an input field of another component (target=\"@cable.value\") through "
            "keyframes (times, values), linearly interpolated or stepwise.",
    .size = sizeof(keyframes),
    .workspace_size = sizeof(keyframes_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = kf_init, .bind = kf_bind, .workspace_free = kf_workspace_free},
    .roles = {[PL_ROLE_CONTROLLER] = &CONTROLLER},
};
