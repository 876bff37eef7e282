/* SPDX-License-Identifier: MIT */
/*
 * The swept-sine (chirp) test: the set-point follows
 *   x(t) = A w(t) sin(phi(t)),  phi(t) = 2 pi F0 D / ln(F1/F0) (e^(t ln(F1/F0) / D) - 1)
 * around the start for D seconds (a logarithmic sweep: the same time per
 * octave; F1 here a sixth of an octave beyond the one asked for), w a
 * raised-cosine fade in and out so the set-point starts and ends at rest,
 * and the amplitude falling as 1/f^2 above the frequency where it would
 * need more than the acceleration bound (sweep_accel). The host pushes x at the coarse
 * instants; the card's B-spline smooths it, which does not matter: the
 * responses are taken against the set-point the card gathered. So the
 * sweep must stay below the coarse period's Nyquist frequency (the
 * B-spline would only make images above it): F1 <= 0.4 / period, the
 * coarse period shortened for the sweep if need be (chirptiming.c).
 * Bounds, nothing moved when one is broken: A 2 pi F1 within the velocity
 * bound; during the sweep the following-error and DAC bounds are the
 * user's (testmove.c). Set-point, encoder and DAC are gathered from rest
 * before the sweep to rest after it (freqresp.c needs the whole
 * transient), every servo cycle as long as the card's memory holds it.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tune.h"

#define LEAD_PERIODS	16	/* at the start before the sweep: one push
				 * (testmove.c) at the shortest coarse period */
#define TAIL_S		0.15	/* at the start after it, to settle */
#define FADE		0.1	/* share of the sweep faded in */
#define FADE_OUT	20	/* periods of the end faded out (at most FADE) */
/* The sweep goes on a sixth of an octave beyond F1, so that its fade-out
 * is above the frequencies reported. */
#define BEYOND		1.122462048309373	/* 2^(1/6) */

struct chirp_ctx {
	struct tune_move m;
	int32_t *pts;		/* the lead, the sweep, the tail: counts */
	unsigned int npts, tail;	/* the sweep's points, the tail's */
	struct tune_chirp_timing timing;
	double accel;		/* counts/s^2 the sweep may reach */
};

double tune_chirp_f1_max(double servo_s)
{
	return TUNE_CHIRP_F_PERIOD / (servo_s * BEYOND);
}

