// SPDX-License-Identifier: MIT
/* The paper's B-spline: equal points, end values, continuity of value,
 * slope and curvature across window shifts. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "sh2000/bspline.h"

static void equal_points(void **state)
{
	double t;

	(void)state;
	for (t = 0.0; t <= 1.0; t += 0.05)
		assert_true(sh2000_bspline(7.0, 7.0, 7.0, 7.0, t) == 7.0);
	assert_true(sh2000_bspline(1e7, 1e7, 1e7, 1e7, 1.0) == 1e7);
}

static void end_values(void **state)
{
	(void)state;
	/* x(0) = (x0+4x1+x2)/6, x(1) = (x1+4x2+x3)/6 */
	assert_true(fabs(sh2000_bspline(1, 2, 4, 8, 0.0) - 13.0 / 6.0) < 1e-12);
	assert_true(fabs(sh2000_bspline(1, 2, 4, 8, 1.0) - 26.0 / 6.0) < 1e-12);
	/* a line is reproduced */
	assert_true(fabs(sh2000_bspline(0, 10, 20, 30, 0.5) - 15.0) < 1e-12);
	/* (p, e, e, e) ends at e: the END padding */
	assert_true(fabs(sh2000_bspline(3, 100, 100, 100, 1.0) - 100.0) < 1e-9);
}

static void continuity(void **state)
{
	const double p[8] = { 0, 3, -2, 10, 50, 40, 41, 39 };
	unsigned int i;

	(void)state;
	for (i = 0; i + 4 < 8; i++) {
		const double *w = &p[i], *n = &p[i + 1];

		assert_true(fabs(sh2000_bspline(w[0], w[1], w[2], w[3], 1) -
				 sh2000_bspline(n[0], n[1], n[2], n[3], 0)) < 1e-9);
		assert_true(fabs(sh2000_bspline_d1(w[0], w[1], w[2], w[3], 1) -
				 sh2000_bspline_d1(n[0], n[1], n[2], n[3], 0)) < 1e-9);
		assert_true(fabs(sh2000_bspline_d2(w[0], w[1], w[2], w[3], 1) -
				 sh2000_bspline_d2(n[0], n[1], n[2], n[3], 0)) < 1e-9);
	}
}

static void derivatives(void **state)
{
	const double h = 1e-6;
	double t;

	(void)state;
	for (t = 0.1; t < 1.0; t += 0.2) {
		double d = (sh2000_bspline(1, 5, 2, 9, t + h) -
			    sh2000_bspline(1, 5, 2, 9, t - h)) / (2 * h);
		double d2 = (sh2000_bspline_d1(1, 5, 2, 9, t + h) -
			     sh2000_bspline_d1(1, 5, 2, 9, t - h)) / (2 * h);

		assert_true(fabs(d - sh2000_bspline_d1(1, 5, 2, 9, t)) < 1e-5);
		assert_true(fabs(d2 - sh2000_bspline_d2(1, 5, 2, 9, t)) < 1e-5);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(equal_points),
		cmocka_unit_test(end_values),
		cmocka_unit_test(continuity),
		cmocka_unit_test(derivatives),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
