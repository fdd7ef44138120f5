/* model.c - state slots of the model, and pl_data: create, copy, save,
 * load, and the per-component workspaces. */
#include "pliant/model.h"
#include "model_internal.h"
#include "walk.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/checked.h"

static int add_slot(pl_model *m, pl_component *owner, const char *name, size_t bytes,
                    size_t elem_size, size_t max_elems)
{
    char path[192], full[256];
    if (m->nslots == m->cap_slots) {
        int cap = m->cap_slots ? 2 * m->cap_slots : 16;
        pl_slot_info *s = realloc(m->slots, (size_t)cap * sizeof *s);
        if (!s) return -1;
        m->slots = s;
        m->cap_slots = cap;
    }
    snprintf(full, sizeof full, "%s.%s", owner ? pl_component_path(owner, path, sizeof path) : "",
             name);
    if (pl_model_find_slot(m, full) >= 0) return -1; /* two slots of one name */
    pl_slot_info *s = &m->slots[m->nslots];
    memset(s, 0, sizeof *s);
    if (!(s->name = strdup(full))) return -1;
    s->owner = owner;
    s->initial_bytes = bytes;
    s->elem_size = elem_size;
    s->max_elems = max_elems;
    s->field = NULL;
    return m->nslots++;
}

int pl_model_add_slot(pl_model *m, pl_component *owner, const char *name, size_t bytes)
{
    return add_slot(m, owner, name, bytes, 0, 0);
}

int pl_model_add_var_slot(pl_model *m, pl_component *owner, const char *name, size_t elem_size,
                          size_t max_elems)
{
    size_t most;
    if (elem_size == 0 || pl_mul_size(elem_size, max_elems, &most)) return -1;
    return add_slot(m, owner, name, 0, elem_size, max_elems);
}

void pl_model_set_slot_check(pl_model *m, int slot, pl_slot_check check)
{
    if (slot >= 0 && slot < m->nslots) m->slots[slot].check = check;
}

int pl_slot_check_finite(const pl_component *owner, const void *data, size_t bytes,
                         pl_error *err)
{
    const double *v = data;
    if (bytes % sizeof(double))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%zu bytes are not whole numbers",
                            bytes);
    for (size_t i = 0; i < bytes / sizeof(double); ++i)
        if (!isfinite(v[i]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "value %zu is %g: expected a "
                                "finite number", i, v[i]);
    return PL_OK;
}

/* Whether `bytes` is a size slot k may have. */
static int size_allowed(const pl_slot_info *s, size_t bytes)
{
    if (!s->elem_size) return bytes == s->initial_bytes;
    return bytes % s->elem_size == 0 && bytes / s->elem_size <= s->max_elems;
}

static int resize(pl_data *d, int slot, size_t bytes);

int pl_model_find_slot(const pl_model *m, const char *fullname)
{
    for (int k = 0; k < m->nslots; ++k)
        if (!strcmp(m->slots[k].name, fullname)) return k;
    return -1;
}

pl_data *pl_data_create(const pl_model *m)
{
    pl_data *d = calloc(1, sizeof *d);
    if (!d) return NULL;
    d->model = m;
    d->nslots = m->nslots;
    size_t ns = (size_t)(m->nslots ? m->nslots : 1);
    d->slots = calloc(ns, sizeof *d->slots);
    d->slot_version = calloc(ns, sizeof *d->slot_version);
    d->slot_writers = calloc(ns, sizeof *d->slot_writers);
    if (!d->slots || !d->slot_version || !d->slot_writers) {
        free(d->slots), free(d->slot_version), free(d->slot_writers);
        free(d);
        return NULL;
    }
    for (int k = 0; k < m->nslots; ++k) /* resize gives each slot its first version, 1 */
        if (resize(d, k, m->slots[k].initial_bytes) != 0 ||
            (m->slots[k].field && pl_input_fill(d, k) != PL_OK)) {
            pl_data_free(d);
            return NULL;
        }
    return d;
}

void pl_data_free(pl_data *d)
{
    if (!d) return;
    pl_data_free_workspaces(d);
    free(d->workspaces);
    for (int k = 0; k < d->nslots; ++k) free(d->slots[k].ptr);
    free(d->slots);
    free(d->slot_version);
    free(d->slot_writers);
    free(d);
}

/* ---- workspaces ---------------------------------------------------------- */

static int by_address(const void *a, const void *b)
{
    uintptr_t x = (uintptr_t) * (pl_component *const *)a, y = (uintptr_t) * (pl_component *const *)b;
    return (x > y) - (x < y);
}

static int collect(pl_component *c, void *user)
{
    pl_model *m = user;
    pl_component **all = realloc(m->components, (size_t)(m->ncomponents + 1) * sizeof *all);
    if (!all) return 1;
    m->components = all;
    m->components[m->ncomponents++] = c;
    return 0;
}

