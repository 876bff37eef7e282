/* SPDX-License-Identifier: MIT */
/*
 * Plant identification on the card for sh2000-tune --auto: a bounded test
 * move (testmove.c) whose set-point is a multisine, gathered every servo
 * cycle (encoder and DAC), then fitted (identfit.c). The excitation is the
 * sum of IDENT_TONES sines from IDENT_F0 up, each of the same velocity
 * amplitude, with Schroeder phases (a low crest factor) under a raised
 * cosine fade in and out, so it starts and ends at rest at the start. It
 * is scaled to the tightest of the bounds: the travel window, the velocity
 * bound (--vmax or the axis' vmax) and the axis' acceleration limit amax;
 * the DAC stays within --dac-max (the card's limit during the test) and
 * the following error within --ferr-max (beyond it the test is aborted and
 * the axis goes back to its start). The card's current gains only have to
 * keep the loop stable: the fit uses the DAC as the card put it out.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "autotune.h"
#include "ident.h"
#include "testmove.h"

#define IDENT_SECONDS	1.5	/* at most, the record's size permitting */
#define IDENT_FADE_S	0.15
#define IDENT_TONES	8
#define IDENT_F0	2.0	/* Hz, the lowest tone */
#define IDENT_RATIO	1.6	/* between tones */
#define LEAD_PERIODS	4
#define BACK_PERIODS	8
#define PRETRIGGER	4
#define NSIG		2	/* encoder, dac */
#define FINE		16	/* evaluation points per coarse period */

/* The unscaled excitation at t (s) of a test lasting len s, in mm. */
static double excitation(double t, double len)
{
	double x = 0, w = 1;

	for (int i = 0; i < IDENT_TONES; i++) {
		double f = IDENT_F0 * pow(IDENT_RATIO, i);
		double ph = -M_PI * i * (i - 1) / IDENT_TONES;

		x += sin(2 * M_PI * f * t + ph) / f;
	}
	if (t < IDENT_FADE_S)
		w = 0.5 - 0.5 * cos(M_PI * t / IDENT_FADE_S);
	else if (t > len - IDENT_FADE_S)
		w = 0.5 - 0.5 * cos(M_PI * (len - t) / IDENT_FADE_S);
	if (t <= 0 || t >= len)
		w = 0;
	return x * w;
}

/* The set-points of the excitation, counts, n coarse periods: scaled to
 * the bounds. NULL when out of memory. */
static int32_t *plan(struct tune_move *s, size_t n, double *amp)
{
	double P = s->pc.period_s, h = P / FINE, len = (double)n * P;
	double xm = 0, vm = 0, am = 0, k, cpm = s->pc.counts_per_mm[s->a];
	int32_t *v = malloc(sizeof(*v) * n);

	for (size_t i = 1; i + 1 < n * FINE; i++) {
		double t = (double)i * h, x0 = excitation(t - h, len);
		double x1 = excitation(t, len), x2 = excitation(t + h, len);

		xm = fmax(xm, fabs(x1));
		vm = fmax(vm, fabs(x2 - x0) / (2 * h));
		am = fmax(am, fabs(x2 - 2 * x1 + x0) / (h * h));
	}
	k = fmin(s->o->travel_mm / xm, fmin(tune_move_vmax(s) / vm,
					    s->pc.amax[s->a] / am));
	*amp = k * xm;
	for (size_t i = 0; v && i < n; i++)
		v[i] = s->start + (int32_t)lround(k * excitation((double)i * P, len) * cpm);
	return v;
}

/* Arm a record of encoder and DAC every servo cycle from the motion's
 * start: *rec its number. An exit code. */
static int arm(struct tune_move *s, size_t periods, unsigned int *rec)
{
	struct sh2000_gather_config gc;
	int r;

	sh2000_gather_config_default(&gc);
	gc.signals[s->a] = 1u << SH2000_GS_ENCODER | 1u << SH2000_GS_DAC;
	gc.period = 1;
	gc.samples = (uint32_t)((periods + LEAD_PERIODS + BACK_PERIODS) *
				s->pc.fine_steps) + PRETRIGGER;
	gc.trigger = SH2000_GATHER_ON_MOTION;
	gc.pretrigger = PRETRIGGER;
	r = sh2000_gather_start(s->h, &gc);
	if (r < 0)
		return tune_move_fail(s, r, "gather");
	*rec = (unsigned int)r;
	return 0;
}

