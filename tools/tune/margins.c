/* SPDX-License-Identifier: MIT */
/*
 * Stability margins of a measured loop L = C P and the closed loop's
 * bandwidth, between the measured frequencies interpolated on a log
 * frequency axis (magnitude in dB and unwrapped phase linear in log f).
 *
 * The phase is unwrapped along the frequencies, then placed so that it
 * lies in (-360, 0] at the crossover: the phase margin is 180 + that
 * phase. A phase crossing is wherever the unwrapped phase passes an odd
 * multiple of -180 (L on the negative real axis). With integral action
 * the loop of a double integrator is conditionally stable: below the
 * crossover the phase passes -180 with |L| > 1, where LOWERING the gain
 * would destabilise it (gm_low_db, negative); the classic gain margin is
 * at the first such crossing above the crossover (|L| < 1).
 */
#include <math.h>

#include "tune.h"

static double db(double complex z)
{
	return 20 * log10(cabs(z));
}

/* Fraction of the way from a to b where the value v is reached. */
static double frac(double a, double b, double v)
{
	return (v - a) / (b - a);
}

/* Log-frequency interpolation between hz[i] and hz[i + 1]. */
static double at(const double *hz, size_t i, double f)
{
	return hz[i] * pow(hz[i + 1] / hz[i], f);
}

double tune_phase_unwrap(double prev, double ph)
{
	while (ph - prev > 180)
		ph -= 360;
	while (ph - prev < -180)
		ph += 360;
	return ph;
}

double tune_phase_margin(double ph)
{
	/* ph into (-360, 0] */
	ph = fmod(ph, 360);
	if (ph > 0)
		ph -= 360;
	return 180 + ph;
}

/* The phase of L in degrees, unwrapped along the frequencies. */
static void unwrap(const struct tune_fr *fr, double *ph)
{
	for (size_t i = 0; i < fr->n; i++) {
		ph[i] = carg(fr->loop[i]) * 180 / M_PI;
		if (i)
			ph[i] = tune_phase_unwrap(ph[i - 1], ph[i]);
	}
}

/* The highest 0 dB crossing of L (falling): the phase margin there. */
static void crossover(const struct tune_fr *fr, const double *ph,
		      struct tune_margins *m)
{
	for (size_t i = fr->n - 1; i-- > 0;) {
		double a = db(fr->loop[i]), b = db(fr->loop[i + 1]);

		if (a >= 0 && b < 0) {
			double f = frac(a, b, 0), p = ph[i] + f * (ph[i + 1] - ph[i]);

			m->wc_hz = at(fr->hz, i, f);
			m->pm_deg = tune_phase_margin(p);
			return;
		}
	}
}

/* The phase crossings of -180 (mod 360): the lowest one with |L| < 1 above
 * the crossover, the highest one with |L| > 1 below it. */
static void phase_crossings(const struct tune_fr *fr, const double *ph,
			    struct tune_margins *m)
{
	for (size_t i = 0; i + 1 < fr->n; i++) {
		/* the odd multiple of 180 between ph[i] and ph[i + 1] (the
		 * steps are below 180 after unwrapping: one at most) */
		double lo = fmin(ph[i], ph[i + 1]), hi = fmax(ph[i], ph[i + 1]);
		double level = 360 * ceil((lo - 180) / 360) + 180;
		double f, g, hz;

		if (level > hi || lo == hi)
			continue;
		f = frac(ph[i], ph[i + 1], level);
		g = db(fr->loop[i]) + f * (db(fr->loop[i + 1]) - db(fr->loop[i]));
		hz = at(fr->hz, i, f);
		if (g < 0 && isnan(m->w180_hz) && !(hz < m->wc_hz)) {
			m->w180_hz = hz;
			m->gm_db = -g;
		} else if (g >= 0 && !(hz > m->wc_hz)) {
			m->w180_low_hz = hz;
			m->gm_low_db = -g;
		}
	}
}

/* The first frequency where the feedback loop's L / (1 + L) falls
 * through -3 dB. Not the measured encoder / set-point: that includes the
 * card's feed-forward, which (tuned to the plant, as the defaults are)
 * keeps it near 0 dB far beyond what the feedback alone can follow. */
static void bandwidth(const struct tune_fr *fr, struct tune_margins *m)
{
	for (size_t i = 0; i + 1 < fr->n; i++) {
		double a = db(fr->loop[i] / (1 + fr->loop[i]));
		double b = db(fr->loop[i + 1] / (1 + fr->loop[i + 1]));

		if (a >= -3 && b < -3) {
			m->bw_hz = at(fr->hz, i, frac(a, b, -3));
			return;
		}
	}
}

int tune_margins(const struct tune_fr *fr, struct tune_margins *m)
{
	double ph[TUNE_FR_MAX];

	m->gm_db = m->pm_deg = m->wc_hz = m->w180_hz = m->bw_hz = NAN;
	m->gm_low_db = m->w180_low_hz = NAN;
	if (fr->n < 2)
		return -1;
	unwrap(fr, ph);
	crossover(fr, ph, m);
	phase_crossings(fr, ph, m);
	bandwidth(fr, m);
	return isnan(m->wc_hz) ? -1 : 0;
}
