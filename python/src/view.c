/* view.c - pliant._core.View: one fixed-size slot of a sim's data, exported
 * through the buffer protocol as doubles, without a copy.  Fixed slots keep
 * their memory for the life of the data (model.h: restore and reset copy into
 * it), and the View holds its Sim, so numpy.frombuffer(view) stays valid for
 * as long as the array lives. */
#include "pliant_py.h"

typedef struct {
    PyObject_HEAD
    pl_py_sim *sim; /* a strong reference: the sim outlives the view */
    int slot;
    int writable;
} pl_py_view;

PyObject *pl_py_view_new(pl_py_sim *sim, int slot, int writable)
{
    const pl_model *m = pl_sim_model(sim->sim);
    if (m->slots[slot].elem_size != 0)
        return PyErr_Format(PyExc_ValueError,
                            "slot '%s' changes size while running: read it with get()",
                            m->slots[slot].name);
    if (pl_data_slot_bytes(pl_py_data(sim), slot) % sizeof(double) != 0)
        return PyErr_Format(PyExc_ValueError, "slot '%s' does not hold doubles",
                            m->slots[slot].name);
    pl_py_view *v = PyObject_New(pl_py_view, &pl_py_view_type);
    if (!v) return NULL;
    v->sim = (pl_py_sim *)Py_NewRef((PyObject *)sim);
    v->slot = slot;
    v->writable = writable;
    return (PyObject *)v;
}

static void view_dealloc(pl_py_view *v)
{
    Py_XDECREF(v->sim);
    PyObject_Free(v);
}

static int view_getbuffer(pl_py_view *v, Py_buffer *b, int flags)
{
    if ((flags & PyBUF_WRITABLE) && !v->writable) {
        PyErr_SetString(PyExc_BufferError, "this state view is read-only");
        b->obj = NULL;
        return -1;
    }
    pl_data *d = pl_py_data(v->sim);
    size_t bytes = pl_data_slot_bytes(d, v->slot);
    b->buf = pl_data_slot(d, v->slot);
    b->obj = Py_NewRef((PyObject *)v);
    /* the owner of the slot (a device copy of it) learns that it may be
     * written at any time until the buffer is released */
    if (v->writable) pl_data_slot_writers(d, v->slot, +1);
    b->len = (Py_ssize_t)bytes;
    b->readonly = !v->writable;
    b->itemsize = sizeof(double);
    b->format = (flags & PyBUF_FORMAT) ? "d" : NULL;
    b->ndim = 1;
    b->shape = NULL;
    b->strides = NULL;
    b->suboffsets = NULL;
    b->internal = NULL;
    if (flags & PyBUF_ND) {
        /* shape lives in the Py_buffer's internal storage */
        Py_ssize_t *shape = PyMem_Malloc(2 * sizeof *shape);
        if (!shape) {
            if (v->writable) pl_data_slot_writers(d, v->slot, -1);
            Py_CLEAR(b->obj);
            PyErr_NoMemory();
            return -1;
        }
        shape[0] = (Py_ssize_t)(bytes / sizeof(double));
        shape[1] = sizeof(double);
        b->shape = shape;
        b->internal = shape;
        if ((flags & PyBUF_STRIDES) == PyBUF_STRIDES) b->strides = shape + 1;
    }
    return 0;
}

static void view_releasebuffer(pl_py_view *v, Py_buffer *b)
{
    if (v->writable) pl_data_slot_writers(pl_py_data(v->sim), v->slot, -1);
    PyMem_Free(b->internal);
}

static PyBufferProcs view_buffer = {(getbufferproc)view_getbuffer,
                                    (releasebufferproc)view_releasebuffer};

static PyObject *view_get_sim(pl_py_view *v, void *closure)
{
    (void)closure;
    return Py_NewRef((PyObject *)v->sim);
}

static PyGetSetDef view_getset[] = {
    {"sim", (getter)view_get_sim, NULL, "the Sim whose memory this is", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

PyTypeObject pl_py_view_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "pliant._core.View",
    .tp_basicsize = sizeof(pl_py_view),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A slot of a Sim's state as a buffer of doubles (numpy.frombuffer)",
    .tp_dealloc = (destructor)view_dealloc,
    .tp_as_buffer = &view_buffer,
    .tp_getset = view_getset,
};
