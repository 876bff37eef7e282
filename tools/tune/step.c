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
 * started by the planner (testmove.c).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tune.h"

#define LEAD_PERIODS	4	/* at the start before the step */
#define BACK_PERIODS	8	/* at the start after the step back */
#define NSIG		3	/* setpoint, encoder, dac */

struct step_ctx {
	struct tune_move m;
	int32_t d;		/* the step, counts */
	unsigned int hold;	/* coarse periods at the step */
};

/* The step within the velocity bound. */
static int check_step(struct step_ctx *s)
{
	struct tune_move *m = &s->m;
	double v;

	s->d = (int32_t)lround(m->o->step_mm * m->pc.counts_per_mm[m->a]);
	v = fabs((double)s->d) / m->pc.counts_per_mm[m->a] / m->pc.period_s;
	if (s->d == 0 || v > m->vlim) {
		sh2000_tool_msg("%s: a step of %g mm in one coarse period (%g ms) is %.1f mm/s: it must be above 0 and within %.1f mm/s (at most %g mm): nothing moved",
				sh2000_device(m->h), m->o->step_mm, m->pc.period_s * 1e3, v,
				m->vlim, m->vlim * m->pc.period_s);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* The record as a trace: t = 0 at the step, cut where it steps back. */
static int to_trace(struct step_ctx *s, unsigned int rec,
		    struct tune_trace *tr)
{
	struct sh2000_gather_info gi;
	int32_t start = s->m.start;
	size_t i, i0 = 0, n;
	double *v;
	int r;

	if ((r = tune_move_read(&s->m, rec, &gi, &v)))
		return r;
	while (i0 < gi.samples && v[NSIG * i0] == start)
		i0++;
	for (n = i0; n < gi.samples && !(v[NSIG * n] == start + s->d); n++)
		;
	while (n < gi.samples && v[NSIG * n] == start + s->d)
		n++;
	tr->n = n;
	tr->t = malloc(4 * n * sizeof(double));
	if (i0 == gi.samples || !tr->t) {
		free(v);
		sh2000_tool_msg("%s: the record holds no step", sh2000_device(s->m.h));
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
	tr->start = start;
	tr->end = start + s->d;
	free(v);
	return 0;
}

/* The step and the way back; an error ends the test. */
static int move(struct tune_move *m)
{
	struct step_ctx *s = (struct step_ctx *)m;
	int r = tune_move_hold(m, m->start, LEAD_PERIODS, 0);

	if (r >= 0)
		r = tune_move_hold(m, m->start + s->d, s->hold, 0);
	if (r >= 0)
		r = tune_move_hold(m, m->start, BACK_PERIODS, SH2000_PUSH_END);
	if (r >= 0)
		r = sh2000_wait_idle(m->h, 10000);
	return r;
}

int tune_step(struct sh2000 *h, const struct tune_opts *o,
	      struct tune_trace *tr)
{
	struct step_ctx s = { .m = { .h = h, .o = o, .a = o->axis, .name = "step" } };
	unsigned int rec = 0;
	int r;

	memset(tr, 0, sizeof(*tr));
	if ((r = tune_move_prepare(&s.m)) || (r = check_step(&s)))
		goto out;
	tr->start = s.m.start;
	if ((r = tune_move_lower_limits(&s.m)))
		goto out;
	s.hold = (unsigned int)ceil(o->hold_s / s.m.pc.period_s);
	r = tune_move_run(&s.m, 1u << SH2000_GS_SETPOINT | 1u << SH2000_GS_ENCODER |
			  1u << SH2000_GS_DAC,
			  (LEAD_PERIODS + s.hold) * s.m.pc.period_s, &rec, move);
	if (!r)
		r = to_trace(&s, rec, tr);
out:
	tune_move_end(&s.m);
	return r;
}

void tune_trace_free(struct tune_trace *tr)
{
	free(tr->t);
	memset(tr, 0, sizeof(*tr));
}
