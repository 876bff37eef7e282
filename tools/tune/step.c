/* SPDX-License-Identifier: MIT */
/*
 * The step test on the card, a bounded test move (testmove.c: the card's
 * limits lowered to the user's during it, the way back after a
 * following-error fault). The step in one coarse period must stay within
 * the velocity limit (the user's and the card's), else nothing moves. The
 * set-point then steps (raw coarse points: the card's B-spline is all the
 * smoothing) and holds, gathered every servo cycle from the motion's
 * start, then steps back.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <sh2000/path.h>
#include <sh2000/run.h>

#include "testmove.h"
#include "tune.h"

#define LEAD_PERIODS	4	/* at the start before the step */
#define BACK_PERIODS	8	/* at the start after the step back */
#define PRETRIGGER	10
#define NSIG		3	/* setpoint, encoder, dac */

/* The step within the velocity bound. */
static int prepare(struct tune_move *s)
{
	const struct tune_opts *o = s->o;
	double vlim, v;
	int r;

	if ((r = tune_move_begin(s)))
		return r;
	s->d = (int32_t)lround(o->step_mm * s->pc.counts_per_mm[s->a]);
	vlim = tune_move_vmax(s);
	v = fabs((double)s->d) / s->pc.counts_per_mm[s->a] / s->pc.period_s;
	if (s->d == 0 || v > vlim) {
		sh2000_tool_msg("%s: a step of %g mm in one coarse period (%g ms) is %.1f mm/s: it must be above 0 and within %.1f mm/s (at most %g mm): nothing moved",
				sh2000_device(s->h), o->step_mm, s->pc.period_s * 1e3, v,
				vlim, vlim * s->pc.period_s);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* The gather record: set-point, encoder, DAC every few servo cycles,
 * from a little before the motion to the end of the hold. Its number in
 * *rec; an exit code. */
static int arm(struct tune_move *s, unsigned int hold, unsigned int *rec)
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
		return tune_move_fail(s, r, "gather");
	*rec = (unsigned int)r;
	return 0;
}

/* The record as a trace: t = 0 at the step, cut where it steps back. */
static int to_trace(struct tune_move *s, unsigned int rec,
		    struct tune_trace *tr)
{
	struct sh2000_gather_info gi;
	size_t i, i0 = 0, n;
	double *v;
	int r;

	if ((r = sh2000_gather_wait(s->h, rec, &gi, 10000)) < 0)
		return tune_move_fail(s, r, "gather");
	v = malloc(sizeof(*v) * NSIG * gi.samples);
	r = v ? sh2000_gather_read(s->h, &gi, 0, gi.samples, v) : -12;
	if (r < 0) {
		free(v);
		return tune_move_fail(s, r, "gather");
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

/* The step and the way back; an error ends the test. */
static int move(struct tune_move *s, unsigned int hold)
{
	int r = tune_move_hold(s, s->start, LEAD_PERIODS, 0);

	if (r >= 0)
		r = tune_move_hold(s, s->start + s->d, hold, 0);
	if (r >= 0)
		r = tune_move_hold(s, s->start, BACK_PERIODS, SH2000_PUSH_END);
	if (r >= 0)
		r = sh2000_wait_idle(s->h, 10000);
	return r;
}

int tune_step(struct sh2000 *h, const struct tune_opts *o,
	      struct tune_trace *tr)
{
	struct tune_move s = { .h = h, .o = o, .a = o->axis };
	unsigned int hold, rec = 0;
	int r;

	memset(tr, 0, sizeof(*tr));
	if ((r = prepare(&s)))
		goto out;
	tr->start = s.start;
	if ((r = tune_move_limits(&s)))
		goto out;
	hold = (unsigned int)ceil(o->hold_s / s.pc.period_s);
	r = arm(&s, hold, &rec);
	if (!r) {
		r = move(&s, hold);
		if (r == -SH2000_EFERR) {
			/* the bound the user set: back to the start */
			sh2000_gather_stop(h);
			r = tune_move_recover(&s, r, "step test");
			goto out;
		}
		if (r < 0) {
			/* anything else (an emergency stop, another fault) is
			 * the operator's or the machine's: left as it is */
			r = tune_move_fail(&s, r, "step test");
			sh2000_gather_stop(h);
			tune_move_restore(&s);
			goto out;
		}
	}
	if (!r)
		r = tune_move_restore(&s);
	else
		tune_move_restore(&s);
	if (!r)
		r = to_trace(&s, rec, tr);
out:
	tune_move_end(&s);
	return r;
}

void tune_trace_free(struct tune_trace *tr)
{
	free(tr->t);
	memset(tr, 0, sizeof(*tr));
}
