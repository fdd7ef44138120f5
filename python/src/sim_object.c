/* sim_object.c - pliant._core.Sim: one pl_sim. */
#include "pliant_py.h"

#include <errno.h>
#include <string.h>

/* Every item of d as `pliant run` prints them, without the last newline
 * (caller frees), or NULL without memory. */
static char *diag_text(const pl_diag *d)
{
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!f) return NULL;
    pl_diag_print(d, f);
    fclose(f);
    while (len && text[len - 1] == '\n') text[--len] = '\0';
    return text;
}

/* Raises InputError with every error and warning of a failed load. */
static void raise_diag(const pl_diag *d)
{
    char *text = diag_text(d);
    if (!text) {
        PyErr_NoMemory();
        return;
    }
    pl_error e;
    pl_error_clear(&e);
    e.code = pl_diag_status(d) == PL_EINTERNAL ? PL_EINTERNAL : PL_EINPUT;
    for (int k = 0; k < d->count; ++k) {
        if (d->items[k].code == PL_OK) continue; /* the first error names the place */
        snprintf(e.file, sizeof e.file, "%s", d->items[k].file);
        e.line = d->items[k].line;
        snprintf(e.where, sizeof e.where, "%s", d->items[k].where);
        break;
    }
    /* every error and warning, as `pliant run` prints them */
    pl_py_raise_text(&e, text ? text : "the scene did not load");
    free(text);
}

/* pl_sim's step callback: the begin hook, inside the C loop. */
static int begin_hook(pl_sim *s, double t, void *user)
{
    (void)s;
    pl_py_sim *self = ((pl_py_sim *)user)->current; /* the owner, or the fork being stepped */
    if (!self || !self->begin) return 0;
    PyObject *tt = PyFloat_FromDouble(t);
    PyObject *r = tt ? PyObject_CallOneArg(self->begin, tt) : NULL;
    Py_XDECREF(tt);
    if (!r) return 1; /* the exception stays set; Sim.step raises it */
    Py_DECREF(r);
    return 0;
}

static int sim_init(pl_py_sim *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"path", "xml", "name", "overrides", "device", NULL};
    PyObject *path = NULL, *overrides = NULL;
    const char *xml = NULL, *name = "<string>", *device = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|O&$zsOz", kwlist, PyUnicode_FSConverter, &path,
                                     &xml, &name, &overrides, &device))
        return -1;
    if (self->sim) {
        PyErr_SetString(PyExc_RuntimeError, "Sim is already loaded");
        goto fail;
    }
    if ((path == NULL) == (xml == NULL)) {
        PyErr_SetString(PyExc_TypeError, "Sim() takes a scene path or xml=..., not both");
        goto fail;
    }
    /* "path.field=value" overrides applied before init (pliant run --set) */
    Py_ssize_t n = 0;
    const char **ov = NULL;
    PyObject *seq = NULL;
    if (overrides && overrides != Py_None) {
        seq = PySequence_Fast(overrides, "overrides must be a sequence of 'path=value' strings");
        if (!seq) goto fail;
        n = PySequence_Fast_GET_SIZE(seq);
        ov = PyMem_Calloc((size_t)n + 1, sizeof *ov);
        if (!ov) {
            Py_DECREF(seq);
            PyErr_NoMemory();
            goto fail;
        }
        for (Py_ssize_t k = 0; k < n; ++k) {
            ov[k] = PyUnicode_AsUTF8(PySequence_Fast_GET_ITEM(seq, k));
            if (!ov[k]) {
                PyMem_Free(ov);
                Py_DECREF(seq);
                goto fail;
            }
        }
    }
    pl_sim_options opt = {0};
    opt.overrides = ov;
    opt.noverrides = (int)n;
    opt.device = device;
    pl_diag diag;
    pl_diag_init(&diag);
    self->sim = path ? pl_sim_load_file(PyBytes_AS_STRING(path), &opt, &diag)
                     : pl_sim_load_string(xml, name, &opt, &diag);
    PyMem_Free(ov);
    Py_XDECREF(seq);
    if (!self->sim) {
        raise_diag(&diag);
        pl_diag_free(&diag);
        goto fail;
    }
    /* the warnings of a load that succeeded (drawing components dropped, ...):
     * the Python side prints them (pliant.Simulation, pliant.sofa) */
    char *warnings = diag.count ? diag_text(&diag) : NULL;
    pl_diag_free(&diag);
    Py_CLEAR(self->warnings);
    if (warnings) {
        self->warnings = PyUnicode_DecodeUTF8(warnings, (Py_ssize_t)strlen(warnings), "replace");
        free(warnings);
        if (!self->warnings) goto fail;
    }
    Py_XDECREF(path);
    pl_sim_set_callback(self->sim, begin_hook, self);
    return 0;
