// SPDX-License-Identifier: MIT
/*
 * Program.run: the second pass (sh2000_run_program) with Python callbacks.
 * The library runs with the GIL released; each callback takes it back
 * (PyGILState_Ensure). The first exception a callback raises (or a signal,
 * e.g. Ctrl-C) stops the run on the path (sh2000_run_stop) and is raised
 * again once the card is at rest; no Python runs after it.
 */
#include <errno.h>
#include <string.h>

#include "binding.h"
#include "program.h"

struct runctx {
	PyObject *progress, *pause;	/* callables, or None */
	struct sh2000 *h;
	struct sh2000_run *run;
	PyObject *exc[3];		/* type, value, traceback */
	int64_t line;			/* the block the card ran last */
};

/* Keep the pending exception for later and stop the run. */
static void failed(struct runctx *rc)
{
	PyErr_Fetch(&rc->exc[0], &rc->exc[1], &rc->exc[2]);
	sh2000_run_stop(rc->run);
}

static PyObject *progress_dict(struct runctx *rc,
			       const struct sh2000_run_progress *p)
{
	PyObject *st = sh2k_status_dict(rc->h, p->status);

	if (!st)
		return NULL;
	return Py_BuildValue("{s:K,s:d,s:I,s:L,s:N}",
			     "points", (unsigned long long)p->points, "t", p->t,
			     "queue_fill", p->queue_fill,
			     "line", (long long)p->seq, "status", st);
}

static void on_progress(void *ctx, const struct sh2000_run_progress *p)
{
	struct runctx *rc = ctx;
	PyGILState_STATE g;

	if (p->seq >= 0)
		rc->line = p->seq;
	if (rc->exc[0])
		return;
	g = PyGILState_Ensure();
	if (PyErr_CheckSignals() == 0 && rc->progress != Py_None) {
		PyObject *d = progress_dict(rc, p), *r = NULL;

		if (d)
			r = PyObject_CallOneArg(rc->progress, d);
		Py_XDECREF(d);
		Py_XDECREF(r);
	}
	if (PyErr_Occurred())
		failed(rc);
	PyGILState_Release(g);
}

/* M0 (M1 with optional_stop): the card is at rest; pause(where, optional)
 * returns to go on. */
static int on_pause(void *ctx, const struct sh2000_prog_block *b)
{
	struct runctx *rc = ctx;
	PyGILState_STATE g;
	char where[300];
	int e = 0;

	if (rc->exc[0])
		return -ECANCELED;
	sh2000_prog_block_where(b, where, sizeof(where));
	g = PyGILState_Ensure();
	if (rc->pause != Py_None) {
		PyObject *r = PyObject_CallFunction(rc->pause, "sO", where,
						    b->u.optional ? Py_True :
						    Py_False);
		Py_XDECREF(r);
	}
	if (PyErr_Occurred()) {
		failed(rc);
		e = -ECANCELED;
	}
	PyGILState_Release(g);
	return e;
}

static PyObject *stats_dict(const struct sh2000_run_stats *s)
{
	return Py_BuildValue("{s:K,s:K,s:K,s:K,s:d,s:d,s:d,s:I,s:I,s:K}",
			     "points", (unsigned long long)s->points,
			     "batches", (unsigned long long)s->batches,
			     "motions", (unsigned long long)s->motions,
			     "polls", (unsigned long long)s->polls,
			     "time_s", s->time_s, "distance_mm", s->distance_mm,
			     "max_ferr_mm", s->max_ferr_mm,
			     "max_ferr_axis", s->max_ferr_axis,
			     "min_fill", s->min_fill,
			     "underruns", (unsigned long long)s->underruns);
}

/* After the run: its stats, or the callback's exception, or sh2000.Error
 * with the run's words and where the card was ("file:line"). */
static PyObject *outcome(PyProgram *p, struct runctx *rc, int e)
{
	struct sh2000_run_stats s;
	char where[320];

	if (rc->exc[0]) {
		PyErr_Restore(rc->exc[0], rc->exc[1], rc->exc[2]);
		return NULL;
	}
	if (e == -SH2000_EPROGRAM)
		return sh2k_program_raise(p, e, NULL, NULL);
	if (e < 0) {
		snprintf(where, sizeof(where), "%s:%lld", p->path,
			 (long long)rc->line);
		return sh2k_raise(e, NULL, sh2000_run_error(rc->run),
				  rc->line > 0 ? where : NULL);
	}
	sh2000_run_stats(rc->run, &s);
	return stats_dict(&s);
}

static int callable_or_none(PyObject *f, const char *what)
{
	if (f == Py_None || PyCallable_Check(f))
		return 1;
	PyErr_Format(PyExc_TypeError, "%s must be callable or None", what);
	return 0;
}

/* run(progress, pause[, override, optional_stop]) after check(): the run's
 * stats as a dict. */
PyObject *sh2k_program_run(PyProgram *p, PyObject *args)
{
	struct runctx rc = { .line = -1 };
	struct sh2000_program_opts o;
	struct sh2000_run_config cfg;
	int stop = 0, e;
	double ovr = 1;
	char msg[512];
	PyObject *res;

	if (!PyArg_ParseTuple(args, "OO|dp", &rc.progress, &rc.pause, &ovr,
			      &stop) || !sh2k_program_ok(p) ||
	    !callable_or_none(rc.progress, "progress") ||
	    !callable_or_none(rc.pause, "pause"))
		return NULL;
	if (!p->checked) {
		PyErr_SetString(PyExc_RuntimeError, "check() the program first");
		return NULL;
	}
	rc.h = p->card->h;
	/* the plan starts where the card stood at check(): a card moved
	 * since is refused, naming the axis, before anything moves */
	SH2K_CALL(p->card, e = sh2000_run_check_start(rc.h, &p->pc, msg,
						      sizeof(msg)));
	if (e < 0)
		return sh2k_raise(e, NULL, msg, NULL);
	sh2000_run_config_default(&cfg);
	cfg.progress = on_progress;
	cfg.ctx = &rc;
	SH2K_CALL(p->card, e = sh2000_run_create(&rc.run, rc.h, &p->pc, &cfg,
						 msg, sizeof(msg)));
	if (e < 0)
		return sh2k_raise(e, NULL, msg, NULL);
	e = sh2000_run_set_override(rc.run, ovr);
	if (!e)
		e = sh2000_prog_reader_rewind(p->reader);
	if (!e) {
		sh2000_program_opts_default(&o);
		o.optional_stop = stop;
		p->running = 1;
		SH2K_CALL(p->card, e = sh2000_run_program(rc.run, p->reader, &o,
							  on_pause, &rc));
		p->running = 0;
	}
	res = outcome(p, &rc, e);
	sh2000_run_destroy(rc.run);
	return res;
}
