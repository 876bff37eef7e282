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
 * servo period (their quotient) changes in between. The steps are taken
 * one prime factor p at a time and in the order that makes the period in
 * between p times SHORTER, never longer (the PID is then sampled faster
 * for a command's time, which a stable loop stands; a longer period
 * could make it unstable): down, COARSE / p then FINE / p; up, FINE * p
 * then COARSE * p. Every step is checked before the first is sent (the
 * servo period in between not below the card's minimum, whole us).
 */
#include <math.h>

#include "tune.h"

static unsigned int smallest_prime(unsigned int n)
{
	for (unsigned int p = 2; p * p <= n; p++)
		if (n % p == 0)
			return p;
	return n;
}

/* Every intermediate step from (coarse, fine) by factors of fine/to_fine
 * possible: the coarse period divisible, the servo period in between
 * not below the card's minimum. */
static int steps_ok(long coarse_us, unsigned int fine, unsigned int to_fine)
{
	while (fine > to_fine) {
		unsigned int p = smallest_prime(fine / to_fine);

		if (coarse_us % p || coarse_us * 1000 / p / fine < SH2000_FW_MIN_SERVO_NS)
			return 0;
		coarse_us /= p;
		fine /= p;
	}
	return 1;
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

static int set(struct tune_move *m, unsigned int id, long v)
{
	int r = sh2000_param_set(m->h, SH2000_GLOBAL, id, (double)v);

	return r < 0 ? tune_move_fail(m, r, "set the coarse period") : 0;
}

/* From (*coarse, *fine) to the fine steps `to`, one prime at a time. */
static int walk(struct tune_move *m, long *coarse, unsigned int *fine,
		unsigned int to)
{
	int r = 0;

	while (!r && *fine > to) {
		unsigned int p = smallest_prime(*fine / to);

		if (!(r = set(m, SH2000_GP_COARSE_PERIOD_US, *coarse / p))) {
			*coarse /= p;
			if (!(r = set(m, SH2000_GP_FINE_STEPS, *fine / p)))
				*fine /= p;
		}
	}
	while (!r && *fine < to) {
		unsigned int p = smallest_prime(to / *fine);

		if (!(r = set(m, SH2000_GP_FINE_STEPS, *fine * p))) {
			*fine *= p;
			if (!(r = set(m, SH2000_GP_COARSE_PERIOD_US, *coarse * p)))
				*coarse *= p;
		}
	}
	return r;
}

int tune_chirp_timing_apply(struct tune_move *m, struct tune_chirp_timing *t,
			    int sweep)
{
	long coarse = t->cur_coarse_us ? t->cur_coarse_us : t->coarse0_us;
	unsigned int fine = t->cur_fine ? t->cur_fine : t->fine0;
	int r = walk(m, &coarse, &fine, sweep ? t->fine : t->fine0);

	t->cur_coarse_us = coarse;
	t->cur_fine = fine;
	m->pc.period_s = coarse * 1e-6;
	m->pc.fine_steps = fine;
	return r;
}
