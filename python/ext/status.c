// SPDX-License-Identifier: MIT
/*
 * The status poll as Python data, and the library's tables the package
 * needs: error codes, card states, axis bits, parameter names and units.
 * Names come from the library (sh2000_state_name, sh2000_fault_name...),
 * never from copies here.
 */
#include <sh2000/program.h>

#include "binding.h"

/* The names of the bits set in mask, as name(bit) gives them. */
static PyObject *bit_names(unsigned int mask, const char *(*name)(unsigned int))
{
	PyObject *l = PyList_New(0);

	for (unsigned int b = 1; l && b && b <= mask; b <<= 1) {
		PyObject *s;

		if (!(mask & b))
			continue;
		s = PyUnicode_FromString(name(b));
		if (!s || PyList_Append(l, s) < 0) {
			Py_XDECREF(s);
			Py_CLEAR(l);
			break;
		}
		Py_DECREF(s);
	}
	return l;
}

static PyObject *axis_dict(const struct sh2000_axis_status *a)
{
	return Py_BuildValue("{s:L,s:i,s:i,s:d,s:d,s:d,s:i,s:I,s:I,s:N}",
			     "pos_counts", (long long)a->pos_counts,
			     "cmd_counts", (int)a->cmd_counts,
			     "ferr_counts", (int)a->ferr_counts,
			     "pos_mm", a->pos_mm, "cmd_mm", a->cmd_mm,
			     "ferr_mm", a->ferr_mm, "dac", (int)a->dac,
			     "state", a->state, "faults", a->faults,
			     "fault_names", bit_names(a->faults,
						      sh2000_axis_fault_name));
}

/* The error the latched faults stand for (None if none). */
static PyObject *status_fault(struct sh2000 *h, const struct sh2000_status *st)
{
	int e = sh2000_status_error(h, st);

	if (e >= 0)
		Py_RETURN_NONE;
	return sh2k_error(e, h, NULL, NULL);
}

/* None, or {"axis": 0..3 or None, "bit", "name", "cycle"} (protocol 1.4) */
static PyObject *first_fault_dict(const struct sh2000_first_fault *ff)
{
	int axis = ff->axis < SH2000_AXES;

	if (!ff->bit)
		Py_RETURN_NONE;
	return Py_BuildValue("{s:N,s:I,s:s,s:K}",
			     "axis", axis ? PyLong_FromUnsignedLong(ff->axis) :
					    Py_NewRef(Py_None),
			     "bit", ff->bit,
			     "name", axis ? sh2000_axis_fault_name(ff->bit) :
					    sh2000_fault_name(ff->bit),
			     "cycle", (unsigned long long)ff->cycle);
}

PyObject *sh2k_status_dict(struct sh2000 *h, const struct sh2000_status *st)
{
	PyObject *axes = PyList_New(SH2000_AXES), *d;

	for (unsigned int a = 0; axes && a < SH2000_AXES; a++) {
		PyObject *x = axis_dict(&st->axis[a]);

		if (!x) {
			Py_CLEAR(axes);
			break;
		}
		PyList_SET_ITEM(axes, a, x);
	}
	if (!axes)
		return NULL;
	d = Py_BuildValue("{s:I,s:s,s:I,s:N,s:I,s:I,s:I,s:K,s:K,s:I,s:K,s:I,s:N,s:N}",
			  "card_state", st->card_state,
			  "card_state_name", sh2000_state_name(st->card_state),
			  "card_faults", st->card_faults,
			  "card_fault_names", bit_names(st->card_faults,
							sh2000_fault_name),
			  "queue_fill", st->queue_fill,
			  "queue_free", st->queue_free,
			  "heartbeat", (unsigned int)st->heartbeat,
			  "heartbeat_age_ns",
			  (unsigned long long)st->heartbeat_age_ns,
			  "card_cycle", (unsigned long long)st->card_cycle,
			  "reject_count", (unsigned int)st->reject_count,
			  "host_time_ns", (unsigned long long)st->host_time_ns,
			  "retries", st->retries, "axes", axes,
			  "first_fault", first_fault_dict(&st->first_fault));
	if (d) {
		PyObject *b = PyBool_FromLong(sh2000_status_faulted(st));

		if (PyDict_SetItemString(d, "faulted", b) < 0)
			Py_CLEAR(d);
		Py_DECREF(b);
	}
	if (d) {
		PyObject *b = PyBool_FromLong(sh2000_state_moving(st->card_state));

		if (PyDict_SetItemString(d, "moving", b) < 0)
			Py_CLEAR(d);
		Py_DECREF(b);
	}
	if (d && h) {
		PyObject *f = status_fault(h, st);

		if (!f || PyDict_SetItemString(d, "fault", f) < 0)
			Py_CLEAR(d);
		Py_XDECREF(f);
	}
	return d;
}

