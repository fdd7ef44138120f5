/* input.c - input fields (PL_FIELD_INPUT, input.h): their slots, filled
 * from the component's value, read and written per pl_data.
 *
 * A slot holds the value as plain numbers: a double, an int (int, bool,
 * enum), 3 doubles (vec3), or the n numbers of a list (its byte count
 * gives n).  Text goes through the field's own parser and formatter on a
 * stand-alone copy of the storage (the field with offset 0). */
#include "model_internal.h"

/* The most values a list input field (a keyframe table, a series of
 * targets) holds; a saved state asking for more is refused. */
#define PL_INPUT_MAX_ELEMS (1u << 20)

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The storage of every numeric kind, addressed as a component at offset 0. */
typedef union value {
    double d;
    int i;
    double v3[3];
    pl_doubles ds;
    pl_ints is;
} value;

static pl_field at_zero(const pl_field *f)
{
    pl_field g = *f;
    g.offset = 0;
    return g;
}

static int numeric(pl_field_type t)
{
    return t != PL_F_STRING && t != PL_F_LINK;
}

/* The bytes of a value stored at p as kind t (lists: their elements); p is
 * a field's member, aligned for its own kind only. */
static const void *value_bytes(pl_field_type t, const void *p, size_t *bytes)
{
    switch (t) {
    case PL_F_DOUBLE: *bytes = sizeof(double); return p;
    case PL_F_VEC3: *bytes = 3 * sizeof(double); return p;
    case PL_F_DOUBLES: {
        const pl_doubles *l = p;
        *bytes = (size_t)l->n * sizeof(double);
        return l->v;
    }
    case PL_F_INTS: {
        const pl_ints *l = p;
        *bytes = (size_t)l->n * sizeof(int);
        return l->v;
    }
    default: *bytes = sizeof(int); return p;
    }
}

/* A view of slot bytes as storage of kind t (lists point into the slot). */
static value slot_value(pl_field_type t, const pl_slot *s)
{
    value v;
    memset(&v, 0, sizeof v);
    switch (t) {
    case PL_F_DOUBLE: memcpy(&v.d, s->ptr, sizeof v.d); break;
    case PL_F_VEC3: memcpy(v.v3, s->ptr, sizeof v.v3); break;
    case PL_F_DOUBLES: v.ds = (pl_doubles){s->ptr, (int)(s->bytes / sizeof(double))}; break;
    case PL_F_INTS: v.is = (pl_ints){s->ptr, (int)(s->bytes / sizeof(int))}; break;
    default: memcpy(&v.i, s->ptr, sizeof v.i); break;
    }
    return v;
}

int pl_input_declare(pl_model *m, pl_component *c, pl_error *err)
{
    for (int k = 0; k < c->type->nfields; ++k) {
        const pl_field *f = &c->type->fields[k];
        if (!(f->flags & PL_FIELD_INPUT)) continue;
        if (!numeric(f->type) || (f->flags & PL_FIELD_OUTPUT))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "%s.%s: an input field must be a numeric field that is not an "
                                "output (type %s)",
                                c->type->name, f->name, pl_field_type_name(f->type));
        /* scalars and vec3 have a fixed size; lists change in length (a
         * variable slot, bounded so that a restored state cannot ask for
         * more than PL_INPUT_MAX_ELEMS values) */
        int slot;
        if (f->type == PL_F_DOUBLES || f->type == PL_F_INTS)
            slot = pl_model_add_var_slot(m, c, f->name,
                                         f->type == PL_F_DOUBLES ? sizeof(double) : sizeof(int),
                                         PL_INPUT_MAX_ELEMS);
        else
            slot = pl_model_add_slot(m, c, f->name,
                                     f->type == PL_F_DOUBLE  ? sizeof(double)
                                     : f->type == PL_F_VEC3 ? 3 * sizeof(double)
                                                            : sizeof(int));
        if (slot < 0)
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "%s.%s: cannot declare its slot",
                                c->type->name, f->name);
        m->slots[slot].field = f;
    }
    return PL_OK;
}

int pl_input_slot(const pl_model *m, const pl_component *c, const pl_field *f)
{
    for (int k = 0; k < m->nslots; ++k)
        if (m->slots[k].owner == c && m->slots[k].field == f) return k;
    return -1;
}

int pl_input_fill(pl_data *d, int slot)
{
    const pl_slot_info *si = &d->model->slots[slot];
    const void *member = (const char *)si->owner + si->field->offset;
    size_t bytes;
    const void *src = value_bytes(si->field->type, member, &bytes);
    return pl_data_store(d, slot, src, bytes);
}