fail:
    Py_XDECREF(path);
    return -1;
}

static int sim_traverse(pl_py_sim *self, visitproc visit, void *arg)
{
    Py_VISIT((PyObject *)self->owner);
    Py_VISIT(self->begin);
    Py_VISIT(self->end);
    return 0;
}

static int sim_clear(pl_py_sim *self)
{
    Py_CLEAR(self->begin);
    Py_CLEAR(self->end);
    Py_CLEAR(self->warnings);
    return 0;
}

static void sim_dealloc(pl_py_sim *self)
{
    PyObject_GC_UnTrack(self);
    if (self->weakrefs) PyObject_ClearWeakRefs((PyObject *)self);
    sim_clear(self);
    if (self->owner) {
        /* a fork: its data goes before the owner's model (it holds the owner) */
        pl_data_free(self->data);
        Py_CLEAR(self->owner);
    } else if (self->sim) {
        pl_sim_free(self->sim);
    }
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static int check(pl_py_sim *self)
{
    if (self->sim) return 0;
    PyErr_SetString(PyExc_RuntimeError, "Sim is not loaded");
    return -1;
}

static pl_py_sim *owner_of(pl_py_sim *self)
{
    return self->owner ? self->owner : self;
}

static int check_idle(pl_py_sim *self, const char *what)
{
    if (check(self)) return -1;
    if (!owner_of(self)->stepping) return 0;
    PyErr_Format(PyExc_RuntimeError, "%s inside a step (from a controller) is not allowed", what);
    return -1;
}

static PyObject *sim_step(pl_py_sim *self, PyObject *args)
{
    int n = 1;
    if (!PyArg_ParseTuple(args, "|i", &n) || check_idle(self, "step()")) return NULL;
    if (n < 0) return PyErr_Format(PyExc_ValueError, "step(%d): expected n >= 0", n);
    pl_py_sim *owner = owner_of(self);
    pl_error err;
    owner->stepping = 1;
    owner->current = self; /* the begin hook calls this Sim's controllers */
    for (int k = 0; k < n; ++k) {
        pl_error_clear(&err);
        int rc = self->data ? pl_sim_step_data(self->sim, self->data, 1, &err)
                            : pl_sim_step(self->sim, 1, &err);
        if (rc == PL_OK && self->end) {
            PyObject *t = PyFloat_FromDouble(pl_py_data(self)->time);
            PyObject *r = t ? PyObject_CallOneArg(self->end, t) : NULL;
            Py_XDECREF(t);
            if (!r) rc = -1;
            Py_XDECREF(r);
        }
        if (rc != PL_OK) {
            owner->stepping = 0;
            if (PyErr_Occurred()) return NULL; /* a controller raised */
            return pl_py_raise(&err);
        }
    }
    owner->stepping = 0;
    Py_RETURN_NONE;
}

/* fork(): a new Sim over the same model (one factorisation, one copy of the
 * meshes) with its own state, a copy of this one's, and its own inputs
 * (pl_data_clone).  Fields that are not inputs belong to the model: setting
 * one in any fork changes it for all. */
static PyObject *sim_fork(pl_py_sim *self, PyObject *noargs)
{
    (void)noargs;
    if (check_idle(self, "fork()")) return NULL;
    PyTypeObject *type = Py_TYPE(self);
    pl_py_sim *f = (pl_py_sim *)type->tp_alloc(type, 0);
    if (!f) return NULL;
    f->data = pl_data_clone(pl_py_data(self));
    if (!f->data) {
        Py_DECREF(f);
        return PyErr_NoMemory();
    }
    f->sim = self->sim;
    f->owner = (pl_py_sim *)Py_NewRef((PyObject *)owner_of(self));
    return (PyObject *)f;
}

/* Field by path as text; grows the buffer for long values (positions). */
static PyObject *sim_get(pl_py_sim *self, PyObject *args)
{
    const char *path;
    if (!PyArg_ParseTuple(args, "s", &path) || check(self)) return NULL;
    for (size_t size = 4096;; size *= 16) {
        char *buf = PyMem_Malloc(size);
        if (!buf) return PyErr_NoMemory();
        pl_error err;
        pl_error_clear(&err);
        if (pl_sim_get_data(self->sim, pl_py_data(self), path, buf, size, &err) == PL_OK) {
            PyObject *s = PyUnicode_FromString(buf);
            PyMem_Free(buf);
            return s;
        }
        PyMem_Free(buf);
        if (!strstr(err.msg, "does not fit") || size > ((size_t)1 << 30)) return pl_py_raise(&err);
    }
}

static PyObject *sim_set(pl_py_sim *self, PyObject *args)
{
    const char *path, *value;
    if (!PyArg_ParseTuple(args, "ss", &path, &value) || check(self)) return NULL;
    pl_error err;
    pl_error_clear(&err);
    if (pl_sim_set_data(self->sim, pl_py_data(self), path, value, &err) != PL_OK)
        return pl_py_raise(&err);
    Py_RETURN_NONE;
}

/* pl_sim_save_state / pl_sim_restore_state for this Sim's data (a fork's too). */
static int state_file(pl_py_sim *self, const char *path, int save, pl_error *err)
{
    if (!self->data)
        return save ? pl_sim_save_state(self->sim, path, err)
                    : pl_sim_restore_state(self->sim, path, err);
    FILE *f = fopen(path, save ? "wb" : "rb");
    if (!f)
        return pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot %s: %s",
                            save ? "write" : "open", strerror(errno));
    int rc = save ? pl_data_save(self->data, f, err) : pl_data_load(self->data, f, err);
    if (fclose(f) != 0 && save && rc == PL_OK)
        rc = pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "cannot write the state file");
    if (rc != PL_OK && !err->file[0]) snprintf(err->file, sizeof err->file, "%s", path);
    return rc;
}

