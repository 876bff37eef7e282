// SPDX-License-Identifier: MIT
/*
 * sh2000._sh2000.Card's commands, segments and clock: enable, disable,
 * stop, reset, estop, home, set_position, push_mm/push_counts, the waits,
 * now_ns and sleep_ns. One library call each, the GIL released.
 */
#include <errno.h>

#include "binding.h"
#include "card_methods.h"

static PyObject *done(PyCard *c, int r)
{
	if (r < 0)
		return sh2k_raise(r, c->h, NULL, NULL);
	return PyLong_FromLong(r);
}

/* The calls with one argument, or none: fn(h), fn(h, unsigned),
 * fn(h, int). */
static PyObject *call0(PyCard *c, int (*fn)(struct sh2000 *))
{
	struct sh2000 *h = sh2k_handle(c);
	int r;

	if (!h)
		return NULL;
	SH2K_CALL(c, r = fn(h));
	return done(c, r);
}

static PyObject *call_u(PyCard *c, PyObject *args,
			int (*fn)(struct sh2000 *, unsigned int))
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned int v;
	int r;

	if (!h || !PyArg_ParseTuple(args, "I", &v))
		return NULL;
	SH2K_CALL(c, r = fn(h, v));
	return done(c, r);
}

static PyObject *call_i(PyCard *c, PyObject *args,
			int (*fn)(struct sh2000 *, int))
{
	struct sh2000 *h = sh2k_handle(c);
	int v, r;

	if (!h || !PyArg_ParseTuple(args, "i", &v))
		return NULL;
	SH2K_CALL(c, r = fn(h, v));
	return done(c, r);
}

PyObject *sh2k_card_enable(PyCard *c, PyObject *args)
{
	return call_u(c, args, sh2000_enable);
}

PyObject *sh2k_card_disable(PyCard *c, PyObject *args)
{
	return call_u(c, args, sh2000_disable);
}

PyObject *sh2k_card_stop(PyCard *c, PyObject *unused)
{
	(void)unused;
	return call0(c, sh2000_stop);
}

PyObject *sh2k_card_reset(PyCard *c, PyObject *unused)
{
	(void)unused;
	return call0(c, sh2000_reset);
}

PyObject *sh2k_card_estop(PyCard *c, PyObject *args)
{
	return call_i(c, args, sh2000_estop);
}

/* home(axis, flags, timeout_ms): homes and waits (sh2000_run_home). */
PyObject *sh2k_card_home(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned int axis, flags;
	char msg[512] = "";
	int ms, r;

	if (!h || !PyArg_ParseTuple(args, "IIi", &axis, &flags, &ms))
		return NULL;
	SH2K_CALL(c, r = sh2000_run_home(h, axis, flags, ms, msg, sizeof(msg)));
	if (r < 0)
		return sh2k_raise(r, h, msg[0] ? msg : NULL, NULL);
	Py_RETURN_NONE;
}

PyObject *sh2k_card_set_position(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned int axis;
	double mm;
	int r;

	if (!h || !PyArg_ParseTuple(args, "Id", &axis, &mm))
		return NULL;
	SH2K_CALL(c, r = sh2000_set_position(h, axis, mm));
	return done(c, r);
}

/* Rows of SH2000_AXES numbers from any sequence of sequences (lists,
 * tuples, a numpy array of shape (n, 4)) into a new array, as doubles;
 * NULL with a Python error. */
static double *points(PyObject *seq, size_t *n)
{
	PyObject *rows = PySequence_Fast(seq, "points must be a sequence of points");
	double *pts = NULL;
	Py_ssize_t k;

	if (!rows)
		return NULL;
	k = PySequence_Fast_GET_SIZE(rows);
	pts = PyMem_Calloc(k ? (size_t)k : 1, SH2000_AXES * sizeof(double));
	for (Py_ssize_t i = 0; pts && i < k; i++) {
		PyObject *row = PySequence_Fast(PySequence_Fast_GET_ITEM(rows, i),
						"a point must be a sequence");

		if (row && PySequence_Fast_GET_SIZE(row) != SH2000_AXES)
			PyErr_Format(PyExc_ValueError,
				     "point %zd: %zd values, one per axis (%u) needed",
				     i, PySequence_Fast_GET_SIZE(row), SH2000_AXES);
		for (unsigned int a = 0; row && !PyErr_Occurred() && a < SH2000_AXES; a++)
			pts[i * SH2000_AXES + a] =
				PyFloat_AsDouble(PySequence_Fast_GET_ITEM(row, a));
		Py_XDECREF(row);
		if (PyErr_Occurred()) {
			PyMem_Free(pts);
			pts = NULL;
		}
	}
	if (!pts && !PyErr_Occurred())
		PyErr_NoMemory();
	Py_DECREF(rows);
	*n = (size_t)k;
	return pts;
}