int pl_model_index_components(pl_model *m)
{
    free(m->components);
    m->components = NULL;
    m->ncomponents = 0;
    if (m->root && walk_pre(m->root, collect, m)) return PL_EINTERNAL;
    if (m->ncomponents)
        qsort(m->components, (size_t)m->ncomponents, sizeof *m->components, by_address);
    return PL_OK;
}

void pl_data_free_workspaces(pl_data *d)
{
    const pl_model *m = d->model;
    if (!d->workspaces) return;
    for (int k = 0; k < m->ncomponents; ++k) {
        void *ws = d->workspaces[k];
        const pl_component *c = m->components[k];
        if (!ws) continue;
        if (c->type->ops.workspace_free) c->type->ops.workspace_free(c, ws);
        free(ws);
        d->workspaces[k] = NULL;
    }
}

void *pl_data_workspace(pl_data *d, const pl_component *c)
{
    const pl_model *m = d->model;
    if (!c || !c->type->workspace_size || !m->ncomponents) return NULL;
    pl_component *const *hit =
        bsearch(&c, m->components, (size_t)m->ncomponents, sizeof *m->components, by_address);
    if (!hit) return NULL;
    if (d->workspaces && d->ws_generation != m->generation) pl_data_free_workspaces(d);
    if (!d->workspaces && !(d->workspaces = calloc((size_t)m->ncomponents, sizeof(void *))))
        return NULL;
    d->ws_generation = m->generation;
    size_t k = (size_t)(hit - m->components);
    if (!d->workspaces[k]) d->workspaces[k] = calloc(1, c->type->workspace_size);
    return d->workspaces[k];
}

/* ---- slot versions ---------------------------------------------------- */

void pl_data_slot_touch(pl_data *d, int slot)
{
    if (slot < 0 || slot >= d->nslots) return;
    if (++d->slot_version[slot] == 0) d->slot_version[slot] = 1; /* 0 means "open for writing" */
}

unsigned long pl_data_slot_version(const pl_data *d, int slot)
{
    if (slot < 0 || slot >= d->nslots || d->slot_writers[slot] > 0) return 0;
    return d->slot_version[slot];
}

/* Opening and closing both make a new version: what was written while the
 * view was open is not the contents an owner saw before. */
void pl_data_slot_writers(pl_data *d, int slot, int delta)
{
    if (slot < 0 || slot >= d->nslots) return;
    d->slot_writers[slot] += delta;
    if (d->slot_writers[slot] < 0) d->slot_writers[slot] = 0;
    pl_data_slot_touch(d, slot);
}

/* Resizes without asking whether the size is allowed; a new version of the
 * slot (its contents are written from outside the owner, or may be). */
static int resize(pl_data *d, int slot, size_t bytes)
{
    pl_slot *s = &d->slots[slot];
    pl_data_slot_touch(d, slot);
    if (bytes == s->bytes) return 0;
    /* never hand out a NULL pointer: an empty slot still owns one byte */
    void *p = realloc(s->ptr, bytes ? bytes : 1);
    if (!p) return -1;
    if (bytes > s->bytes) memset((char *)p + s->bytes, 0, bytes - s->bytes);
    s->ptr = p;
    s->bytes = bytes;
    return 0;
}

int pl_data_resize_slot(pl_data *d, int slot, size_t bytes)
{
    if (slot < d->model->nslots && !size_allowed(&d->model->slots[slot], bytes)) return -1;
    return resize(d, slot, bytes);
}

int pl_data_store(pl_data *d, int slot, const void *src, size_t bytes)
{
    if (pl_data_resize_slot(d, slot, bytes) != 0) return PL_EINTERNAL;
    if (bytes) memcpy(d->slots[slot].ptr, src, bytes);
    return PL_OK;
}

int pl_data_copy(pl_data *dst, const pl_data *src)
{
    if (dst->nslots != src->nslots) return -1;
    for (int k = 0; k < src->nslots; ++k) {
        if (resize(dst, k, src->slots[k].bytes) != 0) return -1;
        if (src->slots[k].bytes) memcpy(dst->slots[k].ptr, src->slots[k].ptr, src->slots[k].bytes);
    }
    dst->time = src->time;
    dst->step = src->step;
    return 0;
}

pl_data *pl_data_clone(const pl_data *src)
{
    pl_data *d = pl_data_create(src->model);
    if (d && pl_data_copy(d, src) != 0) {
        pl_data_free(d);
        return NULL;
    }
    return d;
}

/* File layout: magic, version, time, step, nslots, then per slot its name
 * length, name, byte count and bytes.  Native endianness: a state file is a
 * checkpoint for the same machine, not an exchange format. */
static const char MAGIC[8] = {'P', 'L', 'S', 'T', 'A', 'T', 'E', '1'};

