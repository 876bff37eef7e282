// SPDX-License-Identifier: MIT
/*
 * The DDA paper's [R3] DDA interpolator: lines in 3 axes and arcs in 2 end exactly
 * where they should with exactly |delta| pulses per axis, stay within a
 * count of the ideal geometry, half-loading halves the error, and
 * left-shift normalisation makes the pulses even (the fastest axis pulses
 * at least every second cycle) and the run shorter.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sh2000/path.h"
#include "dda.h"

struct line_dev {
	double a[3], d[3], dd;	/* start, direction, |direction|^2 */
	double max;
	unsigned int steps_bad;	/* a step moved an axis by more than 1 */
	int32_t last[3];
};

static void line_fn(void *ctx, const int32_t pos[3], unsigned int mask)
{
	struct line_dev *l = ctx;
	double t = 0, e = 0, q;
	unsigned int i;

	for (i = 0; i < 3; i++)
		t += (pos[i] - l->a[i]) * l->d[i];
	t /= l->dd;
	for (i = 0; i < 3; i++) {
		q = l->a[i] + t * l->d[i] - pos[i];
		e += q * q;
		if (abs(pos[i] - l->last[i]) > 1 ||
		    ((mask >> i) & 1) != (pos[i] != l->last[i]))
			l->steps_bad++;
		l->last[i] = pos[i];
	}
	l->max = fmax(l->max, sqrt(e));
}

static void run_line(const int32_t s[3], const int32_t e[3], int half,
		     int norm, struct sh2000_dda_result *res,
		     struct line_dev *l)
{
	struct sh2000_dda_config cfg = { 16, half, norm };
	unsigned int i;

	memset(l, 0, sizeof(*l));
	for (i = 0; i < 3; i++) {
		l->a[i] = s[i];
		l->d[i] = (double)e[i] - s[i];
		l->dd += l->d[i] * l->d[i];
		l->last[i] = s[i];
	}
	assert_int_equal(sh2000_dda_line(&cfg, s, e, line_fn, l, res), 0);
	assert_memory_equal(res->end, e, sizeof(res->end));
	for (i = 0; i < 3; i++)
		assert_int_equal(res->pulses[i], (uint64_t)abs(e[i] - s[i]));
	assert_int_equal(l->steps_bad, 0);
}

static void test_dda_line(void **st)
{
	/* the DDA paper's examples: (0,0,0) -> (10,12,0), and a triangle */
	static const int32_t pts[][3] = {
		{ 0, 0, 0 }, { 10, 12, 0 }, { 15, 6, 0 }, { 0, 0, 0 },
		{ -300, 7, 1200 }, { 5, -4000, 13 },
	};
	unsigned int i;

	(void)st;
	for (i = 1; i < sizeof(pts) / sizeof(pts[0]); i++) {
		struct sh2000_dda_result plain, half, norm;
		struct line_dev lp, lh, ln;

		run_line(pts[i - 1], pts[i], 0, 0, &plain, &lp);
		run_line(pts[i - 1], pts[i], 1, 0, &half, &lh);
		run_line(pts[i - 1], pts[i], 1, 1, &norm, &ln);
		/* truncation: under one count per axis; rounding: half */
		assert_true(lp.max < sqrt(3.0));
		assert_true(lh.max <= 0.5 * sqrt(3.0) + 1e-9);
		assert_true(ln.max <= 0.5 * sqrt(3.0) + 1e-9);
		/* 2^bits cycles without normalisation, far fewer with */
		assert_true(plain.iterations <= 65536);
		assert_true(norm.iterations < plain.iterations ||
			    plain.iterations < 4);
		/* normalised: a pulse at least every second cycle */
		assert_true(norm.max_gap <= 1);
		print_message("line %u: plain %llu cycles (gap %llu, dev %.3f), half dev %.3f, normalised %llu cycles (gap %llu)\n",
			      i, (unsigned long long)plain.iterations,
			      (unsigned long long)plain.max_gap, lp.max, lh.max,
			      (unsigned long long)norm.iterations,
			      (unsigned long long)norm.max_gap);
	}
}

