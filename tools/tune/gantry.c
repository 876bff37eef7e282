/* SPDX-License-Identifier: MIT */
/*
 * The gantry test (--gantry): the card's gantry pair (protocol 1.7,
 * docs/protocol.md "Gantry pairs") ramps as LinuxCNC's two joints of one
 * axis do, both sides taking the same moves (each from its own
 * set-point), gathered on the card every servo cycle; twice, with the
 * card's coupling gains and with none (gantry_kp, _ti and _td at 0 for the
 * run, put back after whatever happened). It reports each run's peak
 * skew, the difference of the two sides' following errors that the
 * card's coupling loop drives to zero and its skew limit checks, and how
 * much the coupling cuts it. The pair ends where it started.
 */
#include <math.h>
#include <stdio.h>

#include "tune.h"

/* The ramp's speed without --ramp, mm/s (within the velocity bound). */
#define GANTRY_SPEED	100.0
/* The end of the ramp's record whose skew says whether the pair settled
 * (the record holds 50 ms at rest after the ramp, ramp.c), s. */
#define GANTRY_TAIL_S	0.025

const unsigned int tune_gantry_gain_ids[3] = {
	SH2000_GP_GANTRY_KP, SH2000_GP_GANTRY_TI, SH2000_GP_GANTRY_TD,
};

/* The card's pair, of which the tested axis must be a side: an exit code
 * (a card before 1.7 refuses the parameters: the library says so). */
static int read_pair(struct sh2000 *h, const struct tune_opts *o,
		     struct tune_gantry *p)
{
	char an = sh2000_tool_axis_name(o->axis);
	unsigned int m;
	double mask;
	int r = sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_GANTRY_PAIR, &mask);

	for (unsigned int i = 0; r >= 0 && i < 3; i++)
		r = sh2000_param_get(h, SH2000_GLOBAL, tune_gantry_gain_ids[i], &p->gains[i]);
	if (r >= 0)
		r = sh2000_param_get(h, SH2000_GLOBAL,
				     SH2000_GP_GANTRY_SKEW_LIMIT, &p->limit);
	if (r < 0)
		return sh2000_tool_fail(h, r, "gantry pair");
	m = (unsigned int)mask;
	if (__builtin_popcount(m) != 2) {
		sh2000_tool_msg("%s: the card has no gantry pair (gantry_pair 0; sh2000ctl params load FILE sets one): nothing moved",
				sh2000_device(h));
		return SH2000_EXIT_CARD;
	}
	p->a = (unsigned int)__builtin_ctz(m);
	p->b = (unsigned int)(31 - __builtin_clz(m));
	if (o->axis != p->a && o->axis != p->b) {
		sh2000_tool_msg("%s: axis %c is not a side of the card's gantry pair %c+%c: nothing moved",
				sh2000_device(h), an, sh2000_tool_axis_name(p->a),
				sh2000_tool_axis_name(p->b));
		return SH2000_EXIT_CARD;
	}
	return 0;
}

int tune_gantry_set_gains(struct sh2000 *h, const double g[3])
{
	int r = 0;

	for (unsigned int i = 0; r >= 0 && i < 3; i++)
		r = sh2000_param_set(h, SH2000_GLOBAL, tune_gantry_gain_ids[i], g[i]);
	return r;
}

int tune_gantry_undo(struct tune_move *s)
{
	int r = tune_gantry_set_gains(s->h, s->o->gantry_safe);

	return r < 0 ? tune_move_fail(s, r, "restoring the coupling's gains") : 0;
}

int tune_gantry_calm(struct tune_move *s)
{
	static const double none[3] = { 0, 0, 0 };
	int r = tune_gantry_set_gains(s->h, none);

	return r < 0 ? tune_move_fail(s, r, "uncoupling the pair") : 0;
}

/* The largest |skew| over the record's last GANTRY_TAIL_S: how far the
 * pair is from settled when the ramp's record ends. */
static double tail_peak(const struct tune_ramp *rp)
{
	double end = rp->n ? rp->t[rp->n - 1] : 0, m = 0;

	for (size_t i = 0; i < rp->n; i++)
		if (rp->t[i] >= end - GANTRY_TAIL_S && fabs(rp->skew[i]) > m)
			m = fabs(rp->skew[i]);
	return m;
}

int tune_gantry_ramp(struct sh2000 *h, const struct tune_opts *o,
		     struct tune_gantry *p, const double g[3], double *peak,
		     double *tail)
{
	struct tune_ramp rp;
	int r = tune_gantry_set_gains(h, g), put;

	if (r < 0)
		return sh2000_tool_fail(h, r, "set parameter");
	r = tune_ramp(h, o, &rp);
	if (!r) {
		*peak = rp.skew_peak;
		if (tail)
			*tail = tail_peak(&rp);
		p->travel_mm = rp.travel_mm;
		p->accel_mms2 = rp.accel_mms2;
		p->counts_per_mm = rp.counts_per_mm;
	}
	tune_ramp_free(&rp);
	put = tune_gantry_set_gains(h, p->gains);
	if (put < 0 && !r)
		r = sh2000_tool_fail(h, put, "restoring the coupling's gains");
	return r;
}