/* The record, fitted. An exit code. */
static int fit(struct tune_move *s, unsigned int rec, struct tune_plant *pl)
{
	struct sh2000_gather_info gi;
	double *v, *enc, *dac;
	char why[256];
	int r;

	if ((r = sh2000_gather_wait(s->h, rec, &gi, 10000)) < 0)
		return tune_move_fail(s, r, "gather");
	v = malloc(sizeof(*v) * NSIG * 2 * gi.samples);
	r = v ? sh2000_gather_read(s->h, &gi, 0, gi.samples, v) : -12;
	if (r < 0) {
		free(v);
		return tune_move_fail(s, r, "gather");
	}
	enc = v + NSIG * gi.samples;
	dac = enc + gi.samples;
	for (uint32_t i = 0; i < gi.samples; i++) {
		enc[i] = v[NSIG * i];
		dac[i] = v[NSIG * i + 1];
	}
	r = tune_ident_fit(enc, dac, gi.samples, gi.sample_s, TUNE_IDENT_DMAX,
			   pl, why, sizeof(why));
	free(v);
	if (r < 0) {
		sh2000_tool_msg("%s: identification: %s", sh2000_device(s->h), why);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* The excitation and the way back; an error ends the test. */
static int move(struct tune_move *s, const int32_t *pts, size_t n)
{
	int r = tune_move_hold(s, s->start, LEAD_PERIODS, 0);

	if (r >= 0)
		r = tune_move_points(s, pts, n, 0);
	if (r >= 0)
		r = tune_move_hold(s, s->start, BACK_PERIODS, SH2000_PUSH_END);
	if (r >= 0)
		r = sh2000_wait_idle(s->h, 20000);
	return r;
}

static size_t periods_of(const struct tune_move *s)
{
	double servo = s->pc.period_s / s->pc.fine_steps;
	double cap = (SH2000_GATHER_BUFFER_VALUES / NSIG - PRETRIGGER) * servo;
	double len = fmin(IDENT_SECONDS,
			  cap - (LEAD_PERIODS + BACK_PERIODS + 1) * s->pc.period_s);

	return len > 0 ? (size_t)floor(len / s->pc.period_s) : 0;
}

int tune_ident(struct sh2000 *h, const struct tune_opts *o,
	       struct tune_ident_result *res)
{
	struct tune_move s = { .h = h, .o = o, .a = o->axis };
	unsigned int rec = 0;
	int32_t *pts = NULL;
	size_t n;
	int r;

	memset(res, 0, sizeof(*res));
	if ((r = tune_move_begin(&s)))
		goto out;
	res->start = s.start;
	n = periods_of(&s);
	if (n * s.pc.period_s < 4 * IDENT_FADE_S) {
		sh2000_tool_msg("%s: the card's record holds %.3f s at this servo period, too short to identify: nothing moved",
				sh2000_device(h), (double)n * s.pc.period_s);
		r = SH2000_EXIT_CARD;
		goto out;
	}
	pts = plan(&s, n, &res->amplitude_mm);
	if (!pts) {
		r = tune_move_fail(&s, -12, "identification");
		goto out;
	}
	res->seconds = (double)n * s.pc.period_s;
	if ((r = tune_move_limits(&s)))
		goto out;
	r = arm(&s, n, &rec);
	if (!r && (r = move(&s, pts, n)) < 0) {
		sh2000_gather_stop(h);
		if (r == -SH2000_EFERR) {
			r = tune_move_recover(&s, r, "identification");
			goto out;
		}
		r = tune_move_fail(&s, r, "identification");
	}
	if (!r)
		r = tune_move_restore(&s);
	else
		tune_move_restore(&s);
	if (!r)
		r = fit(&s, rec, &res->plant);
out:
	free(pts);
	tune_move_end(&s);
	return r;
}
