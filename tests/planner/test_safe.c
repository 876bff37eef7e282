/* SPDX-License-Identifier: MIT */
/*
 * Inputs that once made wrong motion, planned as sh2000-upload plans a
 * program, with the card's fine set-points checked against the axes'
 * limits and the program's geometry (spcheck.h):
 *  - arcs whose radius or sweep the geometry cannot resolve (R1e18 became
 *    a whole circle of that radius, R1e17 ran 9 mm past the arc's end)
 *    are refused by the planner's own API too;
 *  - a NURBS whose start point is repeated and whose last weight is tiny:
 *    the arc length on entering the curve was inverted by unbracketed
 *    Newton steps, and the first period from rest jumped 0.356 mm;
 *  - short rest-to-rest moves in compensated output: the interpolating
 *    spline overshot the end point (2.4 um for G0 X0.06 with the
 *    trapezoid) and started backwards;
 *  - arcs of enormous radius whose ends differ in radius: planned as
 *    if they were as short as their sweep, they reached 90 times amax;
 *  - a feed lowered a little on a short last move: the limit it set,
 *    already in force, bound the braking to the stop, which overran;
 *  - short moves braking into a stop beyond a blend at the planner's
 *    default limits: the controller still accelerated when it reached
 *    the blend and braked at 3.2 times an axis' amax; and a blend at full
 *    speed there, which the card's spline passed 2 um beyond.
 *  - a jerk limit far above what a period can use: compensated output
 *    planned slower than at the card model's jerk (3D_Chips 8 % at 5e7)
 *    and passed amax, and a stop a hair nearer than the controller's
 *    search could step stood still for ever (raw output at 5e8, or
 *    50000 mm/s^2 at 5e8: every program at its last stop).
 *  - a slow axis a program never moves bounded its plan (the least amax
 *    of all four axes set the path's share of the acceleration): held
 *    still, it bounds nothing, and a block that moves it is refused.
 *  - short blended moves braking into a drop passed amax (1.0245): the
 *    first pass as the front ends run it plans again with a smaller
 *    margin (sh2000_program_check()).
 * And the check itself: spcheck's distance from a set-point to the path
 * is the nearest segment's, wherever the last match was.
 * `build/x/tests/planner/test_safe` prints what it measured.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include <sh2000/run.h>

#include "spcheck.h"

/* What a planned program did on the card. */
struct run {
	struct sp_check sp;
	struct sp_path path;
	double lo[SH2000_AXES], hi[SH2000_AXES];	/* fine set-points' range */
	double back[SH2000_AXES];	/* largest step back of a fine point */
	double rec_lo, rec_hi;	/* range of the records on X */
	double first_step;	/* largest axis step of the first record, mm */
	double start[SH2000_AXES];
	size_t points;
	uint64_t hash;		/* of every record's counts, in order */
};

/* Every fine set-point: the range, and how far one steps back from the
 * one before (in the direction the axis has gone so far). */
static void run_fine(void *ctx, const double y[SH2000_AXES])
{
	struct run *r = ctx;
	unsigned int k;

	for (k = 0; k < SH2000_AXES; k++) {
		double last = r->sp.x[2][k], sgn = last - r->start[k];

		if (sgn != 0)
			r->back[k] = fmax(r->back[k],
					  sgn > 0 ? last - y[k] : y[k] - last);
		r->lo[k] = fmin(r->lo[k], y[k]);
		r->hi[k] = fmax(r->hi[k], y[k]);
	}
}

static int run_sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct run *r = ctx;
	unsigned int k;

	if (r->points++ == 0)
		for (k = 0; k < SH2000_AXES; k++)
			r->first_step = fmax(r->first_step,
					     fabs(pt->mm[k] - r->start[k]));
	for (k = 0; k < SH2000_AXES; k++)	/* FNV-1a */
		r->hash = (r->hash ^ (uint32_t)pt->counts[k]) *
			  1099511628211ull;
	r->rec_lo = fmin(r->rec_lo, pt->mm[0]);
	r->rec_hi = fmax(r->rec_hi, pt->mm[0]);
	sp_point(&r->sp, pt);
	return 0;
}

/* Read a program of format fmt and plan it with cfg; the set-points
 * checked within tol of the program's path. 0 or the planner's error. */
static int plan_text(int fmt, const char *text,
		     const struct sh2000_path_config *cfg, double tol,
		     struct run *r)
{
	struct sh2000_program prog;
	struct sh2000_prog_diags d;
	struct sh2000_path *p;
	int ret;

	memset(r, 0, sizeof(*r));
	sh2000_program_init(&prog);
	sh2000_prog_diags_init(&d);
	ret = sh2000_program_read(&prog, fmt, "t.ngc", text, strlen(text),
				  NULL, &d);
	if (ret)
		sh2000_prog_diags_print(&d, stderr);
	assert_int_equal(ret, 0);
	assert_int_equal(sp_path_build(&r->path, &prog), 0);
	memcpy(r->start, cfg->start, sizeof(r->start));
	memcpy(r->lo, cfg->start, sizeof(r->lo));
	memcpy(r->hi, cfg->start, sizeof(r->hi));
	sp_init(&r->sp, cfg, cfg->start, &r->path, tol);
	r->sp.each = run_fine;
	r->sp.each_ctx = r;
	assert_int_equal(sh2000_path_create(&p, cfg, run_sink, r, NULL, 0), 0);
	for (size_t i = 0; i < prog.count && !ret; i++)
		ret = sh2000_path_add_block(p, &prog.blocks[i]);
	if (!ret)
		ret = sh2000_path_finish(p);
	if (ret)
		fprintf(stderr, "planner: %s\n", sh2000_path_error(p));
	sh2000_path_destroy(p);
	sh2000_program_free(&prog);
	sh2000_prog_diags_free(&d);
	return ret;
}

static int plan_gcode(const char *text, const struct sh2000_path_config *cfg,
		      double tol, struct run *r)
{
	return plan_text(SH2000_PROG_GCODE, text, cfg, tol, r);
}

/* The planner's defaults at the scale the fuzz harness plans at (1000
 * counts/mm), with every axis at the card model's default limits (400
 * mm/s, 5000 mm/s^2, docs/cardmodel.md) when card is set. */
static void harness_config(struct sh2000_path_config *cfg, int card)
{
	sh2000_path_config_default(cfg);
	for (unsigned int k = 0; k < SH2000_AXES; k++) {
		cfg->counts_per_mm[k] = 1000;
		if (card) {
			cfg->vmax[k] = 400;
			cfg->amax[k] = 5000;
		}
	}
}

