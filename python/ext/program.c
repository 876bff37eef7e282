// SPDX-License-Identifier: MIT
/*
 * sh2000._sh2000.Program: an NC program on a card, the whole-program API
 * of libsh2000-motion (run.h): a reader opened at the card's position
 * (sh2000_prog_reader_open), the first pass that finds every error and
 * plans it all (check: sh2000_program_plan) and the second pass that
 * streams it (run: sh2000_run_create + sh2000_run_program), the order
 * sh2000-upload follows. Callbacks are in program_run.c.
 */
#include <errno.h>
#include <string.h>

#include "binding.h"
#include "program.h"

/* "file:line:column" of a diagnostic ("file" for line 0). */
static void diag_where(const struct sh2000_prog_diag *g, char *buf, size_t len)
{
	const char *f = g->pos.file ? g->pos.file : "?";

	if (g->pos.line)
		snprintf(buf, len, "%s:%u:%u", f, g->pos.line, g->pos.column);
	else
		snprintf(buf, len, "%s", f);
}

/* Every diagnostic so far, formatted as sh2000_prog_diag_format does. */
static PyObject *diag_list(const struct sh2000_prog_diags *d)
{
	PyObject *l = PyList_New(0);
	char buf[1024];

	for (size_t i = 0; l && i < d->count; i++) {
		PyObject *s;

		sh2000_prog_diag_format(&d->items[i], buf, sizeof(buf));
		s = PyUnicode_FromString(buf);
		if (!s || PyList_Append(l, s) < 0)
			Py_CLEAR(l);
		Py_XDECREF(s);
	}
	return l;
}

PyObject *sh2k_program_raise(PyProgram *p, int e, const char *msg,
			     const char *where)
{
	const struct sh2000_prog_diag *first = NULL;
	PyObject *x, *l;
	char at[512];

	for (size_t i = 0; i < p->diags.count && !first; i++)
		if (p->diags.items[i].severity == SH2000_PROG_ERROR)
			first = &p->diags.items[i];
	if (!msg && first) {
		diag_where(first, at, sizeof(at));
		msg = first->message;
		where = at;
	}
	x = sh2k_error(e, NULL, msg, where);
	l = x ? diag_list(&p->diags) : NULL;
	if (l && PyObject_SetAttrString(x, "diagnostics", l) == 0)
		PyErr_SetObject((PyObject *)Py_TYPE(x), x);
	Py_XDECREF(l);
	Py_XDECREF(x);
	return NULL;
}

static int program_init(PyProgram *p, PyObject *args, PyObject *kw)
{
	static char *kwlist[] = { "card", "path", "format", "feed_mm_s", NULL };
	struct sh2000_prog_options po;
	int fmt = SH2000_PROG_AUTO, r;
	double feed = 0;
	const char *path;
	PyCard *card;
	char msg[600];

	if (p->card) {
		PyErr_SetString(PyExc_ValueError, "program is already open");
		return -1;
	}
	if (!PyArg_ParseTupleAndKeywords(args, kw, "O!s|id", kwlist,
					 &PyCard_Type, &card, &path, &fmt, &feed) ||
	    !sh2k_handle(card))
		return -1;
	sh2000_prog_diags_init(&p->diags);
	Py_INCREF(card);
	p->card = card;
	p->path = PyMem_Malloc(strlen(path) + 1);
	if (!p->path) {
		PyErr_NoMemory();
		return -1;
	}
	strcpy(p->path, path);
	SH2K_CALL(card, r = sh2000_run_path_config(card->h, &p->pc));
	if (r < 0) {
		sh2k_raise(r, card->h, NULL, NULL);
		return -1;
	}
	p->margin = p->pc.margin;
	sh2000_prog_options_default(&po);
	memcpy(po.start, p->pc.start, sizeof(po.start));
	po.feed_mm_s = feed;
	r = sh2000_prog_reader_open(&p->reader, fmt, path, &po, &p->diags);
	if (r < 0) {
		snprintf(msg, sizeof(msg), "%s: %s", path,
			 r == -SH2000_EFORMAT ?
			 "cannot tell the format from the name; give format=" :
			 sh2000_strerror(r));
		sh2k_program_raise(p, r, p->diags.errors ? NULL : msg, NULL);
		return -1;
	}
	return 0;
}