static PyObject *sim_save(pl_py_sim *self, PyObject *args)
{
    PyObject *path;
    if (!PyArg_ParseTuple(args, "O&", PyUnicode_FSConverter, &path)) return NULL;
    PyObject *r = NULL;
    pl_error err;
    pl_error_clear(&err);
    if (check(self) == 0) {
        if (state_file(self, PyBytes_AS_STRING(path), 1, &err) != PL_OK)
            pl_py_raise(&err);
        else
            r = Py_NewRef(Py_None);
    }
    Py_DECREF(path);
    return r;
}

static PyObject *sim_restore(pl_py_sim *self, PyObject *args)
{
    PyObject *path;
    if (!PyArg_ParseTuple(args, "O&", PyUnicode_FSConverter, &path)) return NULL;
    PyObject *r = NULL;
    pl_error err;
    pl_error_clear(&err);
    if (check_idle(self, "restore()") == 0) {
        if (state_file(self, PyBytes_AS_STRING(path), 0, &err) != PL_OK)
            pl_py_raise(&err);
        else
            r = Py_NewRef(Py_None);
    }
    Py_DECREF(path);
    return r;
}

static PyObject *sim_reset(pl_py_sim *self, PyObject *noargs)
{
    (void)noargs;
    if (check_idle(self, "reset()")) return NULL;
    if (pl_data_copy(pl_py_data(self), pl_sim_model(self->sim)->initial) != 0)
        return PyErr_NoMemory();
    Py_RETURN_NONE;
}

/* [(name, bytes, fixed)] of every slot of the data: "root/finger/dofs.position". */
static PyObject *sim_slots(pl_py_sim *self, PyObject *noargs)
{
    (void)noargs;
    if (check(self)) return NULL;
    const pl_model *m = pl_sim_model(self->sim);
    const pl_data *d = pl_py_data(self);
    PyObject *list = PyList_New(m->nslots);
    for (int k = 0; list && k < m->nslots; ++k) {
        PyObject *t = Py_BuildValue("(snO)", m->slots[k].name, (Py_ssize_t)d->slots[k].bytes,
                                    m->slots[k].elem_size == 0 ? Py_True : Py_False);
        if (!t) Py_CLEAR(list);
        else PyList_SET_ITEM(list, k, t);
    }
    return list;
}

/* view(slot_name, writable=False): a View of a fixed slot (no copy). */
static PyObject *sim_view(pl_py_sim *self, PyObject *args)
{
    const char *name;
    int writable = 0;
    if (!PyArg_ParseTuple(args, "s|p", &name, &writable) || check(self)) return NULL;
    int slot = pl_model_find_slot(pl_sim_model(self->sim), name);
    if (slot < 0) return PyErr_Format(PyExc_KeyError, "no state slot named '%s'", name);
    return pl_py_view_new(self, slot, writable);
}

/* component(path): the component's full path and type name ("root/finger/dofs",
 * "MechanicalObject"), or the did-you-mean error of a field path. */
static PyObject *sim_component(pl_py_sim *self, PyObject *args)
{
    const char *path;
    if (!PyArg_ParseTuple(args, "s", &path) || check(self)) return NULL;
    pl_component *c = pl_sim_component(self->sim, path);
    if (!c) return PyErr_Format(pl_py_input_error, "no component '%s' in the scene", path);
    char buf[512];
    return Py_BuildValue("(ss)", pl_component_path(c, buf, sizeof buf), c->type->name);
}

/* field_info("path.field"): (type name, flags) of a component's field, e.g.
 * ("double list", PL_FIELD_INPUT | PL_FIELD_RUNTIME), or None when the
 * component or the field is unknown (get() then says why). */
