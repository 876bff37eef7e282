// SPDX-License-Identifier: MIT
/*
 * Feed exact on the card: the card model's fine set-points (every servo
 * cycle), projected onto the exact geometry of the program, move along it
 * no faster than the programmed feed plus 0.01 %, measured as arc length
 * over 10 ms windows (and reported per servo cycle), and no axis exceeds
 * its vmax or amax -- on lines, arcs and NURBS, with speed changes, in
 * compensated and raw output. Measured where the user sees it: on what the
 * card commands, not on the planned points (feedcheck.h).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "feedcheck.h"

#define FEED_SLACK 1e-4		/* 0.01 % */

/* amax: every axis' (0: the planner's default). Returns the fastest
 * 10 ms window's speed over the feed (a fraction). */
static double measure_cfg(const char *name, fc_program_fn prog, int raw,
			  int trap, double amax)
{
	static struct fc_run f;
	struct sh2000_path_config c;
	double win, cyc;

	sh2000_path_config_default(&c);
	for (unsigned int a = 0; amax > 0 && a < 4; a++)
		c.amax[a] = amax;
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
static const double ff_ctrl[8][4] = {
	{ 0, 0, 0, 0 }, { 5, 10, 0, 0 }, { 10, -5, 1, 0 }, { 15, 8, 2, 0 },
	{ 20, 0, 2, 0 }, { 22, 12, 1, 0 }, { 30, 5, 0, 0 }, { 32, 0, 0, 0 },
};
static const double ff_w[8] = { 1, 2, 0.5, 1, 3, 1, 1, 1 };
static const double ff_k[12] = { 0, 0, 0, 0, 0.2, 0.4, 0.5, 0.8, 1, 1, 1, 1 };

static int prog_nurbs(struct sh2000_path *p, struct fc_model *m,
		      const double o[4])
{
	static double pts[2][8][4];
	static const double feeds[2] = { 25, 150 };

	for (unsigned int k = 0; k < 2; k++) {
		struct sh2000_nurbs n = { 3, 8, (const double (*)[4])pts[k],
					  ff_w, ff_k };

		for (unsigned int i = 0; i < 8; i++)
			for (unsigned int a = 0; a < 4; a++)
				pts[k][i][a] = (k ? m->end[a] : o[a]) +
					       ff_ctrl[i][a];
		m->u = 0;
		if (fc_model_nurbs(m, &n, feeds[k]) ||
		    sh2000_path_nurbs(p, &n, feeds[k]))
			return -1;
	}
	return 0;
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

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_feed_lines),
		cmocka_unit_test(test_feed_arcs),
		cmocka_unit_test(test_feed_nurbs),
		cmocka_unit_test(test_feed_period_jerk),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