/* ---- arcs the geometry cannot resolve --------------------------------- */

static size_t emitted;

static int count_sink(void *ctx, const struct sh2000_path_point *pt)
{
	(void)ctx;
	(void)pt;
	emitted++;
	return 0;
}

/* The arc is refused with code want and nothing moves. */
static void expect_arc_refused(const struct sh2000_path_config *cfg,
			       const struct sh2000_path_arc *a, int want)
{
	struct sh2000_path *p;

	emitted = 0;
	assert_int_equal(sh2000_path_create(&p, cfg, count_sink, NULL, NULL, 0),
			 0);
	assert_int_equal(sh2000_path_arc(p, a, 10), want);
	printf("refused: %s\n", sh2000_path_error(p));
	assert_true(strlen(sh2000_path_error(p)) > 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_int_equal(emitted, 0);
	sh2000_path_destroy(p);
}

static void test_arc_unresolvable(void **state)
{
	struct sh2000_path_config cfg;
	struct sh2000_path_arc a;

	(void)state;
	sh2000_path_config_default(&cfg);
	cfg.start[0] = 10;
	memset(&a, 0, sizeof(a));
	a.plane = SH2000_PLANE_XY;
	a.end[0] = 20;
	a.radius_form = 1;
	a.radius = 1e18;
	expect_arc_refused(&cfg, &a, -ERANGE);
	a.radius = 1e17;
	expect_arc_refused(&cfg, &a, -ERANGE);
	/* a helix, in another plane */
	a.plane = SH2000_PLANE_YZ;
	a.end[0] = 10;
	a.end[1] = 10;
	expect_arc_refused(&cfg, &a, -ERANGE);
	/* the centre form, 1e18 mm away */
	a.plane = SH2000_PLANE_XY;
	a.end[0] = 20;
	a.end[1] = 0;
	a.end[2] = 3;
	a.radius_form = 0;
	a.centre[0] = 15;
	a.centre[1] = -1e18;
	expect_arc_refused(&cfg, &a, -ERANGE);
	/* within the geometry's limit, but the long way round a radius of
	 * 5e7 mm leaves the count range of 1000 counts/mm */
	for (unsigned int k = 0; k < SH2000_AXES; k++)
		cfg.counts_per_mm[k] = 1000;
	a.end[2] = 0;
	a.radius_form = 1;
	a.radius = -5e7;
	expect_arc_refused(&cfg, &a, -ERANGE);
}

/* ---- a NURBS with a repeated start and a tiny last weight -------------- */

static void test_nurbs_tiny_weight(void **state)
{
	static const char *const prog[] = {
		/* as found: order 3, the start repeated, weight 1e-4 */
		"G0 X0 Y0\nF600\nG5.2 X0 Y0 P1\nX2 Y2 P0.0001\nG5.3\nM2\n",
		/* the same, cubic, and at a higher feed */
		"G0 X0 Y0\nF6000\nG5.2 X0 Y0 P1 L4\nX1 Y1 P1\nX2 Y2 P0.0001\nG5.3\nM2\n",
		/* a heavy last weight instead */
		"G0 X0 Y0\nF6000\nG5.2 X0 Y0 P1\nX2 Y2 P10000\nG5.3\nM2\n",
	};
	struct sh2000_path_config cfg;
	struct run r;

	(void)state;
	sh2000_path_config_default(&cfg);
	for (size_t i = 0; i < 2 * sizeof(prog) / sizeof(prog[0]); i++) {
		int raw = i % 2;

		cfg.output = raw ? SH2000_OUTPUT_RAW : SH2000_OUTPUT_COMPENSATED;
		assert_int_equal(plan_gcode(prog[i / 2], &cfg, 1e-3, &r), 0);
		printf("nurbs %zu %s: first step %.4f mm, v %.3f a %.3f j %.3f of the limits, %.2e mm off the curve\n",
		       i / 2, raw ? "raw" : "compensated", r.first_step,
		       r.sp.v_ratio, r.sp.a_ratio, r.sp.j_ratio, r.sp.dev);
		/* raw, the first record is the first planned point: from rest
		 * one period cannot go further than the jerk allows, J T^3 / 6
		 * (0.0067 mm; it was 0.356) */
		if (raw)
			assert_true(r.first_step <=
				    cfg.jerk * pow(cfg.period_s, 3) / 6);
		assert_true(r.sp.v_ratio <= 1.0);
		assert_true(r.sp.a_ratio <= 1.0);
		assert_true(r.sp.j_ratio <= 1.0);
		/* the curve is a straight segment: on it */
		assert_true(r.sp.dev <= 1e-6);
		/* it ends where the curve does */
		assert_true(fabs(r.sp.x[2][0] - 2) < 1e-9 &&
			    fabs(r.sp.x[2][1] - 2) < 1e-9);
		sp_path_free(&r.path);
	}
}

/* ---- arcs of enormous radius -------------------------------------------- */

/* Found by the reader + planner fuzz harness: an arc of radius 1e6 mm
 * whose end lies 1 mm further from its centre than its start sweeps
 * 5e-12 rad, 5e-6 mm of its circle, and is all but a straight millimetre
 * of the radius's change. Its length and end tangents counted the sweep
 * alone: the planner took it for 5e-6 mm across the way it goes, and the
 * card jumped the millimetre in a period (90 times amax, 1.28 vmax at
 * the card model's limits). */
static void test_arc_huge_radius(void **state)
{
	static const char *const prog[] = {
		"G2 X20 R1000000 F600\nM2\n",
		"G2 X20 R1000000 F600\nG3 Y1 I-5 J-1000000\nM2\n",
		"G3 Y1 I-5 J-1000000 F6000\nM2\n",
	};
	struct sh2000_path_config cfg;
	struct run r;

	(void)state;
	for (size_t i = 0; i < 2 * sizeof(prog) / sizeof(prog[0]); i++) {
		int card = i % 2;

		harness_config(&cfg, card);
		/* the corner between the two is blended within corner_tol;
		 * a micrometre more, as the harness allows */
		assert_int_equal(plan_gcode(prog[i / 2], &cfg,
					    cfg.corner_tol + 0.001, &r), 0);
		printf("huge arc %zu at %s limits: v %.4f a %.4f of the limits, %.2e mm off the path\n",
		       i / 2, card ? "the card's" : "the planner's", r.sp.v_ratio,
		       r.sp.a_ratio, r.sp.dev);
		assert_true(r.sp.v_ratio <= 1.0);
		assert_true(r.sp.a_ratio <= 1.0);
		assert_true(r.sp.dev <= cfg.corner_tol + 0.001);
		sp_path_free(&r.path);
	}
}

/* ---- a limit in force --------------------------------------------------- */

/* Found by the reader + planner fuzz harness: a feed lowered by 1 mm/min
 * on a short last move, blended with the long one before it. The lower
 * feed holds from feed_zone before that move, which lay behind the
 * carriage while it braked for the program's end; the controller read
 * that limit, met, as one with no room left, and braked at its blend's
 * acceleration instead of the stop's: the stop overran its end point
 * (8.1 times amax at the card model's limits, 4.0 in the fuzz input). */
static void test_feed_drop_into_stop(void **state)
{
	static const char *const feeds[][2] = {
		{ "F24001", "F24000" }, { "F30000", "F18000" },
		{ "F20000", "F18000" }, { "F24000", "F24000" },
	};
	struct sh2000_path_config cfg;
	char text[256];
	struct run r;

	(void)state;
	harness_config(&cfg, 1);
	for (size_t i = 0; i < sizeof(feeds) / sizeof(feeds[0]); i++) {
		snprintf(text, sizeof(text),
			 "G21 G90 G64 P0.01 Q0\n"
			 "G1 X0.276732 Y0.166995 F24000\n"
			 "G1 X0.402456 Y1.00\n"
			 "G1 X3.696576 Y2.9342 %s\n"
			 "G1 X3.759545 Y2.970633 %s\nM2\n",
			 feeds[i][0], feeds[i][1]);
		assert_int_equal(plan_gcode(text, &cfg, 0.011, &r), 0);
		printf("%s then %s: v %.4f a %.4f of the limits, %.6f mm off the path, %.6f mm past the end\n",
		       feeds[i][0], feeds[i][1], r.sp.v_ratio, r.sp.a_ratio,
		       r.sp.dev, r.hi[0] - 3.759545);
		assert_true(r.sp.v_ratio <= 1.0);
		assert_true(r.sp.a_ratio <= 1.0);
		assert_true(r.sp.dev <= 0.011);
		/* past the end point along X no further than a compensated
		 * stop rings (J T^3 / 70, 0.6 um; docs/planner.md) */
		assert_true(r.hi[0] <= 3.759545 + 0.001);
		sp_path_free(&r.path);
	}
}

/* ---- a braking into a drop of the acceleration at its limit ------------- */

/* Found by the reader + planner fuzz harness at the card model's limits:
 * a line brakes into a blend's entry limit at the line's acceleration
 * (4438 mm/s^2), and the blend from the same place allows 3202. Two
 * periods before it the controller had to cut the braking to 3202, too
 * late to slow to the limit: the carriage entered the zigzag of 0.08 mm
 * moves after it at 22 mm/s for 16.6 (1.64 times amax on the card's
 * set-points with the line to X4.45, 1.53 to X4.5, 1.46 to X4.52). */
static void test_brake_into_drop(void **state)
{
	static const char *const corner[] = { "4.45", "4.5", "4.52" };
	struct sh2000_path_config cfg;
	char text[320];
	struct run r;

	(void)state;
	harness_config(&cfg, 1);
	for (size_t i = 0; i < sizeof(corner) / sizeof(corner[0]); i++) {
		snprintf(text, sizeof(text),
			 "G21 G90 G64 P0.01 Q0\n"
			 "G1 X3.398634 Y2.495785 F24000\n"
			 "G1 X%s\n"
			 "G1 X4.545900 Y4.268615\nG1 X4.550414 Y4.354747\n"
			 "G1 X4.604148 Y4.403129\nG1 X4.607884 Y4.474419\n"
			 "G1 X4.670253 Y4.530576\nM2\n", corner[i]);
		assert_int_equal(plan_gcode(text, &cfg, 0.011, &r), 0);
		printf("corner at X%s: v %.4f a %.4f of the limits, %.6f mm off the path\n",
		       corner[i], r.sp.v_ratio, r.sp.a_ratio, r.sp.dev);
		assert_true(r.sp.v_ratio <= 1.0);
		assert_true(r.sp.a_ratio <= 1.0);
		assert_true(r.sp.dev <= 0.011);
		sp_path_free(&r.path);
	}
}

/* ---- short rest-to-rest moves in compensated output -------------------- */

/* Every rest-to-rest move along X from 0: the fine set-points stay in
 * [0, d] and never turn back. */
static void short_moves(enum sh2000_path_profile prof, const char *name)
{
	struct sh2000_path_config cfg;
	double worst_over = 0, worst_back = 0, worst_turn = 0, a = 0;
	char text[64];
	struct run r;

	sh2000_path_config_default(&cfg);
	cfg.profile = prof;
	for (int i = 1; i <= 60; i++) {
		double d = 0.005 * i;

		snprintf(text, sizeof(text), "G0 X%.3f\nM2\n", d);
		assert_int_equal(plan_gcode(text, &cfg, 1e-9, &r), 0);
		/* the records too: the card checks its soft limits on them */
		worst_over = fmax(worst_over, fmax(r.hi[0], r.rec_hi) - d);
		worst_back = fmax(worst_back, -fmin(r.lo[0], r.rec_lo));
		a = fmax(a, r.sp.a_ratio);
		worst_turn = fmax(worst_turn, r.back[0]);
		sp_path_free(&r.path);
	}
	printf("%s: G0 X0.005..0.3 over the end %.3g um, behind the start %.3g um, steps back %.3g um, a %.3f of the limit\n",
	       name, worst_over * 1e3, worst_back * 1e3, worst_turn * 1e3, a);
	/* to the rounding of the spline's sums */
	assert_true(worst_over <= 1e-12);
	assert_true(worst_back <= 1e-12);
	assert_true(worst_turn <= 1e-12);
	assert_true(a <= 1.0);
}

static void test_short_moves(void **state)
{
	(void)state;
	short_moves(SH2000_PROFILE_TRAPEZOID, "trapezoid");
	short_moves(SH2000_PROFILE_SCURVE, "S-curve");
}

/* ---- the check's distance from the path -------------------------------- */

/* The distance of every query to a polyline is its nearest segment's,
 * from wherever the search starts: a walk that moved its centre to each
 * better match skipped the segments in between (0.5 instead of 0.001
 * below, and a fuzz input's set-point 6 um from a NURBS measured 17 um
 * off it). */
static void test_path_distance(void **state)
{
	struct sp_path g;
	double x[SH2000_AXES] = { 0 };
	size_t i, j;

	(void)state;
	memset(&g, 0, sizeof(g));
	/* a spiral of 400 short chords: dense where it winds tight */
	for (i = 0; i < 400; i++) {
		double th = 0.05 * (double)i, r = 0.1 + 0.01 * (double)i;

		x[0] = r * cos(th);
		x[1] = r * sin(th);
		assert_int_equal(sp_add(&g, x, i == 0), 0);
	}
	for (j = 0; j < 2000; j++) {
		double q[SH2000_AXES] = { 0 }, brute = INFINITY, d;

		q[0] = 4.0 * sin(0.37 * (double)j);
		q[1] = 4.0 * cos(0.23 * (double)j);
		for (i = 1; i < g.n; i++)
			brute = fmin(brute, sp_dist_seg(q, g.v[i - 1], g.v[i]));
		/* start the search anywhere, as after the last set-point */
		g.cur = (j * 7919) % g.n;
		d = sp_path_dist(&g, q, 0.0, 1);
		assert_true(fabs(d - brute) <= 1e-12);
	}
	sp_path_free(&g);
	/* a line of unit segments, the last match on the first: the point
	 * 0.001 off the third segment is 0.001 from the path */
	for (i = 0; i < 8; i++) {
		x[0] = (double)i;
		x[1] = 0;
		assert_int_equal(sp_add(&g, x, i == 0), 0);
	}
	x[0] = 2.5;
	x[1] = 0.001;
	g.cur = 1;
	assert_true(fabs(sp_path_dist(&g, x, 0.0, 1) - 0.001) <= 1e-12);
	sp_path_free(&g);
}

/* ---- a stop beyond a blend, at the planner's default limits ----------- */

/* Found by the reader + planner fuzz harness (the same programs are its
 * regress-defaults-* inputs). At amax 50000 mm/s^2 and jerk 5e6 the
 * S-curve ramp lasts 5 periods; a limit beyond a drop of the acceleration
 * (a blend) was taken as met once the motion could be under the speed
 * the blend may be entered at, even with the acceleration still climbing
 * on reaching it: the braking to the program's stop then took an axis to
 * 3.22 (three lines), 3.17 (a chain with a reversal), 1.41 and 1.25 amax
 * on the card's fine set-points, the last two 0.018 and 0.033 mm off the
 * path where 0.011 is allowed. */
static void test_stop_beyond_blend(void **state)
{
	static const struct {
		const char *name, *text;
		double tol;	/* the program's tolerance + 1 um */
	} prog[] = {
		{ "three lines", "G21 G90 G64 P0.1 Q0\n"
		  "G1 X-10.165085 Y2.730781 F24000\n"
		  "G1 X-8.190987 Y1.724928 F24000\n"
		  "G1 X-6.947355 Y0.013215 F24000\nM2\n", 0.101 },
		{ "reversal chain", "G21 G90 G64 P0.1 Q0\n"
		  "G1 X5.581330 Y0.5663083160 F24000\n"
		  "G1 X4.588124 Y0.217392 F24000\n"
		  "G1 X4.981607 Y0.503275 F24000\n"
		  "G1 X5.581330 Y0.566308 F24000\n"
		  "G1 X6.237491 Y0.274166 F24000\n"
		  "G1 X7 F24000\n"
		  "G1 X6.237491 Y0.274166 F24000\nM2\n", 0.101 },
		{ "short chain", "G1 X0.475881 Y0.317899 F24000\n"
		  "G1 X0.391138 Y0.634162 F24000\n"
		  "G1 X0.422996 Y1.038961 F24000\n"
		  "G1 X-0.714303 Y-0.006064 F24000\nM2\n", 0.011 },
		{ "small turn", "G1 X9.3969 Y3.4202 F24000\n"
		  "G1 X13.3969 Y3.4202\nG1 X16.3969 Y3.42021\n"
		  "G1 X20.4927 Y6.2881\nM2\n", 0.011 },
		/* a blend at full speed: the spline passed its ends 2.09 um
		 * beyond it, with a micrometre kept (0.011086 mm) */
		{ "fast blend", "G0 X0 Y10\nG1 X1.431918 Y1.2 F240020\n"
		  "G1 X1.513288 Y-0.352631\nM2\n", 0.011 },
	};
	struct sh2000_path_config cfg;
	struct run r;

	(void)state;
	harness_config(&cfg, 0);
	for (size_t i = 0; i < sizeof(prog) / sizeof(prog[0]); i++) {
		assert_int_equal(plan_gcode(prog[i].text, &cfg, prog[i].tol, &r),
				 0);
		printf("%s: a %.4f of amax, %.6f mm off the path (allowed %.3f)\n",
		       prog[i].name, r.sp.a_ratio, r.sp.dev, prog[i].tol);
		assert_true(r.sp.v_ratio <= 1.0);
		assert_true(r.sp.a_ratio <= 1.0);
		assert_true(r.sp.dev <= prog[i].tol);
		sp_path_free(&r.path);
	}
}

/* ---- a jerk limit above what a period can use -------------------------- */

/* A short chain of lines with a corner taken at rest, a blend and an arc:
 * the first five lines are a random program on which raw output at a jerk
 * of 5e8 stood still 1.2e-6 mm before its end for ever. */
static const char jerk_prog[] =
	"G21 G90 G61\n"
	"G1 X-0.7642 Y0.5219 F600\nG1 X-0.8454 Y0.4276\n"
	"G1 X-0.8415 Y0.4229\nG1 X-0.8334 Y0.4135 Z0.0828\n"
	"G1 X1.0314 Y5.1039\n"
	"G64 P0.01\nG1 X6 Y5.1039 F6000\nG1 X6 Y9\n"
	"G2 X10 Y9 I2 J0\nG1 X10 Y2\nM2\n";

/* Where the controller holds one jerk a period (compensated output at
 * the card model's limits), a jerk above 2 margin amin / T plans exactly
 * as that jerk does, the card model's own 5e6: a higher one only added
 * ringing allowance (0.02 J T), and planned slower. */
static void test_jerk_above_period(void **state)
{
	static const double jerk[] = { 5e6, 5e7, 5e9 };
	struct sh2000_path_config cfg;
	uint64_t hash = 0;
	size_t points = 0;
	struct run r;

	(void)state;
	for (size_t i = 0; i < sizeof(jerk) / sizeof(jerk[0]); i++) {
		harness_config(&cfg, 1);
		cfg.jerk = jerk[i];
		assert_int_equal(plan_gcode(jerk_prog, &cfg, 0.011, &r), 0);
		printf("compensated, jerk %g: %zu records, a %.4f of amax, %.6f mm off the path\n",
		       jerk[i], r.points, r.sp.a_ratio, r.sp.dev);
		assert_true(r.sp.v_ratio <= 1.0);
		assert_true(r.sp.a_ratio <= 1.0);
		assert_true(r.sp.dev <= 0.011);
		if (i) {
			assert_int_equal(r.points, points);
			assert_true(r.hash == hash);
		}
		points = r.points;
		hash = r.hash;
		sp_path_free(&r.path);
	}
}

/* Raw output at jerks far above the card model's, and 50000 mm/s^2 in
 * either output: every plan ends, on the program's path and within the
 * axes' limits. */
static void test_jerk_far_above(void **state)
{
	static const struct {
		double amax, jerk;
		enum sh2000_path_output out;
	} run[] = {
		{ 5000, 5e8, SH2000_OUTPUT_RAW },
		{ 5000, 5e10, SH2000_OUTPUT_RAW },
		{ 50000, 5e8, SH2000_OUTPUT_RAW },
		{ 50000, 5e8, SH2000_OUTPUT_COMPENSATED },
		{ 50000, 5e10, SH2000_OUTPUT_COMPENSATED },
	};
	struct sh2000_path_config cfg;
	struct run r;

	(void)state;
	for (size_t i = 0; i < sizeof(run) / sizeof(run[0]); i++) {
		harness_config(&cfg, 1);
		for (unsigned int k = 0; k < SH2000_AXES; k++)
			cfg.amax[k] = run[i].amax;
		cfg.jerk = run[i].jerk;
		cfg.output = run[i].out;
		assert_int_equal(plan_gcode(jerk_prog, &cfg, 0.011, &r), 0);
		printf("%s, amax %g, jerk %g: %zu records, a %.4f of amax, %.6f mm off the path\n",
		       run[i].out == SH2000_OUTPUT_RAW ? "raw" : "compensated",
		       run[i].amax, run[i].jerk, r.points, r.sp.a_ratio,
		       r.sp.dev);
		assert_true(r.sp.v_ratio <= 1.0);
		assert_true(r.sp.a_ratio <= 1.0);
		assert_true(r.sp.dev <= 0.011);
		assert_true(fabs(r.sp.x[2][0] - 10.0) < 1e-3);
		assert_true(fabs(r.sp.x[2][1] - 2.0) < 1e-3);
		sp_path_free(&r.path);
	}
}

/* ---- the acceleration settled before it drops -------------------------- */

/* Plan prog (format fmt) with every axis at amax: within vmax, within amax
 * (reserve: within the reserve the planner's margin keeps, the first
 * pass' bound) and within tol mm of the path on the card's set-points. */
static void check_at_amax(const char *what, int fmt, const char *prog,
			  double amax, double tol, int reserve)
{
	struct sh2000_path_config cfg;
	struct run r;

	harness_config(&cfg, 1);
	for (unsigned int k = 0; k < SH2000_AXES; k++)
		cfg.amax[k] = amax;
	assert_int_equal(plan_text(fmt, prog, &cfg, tol, &r), 0);
	printf("%s at %g mm/s^2: v %.4f a %.4f of the limits, %.6f mm off the path\n",
	       what, amax, r.sp.v_ratio, r.sp.a_ratio, r.sp.dev);
	assert_true(r.sp.v_ratio <= 1.0);
	assert_true(r.sp.a_ratio <= (reserve ? 2.0 - cfg.margin : 1.0));
	assert_true(r.sp.dev <= tol);
	sp_path_free(&r.path);
}

/* A piece of LinuxCNC's cds.ngc (inches, F600, G64 P0.01 mm): lines and
 * arcs on X, Y and Z (tests/tools/upload/data/still_axes.ngc too). */
static const char cds_piece[] =
	"G20 G90 G64 P0.000394\n"
	"G1 X0 Y2.205 Z1.6875 F600\n"
	"G1 X0 Y2.015\n"
	"G1 X0.3651 Y2.015\n"
	"G3 X0.3650 Y2.0000 I1.6349 J-0.0184\n"
	"G3 X0.3744 Y1.8250 I1.635 J0.0001\n"
	"G1 X0 Y1.825\n"
	"G1 X0 Y1.635\nM2\n";

/* The cds piece at 15000 mm/s^2, where a ramp to amax lasts 1.5
 * periods: the controller holds one jerk a period but cannot land in one.
 * A blend allowing 13682 mm/s^2 runs into an arc allowing 12151 that ends
 * in a corner taken at rest. The motion reached the arc still accelerating, under the speed
 * from which the arc can stop but too late to bring its acceleration
 * down before it: it took the corner at 80 mm/s, 4.1 times amax on the
 * card's set-points. */
static void test_settle_before_drop(void **state)
{
	(void)state;
	check_at_amax("cds piece", SH2000_PROG_GCODE, cds_piece, 15000, 0.011,
		      0);
}

/* ---- no block beyond what the landing can bring down ------------------ */

/* A random program in canonical form (bench_peaks' sweep, written by a
 * generator: its motion mode right after ON_RESET() is read as rs274's
 * reset default, so it runs blended) at 7500
 * mm/s^2: a 0.7 mm diagonal line allowed 9523 mm/s^2, over the 9500 one
 * jerk a period brings down in a period. The controller planned the
 * stop at its end as a landing while the line's start (its ring zone)
 * allowed less, then handed it to the braking of two periods once past
 * it, which could no longer stop: it passed the stop at 56 mm/s, 4.57
 * amax on the card's set-points. */
static void test_landing_within_jt(void **state)
{
	static const char prog[] =
		"1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
		"2 N..... SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"3 N..... SET_G92_OFFSET(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"4 N..... SET_XY_ROTATION(0.0000)\n"
		"5 N..... SET_FEED_REFERENCE(CANON_XYZ)\n"
		"6 N..... ON_RESET()\n"
		"7 N..... SELECT_PLANE(CANON_PLANE_XY)\n"
		"8 N..... SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP, 0.000000)\n"
		"9 N..... SET_FEED_RATE(24000.0000)\n"
		"10 N10 STRAIGHT_FEED(5.7860, -12.1260, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"11 N11 STRAIGHT_FEED(7.8232, -11.2138, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"12 N12 STRAIGHT_FEED(-5.1535, -0.0391, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"13 N13 STRAIGHT_FEED(3.4377, 6.2743, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"14 N14 STRAIGHT_FEED(-7.5864, -18.1481, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"15 N15 STRAIGHT_FEED(-7.6676, -18.0570, -0.4702, 0.0000, 0.0000, 0.0000)\n"
		"16 N16 STRAIGHT_TRAVERSE(-6.9626, -17.1009, -0.4702, 0.0000, 0.0000, 0.0000)\n"
		"17 N17 ARC_FEED(-6.9204, -17.1541, -7.2301, -17.3562, -1, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"18 N18 STRAIGHT_TRAVERSE(-7.4649, -17.0956, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"19 N19 STRAIGHT_FEED(15.1798, -31.2301, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"20 N20 STRAIGHT_FEED(15.2318, -31.1368, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"21 N21 STRAIGHT_FEED(34.3318, -11.9964, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"22 N22 STRAIGHT_FEED(34.3993, -12.0749, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"23 N23 STRAIGHT_FEED(33.9186, -12.6170, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"24 N24 STRAIGHT_TRAVERSE(33.0011, -7.8422, 0.3171, 0.0000, 0.0000, 0.0000)\n"
		"25 N25 STRAIGHT_FEED(35.8743, -12.5907, -0.0680, 0.0000, 0.0000, 0.0000)\n"
		"26 N..... PROGRAM_END()\n";

	(void)state;
	check_at_amax("a stop", SH2000_PROG_CANON, prog, 7500, 0.011, 0);
}

/* A piece of LinuxCNC's 3D_Chips.ngc (rs274's canonical output, G64
 * P0.1) at 10500 mm/s^2, where one jerk a period (9500 mm/s^2 in a
 * period) falls short of the least amax (9975): the lines between its
 * blends allowed more than a period brings down and the blends less, so
 * the controller landed on some limits and braked by its model of two
 * periods into others; it braked into a blend faster than the blend
 * allowed at that speed, 1.20 amax on the card's set-points. Capped to
 * J T, every block can be landed on: 1.028, within the reserve the
 * margin keeps (the stop at the end, exact in a period where the ramp
 * A/J is a period: docs/planner.md "Known limits"). */
static void test_land_short(void **state)
{
	static const char prog[] =
		"1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
		"2 N..... SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"3 N..... SET_G92_OFFSET(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"4 N..... SET_XY_ROTATION(0.0000)\n"
		"5 N..... SET_FEED_REFERENCE(CANON_XYZ)\n"
		"6 N..... ON_RESET()\n"
		"14 N30    USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
		"15 N..... SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.100000)\n"
		"51 N330   SET_FEED_RATE(4500000.0000)\n"
		"3629 N6101  STRAIGHT_FEED(-22.0000, -14.6260, -30.1560, 0.0000, 0.0000, 0.0000)\n"
		"3630 N6111  STRAIGHT_FEED(-22.0000, -14.6180, -30.1100, 0.0000, 0.0000, 0.0000)\n"
		"3631 N6121  STRAIGHT_FEED(-22.0000, -14.5950, -29.9700, 0.0000, 0.0000, 0.0000)\n"
		"3632 N6131  STRAIGHT_FEED(-22.0000, -14.5710, -29.8320, 0.0000, 0.0000, 0.0000)\n"
		"3633 N6141  STRAIGHT_FEED(-22.0000, -14.5630, -29.7920, 0.0000, 0.0000, 0.0000)\n"
		"3634 N6151  STRAIGHT_FEED(-22.0000, -14.5550, -29.7550, 0.0000, 0.0000, 0.0000)\n"
		"3635 N6161  STRAIGHT_FEED(-22.0000, -14.0550, -27.7680, 0.0000, 0.0000, 0.0000)\n"
		"3636 N6171  STRAIGHT_FEED(-22.0000, -13.5550, -26.2110, 0.0000, 0.0000, 0.0000)\n"
		"3637 N6181  STRAIGHT_FEED(-22.0000, -12.5550, -23.6830, 0.0000, 0.0000, 0.0000)\n"
		"3638 N6191  STRAIGHT_FEED(-22.0000, -12.0550, -22.3890, 0.0000, 0.0000, 0.0000)\n"
		"3639 N6201  STRAIGHT_FEED(-22.0000, -11.8050, -21.7910, 0.0000, 0.0000, 0.0000)\n"
		"3640 N6211  STRAIGHT_FEED(-22.0000, -11.5550, -21.1130, 0.0000, 0.0000, 0.0000)\n"
		"3641 N6221  STRAIGHT_FEED(-22.0000, -11.0550, -19.2810, 0.0000, 0.0000, 0.0000)\n"
		"3642 N6231  STRAIGHT_FEED(-22.0000, -10.5550, -17.3540, 0.0000, 0.0000, 0.0000)\n"
		"3643 N6241  STRAIGHT_FEED(-22.0000, -9.5550, -14.2640, 0.0000, 0.0000, 0.0000)\n"
		"3644 N6251  STRAIGHT_FEED(-22.0000, -8.5550, -11.8950, 0.0000, 0.0000, 0.0000)\n"
		"3645 N6261  STRAIGHT_FEED(-22.0000, -8.0550, -10.8260, 0.0000, 0.0000, 0.0000)\n"
		"3646 N6271  STRAIGHT_FEED(-22.0000, -7.8050, -10.3250, 0.0000, 0.0000, 0.0000)\n"
		"3647 N6281  STRAIGHT_FEED(-22.0000, -7.5550, -9.6510, 0.0000, 0.0000, 0.0000)\n"
		"3648 N6291  STRAIGHT_FEED(-22.0000, -7.0550, -7.9980, 0.0000, 0.0000, 0.0000)\n"
		"3649 N6301  STRAIGHT_FEED(-22.0000, -6.8050, -7.2800, 0.0000, 0.0000, 0.0000)\n"
		"3650 N6311  STRAIGHT_FEED(-22.0000, -6.3050, -6.0830, 0.0000, 0.0000, 0.0000)\n"
		"3651 N6321  STRAIGHT_FEED(-22.0000, -6.0550, -5.5740, 0.0000, 0.0000, 0.0000)\n"
		"3652 N6331  STRAIGHT_FEED(-22.0000, -5.5550, -4.7160, 0.0000, 0.0000, 0.0000)\n"
		"3653 N6341  STRAIGHT_FEED(-22.0000, -5.0550, -4.0090, 0.0000, 0.0000, 0.0000)\n"
		"3654 N6351  STRAIGHT_FEED(-22.0000, -4.5550, -3.4270, 0.0000, 0.0000, 0.0000)\n"
		"3655 N6361  STRAIGHT_FEED(-22.0000, -4.0550, -2.8900, 0.0000, 0.0000, 0.0000)\n"
		"3656 N6371  STRAIGHT_FEED(-22.0000, -3.8050, -2.6700, 0.0000, 0.0000, 0.0000)\n"
		"3657 N6381  STRAIGHT_FEED(-22.0000, -3.5550, -2.4950, 0.0000, 0.0000, 0.0000)\n"
		"3658 N6391  STRAIGHT_FEED(-22.0000, -3.0550, -2.2460, 0.0000, 0.0000, 0.0000)\n"
		"3659 N6401  STRAIGHT_FEED(-22.0000, -2.0550, -1.8950, 0.0000, 0.0000, 0.0000)\n"
		"3660 N6411  STRAIGHT_FEED(-22.0000, -1.5550, -1.7470, 0.0000, 0.0000, 0.0000)\n"
		"3661 N6421  STRAIGHT_FEED(-22.0000, -0.5550, -1.5930, 0.0000, 0.0000, 0.0000)\n"
		"4720 N6941  PROGRAM_END()\n"
		"4721 N..... ON_RESET()\n"
		"4722 N..... ON_RESET()\n";

	(void)state;
	check_at_amax("3D_Chips piece", SH2000_PROG_CANON, prog, 10500, 0.101,
		      1);
}

/* ---- axes held still --------------------------------------------------- */

/* The cds piece moves X, Y and Z. On a machine whose X, Y and Z take
 * 20000 mm/s^2 and whose A takes 5000, the least amax (A's) set the path's
 * share of the acceleration for every block: 10 % slower than with a fast
 * A. Held still, A bounds nothing: the plan is the one of a fast A,
 * record for record, within every axis' limits (A's own included) on the
 * card's set-points, and A never leaves its start. */
static void test_still_axes(void **state)
{
	struct sh2000_path_config cfg;
	struct run slow, still, fast;
	unsigned int k;

	(void)state;
	harness_config(&cfg, 1);
	for (k = 0; k < 3; k++)
		cfg.amax[k] = 20000;
	assert_int_equal(plan_gcode(cds_piece, &cfg, 0.011, &slow), 0);
	cfg.still_axes = 1u << 3;
	assert_int_equal(plan_gcode(cds_piece, &cfg, 0.011, &still), 0);
	cfg.still_axes = 0;
	cfg.amax[3] = 20000;
	assert_int_equal(plan_gcode(cds_piece, &cfg, 0.011, &fast), 0);
	printf("XYZ 20000, A 5000: %zu records; A held still: %zu (a %.4f of amax, %.6f mm off the path); A 20000: %zu\n",
	       slow.points, still.points, still.sp.a_ratio, still.sp.dev,
	       fast.points);
	assert_true(still.points < 0.93 * slow.points);
	assert_int_equal(still.points, fast.points);
	assert_true(still.hash == fast.hash);
	assert_true(still.sp.v_ratio <= 1.0);
	assert_true(still.sp.a_ratio <= 1.0);
	assert_true(still.sp.dev <= 0.011);
	assert_true(still.lo[3] == 0.0 && still.hi[3] == 0.0);
	sp_path_free(&slow.path);
	sp_path_free(&still.path);
	sp_path_free(&fast.path);
}

/* An XY program at the card model's limits with Z and A held still at a
 * tenth of them (a fuzz_plan input): the norm of X's and Y's amax alone
 * fell below one jerk a period held for a period, which the controller's
 * landings take every block to allow, and X braked at 1.25 amax. */
static void test_still_two_axes(void **state)
{
	static const char prog[] =
		"G64 G1 X9.9 Y3.8 F14000\nX10.6 Y4.44\nX11.14 Y4.88\n"
		"X11.25 Y5 M2\n";
	struct sh2000_path_config cfg;
	struct run r;

	(void)state;
	harness_config(&cfg, 1);
	cfg.still_axes = 1u << 2 | 1u << 3;
	cfg.vmax[2] = cfg.vmax[3] = 40;
	cfg.amax[2] = cfg.amax[3] = 500;
	assert_int_equal(plan_gcode(prog, &cfg, 0.05, &r), 0);
	printf("XY, Z and A held still: v %.4f a %.4f of the limits, %.6f mm off the path\n",
	       r.sp.v_ratio, r.sp.a_ratio, r.sp.dev);
	assert_true(r.sp.v_ratio <= 1.0);
	assert_true(r.sp.a_ratio <= 1.0);
	assert_true(r.sp.dev <= 0.05);
	sp_path_free(&r.path);
}

/* Every record of a still axis: where it stands (the compensation's
 * arithmetic leaves it an ulp off). */
static double still_at;
static int still_sink(void *ctx, const struct sh2000_path_point *pt)
{
	(void)ctx;
	emitted++;
	if (fabs(pt->mm[3] - still_at) > 1e-12)
		fail_msg("A at %.17g, held at %.17g", pt->mm[3], still_at);
	return 0;
}

/* A primitive that moves a still axis is refused, naming it, and nothing
 * of it is planned; within SH2000_PATH_STILL_TOL_MM (a card that drifted
 * a count between the check and the run) the axis is held where it
 * stands. A still axis beyond the card's four is refused at create. */
static void test_still_refused(void **state)
{
	static const double pts[3][SH2000_AXES] = {
		{ 0, 0, 0, 1 }, { 5, 5, 0, 1 }, { 10, 0, 0, 1.5 } };
	static const double w[3] = { 1, 1, 1 };
	static const double knots[6] = { 0, 0, 0, 1, 1, 1 };
	const struct sh2000_nurbs n = { 2, 3, pts, w, knots };
	struct sh2000_path_config cfg;
	struct sh2000_path_arc arc;
	struct sh2000_path *p;
	double end[SH2000_AXES] = { 10, 0, 0, 1.5 };
	char msg[200];

	(void)state;
	harness_config(&cfg, 1);
	cfg.start[3] = still_at = 1;
	cfg.still_axes = 1u << 3;
	emitted = 0;
	assert_int_equal(sh2000_path_create(&p, &cfg, still_sink, NULL, NULL, 0),
			 0);
	assert_int_equal(sh2000_path_line(p, end, 10), -EINVAL);
	printf("refused: %s\n", sh2000_path_error(p));
	assert_non_null(strstr(sh2000_path_error(p), "line moves A"));
	assert_int_equal(sh2000_path_nurbs(p, &n, 10), -EINVAL);
	assert_non_null(strstr(sh2000_path_error(p), "points[2] moves A"));
	assert_int_equal(sh2000_path_rapid(p, end), -EINVAL);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_int_equal(emitted, 0);
	/* within the tolerance: planned, A held at its start */
	end[3] = 1 + 0.9 * SH2000_PATH_STILL_TOL_MM;
	assert_int_equal(sh2000_path_line(p, end, 10), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_true(emitted > 0);
	sh2000_path_destroy(p);
	/* Z still: an arc in the XZ plane moves it, whatever its ends */
	cfg.still_axes = 1u << 2;
	assert_int_equal(sh2000_path_create(&p, &cfg, still_sink, NULL, NULL, 0),
			 0);
	memset(&arc, 0, sizeof(arc));
	arc.plane = SH2000_PLANE_XZ;
	arc.end[0] = 10;
	arc.end[3] = 1;
	arc.radius_form = 1;
	arc.radius = 5;
	emitted = 0;
	assert_int_equal(sh2000_path_arc(p, &arc, 10), -EINVAL);
	assert_non_null(strstr(sh2000_path_error(p), "arc moves Z"));
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_int_equal(emitted, 0);
	sh2000_path_destroy(p);
	cfg.still_axes = 1u << 4;
	assert_int_equal(sh2000_path_create(&p, &cfg, still_sink, NULL, msg,
					    sizeof(msg)), -EINVAL);
	printf("refused: %s\n", msg);
	assert_non_null(strstr(msg, "still_axes 0x10"));
}

/* ---- the first pass plans again where the planner passes amax ---------- */

/*
 * Short blended moves braking into a drop, at the card model's limits and
 * scale: the planner alone takes an axis past amax here (1.0245 on the
 * fine set-points, a fuzz_plan input). sh2000_program_check() finds that on
 * the records and plans again with a smaller margin; with it, the fine
 * set-points keep amax and the path.
 */
static void test_accel_fit(void **state)
{
	static const char prog[] =
		"G21 G90 G64 P0.1 Q0\nG1 X0.7 F24000\nX7.699 Y2.394\n"
		"X10.928 Y4.70\nX11.029 Y4.8046\nX11.145 Y4.888\n"
		"X13.5 Y7.5\nM2\n";
	struct sh2000_path_config cfg, fit;
	struct sh2000_program_plan plan;
	struct sh2000_prog_reader *rd;
	struct sh2000_prog_diags d;
	struct run r;

	(void)state;
	harness_config(&cfg, 1);
	for (unsigned int k = 0; k < SH2000_AXES; k++)
		cfg.counts_per_mm[k] = 1e5;
	assert_int_equal(plan_gcode(prog, &cfg, 0.101, &r), 0);
	printf("margin %.3f alone: a %.4f of amax\n", cfg.margin, r.sp.a_ratio);
	assert_true(r.sp.a_ratio > 1.0);
	sp_path_free(&r.path);

	fit = cfg;
	sh2000_prog_diags_init(&d);
	assert_int_equal(sh2000_prog_reader_open_text(&rd, SH2000_PROG_GCODE,
						      "t.ngc", prog,
						      strlen(prog), NULL, &d),
			 0);
	assert_int_equal(sh2000_program_check(rd, &fit, NULL, &plan), 0);
	sh2000_prog_reader_close(rd);
	sh2000_prog_diags_free(&d);
	printf("sh2000_program_check: margin %.3f after %u plans, peak %.4f of amax on %c\n",
	       plan.margin, plan.replans + 1, plan.accel_peak,
	       SH2000_AXIS_LETTERS[plan.accel_axis]);
	assert_true(plan.replans >= 1);
	assert_true(fit.margin < cfg.margin);
	assert_float_equal(plan.margin, fit.margin, 0);
	assert_true(plan.accel_peak <= 1.0);
	assert_int_equal(fit.still_axes, 1u << 2 | 1u << 3);

	/* the same moves, then a line beyond a soft limit after a dwell
	 * (which plans the moves to their end first): planned again for
	 * the acceleration, then refused at the line; the margin is left
	 * as it was */
	{
		static const char beyond[] =
			"G21 G90 G64 P0.1 Q0\nG1 X0.7 F24000\nX7.699 Y2.394\n"
			"X10.928 Y4.70\nX11.029 Y4.8046\nX11.145 Y4.888\n"
			"X13.5 Y7.5\nG4 P0\nG1 X30\nM2\n";
		struct sh2000_path_config bad = cfg;
		struct sh2000_program_opts o;
		struct sh2000_limits lim;

		for (unsigned int k = 0; k < SH2000_AXES; k++) {
			lim.lo[k] = -100;
			lim.hi[k] = 20;
		}
		sh2000_program_opts_default(&o);
		o.limits = &lim;
		sh2000_prog_diags_init(&d);
		assert_int_equal(sh2000_prog_reader_open_text(&rd,
				SH2000_PROG_GCODE, "t.ngc", beyond,
				strlen(beyond), NULL, &d), 0);
		assert_int_equal(sh2000_program_check(rd, &bad, &o, &plan),
				 -SH2000_ELIMIT);
		sh2000_prog_reader_close(rd);
		sh2000_prog_diags_free(&d);
		printf("beyond a limit: %u plans, margin %.3f: %s\n",
		       plan.replans + 1, bad.margin, plan.error);
		assert_true(plan.replans >= 1);
		assert_float_equal(bad.margin, cfg.margin, 0);
		assert_string_equal(plan.where, "t.ngc:9:1");
	}

	/* the second pass plans with fit: the same records */
	assert_int_equal(plan_gcode(prog, &fit, 0.101, &r), 0);
	printf("margin %.3f: a %.4f of amax, %.6f mm off the path, %zu records\n",
	       fit.margin, r.sp.a_ratio, r.sp.dev, r.points);
	assert_true(r.sp.a_ratio <= 1.0);
	assert_true(r.sp.v_ratio <= 1.0);
	assert_true(r.sp.dev <= r.sp.tol);
	assert_int_equal(r.points, plan.points);
	sp_path_free(&r.path);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_arc_unresolvable),
		cmocka_unit_test(test_nurbs_tiny_weight),
		cmocka_unit_test(test_arc_huge_radius),
		cmocka_unit_test(test_feed_drop_into_stop),
		cmocka_unit_test(test_brake_into_drop),
		cmocka_unit_test(test_short_moves),
		cmocka_unit_test(test_path_distance),
		cmocka_unit_test(test_stop_beyond_blend),
		cmocka_unit_test(test_jerk_above_period),
		cmocka_unit_test(test_jerk_far_above),
		cmocka_unit_test(test_settle_before_drop),
		cmocka_unit_test(test_landing_within_jt),
		cmocka_unit_test(test_land_short),
		cmocka_unit_test(test_still_axes),
		cmocka_unit_test(test_still_refused),
		cmocka_unit_test(test_still_two_axes),
		cmocka_unit_test(test_accel_fit),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