static PyObject *sim_field_info(pl_py_sim *self, PyObject *args)
{
    const char *path;
    if (!PyArg_ParseTuple(args, "s", &path) || check(self)) return NULL;
    const char *dot = strrchr(path, '.');
    if (!dot || dot == path) Py_RETURN_NONE;
    char comp[512];
    snprintf(comp, sizeof comp, "%.*s", (int)(dot - path), path);
    pl_component *c = pl_sim_component(self->sim, comp);
    const pl_field *f = c ? pl_component_field(c, dot + 1) : NULL;
    if (!f) Py_RETURN_NONE;
    return Py_BuildValue("(si)", pl_field_type_name(f->type), f->flags);
}

static PyObject *sim_set_hooks(pl_py_sim *self, PyObject *args)
{
    PyObject *begin, *end;
    if (!PyArg_ParseTuple(args, "OO", &begin, &end) || check(self)) return NULL;
    if ((begin != Py_None && !PyCallable_Check(begin)) || (end != Py_None && !PyCallable_Check(end)))
        return PyErr_Format(PyExc_TypeError, "set_hooks(begin, end): callables or None");
    Py_XSETREF(self->begin, begin == Py_None ? NULL : Py_NewRef(begin));
    Py_XSETREF(self->end, end == Py_None ? NULL : Py_NewRef(end));
    Py_RETURN_NONE;
}

static PyObject *sim_get_time(pl_py_sim *self, void *closure)
{
    (void)closure;
    if (check(self)) return NULL;
    return PyFloat_FromDouble(pl_py_data(self)->time);
}

static PyObject *sim_get_steps(pl_py_sim *self, void *closure)
{
    (void)closure;
    if (check(self)) return NULL;
    return PyLong_FromLong(pl_py_data(self)->step);
}

static PyObject *sim_get_dt(pl_py_sim *self, void *closure)
{
    (void)closure;
    if (check(self)) return NULL;
    return PyFloat_FromDouble(pl_node_dt(pl_sim_model(self->sim)->root));
}

static PyMethodDef sim_methods[] = {
    {"step", (PyCFunction)sim_step, METH_VARARGS, "step(n=1): advance n time steps"},
    {"fork", (PyCFunction)sim_fork, METH_NOARGS,
     "fork(): a Sim over the same model with its own state (a copy of this one's)"},
    {"get", (PyCFunction)sim_get, METH_VARARGS, "get(path): a field's value as text"},
    {"set", (PyCFunction)sim_set, METH_VARARGS, "set(path, text): change a field"},
    {"save", (PyCFunction)sim_save, METH_VARARGS, "save(file): the state, binary and exact"},
    {"restore", (PyCFunction)sim_restore, METH_VARARGS, "restore(file): a saved state"},
    {"reset", (PyCFunction)sim_reset, METH_NOARGS, "reset(): the state after loading"},
    {"slots", (PyCFunction)sim_slots, METH_NOARGS, "slots(): [(name, bytes, fixed)]"},
    {"view", (PyCFunction)sim_view, METH_VARARGS, "view(slot, writable=False): a View"},
    {"component", (PyCFunction)sim_component, METH_VARARGS, "component(path): (path, type)"},
    {"field_info", (PyCFunction)sim_field_info, METH_VARARGS,
     "field_info(path): (type name, flags) of a field, or None"},
    {"set_hooks", (PyCFunction)sim_set_hooks, METH_VARARGS,
     "set_hooks(begin, end): callables(t) at the start and end of every step"},
    {NULL, NULL, 0, NULL}};

static PyObject *sim_get_warnings(pl_py_sim *self, void *closure)
{
    (void)closure;
    if (self->warnings) return Py_NewRef(self->warnings);
    return PyUnicode_FromString("");
}

static PyGetSetDef sim_getset[] = {
    {"time", (getter)sim_get_time, NULL, "simulated time [s]", NULL},
    {"steps", (getter)sim_get_steps, NULL, "steps taken", NULL},
    {"dt", (getter)sim_get_dt, NULL, "the root's time step [s]", NULL},
    {"warnings", (getter)sim_get_warnings, NULL,
     "the load's warnings, one a line as `pliant run` prints them ('' if none)", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

PyTypeObject pl_py_sim_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "pliant._core.Sim",
    .tp_basicsize = sizeof(pl_py_sim),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "Sim(path) or Sim(xml=text, name=...): one loaded scene (pliant.Simulation)",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)sim_init,
    .tp_dealloc = (destructor)sim_dealloc,
    .tp_traverse = (traverseproc)sim_traverse,
    .tp_clear = (inquiry)sim_clear,
    .tp_weaklistoffset = offsetof(pl_py_sim, weakrefs),
    .tp_methods = sim_methods,
    .tp_getset = sim_getset,
};
