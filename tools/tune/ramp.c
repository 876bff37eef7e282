/* SPDX-License-Identifier: MIT */
/*
 * The ramp test: the set-point accelerates at the axis' AMAX to the
 * ramp's speed, holds it, and stops TRAVEL from the start (a trapezoid in
 * speed, pushed as raw coarse points: the card's B-spline smooths the
 * corners, its feed-forward sees the B-spline's velocity and
 * acceleration), waits, and comes back the same way. Bounds, nothing
 * moved when one is broken: the speed within the velocity bound, room in
 * the travel to reach it; following-error and DAC bounds as the step's
 * (testmove.c). The way out is gathered (set-point, encoder, the card's
 * following error, DAC); the following error is reported where the
 * gathered set-point moves at the ramp's speed and where it accelerates
 * or decelerates.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tune.h"

#define LEAD_PERIODS	4	/* at the start before the ramp */
#define HOLD_S		0.05	/* at the end before coming back */
#define BACK_PERIODS	8	/* at the start after coming back */
#define CRUISE_S	0.05	/* cruise of the default travel */
#define NSIG		4	/* setpoint, encoder, ferr, dac */

struct ramp_ctx {
	struct tune_move m;
	double v, a, travel;	/* mm/s (> 0), mm/s^2, mm */
	int dir;
	int32_t *out, *back;	/* the coarse points each way */
	unsigned int npts, hold;
};

double tune_ramp_travel(double v, double a)
{
	v = fabs(v);
	/* mm, rounded up to a tenth */
	return ceil((v * v / a + v * CRUISE_S) * 10) / 10;
}

