/* model_internal.h - private to the core: how the loader builds the parts
 * of a model that components do not declare themselves. */
#ifndef PLIANT_MODEL_INTERNAL_H
#define PLIANT_MODEL_INTERNAL_H

#include "pliant/input.h"
#include "pliant/model.h"

/* Lists every component of the tree in m->components (for workspaces);
 * PL_OK or PL_EINTERNAL. */
int pl_model_index_components(pl_model *m);
/* Declares the slots of c's input fields (before c's init); PL_EINPUT for
 * an input field of a kind that cannot be one (with a message). */
int pl_input_declare(pl_model *m, pl_component *c, pl_error *err);
/* Writes the component's value of input slot `slot` into d. */
int pl_input_fill(pl_data *d, int slot);
/* Frees every workspace of d (their components must be alive). */
void pl_data_free_workspaces(pl_data *d);

#endif
