/* pliant_py.h - the extension pliant._core: a pl_sim as a Python object.
 *
 * Sim wraps one pl_sim (its own registry, model and data): load, step, time,
 * fields by path, save/restore, and the two hooks a Python controller sets
 * (begin: pl_sim's step callback, inside the C loop; end: after each step of
 * the loop in Sim.step).  View exports one fixed-size slot of the sim's data
 * (positions, velocities, constraint forces) through the buffer protocol,
 * without a copy; it holds a reference to its Sim, so the memory outlives
 * every array made from it. */
#ifndef PLIANT_PY_H
#define PLIANT_PY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <pliant/pliant.h>

typedef struct pl_py_sim {
    PyObject_HEAD
    pl_sim *sim;         /* the owner's pl_sim (a fork borrows it) */
    pl_data *data;       /* a fork's own state over the owner's model; NULL: the sim's */
    struct pl_py_sim *owner; /* a fork: the Sim that owns sim (a strong reference); NULL */
    struct pl_py_sim *current; /* owner: the Sim (itself or a fork) being stepped */
    PyObject *begin;     /* callable(t) called at the start of every step, or NULL */
    PyObject *end;       /* callable(t) called at the end of every step, or NULL */
    int stepping;        /* owner: inside a step of it or a fork: no state may be replaced */
    PyObject *warnings;  /* the load's warnings as `pliant run` prints them (str), or NULL */
    PyObject *weakrefs;
} pl_py_sim;

/* The state a Sim reads and steps: a fork's own, else the sim's. */
static inline pl_data *pl_py_data(const pl_py_sim *s)
{
    return s->data ? s->data : pl_sim_data(s->sim);
}

extern PyTypeObject pl_py_sim_type;
extern PyTypeObject pl_py_view_type;
/* pliant.Error (code 1) and its subclass pliant.InputError (code 2). */
extern PyObject *pl_py_error;
extern PyObject *pl_py_input_error;

/* Raises pliant.Error / InputError from err; returns NULL. */
PyObject *pl_py_raise(const pl_error *err);
/* The same with `text` as the message (file, line, where from err). */
PyObject *pl_py_raise_text(const pl_error *err, const char *text);
/* A View of slot `slot` of sim's data (a fixed slot of doubles), or NULL
 * with an exception set. */
PyObject *pl_py_view_new(pl_py_sim *sim, int slot, int writable);

#endif
