// SPDX-License-Identifier: MIT
/*
 * A move from rest to rest along a line, where the controller holds one
 * jerk a whole period (the card model's limits): it takes no more coarse
 * periods than the fastest profile in whole periods of a simple family
 * (below), computed for each move, lands exactly on its end point and
 * never passes it. A stop used to cost a period more than that (the
 * braking was planned with a ramp of two periods: a 20 mm side of the
 * benchmark's square at 100 mm/s took 113 periods where 112 do).
 *
 * The family: accelerate in na periods to v <= F, cruise m periods,
 * brake in nd periods, with one period to ramp the acceleration up or
 * down (J T >= A here): the speed gained in n periods is at most
 * A T (n - 1), and a profile whose acceleration is symmetric covers v n T
 * / 2 while it changes speed. So N = na + m + nd periods cover up to
 * v T (N - (na + nd) / 2) with v = min(F, A T (na - 1), A T (nd - 1)),
 * and any length below that by a lower v. Every such profile keeps
 * |a| <= A, |j| <= J and v <= F: the fewest periods cannot be more than
 * its least N (they may be fewer on very short moves, where a profile
 * that never holds its acceleration does better).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "planner.h"

/* The least N of the family for length L at feed F, acceleration A and
 * period T. */
static unsigned int family_periods(double L, double F, double A, double T)
{
	unsigned int N, na, nd;

	for (N = 1;; N++)
		for (na = 1; 2 * na <= N + 1; na++)
			for (nd = na; nd <= na + 1 && na + nd <= N; nd++) {
				double v = fmin(F, A * T * (na - 1.0));

				v = fmin(v, A * T * (nd - 1.0));
				if (v * T * (N - 0.5 * (na + nd)) >= L * (1.0 - 1e-12))
					return N;
			}
}

static int null_sink(void *ctx, const struct sh2000_path_point *pt)
{
	(void)ctx;
	(void)pt;
	return 0;
}

struct move_result {
	unsigned int periods, fewest;	/* fewest 0: the family does not hold */
	double past;		/* most the plan went beyond the end, mm */
	double off;		/* the end point's distance from the target */
};

/* G61, one line from the origin along dir (unit) over L at feed F, the
 * card model's limits with amax given: periods until the controller
 * rests, and the family's least for the line's path acceleration. */
static struct move_result run_move(double amax, const double dir[3],
				   double L, double F)
{
	struct sh2000_path_config c;
	struct sh2000_path *p;
	struct move_result r = { 0, 0, 0.0, 0.0 };
	double end[SH2000_AXES] = { 0 };
	char e[256];
	unsigned int a;
	int ret;

	sh2000_path_config_default(&c);
	for (a = 0; a < SH2000_AXES; a++) {
		c.vmax[a] = 400.0;
		c.amax[a] = amax;
	}
	assert_int_equal(sh2000_path_create(&p, &c, null_sink, NULL, e,
					    sizeof(e)), 0);
	assert_true(p->quant);
	assert_int_equal(sh2000_path_set_mode(p, SH2000_PATH_EXACT_PATH, 0, 0),
			 0);
	for (a = 0; a < 3; a++)
		end[a] = dir[a] * L;
	assert_int_equal(sh2000_path_line(p, end, F), 0);
	/* the family ramps in one period: only where J T >= A (a line in
	 * XY at 9000 mm/s^2 takes 11900 along the path, over J T) */
	if (p->blk[p->head].A > p->lim.J * c.period_s) {
		sh2000_path_destroy(p);
		return r;
	}
	r.fewest = family_periods(L, F, p->blk[p->head].A, c.period_s);
	do {
		double along = 0.0;

		ret = pl_period(p);
		assert_true(ret >= 0);
		r.periods++;
		for (a = 0; a < 3; a++)
			along += p->pos[a] * dir[a];
		r.past = fmax(r.past, along - L);
	} while (ret != 1 && r.periods < 100000);
	for (a = 0; a < SH2000_AXES; a++)
		r.off = fmax(r.off, fabs(p->pos[a] - end[a]));
	sh2000_path_destroy(p);
	return r;
}

/* Lengths from 10 um to 60 mm and feeds from 10 to 400 mm/s along X,
 * the XY diagonal and a line in XYZ, at the card model's amax (5000
 * mm/s^2) and at 2000 and 9000 (one jerk a period), where J T >= A. */
static void test_rest_to_rest_periods(void **s)
{
	static const double dirs[3][3] = {
		{ 1, 0, 0 }, { M_SQRT1_2, M_SQRT1_2, 0 },
		{ 0.6, 0.48, 0.64 },
	};
	static const double amaxes[3] = { 5000.0, 2000.0, 9000.0 };
	unsigned int moves = 0, fewer = 0, k, d;
	double past = 0.0, off = 0.0;

	(void)s;
	for (k = 0; k < 3; k++)
		for (d = 0; d < 3; d++)
			for (double F = 10.0; F <= 400.0; F *= 1.61)
				for (double L = 0.01; L <= 60.0; L *= 1.47) {
					struct move_result r =
						run_move(amaxes[k], dirs[d], L, F);

					if (!r.fewest)
						continue;
					if (r.periods > r.fewest)
						print_error("amax %g dir %u F %.17g L %.17g: %u periods, the family's least %u\n",
							    amaxes[k], d, F, L,
							    r.periods, r.fewest);
					assert_true(r.periods <= r.fewest);
					fewer += r.periods < r.fewest;
					past = fmax(past, r.past);
					off = fmax(off, r.off);
					moves++;
				}
	print_message("%u moves from rest to rest: none over the family's least periods, %u under it; end points within %.2g mm, never past by more than %.2g mm\n",
		      moves, fewer, off, past);
	assert_true(off <= 1e-12);
	assert_true(past <= 1e-12);
}

/* The benchmark's square: a 20 mm side at F6000 (100 mm/s) under G61 at
 * the card model's limits. */
static void test_square_side(void **s)
{
	static const double x[3] = { 1, 0, 0 };
	struct move_result r;

	(void)s;
	r = run_move(5000.0, x, 20.0, 100.0);
	print_message("square side 20 mm at 100 mm/s: %u periods (the family's least %u)\n",
		      r.periods, r.fewest);
	assert_int_equal(r.periods, r.fewest);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_rest_to_rest_periods),
		cmocka_unit_test(test_square_side),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
