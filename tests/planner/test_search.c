// SPDX-License-Identifier: MIT
/*
 * The controller's search (search.c): the highest x with f(x) >= 0 for a
 * non-increasing f, to within tol. Checked against what it must equal --
 * a 60-step bisection on the sign, the exact boundary -- on the shapes the
 * controller's room function takes: smooth, zero at the lower end, a flat
 * room that drops (cruising at a limit), a kink between two conditions
 * in different units, a jump. And against the previous method (false
 * position with the Illinois fix and a bisection every third step) for
 * the number of evaluations: the answer is the same to within tol, the
 * cost must not be higher on any shape and is much lower where the
 * controller spends its time (smooth zeros, zeros at the lower end).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "planner.h"

enum shape { SMOOTH, CUBIC, AT_LOW_END, PLATEAU, KINK, JUMP };

static const char *const shape_name[] = { "smooth", "steep cubic",
					  "zero at lo", "plateau", "kink",
					  "jump" };

struct fn {
	enum shape s;
	double r;		/* the boundary */
	double k;		/* a shape parameter */
	unsigned int evals;
};

static double f_at(const void *ctx, double x)
{
	struct fn *f = (struct fn *)ctx;
	double d = f->r - x;

	f->evals++;
	switch (f->s) {
	case SMOOTH:		/* a room that shrinks quadratically, up
				 * to 3 times faster at one end */
		return d + 0.02 * f->k * d * fabs(d);
	case CUBIC:		/* up to 150 times steeper at one end */
		return d * (1.0 + f->k * d * d) + 0.3 * d * fabs(d);
	case AT_LOW_END:	/* the controller exactly on a braking curve */
		return d <= 0.0 ? 2.0 * d : 0.0 * d;
	case PLATEAU:		/* a constant room, then a drop */
		return d >= 0.0 ? 1e-9 : 5.0 * d - 1e-3;
	case KINK:		/* mm near the zero, mm/s above it */
		return fmin(1e-3 * d, f->k * (d + 0.05));
	default:		/* JUMP */
		return d >= 0.0 ? 1e-4 + d : -f->k + d;
	}
}

/* The exact boundary: 60 halvings on the sign alone. */
static double boundary(struct fn *f, double lo, double hi)
{
	unsigned int i;

	for (i = 0; i < 60; i++) {
		double m = 0.5 * (lo + hi);

		if (f_at(f, m) >= 0.0)
			lo = m;
		else
			hi = m;
	}
	return lo;
}

/* The method search.c replaced, for the evaluation count. */
static double previous(struct fn *f, double lo, double hi)
{
	double flo = f_at(f, lo), fhi = f_at(f, hi), tol = (hi - lo) / 65536.0;
	int side = 0, it;

	for (it = 0; it < 40 && hi - lo > tol; it++) {
		double m = it % 3 == 2 || !(flo - fhi > 0.0) ?
			   0.5 * (lo + hi) : (lo * fhi - hi * flo) / (fhi - flo);
		double fm;

		if (!(m > lo && m < hi))
			m = 0.5 * (lo + hi);
		fm = f_at(f, m);
		if (fm >= 0.0) {
			lo = m;
			flo = fm;
			if (side > 0)
				fhi *= 0.5;
			side = 1;
		} else {
			hi = m;
			fhi = fm;
			if (side < 0)
				flo *= 0.5;
			side = -1;
		}
	}
	return lo;
}

static double frnd(unsigned int *st, double lo, double hi)
{
	*st = *st * 1103515245u + 12345u;
	return lo + (hi - lo) * ((*st >> 8) & 0xffffff) / 16777216.0;
}

static void check_shape(enum shape s, double max_mean_evals)
{
	const double lo = -1.0, hi = 1.0, tol = (hi - lo) / 65536.0;
	unsigned int st = 11 + s, i, n = 2000;
	double evals = 0.0, prev_evals = 0.0;
	unsigned int prev_misses = 0, most = 0;

	for (i = 0; i < n; i++) {
		struct fn f = { s, frnd(&st, -0.99, 0.99), frnd(&st, 0.1, 50), 0 };
		double flo, fhi, x, b;

		if (s == AT_LOW_END)
			f.r = lo;
		b = boundary(&f, lo, hi);
		flo = f_at(&f, lo);
		fhi = f_at(&f, hi);
		assert_true(flo >= 0.0 && fhi < 0.0);
		f.evals = 0;
		x = pl_highest_pass(f_at, &f, lo, hi, flo, fhi, tol);
		evals += f.evals;
		most = f.evals > most ? f.evals : most;
		/* it passes, and the boundary is within tol above it */
		assert_true(f_at(&f, x) >= 0.0);
		if (!(x <= b && b - x <= tol))
			fail_msg("%s: r %.17g: found %.17g, boundary %.17g",
				 shape_name[s], f.r, x, b);
		/* the previous method, from its own two end evaluations */
		f.evals = 0;
		x = previous(&f, lo, hi);
		prev_evals += f.evals - 2.0;
		prev_misses += !(x <= b && b - x <= tol);
	}
	evals /= n;
	prev_evals /= n;
	print_message("%-11s evaluations: %5.2f, at most %2u (previous method %5.2f, off by more than tol %u times in %u)\n",
		      shape_name[s], evals, most, prev_evals, prev_misses, n);
	assert_true(evals <= max_mean_evals);
	/* the bisection's 16 steps and 6 more, whatever the shape */
	assert_true(most <= 22);
	assert_true(evals <= prev_evals);
}

static void test_smooth(void **s)
{
	(void)s;
	check_shape(SMOOTH, 6.0);
	check_shape(CUBIC, 16.0);
}

static void test_zero_at_lower_end(void **s)
{
	(void)s;
	check_shape(AT_LOW_END, 2.0);
}

/* Shapes where interpolation has little to go on (a kink is two straight
 * pieces, which the secant takes in two steps): at most 6 steps more than
 * the bisection's 16, and no more than the previous method. */
static void test_plateau_kink_jump(void **s)
{
	(void)s;
	check_shape(PLATEAU, 22.0);
	check_shape(KINK, 3.0);
	check_shape(JUMP, 22.0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_smooth),
		cmocka_unit_test(test_zero_at_lower_end),
		cmocka_unit_test(test_plateau_kink_jump),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