/* The points as counts: each must be a 32-bit integer. */
static int32_t (*counts_of(const double *pts, size_t n))[SH2000_AXES]
{
	int32_t (*ip)[SH2000_AXES] = PyMem_Calloc(n ? n : 1, sizeof(*ip));
	char msg[120];

	if (!ip) {
		PyErr_NoMemory();
		return NULL;
	}
	for (size_t i = 0; i < n * SH2000_AXES; i++) {
		double v = pts[i];

		if (!(v >= INT32_MIN && v <= INT32_MAX) || v != (int32_t)v) {
			snprintf(msg, sizeof(msg),
				 "point %zu: %g is not a count (a 32-bit integer)",
				 i / SH2000_AXES, v);
			PyErr_SetString(PyExc_ValueError, msg);
			PyMem_Free(ip);
			return NULL;
		}
		ip[i / SH2000_AXES][i % SH2000_AXES] = (int32_t)v;
	}
	return ip;
}

/* push_mm(points, flags) / push_counts(points, flags): one batch. */
static PyObject *push(PyCard *c, PyObject *args, int counts)
{
	struct sh2000 *h = sh2k_handle(c);
	int32_t (*ip)[SH2000_AXES] = NULL;
	unsigned int flags;
	PyObject *seq;
	double *pts;
	size_t n;
	int r;

	if (!h || !PyArg_ParseTuple(args, "OI", &seq, &flags))
		return NULL;
	pts = points(seq, &n);
	if (pts && counts && !(ip = counts_of(pts, n))) {
		PyMem_Free(pts);
		pts = NULL;
	}
	if (!pts)
		return NULL;
	if (counts)
		SH2K_CALL(c, r = sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])ip,
						    n, flags));
	else
		SH2K_CALL(c, r = sh2000_push_mm(h, (const double (*)[SH2000_AXES])pts,
						n, flags));
	PyMem_Free(ip);
	PyMem_Free(pts);
	return done(c, r);
}

PyObject *sh2k_card_push_mm(PyCard *c, PyObject *args)
{
	return push(c, args, 0);
}

PyObject *sh2k_card_push_counts(PyCard *c, PyObject *args)
{
	return push(c, args, 1);
}

PyObject *sh2k_card_wait_space(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned int n;
	int ms, r;

	if (!h || !PyArg_ParseTuple(args, "Ii", &n, &ms))
		return NULL;
	SH2K_CALL(c, r = sh2000_wait_space(h, n, ms));
	return done(c, r);
}

PyObject *sh2k_card_wait_idle(PyCard *c, PyObject *args)
{
	return call_i(c, args, sh2000_wait_idle);
}

PyObject *sh2k_card_wait_rest(PyCard *c, PyObject *args)
{
	return call_i(c, args, sh2000_wait_rest);
}

PyObject *sh2k_card_queue_free(PyCard *c, PyObject *unused)
{
	(void)unused;
	return call0(c, sh2000_queue_free);
}

PyObject *sh2k_card_now_ns(PyCard *c, PyObject *unused)
{
	struct sh2000 *h = sh2k_handle(c);
	uint64_t t;

	(void)unused;
	if (!h)
		return NULL;
	SH2K_CALL(c, t = sh2000_now_ns(h));
	return PyLong_FromUnsignedLongLong(t);
}

PyObject *sh2k_card_sleep_ns(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned long long ns;
	int r;

	if (!h || !PyArg_ParseTuple(args, "K", &ns))
		return NULL;
	SH2K_CALL(c, r = sh2000_sleep_ns(h, ns));
	return done(c, r);
}
