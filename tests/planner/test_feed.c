// SPDX-License-Identifier: MIT
/*
 * Feed exact on the card: the card model's fine set-points (every servo
 * cycle), projected onto the exact geometry of the program, move along it
 * no faster than the programmed feed plus 0.01 %, measured as arc length
 * over 10 ms windows (and reported per servo cycle), and no axis exceeds
 * its vmax or amax -- on lines, arcs and NURBS (the free-form curve and
 * the butterfly of curves.h), with speed changes, in compensated and raw
 * output. Measured where the user sees it: on what the card commands, not
 * on the planned points (feedcheck.h).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "curves.h"
#include "feedcheck.h"

#define FEED_SLACK 1e-4		/* 0.01 % */

/* vmax, amax: every axis' (0: the planner's default). Returns the fastest
 * 10 ms window's speed over the feed (a fraction). */
static double measure_lim(const char *name, fc_program_fn prog, int raw,
			  int trap, double vmax, double amax)
{
	static struct fc_run f;
	struct sh2000_path_config c;
	double win, cyc;

	sh2000_path_config_default(&c);
	for (unsigned int a = 0; a < 4; a++) {
		if (vmax > 0)
			c.vmax[a] = vmax;
		if (amax > 0)
			c.amax[a] = amax;
	}
	c.output = raw ? SH2000_OUTPUT_RAW : SH2000_OUTPUT_COMPENSATED;
	if (trap)
		c.profile = SH2000_PROFILE_TRAPEZOID;
	if (fc_run(&f, &c, prog))
		fail_msg("%s: %s", name, f.msg);
	win = fc_overshoot(&f, FC_WINDOW);
	cyc = fc_overshoot(&f, 1);
	print_message("%-24s %-11s %-9s %5.0f feed over programmed: %+.5f %% (10 ms), %+.4f %% (one cycle); axis v %.3f, a %.3f of the limits\n",
		      name, raw ? "raw" : "compensated",
		      trap ? "trapezoid" : "S-curve", f.cfg.amax[0], win * 100,
		      cyc * 100, f.v_ratio, f.a_ratio);
	if (win > FEED_SLACK)
		fail_msg("%s: the card's set-points run %.4f %% over the feed",
			 name, win * 100);
	assert_true(f.v_ratio <= 1.0);
	assert_true(f.a_ratio <= 1.0);
	fc_close(&f);
	return win;
}

static double measure_cfg(const char *name, fc_program_fn prog, int raw,
			  int trap, double amax)
{
	return measure_lim(name, prog, raw, trap, 0, amax);
}

static void measure(const char *name, fc_program_fn prog, int raw)
{
	(void)measure_cfg(name, prog, raw, 0, 0);
}

/* ---- programs ------------------------------------------------------------ */

/* Collinear lines at 300, 100, 250, 50 and 300 mm/s: every speed change
 * happens on a straight path, the feeds exactly programmed. */
static int prog_lines(struct sh2000_path *p, struct fc_model *m,
		      const double o[4])
{
	static const double feeds[5] = { 300, 100, 250, 50, 300 };
	double e[4];

	memcpy(e, o, sizeof(e));
	for (unsigned int i = 0; i < 5; i++) {
		e[0] += 20;
		e[1] += 10;
		if (fc_model_line(m, e, feeds[i]) ||
		    sh2000_path_line(p, e, feeds[i]))
			return -1;
	}
	return 0;
}

/* Two half circles R 10 at 300 then 120 mm/s, and back at 300. */
static int prog_arcs(struct sh2000_path *p, struct fc_model *m,
		     const double o[4])
{
	static const double feeds[3] = { 300, 120, 300 };
	struct sh2000_path_arc a;

	memset(&a, 0, sizeof(a));
	a.plane = SH2000_PLANE_XY;
	memcpy(a.end, o, sizeof(a.end));
	for (unsigned int i = 0; i < 3; i++) {
		a.ccw = 1;
		a.centre[0] = m->end[0] + (i % 2 ? -10 : 10);
		a.centre[1] = m->end[1];
		a.end[0] = m->end[0] + (i % 2 ? -20 : 20);
		if (fc_model_arc(m, &a, feeds[i]) ||
		    sh2000_path_arc(p, &a, feeds[i]))
			return -1;
	}
	return 0;
}

/* The free-form curve of the planner's tests at 25 mm/s (where the
 * curvature changes the speed) and then at 150 mm/s. */
static int prog_nurbs(struct sh2000_path *p, struct fc_model *m,
		      const double o[4])
{
	static double pts[2][FF_NPTS][4];
	static const double feeds[2] = { 25, 150 };

	for (unsigned int k = 0; k < 2; k++) {
		struct sh2000_nurbs n = ff_nurbs(pts[k], k ? m->end : o);

		m->u = 0;
		if (fc_model_nurbs(m, &n, feeds[k]) ||
		    sh2000_path_nurbs(p, &n, feeds[k]))
			return -1;
	}
	return 0;
}