static PyObject *plan_dict(const struct sh2000_program_plan *pl)
{
	return Py_BuildValue("{s:K,s:K,s:d,s:I,s:K,s:d,s:I,s:d,s:I}",
			     "blocks", (unsigned long long)pl->blocks,
			     "points", (unsigned long long)pl->points,
			     "seconds", pl->seconds, "moved", pl->moved,
			     "optional_skipped",
			     (unsigned long long)pl->optional_skipped,
			     "accel_peak", pl->accel_peak,
			     "accel_axis", pl->accel_axis,
			     "margin", pl->margin, "replans", pl->replans);
}

/* check(override, optional_stop): the first pass, from the start. */
static PyObject *program_check(PyProgram *p, PyObject *args)
{
	struct sh2000_program_opts o;
	struct sh2000_limits lim;
	struct sh2000 *h;
	int stop = 0, r;
	double ovr = 1;

	if (!PyArg_ParseTuple(args, "|dp", &ovr, &stop) || !sh2k_program_ok(p))
		return NULL;
	h = p->card->h;
	sh2000_program_opts_default(&o);
	o.override = ovr;
	o.optional_stop = stop;
	o.limits = &lim;
	p->checked = 0;
	SH2K_CALL(p->card, r = sh2000_limits_get(h, &lim));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	/* a program read with errors has them all in the diagnostics: the
	 * same error again (a rewound reader stops at its first error) */
	if (p->diags.errors)
		return sh2k_program_raise(p, -SH2000_EPROGRAM, NULL, NULL);
	/* the first pass reads a fresh reader: rewinding it would make it
	 * a replay, which stops at the first error instead of listing all;
	 * a reader read before is at its first line after the scan below */
	/* the axes it moves (a scan that leaves the reader as it was, at
	 * its first line: a fresh one still fresh), the plan, and the
	 * margin that keeps every axis within its amax, into p->pc: the
	 * second pass plans with it */
	p->read = 1;
	p->pc.margin = p->margin;
	SH2K_CALL(p->card, r = sh2000_program_check(p->reader, &p->pc, &o,
						    &p->plan));
	if (r == -SH2000_EPROGRAM)
		return sh2k_program_raise(p, r, NULL, NULL);
	if (r < 0)
		return sh2k_program_raise(p, r, p->plan.error[0] ? p->plan.error :
					  sh2000_strerror(r),
					  p->plan.where[0] ? p->plan.where : NULL);
	p->checked = 1;
	return plan_dict(&p->plan);
}

static PyObject *program_diagnostics(PyProgram *p, PyObject *unused)
{
	(void)unused;
	return diag_list(&p->diags);
}

static void program_free(PyProgram *p)
{
	sh2000_prog_reader_close(p->reader);
	p->reader = NULL;
	if (p->card)
		sh2000_prog_diags_free(&p->diags);
	Py_CLEAR(p->card);
	PyMem_Free(p->path);
	p->path = NULL;
}

static PyObject *program_close(PyProgram *p, PyObject *unused)
{
	(void)unused;
	if (p->running) {
		PyErr_SetString(PyExc_RuntimeError, "program is running");
		return NULL;
	}
	program_free(p);
	Py_RETURN_NONE;
}

static void program_dealloc(PyProgram *p)
{
	program_free(p);
	Py_TYPE(p)->tp_free((PyObject *)p);
}

int sh2k_program_ok(PyProgram *p)
{
	if (!p->reader) {
		PyErr_SetString(PyExc_ValueError, "program is closed");
		return 0;
	}
	if (p->running) {
		PyErr_SetString(PyExc_RuntimeError, "program is running");
		return 0;
	}
	return sh2k_handle(p->card) != NULL;
}

#define M SH2K_METHOD
static PyMethodDef program_methods[] = {
	M("check", program_check, METH_VARARGS,
	  "check([override, optional_stop]): sh2000_program_check, a dict"),
	M("run", sh2k_program_run, METH_VARARGS,
	  "run(progress, pause, override, optional_stop): sh2000_run_program"),
	M("diagnostics", program_diagnostics, METH_NOARGS,
	  "diagnostics(): every error and warning so far"),
	M("close", program_close, METH_NOARGS, "close()"),
	{ NULL, NULL, 0, NULL },
};
#undef M

PyTypeObject PyProgram_Type = {
	PyVarObject_HEAD_INIT(NULL, 0)
	.tp_name = "sh2000._sh2000.Program",
	.tp_doc = "Program(card, path[, format, feed_mm_s]): an NC program",
	.tp_basicsize = sizeof(PyProgram),
	.tp_flags = Py_TPFLAGS_DEFAULT,
	.tp_new = PyType_GenericNew,
	.tp_init = (initproc)program_init,
	.tp_dealloc = (destructor)program_dealloc,
	.tp_methods = program_methods,
};