/* The slot of c's input member at `member`, or -1. */
static int find(const pl_data *d, const pl_component *c, const void *member)
{
    if (!d || !c) return -1;
    size_t offset = (size_t)((const char *)member - (const char *)c);
    const pl_model *m = d->model;
    for (int k = 0; k < m->nslots && k < d->nslots; ++k)
        if (m->slots[k].owner == c && m->slots[k].field && m->slots[k].field->offset == offset)
            return k;
    return -1;
}

double pl_input_double(const pl_data *d, const pl_component *c, const double *member)
{
    int k = find(d, c, member);
    return k < 0 ? *member : slot_value(PL_F_DOUBLE, &d->slots[k]).d;
}

int pl_input_int(const pl_data *d, const pl_component *c, const int *member)
{
    int k = find(d, c, member);
    return k < 0 ? *member : slot_value(PL_F_INT, &d->slots[k]).i;
}

const double *pl_input_vec3(const pl_data *d, const pl_component *c, const double *member)
{
    int k = find(d, c, member);
    return k < 0 ? member : (const double *)d->slots[k].ptr;
}

pl_doubles pl_input_doubles(const pl_data *d, const pl_component *c, const pl_doubles *member)
{
    int k = find(d, c, member);
    return k < 0 ? *member : slot_value(PL_F_DOUBLES, &d->slots[k]).ds;
}

pl_ints pl_input_ints(const pl_data *d, const pl_component *c, const pl_ints *member)
{
    int k = find(d, c, member);
    return k < 0 ? *member : slot_value(PL_F_INTS, &d->slots[k]).is;
}

/* The slot of input field f of c in d, or -1 with err filled. */
static int slot_of(const pl_data *d, const pl_component *c, const pl_field *f, pl_error *err)
{
    int k = (f->flags & PL_FIELD_INPUT) ? find(d, c, (const char *)c + f->offset) : -1;
    if (k < 0)
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s.%s is not an input field of this data",
                     c->name, f->name);
    return k;
}

/* Checks an integer kind's value (bool 0/1, enum among its choices). */
static int check_int(const pl_field *f, long v, pl_error *err)
{
    int nchoices = 0;
    if (f->type == PL_F_ENUM)
        while (f->choices && f->choices[nchoices]) nchoices++;
    if (f->type == PL_F_BOOL && v != 0 && v != 1)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s: expected 0 or 1, got %ld",
                            f->name, v);
    if (f->type == PL_F_ENUM && (v < 0 || v >= nchoices))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "%s: expected a choice index 0 .. %d, got %ld", f->name, nchoices - 1,
                            v);
    if (v < -2147483647L || v > 2147483647L)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s: %ld is not an int", f->name, v);
    return PL_OK;
}

int pl_input_set(pl_data *d, const pl_component *c, const pl_field *f, const double *v, int n,
                 pl_error *err)
{
    int k = slot_of(d, c, f, err);
    if (k < 0) return PL_EINPUT;
    int want = f->type == PL_F_VEC3 ? 3 : (f->type == PL_F_DOUBLES || f->type == PL_F_INTS) ? -1 : 1;
    if (want > 0 && n != want)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s: expected %d number(s), got %d",
                            f->name, want, n);
    for (int j = 0; j < n; ++j)
        if (!isfinite(v[j]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s: value %d is not finite",
                                f->name, j + 1);
    if (f->type == PL_F_DOUBLE || f->type == PL_F_VEC3 || f->type == PL_F_DOUBLES)
        return pl_data_store(d, k, v, (size_t)n * sizeof *v);
    for (int j = 0; j < n; ++j) {
        int rc = check_int(f, lround(v[j]), err);
        if (rc) return rc;
    }
    if (pl_data_resize_slot(d, k, (size_t)n * sizeof(int)) != 0) return PL_EINTERNAL;
    int *out = d->slots[k].ptr;
    for (int j = 0; j < n; ++j) out[j] = (int)lround(v[j]);
    return PL_OK;
}

int pl_input_set_text(pl_data *d, const pl_component *c, const pl_field *f, const char *text,
                      pl_error *err)
{
    int k = slot_of(d, c, f, err);
    if (k < 0) return PL_EINPUT;
    pl_field g = at_zero(f);
    value v;
    memset(&v, 0, sizeof v);
    int rc = pl_field_parse(&g, &v, text, err);
    if (rc) return rc;
    size_t bytes;
    const void *src = value_bytes(f->type, &v, &bytes);
    rc = pl_data_store(d, k, src, bytes);
    pl_field_release(&g, &v);
    return rc;
}

int pl_input_format(const pl_data *d, const pl_component *c, const pl_field *f, char *buf,
                    size_t size)
{
    pl_error err;
    int k = slot_of(d, c, f, &err);
    if (k < 0) return PL_EINPUT;
    pl_field g = at_zero(f);
    value v = slot_value(f->type, &d->slots[k]);
    return pl_field_format(&g, &v, buf, size);
}