int pl_data_save(const pl_data *d, FILE *f, pl_error *err)
{
    uint64_t n = (uint64_t)d->nslots;
    int64_t step = d->step;
    if (fwrite(MAGIC, 1, 8, f) != 8 || fwrite(&d->time, sizeof d->time, 1, f) != 1 ||
        fwrite(&step, sizeof step, 1, f) != 1 || fwrite(&n, sizeof n, 1, f) != 1)
        goto fail;
    for (int k = 0; k < d->nslots; ++k) {
        const char *name = d->model->slots[k].name;
        uint64_t len = strlen(name), bytes = d->slots[k].bytes;
        if (fwrite(&len, sizeof len, 1, f) != 1 || fwrite(name, 1, len, f) != len ||
            fwrite(&bytes, sizeof bytes, 1, f) != 1 ||
            (bytes && fwrite(d->slots[k].ptr, 1, bytes, f) != bytes))
            goto fail;
    }
    return PL_OK;
fail:
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "cannot write the state file");
}

/* Reads a slot's `bytes` bytes into tmp's slot k.  A fixed slot has been
 * checked to have its declared size; a variable one grows chunk by chunk
 * as the bytes arrive, so a file that announces 384 GiB and holds 10 bytes
 * costs 1 MiB, not a 384 GiB allocation. */
static int read_slot(pl_data *tmp, int k, uint64_t bytes, FILE *f)
{
    const size_t chunk = (size_t)1 << 20;
    size_t got = 0;
    while (got < bytes) {
        size_t n = bytes - got < chunk ? (size_t)(bytes - got) : chunk;
        if (resize(tmp, k, got + n) != 0 || fread((char *)tmp->slots[k].ptr + got, 1, n, f) != n)
            return -1;
        got += n;
    }
    return resize(tmp, k, (size_t)bytes);
}

static int load_slots(pl_data *tmp, FILE *f, pl_error *err)
{
    char name[512];
    const pl_model *m = tmp->model;
    for (int k = 0; k < tmp->nslots; ++k) {
        const pl_slot_info *s = &m->slots[k];
        uint64_t len, bytes;
        if (fread(&len, sizeof len, 1, f) != 1 || len >= sizeof name ||
            fread(name, 1, len, f) != len || fread(&bytes, sizeof bytes, 1, f) != 1)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "truncated or corrupt state file "
                                "(in the header of slot %d)", k);
        name[len] = '\0';
        if (strcmp(name, s->name) != 0)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "the state file's slot %d is '%s', this scene's is '%s'", k,
                                name, s->name);
        /* the size is checked against the declaration before anything is allocated */
        if (bytes > SIZE_MAX || !size_allowed(s, (size_t)bytes)) {
            if (!s->elem_size)
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "slot '%s' holds %llu bytes in the state file; this scene's "
                                    "has %zu: the file belongs to another scene or is corrupt",
                                    s->name, (unsigned long long)bytes, s->initial_bytes);
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "slot '%s' holds %llu bytes in the state file: expected a "
                                "multiple of %zu, at most %zu elements",
                                s->name, (unsigned long long)bytes, s->elem_size, s->max_elems);
        }
        if (read_slot(tmp, k, bytes, f) != 0)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "truncated state file: slot '%s' "
                                "announces %llu bytes", s->name, (unsigned long long)bytes);
        if (s->check && s->check(s->owner, tmp->slots[k].ptr, tmp->slots[k].bytes, err)) {
            char msg[sizeof err->msg];
            snprintf(msg, sizeof msg, "%s", err->msg);
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "slot '%s': %s", s->name, msg);
        }
    }
    if (fgetc(f) != EOF)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "the state file goes on after its last slot: corrupt");
    return PL_OK;
}

int pl_data_load(pl_data *d, FILE *f, pl_error *err)
{
    char magic[8];
    uint64_t n;
    int64_t step;
    double time;
    if (fread(magic, 1, 8, f) != 8 || memcmp(magic, MAGIC, 8) != 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "not a Pliant state file");
    if (fread(&time, sizeof time, 1, f) != 1 || fread(&step, sizeof step, 1, f) != 1 ||
        fread(&n, sizeof n, 1, f) != 1)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "truncated state file");
    if (!isfinite(time))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "the state file's time is %g: expected a finite time [s]", time);
    if (step < 0 || (uint64_t)step > (uint64_t)LONG_MAX)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "the state file's step count %lld is negative", (long long)step);
    if (n != (uint64_t)d->nslots)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "the state file has %llu slots, this scene has %d: it belongs to "
                            "another scene",
                            (unsigned long long)n, d->nslots);
    /* read into a scratch copy first so a bad file leaves d untouched */
    pl_data *tmp = pl_data_create(d->model);
    if (!tmp) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    int rc = load_slots(tmp, f, err);
    if (rc == PL_OK) {
        tmp->time = time;
        tmp->step = (long)step;
        if (pl_data_copy(d, tmp) != 0)
            rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    }
    pl_data_free(tmp);
    return rc;
}
