// SPDX-License-Identifier: MIT
/*
 * Full feed on free-form curves, measured where the user sees it: the
 * butterfly and the free-form NURBS of tests/planner/curves.h, each from
 * rest to rest at one feed F, run through the card model and measured on
 * its fine set-points as the feed test measures them (feedcheck.h: every
 * servo cycle projected onto the exact curve, the arc length travelled).
 * One table row per curve, feed and output:
 *
 *  - L, the cycle time (the first servo cycle whose set-point moves to the
 *    last), L/F and their ratio;
 *  - the time at >= 99.9 % of F, per servo cycle (the compensated spline
 *    ripples within single cycles) and over 10 ms windows (the cycle
 *    counts when the 10 ms around it is), in seconds and as a share of
 *    the cycle time;
 *  - the peak speed over F, over 10 ms windows and per servo cycle;
 *  - the share of L where the planner's own curve limit (pl_curve_vlim():
 *    the centripetal share of the smallest amax, the chord tolerance, the
 *    normal jerk, the axes' vmax) allows F, against the share of L run at
 *    >= 99.9 % of F (10 ms windows).
 *
 * At the card model's limits (400 mm/s, 5000 mm/s^2, the default jerk),
 * then at the planner's defaults; compensated output, S-curve, and raw.
 * Prints figures; never fails on them.
 * Usage: bench_feed
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "curves.h"
#include "feedcheck.h"
#include "planner.h"

#define AT_FEED 0.999		/* "at the feed": >= 99.9 % of F */
#define CURVE_PIECES 20000	/* the curve limit, sampled */

struct bcase {
	const char *name;
	int bfly;		/* the butterfly, else the free-form curve */
	double feed;
};

static const struct bcase cases[] = {
	{ "butterfly", 1, 25 },
	{ "butterfly", 1, 100 },
	{ "butterfly", 1, 300 },
	{ "free-form", 0, 25 },
	{ "free-form", 0, 150 },
};

/* the case fc_run() is running (its program takes no argument) */
static const struct bcase *running;
static struct bfly bf;
static double ff_pts[FF_NPTS][4];
static struct sh2000_nurbs curve;

static int program(struct sh2000_path *p, struct fc_model *m,
		   const double o[4])
{
	curve = running->bfly ? bfly_nurbs(&bf, o) : ff_nurbs(ff_pts, o);
	if (fc_model_nurbs(m, &curve, running->feed))
		return -1;
	return sh2000_path_nurbs(p, &curve, running->feed);
}

/* The share of the curve's length where the planner's curve limit, at
 * path p's configuration, allows the feed. */
static double curve_allows(const struct sh2000_path *p, double feed)
{
	double u0 = sh2000_nurbs_umin(&curve), u1 = sh2000_nurbs_umax(&curve);
	double all = 0, fast = 0;

	for (unsigned int k = 0; k < CURVE_PIECES; k++) {
		double a = u0 + (u1 - u0) * k / CURVE_PIECES;
		double b = u0 + (u1 - u0) * (k + 1) / CURVE_PIECES;
		double c[4], d1[4], d2[4], t[4], v, dd = 0, cr = 0, kappa, ds;

		sh2000_nurbs_eval(&curve, 0.5 * (a + b), c, d1, d2);
		v = fc_norm4(d1);
		for (unsigned int i = 0; i < 4; i++) {
			t[i] = d1[i] / v;
			dd += d1[i] * d2[i];
			cr += d2[i] * d2[i];
		}
		/* |C' x C''| / |C'|^3, in four axes */
		kappa = sqrt(fmax(v * v * cr - dd * dd, 0)) / (v * v * v);
		ds = fc_nurbs_len(&curve, a, b);
		all += ds;
		if (pl_curve_vlim(p, t, kappa) >= feed)
			fast += ds;
	}
	return fast / all;
}

/* One row. */
static int row(const struct bcase *bc, const struct sh2000_path_config *c)
{
	static struct fc_run f;
	double L, T, LF, t_cyc = 0, t_win = 0, s_win = 0, share;
	size_t h = FC_WINDOW / 2;

	running = bc;
	if (fc_run(&f, c, program)) {
		printf("| %s | %.0f | %s | failed: %s |\n", bc->name, bc->feed,
		       c->output == SH2000_OUTPUT_RAW ? "raw" : "compensated",
		       f.msg);
		fc_close(&f);
		return -1;
	}
	L = fc_length(&f.m);
	T = (f.moved1 - f.moved0 + 1) * f.tau;
	LF = L / bc->feed;
	/* cycle i: from set-point i - 1 to i */
	for (size_t i = 1; i < f.n; i++) {
		double ds = f.s[i] - f.s[i - 1];
		double F = fc_feed_over(&f.m, f.s[i - 1], f.s[i]);

		if (ds / f.tau >= AT_FEED * F)
			t_cyc += f.tau;
		if (i - 1 >= h && i - 1 + h < f.n) {
			size_t j = i - 1 - h;

			F = fc_feed_over(&f.m, f.s[j], f.s[j + FC_WINDOW]);
			if (fc_speed(&f, j, FC_WINDOW) >= AT_FEED * F) {
				t_win += f.tau;
				s_win += ds;
			}
		}
	}
	share = curve_allows(f.p, bc->feed);
	printf("| %s | %.0f | %s | %.2f | %.3f | %.3f | %.4f | %.3f (%.1f %%) | %.3f (%.1f %%) | %.5f | %.5f | %.1f %% | %.1f %% |\n",
	       bc->name, bc->feed,
	       c->output == SH2000_OUTPUT_RAW ? "raw" : "compensated", L, T,
	       LF, T / LF, t_cyc, 100 * t_cyc / T, t_win, 100 * t_win / T,
	       1 + fc_overshoot(&f, FC_WINDOW), 1 + fc_overshoot(&f, 1),
	       100 * share, 100 * s_win / L);
	fc_close(&f);
	return 0;
}

static void table(const char *title, double vmax, double amax)
{
	struct sh2000_path_config c;

	sh2000_path_config_default(&c);
	for (unsigned int a = 0; vmax > 0 && a < 4; a++)
		c.vmax[a] = vmax;
	for (unsigned int a = 0; amax > 0 && a < 4; a++)
		c.amax[a] = amax;
	printf("\n%s: vmax %.0f mm/s, amax %.0f mm/s^2, jerk %.0f mm/s^3, S-curve\n\n",
	       title, c.vmax[0], c.amax[0], c.jerk);
	printf("| curve | F mm/s | output | L mm | cycle s | L/F s | cycle / (L/F) | >= 99.9 %% F, per cycle: s (of cycle) | >= 99.9 %% F, 10 ms: s (of cycle) | peak / F, 10 ms | peak / F, per cycle | L where the curve allows F | L at >= 99.9 %% F, 10 ms |\n");
	printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		c.output = SH2000_OUTPUT_COMPENSATED;
		(void)row(&cases[i], &c);
		c.output = SH2000_OUTPUT_RAW;
		(void)row(&cases[i], &c);
	}
}

int main(void)
{
	printf("Full feed on free-form curves, on the card model's set-points (servo cycle 100 us)\n");
	table("card model's limits", 400, 5000);
	table("planner's defaults", 0, 0);
	return 0;
}