struct arc_dev {
	double cx, cy, r;
	double max;
	uint64_t n;
};

static void arc_fn(void *ctx, const int32_t pos[3], unsigned int mask)
{
	struct arc_dev *a = ctx;

	(void)mask;
	a->max = fmax(a->max, fabs(hypot(pos[0] - a->cx, pos[1] - a->cy) - a->r));
	a->n++;
}

static void test_dda_arc(void **st)
{
	struct sh2000_dda_config cfg = { 16, 1, 1 };
	struct sh2000_dda_result res;
	struct arc_dev d;
	int32_t c[2] = { 0, 0 }, s[2], e[2];
	int ccw;

	(void)st;
	/* the DDA paper's quarter: (15,0) -> (0,15) ccw; and R 5, 8 */
	for (ccw = 0; ccw <= 1; ccw++) {
		static const int32_t R[] = { 5, 8, 15, 1000, 20000 };
		unsigned int i;

		for (i = 0; i < sizeof(R) / sizeof(R[0]); i++) {
			s[0] = R[i];
			s[1] = 0;
			e[0] = 0;
			e[1] = ccw ? R[i] : -R[i];
			memset(&d, 0, sizeof(d));
			d.r = R[i];
			assert_int_equal(sh2000_dda_arc(&cfg, c, s, e, ccw, arc_fn,
							&d, &res), 0);
			assert_int_equal(res.end[0], e[0]);
			assert_int_equal(res.end[1], e[1]);
			assert_int_equal(res.pulses[0], (uint64_t)R[i]);
			assert_int_equal(res.pulses[1], (uint64_t)R[i]);
			print_message("arc R %d %s: %.3f counts off the circle, %llu cycles\n",
				      R[i], ccw ? "ccw" : "cw", d.max,
				      (unsigned long long)res.iterations);
			assert_true(d.max <= 2.0);
			/* full circle: start == end */
			memset(&d, 0, sizeof(d));
			d.r = R[i];
			assert_int_equal(sh2000_dda_arc(&cfg, c, s, s, ccw, arc_fn,
							&d, &res), 0);
			assert_int_equal(res.end[0], s[0]);
			assert_int_equal(res.end[1], s[1]);
			assert_int_equal(res.pulses[0], 4 * (uint64_t)R[i]);
			assert_int_equal(res.pulses[1], 4 * (uint64_t)R[i]);
			print_message("circle R %d %s: %.3f counts off\n", R[i],
				      ccw ? "ccw" : "cw", d.max);
			assert_true(d.max <= 2.0);
		}
	}
	/* an arc off the axes, centre not at the origin */
	c[0] = 100;
	c[1] = -50;
	s[0] = 100 + 300;
	s[1] = -50 + 400;
	e[0] = 100 - 400;
	e[1] = -50 - 300;
	memset(&d, 0, sizeof(d));
	d.cx = 100;
	d.cy = -50;
	d.r = 500;
	assert_int_equal(sh2000_dda_arc(&cfg, c, s, e, 1, arc_fn, &d, &res), 0);
	assert_int_equal(res.end[0], e[0]);
	assert_int_equal(res.end[1], e[1]);
	assert_true(d.max <= 2.0);
}

static void test_dda_bad(void **st)
{
	struct sh2000_dda_config cfg = { 8, 1, 1 };
	struct sh2000_dda_result res;
	int32_t s[3] = { 0, 0, 0 }, e[3] = { 300, 0, 0 };
	int32_t c[2] = { 0, 0 }, a[2] = { 10, 0 }, b[2] = { 0, 20 };

	(void)st;
	assert_int_equal(sh2000_dda_line(&cfg, s, e, NULL, NULL, &res), -ERANGE);
	cfg.bits = 1;
	assert_int_equal(sh2000_dda_line(&cfg, s, e, NULL, NULL, &res), -EINVAL);
	cfg.bits = 16;
	assert_int_equal(sh2000_dda_arc(&cfg, c, a, b, 1, NULL, NULL, &res),
			 -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_dda_line),
		cmocka_unit_test(test_dda_arc),
		cmocka_unit_test(test_dda_bad),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
