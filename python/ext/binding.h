/* SPDX-License-Identifier: MIT */
/*
 * The CPython extension sh2000._sh2000: libsh2000 and libsh2000-motion as
 * Python objects, one C call per method. The pure-Python package sh2000
 * (python/sh2000/) wraps it in dataclasses; docs/python.md is the guide.
 *
 * Every library error becomes sh2000.Error (python/sh2000/_error.py) with
 * the code as the library gives it, made positive (SH2000_E* or errno),
 * the code's name (sh2000_strerror) and the handle's message.
 */
#ifndef SH2000_PY_BINDING_H
#define SH2000_PY_BINDING_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <sh2000/run.h>
#include <sh2000/sh2000.h>

/* An open card. busy counts the calls running without the GIL: close()
 * waits for none, it refuses while any runs. */
typedef struct {
	PyObject_HEAD
	struct sh2000 *h;
	unsigned int busy;
} PyCard;

extern PyTypeObject PyCard_Type;
extern PyTypeObject PyProgram_Type;

/* Raise sh2000.Error for library code e (negative); msg NULL: the
 * handle's last error (h may be NULL), where NULL or a "file:line:col".
 * Returns NULL. */
PyObject *sh2k_raise(int e, struct sh2000 *h, const char *msg,
		     const char *where);
/* The same, returning the instance without raising (NULL on failure). */
PyObject *sh2k_error(int e, struct sh2000 *h, const char *msg,
		     const char *where);
/* The card's handle, or NULL with ValueError("card is closed"). */
struct sh2000 *sh2k_handle(PyCard *c);
/* Around a library call that may wait: the GIL released, close()
 * refused meanwhile. */
#define SH2K_CALL(card, stmt) do {			\
		(card)->busy++;				\
		Py_BEGIN_ALLOW_THREADS			\
		stmt;					\
		Py_END_ALLOW_THREADS			\
		(card)->busy--;				\
	} while (0)

/* struct sh2000_status as a dict with the struct's field names (axes: a
 * list of dicts), plus the names of state and faults and "fault": the
 * sh2000.Error its latched faults stand for, or None. */
PyObject *sh2k_status_dict(struct sh2000 *h, const struct sh2000_status *st);

/* Module-level functions and constants of the status and parameter
 * tables (status.c). */
int sh2k_add_constants(PyObject *m);
/* The module's gather_signals, gather_signal_id, gather_column (gather.c). */
int sh2k_add_gather(PyObject *m);

/* One row of a PyMethodDef table (the cast every METH_* function needs). */
#define SH2K_METHOD(name, fn, flags, doc) \
	{ name, (PyCFunction)(void (*)(void))(fn), flags, doc }

#endif /* SH2000_PY_BINDING_H */
