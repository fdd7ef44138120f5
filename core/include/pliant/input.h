/* input.h - input fields: values that drive a simulation (a cable's pull,
 * a target's motion) and live in each pl_data, not in the model.
 *
 * A field flagged PL_FIELD_INPUT (numeric kinds: double, int, bool, enum,
 * vec3, double and int lists) gets a slot in the data, named like the field
 * ("root/finger/cable.value"), which the core declares before the
 * component's init and fills from the component's parsed value whenever a
 * data is created.  From then on the data holds the current value: the
 * Keyframes controller and pl_sim_set write it there, save/restore and
 * reset carry it, and two pl_data of one model can be driven differently.
 * The member in the component struct keeps the scene's value (the model's
 * default).
 *
 * During a step a component reads an input with the accessor of its kind,
 * passing the address of its own member:
 *
 *     double damping = pl_input_double(ctx->data, c, &s->damping);
 *     pl_doubles value = pl_input_doubles(ctx->data, c, &cable->value);
 *
 * When d holds no slot for that member (a component used outside a loaded
 * model, or a member that is not an input field) the accessors return the
 * component's own value. */
#ifndef PLIANT_INPUT_H
#define PLIANT_INPUT_H

#include "component.h"
#include "model.h"

#ifdef __cplusplus
extern "C" {
#endif

PL_API double pl_input_double(const pl_data *d, const pl_component *c, const double *member);
/* int, bool and enum fields */
PL_API int pl_input_int(const pl_data *d, const pl_component *c, const int *member);
/* 3 values */
PL_API const double *pl_input_vec3(const pl_data *d, const pl_component *c, const double *member);
/* A read-only view of the list (valid until the value is set again). */
PL_API pl_doubles pl_input_doubles(const pl_data *d, const pl_component *c, const pl_doubles *member);
PL_API pl_ints pl_input_ints(const pl_data *d, const pl_component *c, const pl_ints *member);

/* Sets input field f of c in d from n numbers (integer kinds take the
 * rounded values; a bool is 0 or 1, an enum an index among its choices;
 * vec3 needs 3 numbers, scalars 1, lists any count).  PL_EINPUT with a
 * message for a wrong count or a value out of range; d is then unchanged. */
PL_API int pl_input_set(pl_data *d, const pl_component *c, const pl_field *f, const double *v, int n,
                        pl_error *err);
/* Same from text, through the field's parser (as a scene or --set gives it). */
PL_API int pl_input_set_text(pl_data *d, const pl_component *c, const pl_field *f, const char *text,
                             pl_error *err);
/* The current value as text (as it would be written in XML). */
PL_API int pl_input_format(const pl_data *d, const pl_component *c, const pl_field *f, char *buf,
                           size_t size);
/* The slot of input field f of c in m, or -1. */
PL_API int pl_input_slot(const pl_model *m, const pl_component *c, const pl_field *f);

#ifdef __cplusplus
}
#endif
#endif
