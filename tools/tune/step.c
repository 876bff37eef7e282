/* SPDX-License-Identifier: MIT */
/*
 * The step test on the card. Bounds first, nothing moved when one is
 * broken: the step in one coarse period must stay within the velocity
 * limit (the user's and the card's); during the test the card's
 * following-error limit and DAC limit are lowered to the user's, so the
 * carriage stays within the step plus that following error and the DAC
 * within its bound. The set-point then steps (raw coarse points: the
 * card's B-spline is all the smoothing) and holds, gathered every servo
 * cycle from the motion's start, then steps back. Afterwards, whatever
 * happened, the limits are put back; after a following-error fault the
 * card is reset, the axis enabled again and moved back to where it
 * started by the planner (libsh2000-motion's runner).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <sh2000/path.h>
#include <sh2000/run.h>

#include "tune.h"

#define LEAD_PERIODS	4	/* at the start before the step */
#define BACK_PERIODS	8	/* at the start after the step back */
#define PRETRIGGER	10
#define NSIG		3	/* setpoint, encoder, dac */

struct step_ctx {
	struct sh2000 *h;
	const struct tune_opts *o;
	unsigned int a;
	struct sh2000_path_config pc;
	int32_t p[SH2000_AXES];	/* every axis' set-point, counts */
	int32_t start, d;	/* counts */
	double ferr0, dac0;	/* the card's limits before the test */
	int enabled_by_us;
};

static int fail(struct step_ctx *s, int r, const char *what)
{
	return sh2000_tool_fail(s->h, r, what);
}

/* n coarse points with the axis at v, in batches the ring has room for. */
static int push_hold(struct step_ctx *s, int32_t v, unsigned int n,
		     unsigned int flags)
{
	int32_t pts[32][SH2000_AXES];
	int r = 0;

	while (n) {
		unsigned int k = n < 32 ? n : 32;

		for (unsigned int i = 0; i < k; i++) {
			memcpy(pts[i], s->p, sizeof(pts[i]));
			pts[i][s->a] = v;
		}
		r = sh2000_wait_space(s->h, k, 5000);
		if (r >= 0)
			r = sh2000_push_counts(s->h, (const int32_t (*)[SH2000_AXES])pts,
					       k, k == n ? flags : 0);
		if (r < 0)
			return r;
		n -= k;
	}
	return 0;
}

/* The card idle and unfaulted, the axis enabled, the step within bounds. */
static int prepare(struct step_ctx *s)
{
	const struct tune_opts *o = s->o;
	char an = sh2000_tool_axis_name(s->a);
	struct sh2000_status st;
	double vlim, v;
	int r;

	if ((r = sh2000_poll(s->h, &st)) < 0 || (r = sh2000_status_error(s->h, &st)) < 0)
		return fail(s, r, "cannot test");
	if (st.card_state != SH2000_STATE_IDLE) {
		sh2000_tool_msg("%s: card is %s, not idle: nothing moved",
				sh2000_device(s->h), sh2000_state_name(st.card_state));
		return SH2000_EXIT_CARD;
	}
	if (!(st.axis[s->a].state & SH2000_AXIS_ENABLED)) {
		if (!o->enable) {
			sh2000_tool_msg("%s: axis %c is not enabled (sh2000ctl enable %c, or --enable): nothing moved",
					sh2000_device(s->h), an, an);
			return SH2000_EXIT_CARD;
		}
		if ((r = sh2000_enable(s->h, 1u << s->a)) < 0)
			return fail(s, r, "enable");
		s->enabled_by_us = 1;
		if ((r = sh2000_poll(s->h, &st)) < 0)
			return fail(s, r, "status");
	}
	if ((r = sh2000_run_path_config(s->h, &s->pc)) < 0)
		return fail(s, r, "get parameter");
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		s->p[a] = (int32_t)st.axis[a].cmd_counts;
	s->start = s->p[s->a];
	s->d = (int32_t)lround(o->step_mm * s->pc.counts_per_mm[s->a]);
	vlim = s->pc.vmax[s->a];
	if (o->vmax > 0 && o->vmax < vlim)
		vlim = o->vmax;
	v = fabs((double)s->d) / s->pc.counts_per_mm[s->a] / s->pc.period_s;
	if (s->d == 0 || v > vlim) {
		sh2000_tool_msg("%s: a step of %g mm in one coarse period (%g ms) is %.1f mm/s: it must be above 0 and within %.1f mm/s (at most %g mm): nothing moved",
				sh2000_device(s->h), o->step_mm, s->pc.period_s * 1e3, v,
				vlim, vlim * s->pc.period_s);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* The user's following-error and DAC bounds on the card, all or none. */
static int lower_limits(struct step_ctx *s)
{
	double ferr, dac;
	int r;

	if ((r = sh2000_param_get(s->h, s->a, SH2000_P_FERR_LIMIT, &s->ferr0)) < 0 ||
	    (r = sh2000_param_get(s->h, s->a, SH2000_P_DAC_LIMIT, &s->dac0)) < 0)
		return fail(s, r, "get parameter");
	ferr = s->o->ferr_max_mm < s->ferr0 ? s->o->ferr_max_mm : s->ferr0;
	dac = s->o->dac_max > 0 && s->o->dac_max < s->dac0 ? s->o->dac_max : s->dac0;
	r = sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, ferr);
	if (r >= 0) {
		r = sh2000_param_set(s->h, s->a, SH2000_P_DAC_LIMIT, dac);
		if (r < 0)
			sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, s->ferr0);
	}
	return r < 0 ? fail(s, r, "set parameter") : 0;
}