/* --enable: the sides enabled once for both runs (a side disabled
 * between them would sag, its set-point following it); without it the
 * first run's preparation says which side is not enabled. Then the
 * sides' set-points: an exit code. */
static int enable_pair(struct sh2000 *h, const struct tune_opts *o,
		       struct tune_gantry *p)
{
	struct sh2000_status st;
	unsigned int off = 0;
	int r = sh2000_poll(h, &st);

	for (unsigned int i = 0; r >= 0 && i < 2; i++) {
		unsigned int s = i ? p->b : p->a;

		if (!(st.axis[s].state & SH2000_AXIS_ENABLED))
			off |= 1u << s;
	}
	if (r >= 0 && off && o->enable && st.card_state == SH2000_STATE_IDLE) {
		r = sh2000_enable(h, off);
		if (r >= 0)
			p->enabled_by_us = off;
		if (r >= 0)
			r = sh2000_poll(h, &st);
	}
	if (r < 0)
		return sh2000_tool_fail(h, r, "enable");
	p->start[0] = (double)st.axis[p->a].cmd_counts;
	p->start[1] = (double)st.axis[p->b].cmd_counts;
	return 0;
}

void tune_gantry_end(struct sh2000 *h, struct tune_gantry *p)
{
	if (p->enabled_by_us)
		sh2000_disable(h, p->enabled_by_us);
	p->enabled_by_us = 0;
}

static int gantry_begin(struct sh2000 *h, const struct tune_opts *o,
			     struct tune_gantry *p, struct tune_opts *g)
{
	int r;

	p->coupled = p->uncoupled = NAN;
	p->start[0] = p->start[1] = NAN;
	p->enabled_by_us = 0;
	if ((r = read_pair(h, o, p)) || (r = enable_pair(h, o, p)))
		return r;
	*g = *o;
	g->axis = p->a;
	g->follow = 1u << p->b;
	g->enable = 0;	/* enable_pair's */
	p->speed_mms = g->ramp_mms = o->ramp_mms ? o->ramp_mms : GANTRY_SPEED;
	return 0;
}

int tune_gantry_measure(struct sh2000 *h, const struct tune_opts *o,
			struct tune_gantry *p, struct tune_opts *g)
{
	static const double none[3] = { 0, 0, 0 };
	int r = gantry_begin(h, o, p, g);

	if (!r && p->gains[0] > 0)
		r = tune_gantry_ramp(h, g, p, p->gains, &p->coupled, NULL);
	if (!r)
		r = tune_gantry_ramp(h, g, p, none, &p->uncoupled, NULL);
	return r;
}

int tune_gantry(struct sh2000 *h, const struct tune_opts *o,
		struct tune_gantry *p)
{
	struct tune_opts g;

	return tune_gantry_measure(h, o, p, &g);
}

void tune_gantry_report(const struct tune_gantry *p)
{
	double um = 1e3 / p->counts_per_mm;

	printf("gantry %c+%c: ramp %g mm/s over %g mm and back (accelerating at %g mm/s^2), both sides\n",
	       sh2000_tool_axis_name(p->a), sh2000_tool_axis_name(p->b), p->speed_mms,
	       p->travel_mm, p->accel_mms2);
	printf("skew limit              %.0f counts  %.4f um\n", p->limit, p->limit * um);
	if (isnan(p->coupled))
		printf("peak skew, coupled      not measured: the card's gantry_kp is 0\n");
	else
		printf("peak skew, coupled      %.1f counts  %.4f um  (kp %g ti %g td %g)\n",
		       p->coupled, p->coupled * um, p->gains[0], p->gains[1], p->gains[2]);
	printf("peak skew, uncoupled    %.1f counts  %.4f um\n", p->uncoupled,
	       p->uncoupled * um);
	if (p->coupled >= 1)
		printf("coupling cuts the peak  %.1fx\n", p->uncoupled / p->coupled);
	else if (!isnan(p->coupled))
		printf("coupling cuts the peak  more than %.0fx (coupled below a count)\n",
		       p->uncoupled);
}

int tune_run_gantry(struct sh2000 *h, const struct tune_opts *o)
{
	struct tune_gantry p;
	int r = tune_gantry(h, o, &p);

	if (!r)
		tune_gantry_report(&p);
	/* also after an abort: both sides back where they were */
	if ((!r || r == SH2000_EXIT_ABORTED) &&
	    (tune_check_back(h, p.a, p.start[0]) ||
	     tune_check_back(h, p.b, p.start[1])))
		r = SH2000_EXIT_CARD;
	tune_gantry_end(h, &p);
	return r;
}
