// SPDX-License-Identifier: MIT
/*
 * The profile arithmetic the look-ahead rests on: pl_reach_back() is the
 * exact inverse of pl_trans_len() (the start speed of a transition of a
 * given length), in both S-curve regimes (below and at the acceleration
 * limit) and for the trapezoid, and pl_brake_dist() agrees with
 * pl_trans_len() from rest acceleration.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "planner.h"

static double frnd(unsigned int *st, double lo, double hi)
{
	*st = *st * 1103515245u + 12345u;
	return lo + (hi - lo) * ((*st >> 8) & 0xffffff) / 16777216.0;
}

static void check_inverse(const struct pl_limits *lim, unsigned int n)
{
	unsigned int st = 7, i, below = 0, at = 0;

	for (i = 0; i < n; i++) {
		double v1 = i % 5 ? frnd(&st, 0, 500) : 0.0;
		double L = exp(frnd(&st, log(1e-5), log(50)));
		double v0 = pl_reach_back(lim, v1, L);
		double back = pl_trans_len(lim, v0, v1);
		/* what rounding v0 to a double may change in the length:
		 * dL/d(dv) is about L / (2 dv) for small dv, L / dv at most */
		double dv = v0 - v1;
		double tol = 1e-9 * L +
			     (dv > 0 ? L / dv * v0 * 4.5e-16 : 0);

		assert_true(v0 >= v1);
		/* the transition from v0 fits L exactly */
		if (fabs(back - L) > tol)
			fail_msg("v1 %g L %g: v0 %.17g gives %.17g", v1, L, v0,
				 back);
		/* and it agrees with the braking distance */
		assert_true(fabs(pl_brake_dist(lim, v0, 0.0, v1) - L) <
			    1e-7 * L + 10 * tol);
		if (!isinf(lim->J) && v0 - v1 < lim->A * lim->A / lim->J)
			below++;
		else
			at++;
	}
	/* both regimes were exercised */
	if (!isinf(lim->J))
		assert_true(below > n / 10 && at > n / 10);
}

static void test_reach_back_scurve(void **s)
{
	struct pl_limits lim = { .A = 23750, .J = 4.75e6 };

	(void)s;
	check_inverse(&lim, 100000);
}

static void test_reach_back_trapezoid(void **s)
{
	struct pl_limits lim = { .A = 1000, .J = INFINITY };

	(void)s;
	check_inverse(&lim, 10000);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_reach_back_scurve),
		cmocka_unit_test(test_reach_back_trapezoid),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