/* After a fault: reset, limits back, the axis enabled and at its start. */
static int recover(struct step_ctx *s, int fault)
{
	struct sh2000_run_config rc;
	struct sh2000_run *run = NULL;
	double target[SH2000_AXES];
	char err[512] = "";
	int r;

	sh2000_tool_msg("%s: step test aborted: %s (limit %g mm during the test); returning to the start",
			sh2000_device(s->h), sh2000_strerror(fault),
			s->o->ferr_max_mm < s->ferr0 ? s->o->ferr_max_mm : s->ferr0);
	if ((r = sh2000_reset(s->h)) < 0 ||
	    (r = sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, s->ferr0)) < 0 ||
	    (r = sh2000_param_set(s->h, s->a, SH2000_P_DAC_LIMIT, s->dac0)) < 0 ||
	    (r = sh2000_enable(s->h, 1u << s->a)) < 0 ||
	    (r = sh2000_run_path_config(s->h, &s->pc)) < 0)
		return fail(s, r, "recovering");
	sh2000_run_config_default(&rc);
	r = sh2000_run_create(&run, s->h, &s->pc, &rc, err, sizeof(err));
	if (r < 0) {
		sh2000_tool_msg("%s", err);
		return sh2000_tool_exit_code(r);
	}
	memcpy(target, s->pc.start, sizeof(target));
	target[s->a] = s->start / s->pc.counts_per_mm[s->a];
	r = sh2000_path_move_abs(sh2000_run_path(run), target, 0);
	if (r >= 0)
		r = sh2000_run_finish(run);
	if (r < 0)
		sh2000_tool_msg("%s", sh2000_run_error(run));
	sh2000_run_destroy(run);
	return r < 0 ? sh2000_tool_exit_code(r) : TUNE_EXIT_ABORTED;
}

/* The gather record: set-point, encoder, DAC every few servo cycles,
 * from a little before the motion to the end of the hold. Its number in
 * *rec; an exit code. */
static int arm(struct step_ctx *s, unsigned int hold, unsigned int *rec)
{
	struct sh2000_gather_config gc;
	double servo = s->pc.period_s / s->pc.fine_steps;
	double span = (LEAD_PERIODS + hold) * s->pc.period_s;
	unsigned int max = SH2000_GATHER_BUFFER_VALUES / NSIG - PRETRIGGER;
	int r;

	sh2000_gather_config_default(&gc);
	gc.signals[s->a] = 1u << SH2000_GS_SETPOINT | 1u << SH2000_GS_ENCODER |
			   1u << SH2000_GS_DAC;
	gc.period = (unsigned int)ceil(span / servo / max);
	gc.samples = (uint32_t)ceil(span / (servo * gc.period)) + PRETRIGGER;
	gc.trigger = SH2000_GATHER_ON_MOTION;
	gc.pretrigger = PRETRIGGER;
	r = sh2000_gather_start(s->h, &gc);
	if (r < 0)
		return fail(s, r, "gather");
	*rec = (unsigned int)r;
	return 0;
}

