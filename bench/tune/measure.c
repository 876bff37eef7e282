/* SPDX-License-Identifier: MIT */
/*
 * The benchmark's measure of a set of gains: the circle's max following
 * error is at the encoder's quantisation (2-3 counts, of which a count is
 * the scale's step), so one run of it is a draw: the same gains give
 * 2.7..3.4 counts as the circle starts at another angle or the carriage a
 * quarter count further (`bench_tune variants`), more than the 10 % the
 * benchmark compares. The measure is the worst over CIRCLE_VARIANTS runs:
 * start angles 45 deg apart, start positions a quarter count apart (the
 * phase of the servo cycle changes nothing in virtual time: the plant
 * steps per servo cycle). Variant 0 is circle_with()'s run, so one run
 * is a lower bound of the measure. The verdict's runs are the other 56 of
 * 64: the same angles at start positions an eighth of a count apart.
 */
#include <math.h>

#include "bench_tune.h"

void circle_variant_of(unsigned int i, struct circle_variant *v)
{
	unsigned int a = i % 8, round = i / 8;

	v->angle_deg = 45.0 * a;
	/* in each round of eight the quarter counts shift by one, so that
	 * 32 variants are all 8 angles x 4 start positions; the next 32 the
	 * same an eighth of a count further */
	v->start_counts = 0.25 * ((a + round) % 4) + (round >= 4 ? 0.125 : 0);
	v->phase = 0;
}

int circle_measure_from(const struct bench_machine *m,
			const struct tune_gains *g, unsigned int first,
			unsigned int n, struct circle_result *res)
{
	*res = (struct circle_result){ 0 };
	for (unsigned int i = first; i < first + n; i++) {
		struct circle_variant v;
		struct circle_result r;

		circle_variant_of(i, &v);
		if (circle_variant_with(m, g, &v, &r) < 0)
			return -1;
		if (r.unstable) {
			*res = r;	/* the first that was, and why */
			return 0;
		}
		res->max_ferr = fmax(res->max_ferr, r.max_ferr);
		res->rms_ferr = fmax(res->rms_ferr, r.rms_ferr);
		res->feed = fmax(res->feed, r.feed);
	}
	return 0;
}

int circle_measure(const struct bench_machine *m, const struct tune_gains *g,
		   unsigned int n, struct circle_result *res)
{
	return circle_measure_from(m, g, 0, n, res);
}

void circle_worst(const struct circle_result *a, const struct circle_result *b,
		  struct circle_result *res)
{
	if (a->unstable || b->unstable) {
		*res = a->unstable ? *a : *b;
		return;
	}
	*res = *a;
	res->max_ferr = fmax(a->max_ferr, b->max_ferr);
	res->rms_ferr = fmax(a->rms_ferr, b->rms_ferr);
	res->feed = fmax(a->feed, b->feed);
}