/* param_table(): (id, name, unit, is_global) for every parameter. */
static PyObject *py_param_table(PyObject *self, PyObject *unused)
{
	PyObject *l = PyList_New(0);

	(void)self;
	(void)unused;
	for (unsigned int id = 0; l && id < SH2000_GP_END; id++) {
		PyObject *t;

		if (!sh2000_param_lookup(id))
			continue;
		t = Py_BuildValue("(Issi)", id, sh2000_param_name(id),
				  sh2000_param_unit(id),
				  id >= SH2000_GP_FIRST);
		if (!t || PyList_Append(l, t) < 0)
			Py_CLEAR(l);
		Py_XDECREF(t);
	}
	return l;
}

/* param_id(name): the id, or sh2000.Error EPARAM naming the name. */
static PyObject *py_param_id(PyObject *self, PyObject *arg)
{
	const char *name = PyUnicode_AsUTF8(arg);
	char msg[160];
	int id;

	(void)self;
	if (!name)
		return NULL;
	id = sh2000_param_id(name);
	if (id >= 0)
		return PyLong_FromLong(id);
	snprintf(msg, sizeof(msg), "unknown parameter '%.100s'", name);
	return sh2k_raise(id, NULL, msg, NULL);
}

static PyMethodDef table_methods[] = {
	{ "param_table", py_param_table, METH_NOARGS,
	  "param_table(): (id, name, unit, is_global) of every parameter" },
	{ "param_id", py_param_id, METH_O,
	  "param_id(name): the parameter's id; sh2000.Error if unknown" },
	{ NULL, NULL, 0, NULL },
};

#define C(name) { #name, SH2000_##name }
static const struct { const char *name; long v; } constants[] = {
	/* errors: sh2000.Error.code */
	C(EVERSION), C(EMAGIC), C(EHEARTBEAT), C(ETIMEOUT), C(EQUEUE_FULL),
	C(EPARAM), C(ETORN), C(ENOTSIM), C(ESTOPPED), C(EOWNED),
	C(ECMD_OP), C(ECMD_AXIS), C(ECMD_PARAM), C(ECMD_VALUE),
	C(ECMD_BUSY), C(ECMD_FAULTED), C(ECMD_CHECKSUM), C(ECMD_DISABLED),
	C(ECMD_UNKNOWN), C(EESTOP), C(EUNDERRUN), C(EHOST_TIMEOUT),
	C(EREJECTED), C(EPROTOCOL), C(EFAULTED), C(EFERR), C(ESOFT_LIMIT),
	C(EHARD_LIMIT), C(EDAC_SAT), C(ECOUNTER), C(EHOME), C(EPROGRAM),
	C(EFORMAT), C(ELIMIT), C(EMOVED), C(EGANTRY),
	/* card states: Status.card_state */
	C(STATE_BOOT), C(STATE_IDLE), C(STATE_RUNNING), C(STATE_STOPPING),
	C(STATE_HOMING), C(STATE_FAULT), C(STATE_ESTOP),
	/* axis state bits: AxisStatus.state */
	C(AXIS_ENABLED), C(AXIS_HOMED), C(AXIS_HOMING), C(AXIS_MOVING),
	C(AXIS_LIMIT_POS), C(AXIS_LIMIT_NEG), C(AXIS_HOME_SW), C(AXIS_INDEX),
	C(AXES),
	/* Card.backend */
	C(BACKEND_DEV), C(BACKEND_IO), C(BACKEND_SIM), C(BACKEND_SHM),
	C(BACKEND_PORTS),
	/* program formats */
	C(PROG_AUTO), C(PROG_GCODE), C(PROG_CANON), C(PROG_CSV),
	C(PROG_NURBS_JSON),
	/* Card.home flags */
	C(HOME_F_INDEX),
	/* data gathering: errors, triggers, record states */
	C(EGATHER_CHECK), C(EGATHER_LOST), C(GATHER_NOW), C(GATHER_ON_MOTION),
	C(GATHER_ON_FAULT), C(GATHER_OFF), C(GATHER_ARMED),
	C(GATHER_RECORDING), C(GATHER_DONE), C(GATHER_NO_TRIGGER),
	C(GATHER_BUFFER_VALUES),
};
#undef C

int sh2k_add_constants(PyObject *m)
{
	for (size_t i = 0; i < sizeof(constants) / sizeof(constants[0]); i++)
		if (PyModule_AddIntConstant(m, constants[i].name,
					    constants[i].v) < 0)
			return -1;
	return PyModule_AddFunctions(m, table_methods);
}
