// SPDX-License-Identifier: MIT
/*
 * sh2000._sh2000.Card's data gathering (protocol 1.2): gather_start, _stop,
 * _info, _wait and _read, one sh2000_gather_* call each, and the module's
 * gather_config_default, gather_column and signal table. A record description travels as a dict with
 * struct sh2000_gather_info's field names (gather_read and gather_column
 * take it back), and gather_read hands the values over as a bytearray of
 * doubles, so the extension needs no numpy: the Python layer
 * (sh2000/_gather.py) shapes them into arrays.
 */
#include <stddef.h>
#include <string.h>

#include "binding.h"
#include "card_methods.h"

_Static_assert(sizeof(unsigned int) == sizeof(uint32_t),
	       "the info's fields are copied as 32-bit words");

/* The 32-bit fields of struct sh2000_gather_info, both ways. */
#define F(name) { #name, offsetof(struct sh2000_gather_info, name) }
static const struct { const char *name; size_t off; } info_fields[] = {
	F(state), F(record), F(trigger), F(period), F(values), F(samples),
	F(capacity), F(pretrigger), F(trigger_index), F(first_cycle),
	F(trigger_cycle), F(buffer),
};
#undef F
#define N_INFO_FIELDS (sizeof(info_fields) / sizeof(info_fields[0]))

static PyObject *info_dict(const struct sh2000_gather_info *gi)
{
	PyObject *d = Py_BuildValue("{s:(IIII),s:d}", "signals",
				    gi->signals[0], gi->signals[1],
				    gi->signals[2], gi->signals[3],
				    "sample_s", gi->sample_s);

	for (size_t i = 0; d && i < N_INFO_FIELDS; i++) {
		uint32_t v;
		PyObject *o;

		memcpy(&v, (const char *)gi + info_fields[i].off, sizeof(v));
		o = PyLong_FromUnsignedLong(v);
		if (!o || PyDict_SetItemString(d, info_fields[i].name, o) < 0)
			Py_CLEAR(d);
		Py_XDECREF(o);
	}
	return d;
}

/* A 32-bit unsigned from o; -1 with a Python error naming what. */
static int u32_of(PyObject *o, const char *what, uint32_t *v)
{
	unsigned long l = o ? PyLong_AsUnsignedLong(o) : 0;

	if (!o)
		PyErr_Format(PyExc_KeyError, "gather info: no %s", what);
	else if (!PyErr_Occurred() && l > UINT32_MAX)
		PyErr_Format(PyExc_OverflowError, "%s: %lu is above 2^32 - 1",
			     what, l);
	if (PyErr_Occurred())
		return -1;
	*v = (uint32_t)l;
	return 0;
}

/* The dict info_dict() made (or its copy) back into *gi. */
static int info_of(PyObject *d, struct sh2000_gather_info *gi)
{
	PyObject *sig, *sample_s;

	memset(gi, 0, sizeof(*gi));
	if (!PyDict_Check(d)) {
		PyErr_SetString(PyExc_TypeError, "gather info must be a dict");
		return -1;
	}
	for (size_t i = 0; i < N_INFO_FIELDS; i++) {
		uint32_t v;

		if (u32_of(PyDict_GetItemString(d, info_fields[i].name),
			   info_fields[i].name, &v) < 0)
			return -1;
		memcpy((char *)gi + info_fields[i].off, &v, sizeof(v));
	}
	sig = PyDict_GetItemString(d, "signals");
	sample_s = PyDict_GetItemString(d, "sample_s");
	if (!sig || !sample_s ||
	    !PyArg_ParseTuple(sig, "IIII", &gi->signals[0], &gi->signals[1],
			      &gi->signals[2], &gi->signals[3])) {
		if (!PyErr_Occurred())
			PyErr_SetString(PyExc_KeyError,
					"gather info: no signals or sample_s");
		return -1;
	}
	gi->sample_s = PyFloat_AsDouble(sample_s);
	return PyErr_Occurred() ? -1 : 0;
}

/* O& converter: a Python int that fits 32 bits unsigned. */
static int u32_arg(PyObject *o, void *out)
{
	return u32_of(o, "gather: a count", out) < 0 ? 0 : 1;
}

/* gather_start((x, y, z, a signal masks), period, samples, trigger,
 * pretrigger): the record's number. */
PyObject *sh2k_card_gather_start(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_gather_config gc;
	uint32_t sig[SH2000_AXES], period, trigger;
	int r;

	if (!h || !PyArg_ParseTuple(args, "(O&O&O&O&)O&O&O&O&",
				    u32_arg, &sig[0], u32_arg, &sig[1],
				    u32_arg, &sig[2], u32_arg, &sig[3],
				    u32_arg, &period, u32_arg, &gc.samples,
				    u32_arg, &trigger, u32_arg, &gc.pretrigger))
		return NULL;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		gc.signals[a] = sig[a];
	gc.period = period;
	gc.trigger = trigger;
	SH2K_CALL(c, r = sh2000_gather_start(h, &gc));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	return PyLong_FromLong(r);
}

PyObject *sh2k_card_gather_stop(PyCard *c, PyObject *unused)
{
	struct sh2000 *h = sh2k_handle(c);
	int r;

	(void)unused;
	if (!h)
		return NULL;
	SH2K_CALL(c, r = sh2000_gather_stop(h));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	Py_RETURN_NONE;
}