/* The butterfly at feed F, from rest to rest. */
static int prog_bfly(struct sh2000_path *p, struct fc_model *m,
		     const double o[4], double feed)
{
	static struct bfly b;
	struct sh2000_nurbs n = bfly_nurbs(&b, o);

	m->u = 0;
	if (fc_model_nurbs(m, &n, feed) || sh2000_path_nurbs(p, &n, feed))
		return -1;
	return 0;
}

static int prog_bfly_25(struct sh2000_path *p, struct fc_model *m,
			const double o[4])
{
	return prog_bfly(p, m, o, 25);
}

static int prog_bfly_300(struct sh2000_path *p, struct fc_model *m,
			 const double o[4])
{
	return prog_bfly(p, m, o, 300);
}

static void test_feed_lines(void **s)
{
	(void)s;
	measure("lines, 5 feeds", prog_lines, 0);
	measure("lines, 5 feeds", prog_lines, 1);
	(void)measure_cfg("lines, 5 feeds", prog_lines, 0, 1, 0);
	(void)measure_cfg("lines, 5 feeds", prog_lines, 1, 1, 0);
}

static void test_feed_arcs(void **s)
{
	(void)s;
	measure("arcs R 10, 3 feeds", prog_arcs, 0);
	measure("arcs R 10, 3 feeds", prog_arcs, 1);
	(void)measure_cfg("arcs R 10, 3 feeds", prog_arcs, 0, 1, 0);
}

static void test_feed_nurbs(void **s)
{
	(void)s;
	measure("free-form NURBS, 25/150", prog_nurbs, 0);
	measure("free-form NURBS, 25/150", prog_nurbs, 1);
}

/* At the card model's 5000 mm/s^2, where the S-curve ramps within a
 * period and the controller holds one jerk a whole period (control.c):
 * the compensated spline then follows the plan itself, and the cruise is
 * the programmed feed, which the card's set-points reach within 0.01 %
 * (the fastest 10 ms window) as well as never pass by more. */
static void test_feed_period_jerk(void **s)
{
	(void)s;
	assert_true(measure_cfg("lines, 5 feeds", prog_lines, 0, 0, 5000) >=
		    -FEED_SLACK);
	assert_true(measure_cfg("arcs R 10, 3 feeds", prog_arcs, 0, 0,
				5000) >= -FEED_SLACK);
	assert_true(measure_cfg("free-form NURBS, 25/150", prog_nurbs, 0, 0,
				5000) >= -FEED_SLACK);
}

/* The butterfly can be planned as one curve: its derivative never
 * vanishes (the planner refuses a curve that stands still) and its
 * tangent never turns back (a cusp), sampled 20000 times: between two
 * samples it turns by at most 0.0125 rad (at the loops beside the body),
 * where a cusp would turn it by half a turn. */
static void test_butterfly_shape(void **s)
{
	static const double o[4] = { 0, 0, 0, 0 };
	struct bfly b;
	struct sh2000_nurbs n = bfly_nurbs(&b, o);
	double c[4], d[4], t0[4] = { 0 }, vmin = INFINITY, cmin = 1;

	(void)s;
	assert_int_equal(sh2000_nurbs_check(&n, NULL, 0), 0);
	for (unsigned int k = 0; k <= 20000; k++) {
		double v, dot = 0;

		sh2000_nurbs_eval(&n, k / 20000.0, c, d, NULL);
		v = fc_norm4(d);
		vmin = fmin(vmin, v);
		for (unsigned int a = 0; a < 4; a++) {
			dot += t0[a] * d[a] / v;
			t0[a] = d[a] / v;
		}
		if (k)
			cmin = fmin(cmin, dot);
	}
	print_message("butterfly: |C'(u)| >= %.2f mm, the tangent turns by at most %.4f rad a sample\n",
		      vmin, acos(cmin));
	assert_true(vmin > 40);
	assert_true(cmin > cos(0.1));
}

/* The butterfly at the card model's limits (400 mm/s, 5000 mm/s^2, the
 * default jerk), compensated, S-curve, at 25 mm/s (the curvature slows it
 * only at the two small loops beside the body) and 300 mm/s (which it
 * allows on half the length): never over the feed, and the fastest 10 ms
 * window at it within 0.01 %. */
static void test_feed_butterfly(void **s)
{
	(void)s;
	assert_true(measure_lim("butterfly, 25", prog_bfly_25, 0, 0, 400,
				5000) >= -FEED_SLACK);
	assert_true(measure_lim("butterfly, 300", prog_bfly_300, 0, 0, 400,
				5000) >= -FEED_SLACK);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_feed_lines),
		cmocka_unit_test(test_feed_arcs),
		cmocka_unit_test(test_feed_nurbs),
		cmocka_unit_test(test_feed_period_jerk),
		cmocka_unit_test(test_butterfly_shape),
		cmocka_unit_test(test_feed_butterfly),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
