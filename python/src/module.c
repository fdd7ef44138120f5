/* module.c - pliant._core: the module, its exceptions and error conversion. */
#include "pliant_py.h"

PyObject *pl_py_error;
PyObject *pl_py_input_error;

PyObject *pl_py_raise(const pl_error *err)
{
    char buf[2048];
    pl_error_format(err, buf, sizeof buf);
    return pl_py_raise_text(err, buf);
}

PyObject *pl_py_raise_text(const pl_error *err, const char *text)
{
    PyObject *cls = err->code == PL_EINPUT ? pl_py_input_error : pl_py_error;
    PyObject *exc = PyObject_CallFunction(cls, "s", text);
    if (!exc) return NULL;
    /* file, line and component path as attributes, for programs */
    PyObject *code = PyLong_FromLong(err->code), *line = PyLong_FromLong(err->line);
    PyObject *file = PyUnicode_DecodeFSDefault(err->file);
    PyObject *where = PyUnicode_FromString(err->where);
    if (code && line && file && where) {
        PyObject_SetAttrString(exc, "code", code);
        PyObject_SetAttrString(exc, "file", file);
        PyObject_SetAttrString(exc, "line", line);
        PyObject_SetAttrString(exc, "where", where);
    }
    Py_XDECREF(code);
    Py_XDECREF(line);
    Py_XDECREF(file);
    Py_XDECREF(where);
    PyErr_SetObject(cls, exc);
    Py_DECREF(exc);
    return NULL;
}

/* The SOFA vocabulary table of libpliant as TSV text (sofa.h): the same table
 * the XML loader applies, read by pliant.sofa instead of a copy of its own. */
static PyObject *sofa_vocabulary(PyObject *self, PyObject *noargs)
{
    (void)self;
    (void)noargs;
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!f) return PyErr_NoMemory();
    int rc = pl_sofa_write_vocabulary(f, "tsv");
    fclose(f);
    if (rc != 0) {
        free(text);
        PyErr_SetString(pl_py_error, "cannot write the SOFA vocabulary");
        return NULL;
    }
    PyObject *s = PyUnicode_DecodeUTF8(text, (Py_ssize_t)len, "strict");
    free(text);
    return s;
}

/* set_log_level(level): 0 errors, 1 warnings, 2 info (default), 3 debug (process-wide, log.h). */
static PyObject *set_log_level(PyObject *self, PyObject *args)
{
    (void)self;
    int level;
    if (!PyArg_ParseTuple(args, "i", &level)) return NULL;
    pl_log_set_level((pl_log_level)level);
    Py_RETURN_NONE;
}

static PyMethodDef module_methods[] = {
    {"set_log_level", set_log_level, METH_VARARGS,
     "set_log_level(level): 0 errors, 1 warnings, 2 info (default), 3 debug (process-wide)"},
    {"sofa_vocabulary", sofa_vocabulary, METH_NOARGS,
     "SOFA's vocabulary as Pliant reads it: TSV text, one entry a line (pliant/sofa.h)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "_core",
                                        "Pliant's C API for Python (see the package pliant).",
                                        -1, module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__core(void);
PyMODINIT_FUNC PyInit__core(void)
{
    if (PyType_Ready(&pl_py_sim_type) < 0 || PyType_Ready(&pl_py_view_type) < 0) return NULL;
    PyObject *m = PyModule_Create(&module_def);
    if (!m) return NULL;
    pl_py_error = PyErr_NewExceptionWithDoc(
        "pliant.Error", "An error of Pliant (code 1: internal; InputError: code 2).", NULL, NULL);
    pl_py_input_error = PyErr_NewExceptionWithDoc(
        "pliant.InputError",
        "Bad input: a scene, a field path or value, a state file (the CLI's exit code 2).",
        pl_py_error, NULL);
    if (!pl_py_error || !pl_py_input_error || PyModule_AddObjectRef(m, "Error", pl_py_error) < 0 ||
        PyModule_AddObjectRef(m, "InputError", pl_py_input_error) < 0 ||
        PyModule_AddObjectRef(m, "Sim", (PyObject *)&pl_py_sim_type) < 0 ||
        PyModule_AddObjectRef(m, "View", (PyObject *)&pl_py_view_type) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
