// SPDX-License-Identifier: MIT
/*
 * sh2000._sh2000.Card: one open card (struct sh2000). Each method is one
 * libsh2000 call with the GIL released while the library may wait; axis
 * numbers, masks and parameter ids come from the Python layer, values in
 * the library's own units (mm, ms, ns).
 */
#include <errno.h>

#include "binding.h"
#include "card_methods.h"

struct sh2000 *sh2k_handle(PyCard *c)
{
	if (!c->h)
		PyErr_SetString(PyExc_ValueError, "card is closed");
	return c->h;
}

/* None for r >= 0, else sh2000.Error with the handle's message. */
static PyObject *result(PyCard *c, int r)
{
	if (r < 0)
		return sh2k_raise(r, c->h, NULL, NULL);
	Py_RETURN_NONE;
}

static int card_init(PyCard *c, PyObject *args, PyObject *kw)
{
	static char *kwlist[] = { "device", NULL };
	const char *device = NULL;
	char msg[512] = "";
	struct sh2000 *h = NULL;
	int r;

	if (!PyArg_ParseTupleAndKeywords(args, kw, "|z", kwlist, &device))
		return -1;
	if (c->h) {
		PyErr_SetString(PyExc_ValueError, "card is already open");
		return -1;
	}
	Py_BEGIN_ALLOW_THREADS
	r = sh2000_open(&h, device, msg, sizeof(msg));
	Py_END_ALLOW_THREADS
	if (r < 0) {
		sh2k_raise(r, NULL, msg[0] ? msg : NULL, NULL);
		return -1;
	}
	c->h = h;
	return 0;
}

static PyObject *card_close(PyCard *c, PyObject *unused)
{
	(void)unused;
	if (c->busy) {
		PyErr_SetString(PyExc_RuntimeError,
				"card is in use by another thread");
		return NULL;
	}
	if (c->h)
		sh2000_close(c->h);
	c->h = NULL;
	Py_RETURN_NONE;
}

static void card_dealloc(PyCard *c)
{
	if (c->h)
		sh2000_close(c->h);
	Py_TYPE(c)->tp_free((PyObject *)c);
}

static PyObject *card_info(PyCard *c, PyObject *unused)
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned int v;

	(void)unused;
	if (!h)
		return NULL;
	v = sh2000_card_version(h);
	return Py_BuildValue("{s:s,s:i,s:N,s:I}", "device", sh2000_device(h),
			     "backend", (int)sh2000_backend(h), "card_protocol",
			     PyUnicode_FromFormat("%u.%u",
						  SH2000_PROTO_VERSION_MAJOR(v),
						  SH2000_PROTO_VERSION_MINOR(v)),
			     "queue_size", sh2000_queue_size(h));
}

static PyObject *card_status(PyCard *c, PyObject *unused)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_status st;
	int r;

	(void)unused;
	if (!h)
		return NULL;
	SH2K_CALL(c, r = sh2000_poll(h, &st));
	/* a stopped heartbeat comes with the status filled: the caller
	 * sees it as Status.fault, not as an exception */
	if (r < 0 && r != -SH2000_EHEARTBEAT)
		return sh2k_raise(r, h, NULL, NULL);
	return sh2k_status_dict(h, &st);
}

static PyObject *card_param_get(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned int id;
	double v = 0;
	int axis, r;

	if (!h || !PyArg_ParseTuple(args, "iI", &axis, &id))
		return NULL;
	SH2K_CALL(c, r = sh2000_param_get(h, axis, id, &v));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	return PyFloat_FromDouble(v);
}

static PyObject *card_param_set(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	unsigned int id;
	double v;
	int axis, r;

	if (!h || !PyArg_ParseTuple(args, "iId", &axis, &id, &v))
		return NULL;
	SH2K_CALL(c, r = sh2000_param_set(h, axis, id, v));
	return result(c, r);
}

/* axis_params_get(axis): every per-axis parameter, indexed by id. */
static PyObject *card_axis_params_get(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_axis_params p;
	PyObject *l;
	unsigned int axis;
	int r;

	if (!h || !PyArg_ParseTuple(args, "I", &axis))
		return NULL;
	SH2K_CALL(c, r = sh2000_axis_params_get(h, axis, &p));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	l = PyList_New(SH2000_AXIS_PARAMS);
	for (unsigned int i = 0; l && i < SH2000_AXIS_PARAMS; i++) {
		PyObject *f = PyFloat_FromDouble(p.v[i]);

		if (!f) {
			Py_CLEAR(l);
			break;
		}
		PyList_SET_ITEM(l, i, f);
	}
	return l;
}

