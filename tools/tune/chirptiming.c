/* SPDX-License-Identifier: MIT */
/*
 * The card's coarse period for a sweep. The set-point the host can give
 * changes once a coarse period (the card's B-spline only smooths between
 * the records), so a sweep up to F1 needs F1 <= 0.4 / coarse period; the
 * default 2 ms carries 200 Hz, while a loop's gain margin usually lies
 * near the servo rate. For the sweep, the coarse period is shortened to a
 * whole number of servo cycles that carries F1 (FINE_STEPS a divisor of
 * its value), the servo period unchanged, and put back afterwards.
 *
 * The card takes COARSE_PERIOD_US and FINE_STEPS one at a time, and the
 * servo period (their quotient) changes in between: libsh2000's
 * sh2000_set_timing() walks through legal states, and only through
 * states whose servo period is not longer than at the ends when there is
 * such a path (the PID is then sampled faster for a command's time, which
 * a stable loop stands; a longer period could make it unstable). The plan
 * asks for such a path (sh2000_timing_path(), SH2000_TIMING_NO_LONGER)
 * before anything is sent.
 */
#include <math.h>

#include "tune.h"

/* A path from (coarse_us, fine) to the fine steps `to` (the servo period
 * kept) whose states in between never lengthen the servo period. */
static int steps_ok(long coarse_us, unsigned int fine, unsigned int to)
{
	struct sh2000_timing_step st[SH2000_TIMING_STEPS_MAX];

	return sh2000_timing_path((unsigned int)coarse_us, fine,
				  (unsigned int)(coarse_us / (long)(fine / to)), to,
				  SH2000_TIMING_NO_LONGER, st,
				  SH2000_TIMING_STEPS_MAX) >= 0;
}

int tune_chirp_timing_plan(const struct tune_move *m, double f1_hz,
			   struct tune_chirp_timing *t)
{
	double servo = m->pc.period_s / m->pc.fine_steps;

	t->coarse0_us = lround(m->pc.period_s * 1e6);
	t->fine0 = m->pc.fine_steps;
	t->coarse_us = t->coarse0_us;
	t->fine = t->fine0;
	/* the most servo cycles per coarse period that still carry F1 */
	for (unsigned int n = t->fine0; n >= 1; n--) {
		if (t->fine0 % n || servo * n * f1_hz > TUNE_CHIRP_F_PERIOD)
			continue;
		if (!steps_ok(t->coarse0_us, t->fine0, n))
			continue;
		t->fine = n;
		t->coarse_us = t->coarse0_us / (long)(t->fine0 / n);
		return 0;
	}
	return -1;
}

int tune_chirp_timing_apply(struct tune_move *m, struct tune_chirp_timing *t,
			    int sweep)
{
	double coarse = 0, fine = 0;
	int r = sh2000_set_timing(m->h, (unsigned int)(sweep ? t->coarse_us : t->coarse0_us),
				  sweep ? t->fine : t->fine0);
	int g;

	if (r < 0)
		r = tune_move_fail(m, r, "set the coarse period");
	/* where the card is, also after a failure half-way */
	if ((g = sh2000_param_get(m->h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US,
				  &coarse)) < 0 ||
	    (g = sh2000_param_get(m->h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS,
				  &fine)) < 0)
		return r ? r : tune_move_fail(m, g, "read the timing back");
	m->pc.period_s = coarse * 1e-6;
	m->pc.fine_steps = (unsigned int)fine;
	return r;
}
