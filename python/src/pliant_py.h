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

typedef struct {
    PyObject_HEAD
    pl_sim *sim;
    PyObject *begin;     /* callable(t) called at the start of every step, or NULL */
    PyObject *end;       /* callable(t) called at the end of every step, or NULL */
    int stepping;        /* inside Sim.step: the state may not be replaced */
    PyObject *weakrefs;
} pl_py_sim;

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