/* axis_params_set(axis, values): all checked, then all set, or none. */
static PyObject *card_axis_params_set(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_axis_params p;
	PyObject *seq, *fast;
	unsigned int axis;
	int r;

	if (!h || !PyArg_ParseTuple(args, "IO", &axis, &seq))
		return NULL;
	fast = PySequence_Fast(seq, "values must be a sequence");
	if (!fast)
		return NULL;
	if (PySequence_Fast_GET_SIZE(fast) != SH2000_AXIS_PARAMS) {
		Py_DECREF(fast);
		return PyErr_Format(PyExc_ValueError, "values: %u needed",
				    SH2000_AXIS_PARAMS);
	}
	for (unsigned int i = 0; i < SH2000_AXIS_PARAMS; i++)
		p.v[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(fast, i));
	Py_DECREF(fast);
	if (PyErr_Occurred())
		return NULL;
	SH2K_CALL(c, r = sh2000_axis_params_set(h, axis, &p));
	return result(c, r);
}

#define M SH2K_METHOD
static PyMethodDef card_methods[] = {
	M("close", card_close, METH_NOARGS, "close(): sh2000_close"),
	M("info", card_info, METH_NOARGS,
	  "info(): device, backend, card protocol, queue size"),
	M("status", card_status, METH_NOARGS, "status(): sh2000_poll as a dict"),
	M("param_get", card_param_get, METH_VARARGS,
	  "param_get(axis, id): sh2000_param_get (axis -1: global)"),
	M("param_set", card_param_set, METH_VARARGS,
	  "param_set(axis, id, value): sh2000_param_set"),
	M("axis_params_get", card_axis_params_get, METH_VARARGS,
	  "axis_params_get(axis): sh2000_axis_params_get"),
	M("axis_params_set", card_axis_params_set, METH_VARARGS,
	  "axis_params_set(axis, values): sh2000_axis_params_set"),
	M("enable", sh2k_card_enable, METH_VARARGS, "enable(mask)"),
	M("disable", sh2k_card_disable, METH_VARARGS, "disable(mask)"),
	M("stop", sh2k_card_stop, METH_NOARGS, "stop()"),
	M("reset", sh2k_card_reset, METH_NOARGS, "reset()"),
	M("estop", sh2k_card_estop, METH_VARARGS, "estop(timeout_ms)"),
	M("home", sh2k_card_home, METH_VARARGS,
	  "home(axis, flags, timeout_ms): sh2000_run_home"),
	M("set_position", sh2k_card_set_position, METH_VARARGS,
	  "set_position(axis, mm)"),
	M("push_mm", sh2k_card_push_mm, METH_VARARGS,
	  "push_mm(points, flags): one all-or-nothing batch"),
	M("push_counts", sh2k_card_push_counts, METH_VARARGS,
	  "push_counts(points, flags): one all-or-nothing batch"),
	M("wait_space", sh2k_card_wait_space, METH_VARARGS,
	  "wait_space(n, timeout_ms)"),
	M("wait_idle", sh2k_card_wait_idle, METH_VARARGS, "wait_idle(timeout_ms)"),
	M("wait_rest", sh2k_card_wait_rest, METH_VARARGS, "wait_rest(timeout_ms)"),
	M("queue_free", sh2k_card_queue_free, METH_NOARGS, "queue_free()"),
	M("now_ns", sh2k_card_now_ns, METH_NOARGS, "now_ns(): the card's clock"),
	M("sleep_ns", sh2k_card_sleep_ns, METH_VARARGS,
	  "sleep_ns(ns): let card time pass"),
	M("gather_start", sh2k_card_gather_start, METH_VARARGS,
	  "gather_start(signals, period, samples, trigger, pretrigger)"),
	M("gather_stop", sh2k_card_gather_stop, METH_NOARGS, "gather_stop()"),
	M("gather_info", sh2k_card_gather_info, METH_NOARGS,
	  "gather_info(): the record (or configuration) as a dict"),
	M("gather_wait", sh2k_card_gather_wait, METH_VARARGS,
	  "gather_wait(record, timeout_ms): its info once DONE"),
	M("gather_read", sh2k_card_gather_read, METH_VARARGS,
	  "gather_read(info, first, n): a bytearray of doubles"),
	M("comp_load", sh2k_card_comp_load, METH_VARARGS,
	  "comp_load(path): sh2000_comp_load_file"),
	M("comp_clear", sh2k_card_comp_clear, METH_NOARGS, "comp_clear()"),
	M("comp_status", sh2k_card_comp_status, METH_NOARGS,
	  "comp_status(): the active tables as a dict"),
	{ NULL, NULL, 0, NULL },
};
#undef M

PyTypeObject PyCard_Type = {
	PyVarObject_HEAD_INIT(NULL, 0)
	.tp_name = "sh2000._sh2000.Card",
	.tp_doc = "Card(device): an open SH-2000TH card (libsh2000)",
	.tp_basicsize = sizeof(PyCard),
	.tp_flags = Py_TPFLAGS_DEFAULT,
	.tp_new = PyType_GenericNew,
	.tp_init = (initproc)card_init,
	.tp_dealloc = (destructor)card_dealloc,
	.tp_methods = card_methods,
};