PyObject *sh2k_card_gather_info(PyCard *c, PyObject *unused)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_gather_info gi;
	int r;

	(void)unused;
	if (!h)
		return NULL;
	SH2K_CALL(c, r = sh2000_gather_info(h, &gi));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	return info_dict(&gi);
}

/* gather_wait(record, timeout_ms): the info of the finished record. */
PyObject *sh2k_card_gather_wait(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_gather_info gi;
	uint32_t rec;
	int ms, r;

	if (!h || !PyArg_ParseTuple(args, "O&i", u32_arg, &rec, &ms))
		return NULL;
	SH2K_CALL(c, r = sh2000_gather_wait(h, rec, &gi, ms));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	return info_dict(&gi);
}

/* gather_read(info, first, n): samples [first, first + n) as a bytearray
 * of n * info["values"] doubles, sample after sample. */
PyObject *sh2k_card_gather_read(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_gather_info gi;
	PyObject *d, *out;
	uint32_t first, n, room;
	int r;

	if (!h || !PyArg_ParseTuple(args, "OO&O&", &d, u32_arg, &first,
				    u32_arg, &n) || info_of(d, &gi) < 0)
		return NULL;
	/* room only for samples the record has: beyond it the library
	 * refuses (-EINVAL, naming them) before it writes any */
	room = (uint64_t)first + n > gi.samples ? 0 : n;
	out = PyByteArray_FromStringAndSize(NULL, (Py_ssize_t)room * gi.values *
					    (Py_ssize_t)sizeof(double));
	if (!out)
		return NULL;
	/* the new bytearray is ours alone until returned */
	SH2K_CALL(c, r = sh2000_gather_read(h, &gi, first, n,
					    (double *)(void *)PyByteArray_AS_STRING(out)));
	if (r < 0) {
		Py_DECREF(out);
		return sh2k_raise(r, h, NULL, NULL);
	}
	return out;
}

/* gather_column(info, k): (axis, signal id) of value k of a sample. */
static PyObject *py_gather_column(PyObject *self, PyObject *args)
{
	struct sh2000_gather_info gi;
	unsigned int axis, sig, k;
	PyObject *d;
	int r;

	(void)self;
	if (!PyArg_ParseTuple(args, "OI", &d, &k) || info_of(d, &gi) < 0)
		return NULL;
	r = sh2000_gather_column(&gi, k, &axis, &sig);
	if (r < 0)
		return sh2k_raise(r, NULL, NULL, NULL);
	return Py_BuildValue("(II)", axis, sig);
}

/* gather_config_default(): sh2000_gather_config_default as a dict. */
static PyObject *py_gather_config_default(PyObject *self, PyObject *unused)
{
	struct sh2000_gather_config gc;

	(void)self;
	(void)unused;
	sh2000_gather_config_default(&gc);
	return Py_BuildValue("{s:(IIII),s:I,s:I,s:I,s:I}", "signals",
			     gc.signals[0], gc.signals[1], gc.signals[2],
			     gc.signals[3], "period", gc.period, "samples",
			     (unsigned int)gc.samples, "trigger", gc.trigger,
			     "pretrigger", (unsigned int)gc.pretrigger);
}

/* gather_signals(): (id, name, unit) of every signal, from the library. */
static PyObject *py_gather_signals(PyObject *self, PyObject *unused)
{
	const struct sh2000_gather_signal_info *si;
	PyObject *l = PyList_New(0);

	(void)self;
	(void)unused;
	for (unsigned int id = 0; l && (si = sh2000_gather_signal_lookup(id)); id++) {
		PyObject *t = Py_BuildValue("(Iss)", si->id, si->name, si->unit);

		if (!t || PyList_Append(l, t) < 0)
			Py_CLEAR(l);
		Py_XDECREF(t);
	}
	return l;
}

/* gather_signal_id(name): the id, or sh2000.Error EPARAM naming it. */
static PyObject *py_gather_signal_id(PyObject *self, PyObject *arg)
{
	const struct sh2000_gather_signal_info *si;
	const char *name = PyUnicode_AsUTF8(arg);
	char msg[320];
	size_t len;

	(void)self;
	if (!name)
		return NULL;
	si = sh2000_gather_signal_by_name(name);
	if (si)
		return PyLong_FromLong(si->id);
	len = (size_t)snprintf(msg, sizeof(msg),
			       "gather: '%.100s' is not a signal (", name);
	for (unsigned int id = 0; len < sizeof(msg) &&
	     (si = sh2000_gather_signal_lookup(id)); id++)
		len += (size_t)snprintf(msg + len, sizeof(msg) - len, "%s%s",
					id ? " " : "", si->name);
	if (len < sizeof(msg))
		snprintf(msg + len, sizeof(msg) - len, ")");
	return sh2k_raise(-SH2000_EPARAM, NULL, msg, NULL);
}

static PyMethodDef gather_methods[] = {
	{ "gather_config_default", py_gather_config_default, METH_NOARGS,
	  "gather_config_default(): sh2000_gather_config_default as a dict" },
	{ "gather_signals", py_gather_signals, METH_NOARGS,
	  "gather_signals(): (id, name, unit) of every gather signal" },
	{ "gather_signal_id", py_gather_signal_id, METH_O,
	  "gather_signal_id(name): the signal's id; sh2000.Error if unknown" },
	{ "gather_column", py_gather_column, METH_VARARGS,
	  "gather_column(info, k): (axis, signal id) of value k of a sample" },
	{ NULL, NULL, 0, NULL },
};

int sh2k_add_gather(PyObject *m)
{
	return PyModule_AddFunctions(m, gather_methods);
}
