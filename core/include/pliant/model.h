/* model.h - the model (built once) apart from the data (mutable state).
 *
 * As MuJoCo separates mjModel from mjData: topology, materials, factors
 * and everything derived from fields belong to the components, i.e. to the
 * model.  Everything that evolves in time (positions, velocities,
 * multipliers, contacts, duals, time itself) lives in a pl_data, as named
 * byte slots that components declare during init.  A pl_data can be copied,
 * saved, restored and reset, and several pl_data can step over one model. */
#ifndef PLIANT_MODEL_H
#define PLIANT_MODEL_H

#include "api.h"
#include <stddef.h>
#include <stdio.h>
#include "component.h"
#include "node.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Checks the contents of a slot restored from a file (indices in range,
 * finite values): PL_OK, or PL_EINPUT with a message in err.  A saved state
 * is input like any other file. */
typedef int (*pl_slot_check)(const pl_component *owner, const void *data, size_t bytes,
                             pl_error *err);

typedef struct pl_slot_info {
    char *name;            /* "root/bar/dofs.position" (owner path + name) */
    pl_component *owner;
    size_t initial_bytes;  /* fixed slots: their size, for ever */
    size_t elem_size;      /* variable slots: bytes per element (0: a fixed slot) */
    size_t max_elems;      /* variable slots: at most this many elements */
    pl_slot_check check;   /* NULL: any contents of the right size */
} pl_slot_info;

typedef struct pl_model {
    pl_node *root;
    char *file;                 /* scene file ("<string>" when loaded from text) */
    pl_slot_info *slots;
    int nslots, cap_slots;
    struct pl_data *initial;    /* the state right after loading: what reset restores */
    const struct pl_work_limits *ceiling; /* caps no scene can raise (NULL: none) */
} pl_model;

typedef struct pl_slot {
    void *ptr;
    size_t bytes;
} pl_slot;

typedef struct pl_data {
    const pl_model *model;
    double time;                /* simulated time [s] */
    long step;                  /* steps taken */
    pl_slot *slots;             /* model->nslots entries */
    int nslots;
} pl_data;

/* Declares a FIXED-size state slot of `bytes` bytes owned by c (during
 * init): it keeps that size, and a saved state whose slot has another size
 * is refused.  Returns its index (>= 0) or -1 on allocation failure. */
PL_API int pl_model_add_slot(pl_model *m, pl_component *owner, const char *name, size_t bytes);
/* Declares a VARIABLE state slot (contacts, rows: resized at run time),
 * empty at first, holding 0..max_elems elements of elem_size bytes (> 0).
 * pl_data_resize_slot and pl_data_load refuse other sizes. */
PL_API int pl_model_add_var_slot(pl_model *m, pl_component *owner, const char *name,
                                 size_t elem_size, size_t max_elems);
/* Sets the check pl_data_load runs on the slot's restored contents. */
PL_API void pl_model_set_slot_check(pl_model *m, int slot, pl_slot_check check);
/* A ready check for slots of doubles: every value finite. */
PL_API int pl_slot_check_finite(const pl_component *owner, const void *data, size_t bytes,
                                pl_error *err);
/* Index of the slot named "path.name", or -1. */
PL_API int pl_model_find_slot(const pl_model *m, const char *fullname);

/* A new data with every slot allocated and zeroed; NULL on failure. */
PL_API pl_data *pl_data_create(const pl_model *m);
/* A deep copy; NULL on failure. */
PL_API pl_data *pl_data_clone(const pl_data *src);
/* Copies src into dst (same model); resizes dst's slots. */
PL_API int pl_data_copy(pl_data *dst, const pl_data *src);
PL_API void pl_data_free(pl_data *d);

static inline void *pl_data_slot(const pl_data *d, int slot)
{
    return d->slots[slot].ptr;
}
static inline size_t pl_data_slot_bytes(const pl_data *d, int slot)
{
    return d->slots[slot].bytes;
}
/* Grows or shrinks a variable slot (contacts change in number); new bytes
 * are zero.  -1 when out of memory or when `bytes` is not a size the slot
 * was declared with (a fixed slot keeps its size). */
PL_API int pl_data_resize_slot(pl_data *d, int slot, size_t bytes);

/* Resizes a slot to `bytes` and copies src into it (a per-step list such as
 * the contacts of a step); PL_OK or PL_EINTERNAL. */
PL_API int pl_data_store(pl_data *d, int slot, const void *src, size_t bytes);

/* Binary save/restore of a whole state (time, step, every slot by name).
 * Restoring treats the file as untrusted input: it must belong to a model
 * with the same slots, every slot's size must be one its declaration allows
 * (checked before anything is allocated; variable slots grow only as their
 * bytes actually arrive), the time must be finite, and each slot's check
 * must accept its contents.  On any error d is left untouched. */
PL_API int pl_data_save(const pl_data *d, FILE *f, pl_error *err);
PL_API int pl_data_load(pl_data *d, FILE *f, pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