/* A coarse period that carries F1. */
static int check_timing(struct chirp_ctx *c)
{
	const struct tune_opts *o = c->m.o;
	double servo = c->m.pc.period_s / c->m.pc.fine_steps;

	if (tune_chirp_timing_plan(&c->m, o->f1_hz * BEYOND, &c->timing)) {
		sh2000_tool_msg("%s: --chirp up to %g Hz: the card's servo period (%g ms) carries a sweep up to %g Hz: nothing moved",
				sh2000_device(c->m.h), o->f1_hz, servo * 1e3,
				floor(TUNE_CHIRP_F_PERIOD / servo / BEYOND));
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* The sweep's top speed (at F1, or where the acceleration bound takes
 * over) within the velocity bound. */
static int check_speed(struct chirp_ctx *c)
{
	const struct tune_opts *o = c->m.o;
	double amp = o->amplitude_mm * c->m.pc.counts_per_mm[c->m.a];
	double f = fmin(o->f1_hz * BEYOND, sqrt(c->accel / amp) / (2 * M_PI));
	double v = o->amplitude_mm * 2 * M_PI * f;

	if (v > c->m.vlim) {
		sh2000_tool_msg("%s: --amplitude %g mm at %.4g Hz is %.1f mm/s: it must be within %.1f mm/s (at most %g mm): nothing moved",
				sh2000_device(c->m.h), o->amplitude_mm, f, v,
				c->m.vlim, c->m.vlim / (2 * M_PI * f));
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/*
 * The acceleration the sweep holds above the frequency where its
 * amplitude would demand more (counts/s^2): --accel, or what takes half
 * the test's DAC bound by the card's own acceleration feed-forward (KAFF,
 * codes per count/s^2: its model of the axis' inertia, so a heavier axis
 * gets a gentler sweep; half leaves the feedback room), or without KAFF
 * the axis' AMAX.
 */
static void sweep_accel(struct chirp_ctx *c, const struct tune_fr *fr)
{
	const struct tune_opts *o = c->m.o;

	if (o->accel_mms2 > 0)
		c->accel = o->accel_mms2 * fr->counts_per_mm;
	else if (fr->gains.kaff > 0)
		c->accel = 0.5 * c->m.dac_bound / fr->gains.kaff;
	else
		c->accel = c->m.pc.amax[c->m.a] * fr->counts_per_mm;
}

/* The fade at t of a sweep of d seconds ending at f1: in over a tenth of
 * it, out over a few periods of f1 only (a tenth of a log sweep is its
 * top half octave or more, where the gain margin often lies). */
static double fade(double t, double d, double f1)
{
	double e = fmin(t / (FADE * d), (d - t) / fmin(FADE * d, FADE_OUT / f1));

	return e >= 1 ? 1 : e <= 0 ? 0 : 0.5 * (1 - cos(M_PI * e));
}

static int make_points(struct chirp_ctx *c)
{
	const struct tune_opts *o = c->m.o;
	double tc = c->m.pc.period_s, d = o->duration_s;
	double k = log(o->f1_hz * BEYOND / o->f0_hz) / d;
	double amp = o->amplitude_mm * c->m.pc.counts_per_mm[c->m.a], fa;

	c->npts = (unsigned int)ceil(d / tc) + 1;
	c->tail = (unsigned int)ceil(TAIL_S / tc);
	c->pts = malloc(sizeof(*c->pts) * (LEAD_PERIODS + c->npts + c->tail));
	if (!c->pts) {
		sh2000_tool_msg("out of memory");
		return SH2000_EXIT_CARD;
	}
	/* above fa the amplitude falls as 1/f^2: the acceleration stays at
	 * its bound */
	fa = sqrt(c->accel / amp) / (2 * M_PI);
	for (unsigned int i = 0; i < LEAD_PERIODS; i++)
		*c->pts++ = c->m.start;
	for (unsigned int i = 0; i < c->tail; i++)
		c->pts[c->npts + i] = c->m.start;
	for (unsigned int i = 0; i < c->npts; i++) {
		double t = fmin(i * tc, d), f = o->f0_hz * exp(k * t);
		double phi = 2 * M_PI * o->f0_hz / k * (exp(k * t) - 1);
		double a = f > fa ? amp * (fa / f) * (fa / f) : amp;

		c->pts[i] = c->m.start + (int32_t)lround(a * fade(t, d, o->f1_hz * BEYOND) * sin(phi));
	}
	c->pts -= LEAD_PERIODS;
	return 0;
}

/* The card's timing back (after the sweep; after a fault before the way
 * back). */
static int undo_timing(struct tune_move *m)
{
	return tune_chirp_timing_apply(m, &((struct chirp_ctx *)m)->timing, 0);
}

/* All in one run of batches: with a coarse period of one servo cycle a
 * few records of lead alone would run out while the host comes back. */
static int move(struct tune_move *m)
{
	struct chirp_ctx *c = (struct chirp_ctx *)m;
	int r = tune_move_push(m, c->pts, LEAD_PERIODS + c->npts + c->tail,
			       SH2000_PUSH_END);

	if (r >= 0)
		r = sh2000_wait_idle(m->h, 10000);
	return r;
}

/* The record as the responses at fr->hz. */
/* The DAC amplitude the set-point drives at each frequency, codes: the
 * measured response to it times the set-point's amplitude there
 * (make_points' law), from the top down and never more than the next
 * higher frequency's scaled by f (a mass wants the force to fall as f^2,
 * friction as f: no plant's falls slower), so that the PID's answer to
 * the encoder's quantisation, which correlates with the set-point by
 * chance at low frequencies, cannot pass for excitation. */
static void dac_amplitudes(const struct chirp_ctx *c, const struct tune_fr *fr,
			   const double complex *td, double *dac)
{
	double amp = c->m.o->amplitude_mm * c->m.pc.counts_per_mm[c->m.a];
	double fa = sqrt(c->accel / amp) / (2 * M_PI);

	for (size_t i = fr->n; i-- > 0;) {
		double f = fr->hz[i], a = f > fa ? amp * (fa / f) * (fa / f) : amp;

		dac[i] = cabs(td[i]) * a;
		if (i + 1 < fr->n)
			dac[i] = fmin(dac[i], dac[i + 1] * f / fr->hz[i + 1]);
	}
}

/* The responses at the frequencies where that DAC amplitude is at least
 * what the PID gives for TUNE_FR_MIN_ERR counts of error. The others are
 * left out and counted: their plant would be the PID's answer to the
 * encoder's quantisation. */
static void keep_excited(const struct chirp_ctx *c, struct tune_fr *fr,
			 const double complex *te, const double complex *td)
{
	double dac[TUNE_FR_MAX];
	size_t k = 0;

	dac_amplitudes(c, fr, td, dac);
	fr->weak = 0;
	for (size_t i = 0; i < fr->n; i++) {
		double f = fr->hz[i];
		double complex C = tune_pid_response(&fr->gains, fr->servo_s, f);

		if (dac[i] < TUNE_FR_MIN_ERR * cabs(C)) {
			if (!fr->weak++)
				fr->weak_lo_hz = f;
			fr->weak_hi_hz = f;
			continue;
		}
		fr->hz[k] = f;
		fr->closed[k] = te[i];
		fr->plant[k] = te[i] / td[i];
		fr->ctrl[k] = C;
		fr->loop[k] = fr->ctrl[k] * fr->plant[k];
		k++;
	}
	fr->n = k;
}

static int analyse(struct chirp_ctx *c, unsigned int rec, struct tune_fr *fr)
{
	struct sh2000_gather_info gi;
	double *v, *sig;
	double complex te[TUNE_FR_MAX], td[TUNE_FR_MAX];
	size_t n;
	int r;

	if ((r = tune_move_read(&c->m, rec, &gi, &v)))
		return r;
	n = gi.samples;
	sig = malloc(sizeof(*sig) * 3 * n);
	if (!sig || n < 2) {
		free(v);
		free(sig);
		sh2000_tool_msg("%s: the record holds no sweep", sh2000_device(c->m.h));
		return SH2000_EXIT_CARD;
	}
	/* each signal less its value at rest: finite sequences */
	for (size_t i = 0; i < n; i++)
		for (int k = 0; k < 3; k++) {
			sig[k * n + i] = v[3 * i + k] - v[k];
			if (k == 2 && fabs(sig[k * n + i]) > fr->peak_dac)
				fr->peak_dac = fabs(sig[k * n + i]);
			if (k == 2 && fabs(v[3 * i + k]) >= c->m.dac_bound)
				fr->dac_saturated = 1;
		}
	fr->sample_s = gi.sample_s;
	tune_fr_ratio(sig, sig + n, n, gi.sample_s, fr->hz, fr->n, te);
	tune_fr_ratio(sig, sig + 2 * n, n, gi.sample_s, fr->hz, fr->n, td);
	keep_excited(c, fr, te, td);
	free(sig);
	free(v);
	return 0;
}

int tune_chirp(struct sh2000 *h, const struct tune_opts *o,
	       struct tune_fr *fr)
{
	struct chirp_ctx c = { .m = { .h = h, .o = o, .a = o->axis, .name = "chirp",
				      .undo = undo_timing } };
	unsigned int rec = 0;
	int r;

	memset(fr, 0, sizeof(*fr));
	fr->n = TUNE_FR_POINTS;
	tune_fr_grid(o->f0_hz, o->f1_hz, fr->n, fr->hz);
	if ((r = tune_move_prepare(&c.m)) || (r = check_timing(&c)))
		goto out;
	if ((r = tune_read_gains(h, c.m.a, &fr->gains)) < 0) {
		r = tune_move_fail(&c.m, r, "get parameter");
		goto out;
	}
	fr->servo_s = c.m.pc.period_s / c.m.pc.fine_steps;
	fr->coarse_s = c.m.pc.period_s;
	fr->sweep_coarse_s = c.timing.coarse_us * 1e-6;
	fr->counts_per_mm = c.m.pc.counts_per_mm[c.m.a];
	if ((r = tune_move_lower_limits(&c.m)))
		goto out;
	sweep_accel(&c, fr);
	if ((r = check_speed(&c))) {
		tune_move_restore(&c.m);
		goto out;
	}
	if ((r = tune_chirp_timing_apply(&c.m, &c.timing, 1)) || (r = make_points(&c))) {
		tune_chirp_timing_apply(&c.m, &c.timing, 0);
		tune_move_restore(&c.m);
		goto out;
	}
	r = tune_move_run(&c.m, 1u << SH2000_GS_SETPOINT | 1u << SH2000_GS_ENCODER |
			  1u << SH2000_GS_DAC,
			  (LEAD_PERIODS + c.npts + c.tail) * c.m.pc.period_s, &rec, move);
	if (!r)
		r = analyse(&c, rec, fr);
out:
	free(c.pts);
	tune_move_end(&c.m);
	return r;
}