/* The record as a trace: t = 0 at the step, cut where it steps back. */
static int to_trace(struct step_ctx *s, unsigned int rec,
		    struct tune_trace *tr)
{
	struct sh2000_gather_info gi;
	size_t i, i0 = 0, n;
	double *v;
	int r;

	if ((r = sh2000_gather_wait(s->h, rec, &gi, 10000)) < 0)
		return fail(s, r, "gather");
	v = malloc(sizeof(*v) * NSIG * gi.samples);
	r = v ? sh2000_gather_read(s->h, &gi, 0, gi.samples, v) : -12;
	if (r < 0) {
		free(v);
		return fail(s, r, "gather");
	}
	while (i0 < gi.samples && v[NSIG * i0] == s->start)
		i0++;
	for (n = i0; n < gi.samples && !(v[NSIG * n] == s->start + s->d); n++)
		;
	while (n < gi.samples && v[NSIG * n] == s->start + s->d)
		n++;
	tr->n = n;
	tr->t = malloc(4 * n * sizeof(double));
	if (i0 == gi.samples || !tr->t) {
		free(v);
		sh2000_tool_msg("%s: the record holds no step", sh2000_device(s->h));
		return SH2000_EXIT_CARD;
	}
	tr->sp = tr->t + n;
	tr->enc = tr->sp + n;
	tr->dac = tr->enc + n;
	for (i = 0; i < n; i++) {
		tr->t[i] = ((double)i - (double)i0) * gi.sample_s;
		tr->sp[i] = v[NSIG * i];
		tr->enc[i] = v[NSIG * i + 1];
		tr->dac[i] = v[NSIG * i + 2];
	}
	tr->start = s->start;
	tr->end = s->start + s->d;
	free(v);
	return 0;
}

static int restore(struct step_ctx *s)
{
	int r = sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, s->ferr0);

	if (r >= 0)
		r = sh2000_param_set(s->h, s->a, SH2000_P_DAC_LIMIT, s->dac0);
	return r < 0 ? fail(s, r, "restoring the limits") : 0;
}

/* The step and the way back; an error ends the test. */
static int move(struct step_ctx *s, unsigned int hold)
{
	int r = push_hold(s, s->start, LEAD_PERIODS, 0);

	if (r >= 0)
		r = push_hold(s, s->start + s->d, hold, 0);
	if (r >= 0)
		r = push_hold(s, s->start, BACK_PERIODS, SH2000_PUSH_END);
	if (r >= 0)
		r = sh2000_wait_idle(s->h, 10000);
	return r;
}

int tune_step(struct sh2000 *h, const struct tune_opts *o,
	      struct tune_trace *tr)
{
	struct step_ctx s = { .h = h, .o = o, .a = o->axis };
	unsigned int hold, rec = 0;
	int r;

	memset(tr, 0, sizeof(*tr));
	if ((r = prepare(&s)))
		goto out;
	tr->start = s.start;
	if ((r = lower_limits(&s)))
		goto out;
	hold = (unsigned int)ceil(o->hold_s / s.pc.period_s);
	r = arm(&s, hold, &rec);
	if (!r) {
		r = move(&s, hold);
		if (r == -SH2000_EFERR) {
			/* the bound the user set: back to the start */
			sh2000_gather_stop(h);
			r = recover(&s, r);
			goto out;
		}
		if (r < 0) {
			/* anything else (an emergency stop, another fault) is
			 * the operator's or the machine's: left as it is */
			r = fail(&s, r, "step test");
			sh2000_gather_stop(h);
			restore(&s);
			goto out;
		}
	}
	if (!r)
		r = restore(&s);
	else
		restore(&s);
	if (!r)
		r = to_trace(&s, rec, tr);
out:
	if (s.enabled_by_us)
		sh2000_disable(h, 1u << s.a);
	return r;
}

void tune_trace_free(struct tune_trace *tr)
{
	free(tr->t);
	memset(tr, 0, sizeof(*tr));
}
