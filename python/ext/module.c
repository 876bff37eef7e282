// SPDX-License-Identifier: MIT
/*
 * sh2000._sh2000: module set-up (the types, status.c's constants,
 * gather.c's), the error helper every method uses, strerror() and
 * version().
 */
#include <errno.h>
#include <string.h>

#include "binding.h"

/* sh2000._error.Error, fetched once at import. */
static PyObject *error_class;

PyObject *sh2k_error(int e, struct sh2000 *h, const char *msg,
		     const char *where)
{
	char buf[512] = "";

	if (!msg && h)
		sh2000_last_error_copy(h, buf, sizeof(buf));
	if (!msg)
		msg = buf[0] ? buf : sh2000_strerror(e);
	return PyObject_CallFunction(error_class, "isss", e < 0 ? -e : e,
				     sh2000_strerror(e), msg, where);
}

PyObject *sh2k_raise(int e, struct sh2000 *h, const char *msg,
		     const char *where)
{
	PyObject *x = sh2k_error(e, h, msg, where);

	if (x) {
		PyErr_SetObject(error_class, x);
		Py_DECREF(x);
	}
	return NULL;
}

static PyObject *py_strerror(PyObject *self, PyObject *arg)
{
	long code = PyLong_AsLong(arg);

	(void)self;
	if (code == -1 && PyErr_Occurred())
		return NULL;
	return PyUnicode_FromString(sh2000_strerror(code > 0 ? (int)-code :
						    (int)code));
}

/* The running library's version and SONAME major, and the protocol
 * version it speaks (the one the extension was built against). */
static PyObject *py_version(PyObject *self, PyObject *unused)
{
	PyObject *proto = PyUnicode_FromFormat("%u.%u", SH2000_PROTO_MAJOR,
					       SH2000_PROTO_MINOR);

	(void)self;
	(void)unused;
	if (!proto)
		return NULL;
	return Py_BuildValue("{s:s,s:I,s:N}", "library", sh2000_version(),
			     "soversion", sh2000_soversion(), "protocol",
			     proto);
}

static PyMethodDef methods[] = {
	{ "strerror", py_strerror, METH_O,
	  "strerror(code): the library's name of an error code" },
	{ "version", py_version, METH_NOARGS,
	  "version(): the running library's versions" },
	{ NULL, NULL, 0, NULL },
};

static struct PyModuleDef module = {
	PyModuleDef_HEAD_INIT, "sh2000._sh2000",
	"libsh2000 and libsh2000-motion (use the package sh2000)", -1,
	methods, NULL, NULL, NULL, NULL,
};

static int add_type(PyObject *m, PyTypeObject *t, const char *name)
{
	if (PyType_Ready(t) < 0)
		return -1;
	Py_INCREF(t);
	if (PyModule_AddObject(m, name, (PyObject *)t) < 0) {
		Py_DECREF(t);
		return -1;
	}
	return 0;
}

PyMODINIT_FUNC PyInit__sh2000(void)
{
	PyObject *m, *errmod;

	errmod = PyImport_ImportModule("sh2000._error");
	if (!errmod)
		return NULL;
	error_class = PyObject_GetAttrString(errmod, "Error");
	Py_DECREF(errmod);
	if (!error_class)
		return NULL;
	m = PyModule_Create(&module);
	if (!m)
		return NULL;
	if (add_type(m, &PyCard_Type, "Card") < 0 ||
	    add_type(m, &PyProgram_Type, "Program") < 0 ||
	    sh2k_add_constants(m) < 0 || sh2k_add_gather(m) < 0) {
		Py_DECREF(m);
		return NULL;
	}
	return m;
}