static int check_ramp(struct ramp_ctx *c)
{
	struct tune_move *m = &c->m;
	double need;

	c->v = fabs(m->o->ramp_mms);
	c->dir = m->o->ramp_mms < 0 ? -1 : 1;
	c->a = m->pc.amax[m->a];
	c->travel = m->o->travel_mm > 0 ? m->o->travel_mm : tune_ramp_travel(c->v, c->a);
	need = c->v * c->v / c->a;
	if (c->v > m->vlim) {
		sh2000_tool_msg("%s: a ramp at %g mm/s is beyond the velocity bound %.1f mm/s: nothing moved",
				sh2000_device(m->h), c->v, m->vlim);
		return SH2000_EXIT_CARD;
	}
	if (c->travel <= need) {
		sh2000_tool_msg("%s: a ramp at %g mm/s accelerating at %g mm/s^2 needs more than %g mm of travel to reach its speed (--travel %g): nothing moved",
				sh2000_device(m->h), c->v, c->a, need, c->travel);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* Distance along the trapezoid at t (mm). */
static double along(const struct ramp_ctx *c, double t)
{
	double ta = c->v / c->a, tc = (c->travel - c->v * ta) / c->v;
	double total = 2 * ta + tc;

	if (t <= 0)
		return 0;
	if (t < ta)
		return 0.5 * c->a * t * t;
	if (t < ta + tc)
		return 0.5 * c->v * ta + c->v * (t - ta);
	if (t < total)
		return c->travel - 0.5 * c->a * (total - t) * (total - t);
	return c->travel;
}

static int make_points(struct ramp_ctx *c)
{
	double tc = c->m.pc.period_s, cpm = c->m.pc.counts_per_mm[c->m.a];
	double total = 2 * c->v / c->a + (c->travel - c->v * c->v / c->a) / c->v;

	c->npts = (unsigned int)ceil(total / tc) + 1;
	c->hold = (unsigned int)ceil(HOLD_S / tc);
	c->out = malloc(2 * sizeof(*c->out) * c->npts);
	if (!c->out) {
		sh2000_tool_msg("out of memory");
		return SH2000_EXIT_CARD;
	}
	c->back = c->out + c->npts;
	for (unsigned int i = 0; i < c->npts; i++) {
		int32_t d = (int32_t)lround(c->dir * along(c, i * tc) * cpm);

		c->out[i] = c->m.start + d;
		c->back[c->npts - 1 - i] = c->m.start + d;
	}
	return 0;
}

static int move(struct tune_move *m)
{
	struct ramp_ctx *c = (struct ramp_ctx *)m;
	int r = tune_move_hold(m, m->start, LEAD_PERIODS, 0);

	if (r >= 0)
		r = tune_move_push(m, c->out, c->npts, 0);
	if (r >= 0)
		r = tune_move_hold(m, c->out[c->npts - 1], c->hold, 0);
	if (r >= 0)
		r = tune_move_push(m, c->back, c->npts, 0);
	if (r >= 0)
		r = tune_move_hold(m, m->start, BACK_PERIODS, SH2000_PUSH_END);
	if (r >= 0)
		r = sh2000_wait_idle(m->h, 10000);
	return r;
}

/* Cruise: the set-point's speed (central difference) within 0.2 % of the
 * ramp's, plus what rounding to counts makes of it. */
static void mark_cruise(struct tune_ramp *rp, double ts)
{
	double v = rp->speed_mms * rp->counts_per_mm;

	for (size_t i = 0; i < rp->n; i++) {
		double s = i && i + 1 < rp->n ? (rp->sp[i + 1] - rp->sp[i - 1]) / (2 * ts) : 0;

		rp->cruise[i] = fabs(fabs(s) - fabs(v)) <= 0.002 * fabs(v) + 1 / ts;
	}
}

/* Where the axis' signals and the follower's begin in a sample of the
 * record (the card's layout: axis 0..3, each in ascending signal order). */
static void columns(const struct tune_move *m, size_t *oa, size_t *ob)
{
	unsigned int f = m->o->follow;

	*oa = f && (unsigned int)__builtin_ctz(f) < m->a ? NSIG : 0;
	*ob = f ? NSIG - *oa : 0;
}

static int to_ramp(struct ramp_ctx *c, unsigned int rec, struct tune_ramp *rp)
{
	struct sh2000_gather_info gi;
	double *v, **col[NSIG] = { &rp->sp, &rp->enc, &rp->ferr, &rp->dac };
	size_t n, oa, ob, w;
	int r;

	if ((r = tune_move_read(&c->m, rec, &gi, &v)))
		return r;
	n = gi.samples;
	w = gi.values;
	columns(&c->m, &oa, &ob);
	rp->t = malloc(sizeof(double) * (NSIG + 2) * n);
	rp->cruise = malloc(n + 1);
	if (!rp->t || !rp->cruise || gi.trigger_index >= n) {
		free(v);
		sh2000_tool_msg("%s: the record holds no ramp", sh2000_device(c->m.h));
		return SH2000_EXIT_CARD;
	}
	rp->n = n;
	for (int k = 0; k < NSIG; k++)
		*col[k] = rp->t + (size_t)(k + 1) * n;
	if (c->m.o->follow)
		rp->skew = rp->t + (size_t)(NSIG + 1) * n;
	for (size_t i = 0; i < n; i++) {
		rp->t[i] = ((double)i - (double)gi.trigger_index) * gi.sample_s;
		for (int k = 0; k < NSIG; k++)
			(*col[k])[i] = v[w * i + oa + k];
		/* the third signal is the following error */
		if (rp->skew)
			rp->skew[i] = v[w * i + oa + 2] - v[w * i + ob + 2];
	}
	free(v);
	mark_cruise(rp, gi.sample_s);
	tune_ramp_figures(rp);
	return 0;
}

void tune_ramp_figures(struct tune_ramp *rp)
{
	double sum = 0;

	rp->cruise_peak = rp->cruise_rms = rp->accel_peak = rp->peak_dac = 0;
	rp->cruise_n = 0;
	rp->skew_peak = 0;
	for (size_t i = 0; i < rp->n; i++) {
		double e = fabs(rp->ferr[i]);
		int moving = i && rp->sp[i] != rp->sp[i - 1];

		if (rp->skew && fabs(rp->skew[i]) > rp->skew_peak)
			rp->skew_peak = fabs(rp->skew[i]);
		if (fabs(rp->dac[i]) > rp->peak_dac)
			rp->peak_dac = fabs(rp->dac[i]);
		if (rp->cruise[i]) {
			rp->cruise_n++;
			sum += e * e;
			if (e > rp->cruise_peak)
				rp->cruise_peak = e;
		} else if (moving && e > rp->accel_peak) {
			rp->accel_peak = e;
		}
	}
	rp->cruise_rms = rp->cruise_n ? sqrt(sum / rp->cruise_n) : NAN;
}

int tune_ramp(struct sh2000 *h, const struct tune_opts *o,
	      struct tune_ramp *rp)
{
	struct ramp_ctx c = { .m = { .h = h, .o = o, .a = o->axis, .name = "ramp" } };
	unsigned int rec = 0;
	int r;

	memset(rp, 0, sizeof(*rp));
	if (o->gantry_safe) {
		c.m.undo = tune_gantry_undo;
		c.m.calm = tune_gantry_calm;
	}
	if ((r = tune_move_prepare(&c.m)) || (r = check_ramp(&c)))
		goto out;
	rp->start = c.m.start;
	rp->counts_per_mm = c.m.pc.counts_per_mm[c.m.a];
	rp->speed_mms = o->ramp_mms;
	rp->travel_mm = c.travel;
	rp->accel_mms2 = c.a;
	if ((r = make_points(&c)) || (r = tune_move_lower_limits(&c.m)))
		goto out;
	r = tune_move_run(&c.m, 1u << SH2000_GS_SETPOINT | 1u << SH2000_GS_ENCODER |
			  1u << SH2000_GS_FERR | 1u << SH2000_GS_DAC,
			  (LEAD_PERIODS + c.npts + c.hold) * c.m.pc.period_s, &rec, move);
	if (!r)
		r = to_ramp(&c, rec, rp);
out:
	free(c.out);
	tune_move_end(&c.m);
	return r;
}

void tune_ramp_free(struct tune_ramp *rp)
{
	free(rp->t);
	free(rp->cruise);
	memset(rp, 0, sizeof(*rp));
}
