/* model.h - the model (built once) apart from the data (mutable state).
 *
 * As MuJoCo separates mjModel from mjData: topology, materials, factors
 * and everything derived from fields belong to the components, i.e. to the
 * model, which a step only reads.  Everything a step writes lives in a
 * pl_data:
 *   - slots: named bytes that components declare during init, holding what
 *     evolves in time (positions, velocities, multipliers, contacts, duals)
 *     and the current values of input fields (input.h).  Copied, saved,
 *     restored and reset with the data.
 *   - workspaces: one block per component that asks for one (its type's
 *     workspace_size), for per-step scratch and results (the solver's
 *     vectors, the step's rows, device buffers and graphs).  Made when first
 *     asked for, freed with the data, never copied or saved: nothing in a
 *     workspace survives from one step to the next that a restored state
 *     would need.
 * So several pl_data can step over one model, interleaved, each exactly as
 * if alone. */
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
    const pl_field *field; /* the input field whose value it holds (input.h), or NULL */
} pl_slot_info;

typedef struct pl_model {
    pl_node *root;
    char *file;                 /* scene file ("<string>" when loaded from text) */
    pl_slot_info *slots;
    int nslots, cap_slots;
    struct pl_data *initial;    /* the state right after loading: what reset restores */
    const struct pl_work_limits *ceiling; /* caps no scene can raise (NULL: none) */
    pl_component **components;  /* every component, sorted by address (workspace lookup) */
    int ncomponents;
    unsigned long generation;   /* counts rebuilds (reinit): older workspaces are remade */
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
    void **workspaces;          /* model->ncomponents entries, NULL until asked for */
    unsigned long ws_generation; /* the model's generation they were made for */
    /* Since ABI 5.10 (read them through pl_data_slot_version): per slot, a
     * count of the writes that came from outside its owner, and how many
     * writable views of it are open. */
    unsigned long *slot_version;
    int *slot_writers;
} pl_data;

/* Declares a FIXED-size state slot of `bytes` bytes owned by c (during
 * init, through ctx->build): it keeps that size, and a saved state whose slot has another size
 * is refused.  Returns its index (>= 0) or -1 on allocation failure
 * or when c already has a slot of that name. */
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

/* A new data: component slots zeroed, input slots holding their field's
 * value in the component (input.h); NULL on failure. */
PL_API pl_data *pl_data_create(const pl_model *m);
/* A deep copy of the slots, time and step (not the workspaces); NULL on
 * failure. */
PL_API pl_data *pl_data_clone(const pl_data *src);
/* Copies src into dst (same model); resizes dst's slots.  dst keeps its
 * workspaces. */
PL_API int pl_data_copy(pl_data *dst, const pl_data *src);
/* Frees the data and its workspaces: call it while the model's components
 * are alive (before pl_sim_free). */
PL_API void pl_data_free(pl_data *d);

/* The workspace of component c in d: c->type->workspace_size bytes, zeroed
 * when first asked for in d (and again after the model was rebuilt), kept
 * until d is freed, never copied or saved.  NULL when the type declares no
 * workspace, c is not part of d's model, or memory runs out.  Per-step
 * scratch and results go here, never into the component (MuJoCo keeps
 * plugin state in mjData likewise). */
PL_API void *pl_data_workspace(pl_data *d, const pl_component *c);

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

#if PL_ABI_TARGET_MINOR >= 10
/* A slot's version, for an owner that keeps a copy of its slot elsewhere
 * (the device copy of ADMM duals): it changes whenever code other than the
 * owner may have replaced the slot's contents (pl_data_copy into d, so
 * restore and reset, pl_data_load, pl_data_store, pl_data_resize_slot,
 * pl_data_slot_touch, a writable view opened or closed) and reads 0 while
 * a writable view of the slot is open.  An owner that notes the version
 * after its own last write of the slot may skip reading the slot back when
 * the version is the same and not 0: nobody else has changed it.  Never 0
 * otherwise.  Since ABI 5.10. */
PL_API unsigned long pl_data_slot_version(const pl_data *d, int slot);
/* Tells the slot's owner that its contents were written from outside (a
 * new version).  Since ABI 5.10. */
PL_API void pl_data_slot_touch(pl_data *d, int slot);
/* A writable view of the slot opens (delta +1) or closes (-1): code that
 * hands out the slot's memory for writing at times it does not control
 * (the Python binding's views).  Since ABI 5.10. */
PL_API void pl_data_slot_writers(pl_data *d, int slot, int delta);
#endif

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
