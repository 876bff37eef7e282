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

#define IDENT_SECONDS	1.5	/* at most, the record's size permitting */
#define IDENT_FADE_S	0.15
#define IDENT_TONES	8
#define IDENT_F0	2.0	/* Hz, the lowest tone */
#define IDENT_RATIO	1.6	/* between tones */
#define LEAD_PERIODS	4
#define BACK_PERIODS	8
#define NSIG		2	/* encoder, dac */
#define RECORD_SPARE	16	/* samples: testmove.c's pretrigger and more */
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
	k = fmin(s->o->travel_mm / xm, fmin(s->vlim / vm,
					    s->pc.amax[s->a] / am));
	*amp = k * xm;
	for (size_t i = 0; v && i < n; i++)
		v[i] = s->start + (int32_t)lround(k * excitation((double)i * P, len) * cpm);
	return v;
}

/* The record, fitted. An exit code. */
static int fit(struct tune_move *s, unsigned int rec, struct tune_plant *pl)
{
	struct sh2000_gather_info gi;
	double *v, *enc = NULL;
	char why[256];
	int r;

	if ((r = tune_move_read(s, rec, &gi, &v)))
		return r;
	if (gi.period != 1) {
		sh2000_tool_msg("%s: identification: the record is not every servo cycle", sh2000_device(s->h));
		free(v);
		return SH2000_EXIT_CARD;
	}
	enc = malloc(sizeof(*enc) * 2 * gi.samples);
	if (!enc) {
		free(v);
		return tune_move_fail(s, -12, "identification");
	}
	for (uint32_t i = 0; i < gi.samples; i++) {
		enc[i] = v[NSIG * i];
		enc[gi.samples + i] = v[NSIG * i + 1];
	}
	r = tune_ident_fit(enc, enc + gi.samples, gi.samples, gi.sample_s,
			   TUNE_IDENT_DMAX, pl, why, sizeof(why));
	free(enc);
	free(v);
	if (r < 0) {
		sh2000_tool_msg("%s: identification: %s", sh2000_device(s->h), why);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* The excitation (ident_ctx's points) and the way back; tune_move_run()
 * arms the record before and puts the limits back after. */
struct ident_ctx {
	struct tune_move m;	/* first: tune_move_run() hands it back */
	int32_t *pts;
	size_t n;
};

static int move(struct tune_move *m)
{
	const struct ident_ctx *c = (const struct ident_ctx *)m;
	int r = tune_move_hold(m, m->start, LEAD_PERIODS, 0);

	if (r >= 0)
		r = tune_move_push(m, c->pts, (unsigned int)c->n, 0);
	if (r >= 0)
		r = tune_move_hold(m, m->start, BACK_PERIODS, SH2000_PUSH_END);
	if (r >= 0)
		r = sh2000_wait_idle(m->h, 20000);
	return r;
}

/* The excitation's coarse periods: as long as IDENT_SECONDS, or as the
 * card's record holds every servo cycle of it and of the way there and
 * back. */
static size_t periods_of(const struct tune_move *s)
{
	double servo = s->pc.period_s / s->pc.fine_steps;
	double cap = (SH2000_GATHER_BUFFER_VALUES / NSIG - RECORD_SPARE) * servo;
	double len = fmin(IDENT_SECONDS,
			  cap - (LEAD_PERIODS + BACK_PERIODS + 1) * s->pc.period_s);

	return len > 0 ? (size_t)floor(len / s->pc.period_s) : 0;
}

int tune_ident(struct sh2000 *h, const struct tune_opts *o,
	       struct tune_ident_result *res)
{
	struct ident_ctx c = { .m = { .h = h, .o = o, .a = o->axis,
				      .name = "identification" } };
	struct tune_move *s = &c.m;
	unsigned int rec = 0;
	int r;

	memset(res, 0, sizeof(*res));
	if ((r = tune_move_prepare(s)))
		goto out;
	res->start = s->start;
	c.n = periods_of(s);
	if (c.n * s->pc.period_s < 4 * IDENT_FADE_S) {
		sh2000_tool_msg("%s: the card's record holds %.3f s at this servo period, too short to identify: nothing moved",
				sh2000_device(h), (double)c.n * s->pc.period_s);
		r = SH2000_EXIT_CARD;
		goto out;
	}
	c.pts = plan(s, c.n, &res->amplitude_mm);
	if (!c.pts) {
		r = tune_move_fail(s, -12, "identification");
		goto out;
	}
	res->seconds = (double)c.n * s->pc.period_s;
	if ((r = tune_move_lower_limits(s)))
		goto out;
	r = tune_move_run(s, 1u << SH2000_GS_ENCODER | 1u << SH2000_GS_DAC,
			  (double)(c.n + LEAD_PERIODS + BACK_PERIODS) * s->pc.period_s,
			  &rec, move);
	if (!r)
		r = fit(s, rec, &res->plant);
out:
	free(c.pts);
	tune_move_end(s);
	return r;
}
