// SPDX-License-Identifier: MIT
/*
 * The path tolerance as LinuxCNC defines it (G64 P, G61, G61.1), checked
 * where it matters: the card model's fine set-points against the exact
 * programmed polyline of a program with sharp corners. G64 P<tol> keeps
 * every set-point within tol of the path (and a count of the card), a
 * smaller tolerance is never faster; G61 stops on every corner to a count
 * without ringing past it; G61.1 stops at every block end; G64 alone is
 * the fastest.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "plcard.h"

/* A zigzag with 90 and 135 degree corners, 3 mm legs, at 200 mm/s. */
#define NPTS 9
#define FEED 200.0
#define COUNT 0.00001		/* mm: one count of the card at 10 nm */

static const double pts[NPTS][2] = {
	{ 0, 0 }, { 3, 0 }, { 3, 3 }, { 6, 3 }, { 3, 6 }, { 6, 6 },
	{ 6, 9 }, { 9, 6 }, { 12, 6 },
};

struct dev {
	double o[4];
	double max;		/* largest distance to the polyline, mm */
	double near[NPTS];	/* closest approach to each vertex */
	unsigned int leg;	/* the leg being run: from pts[leg] */
	double past;		/* farthest past a leg's end along it */
	uint64_t cycles;	/* servo cycles from the first move to rest */
	double last[4];
	int moving;
};

static int discard(void *ctx, const struct sh2000_path_point *pt)
{
	(void)ctx;
	(void)pt;
	return 0;
}

static double seg_dist(const double *p, const double *a, const double *b)
{
	double dx = b[0] - a[0], dy = b[1] - a[1], t;

	t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy);
	t = fmin(fmax(t, 0), 1);
	return hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}

static void on_fine(void *ctx, const double x[4], const double act[4])
{
	struct dev *d = ctx;
	double p[2] = { x[0] - d->o[0], x[1] - d->o[1] }, m = INFINITY;
	unsigned int i;

	(void)act;
	for (i = 0; i + 1 < NPTS; i++)
		m = fmin(m, seg_dist(p, pts[i], pts[i + 1]));
	d->max = fmax(d->max, m);
	for (i = 0; i < NPTS; i++)
		d->near[i] = fmin(d->near[i], hypot(p[0] - pts[i][0],
						    p[1] - pts[i][1]));
	/* past the end of the leg along it (ringing through the stop); the
	 * next leg once the vertex is reached to a count */
	if (d->leg + 1 < NPTS) {
		const double *a = pts[d->leg], *b = pts[d->leg + 1];
		double L = hypot(b[0] - a[0], b[1] - a[1]);

		d->past = fmax(d->past, ((p[0] - b[0]) * (b[0] - a[0]) +
					 (p[1] - b[1]) * (b[1] - a[1])) / L);
		if (hypot(p[0] - b[0], p[1] - b[1]) <= COUNT)
			d->leg++;
	}
	if (memcmp(x, d->last, sizeof(d->last)))
		d->moving = 1;
	if (d->moving)
		d->cycles++;
	memcpy(d->last, x, sizeof(d->last));
}

/* Run the zigzag in a mode; the deviation and the time it took. */
static void run(enum sh2000_path_mode mode, double tol, int raw,
		struct dev *d)
{
	static struct plcard pc;
	struct sh2000_path_config c;
	struct sh2000_path *p;
	unsigned int i;

	memset(d, 0, sizeof(*d));
	for (i = 0; i < NPTS; i++)
		d->near[i] = INFINITY;
	sh2000_path_config_default(&c);
	if (raw)
		c.output = SH2000_OUTPUT_RAW;
	assert_int_equal(plcard_open(&pc, c.vmax, c.amax, 1, d->o), 0);
	memcpy(c.start, d->o, sizeof(c.start));
	memcpy(d->last, d->o, sizeof(d->last));
	pc.fn = on_fine;
	pc.ctx = d;
	assert_int_equal(sh2000_path_create(&p, &c, plcard_sink, &pc, NULL, 0), 0);
	assert_int_equal(sh2000_path_set_mode(p, mode, tol, 0), 0);
	pc.record = 1;
	for (i = 1; i < NPTS; i++) {
		double e[4];

		memcpy(e, d->o, sizeof(e));
		e[0] += pts[i][0];
		e[1] += pts[i][1];
		assert_int_equal(sh2000_path_line(p, e, FEED), 0);
	}
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_int_equal(plcard_idle(&pc), 0);
	sh2000_path_destroy(p);
	plcard_close(&pc);
}

static void test_blend_tolerances(void **s)
{
	static const double tols[] = { 0.1, 0.05, 0.01, 0.002 };
	struct dev d;
	uint64_t first = 0, g61;
	unsigned int i, slower = 0;

	(void)s;
	run(SH2000_PATH_EXACT_PATH, 0, 0, &d);
	g61 = d.cycles;
	for (i = 0; i < sizeof(tols) / sizeof(tols[0]); i++) {
		run(SH2000_PATH_BLEND, tols[i], 0, &d);
		print_message("G64 P%-6g  max deviation %.6f mm, %llu servo cycles\n",
			      tols[i], d.max, (unsigned long long)d.cycles);
		/* within the tolerance and a count on the card's own
		 * set-points */
		assert_true(d.max <= tols[i] + COUNT);
		/* a corner is rounded when the tolerance allows, or, where
		 * stopping on it is faster than the blend (a turn wider than
		 * 57 degrees between moves much faster than the blend,
		 * blend.c), visited to a count: never cut short of P */
		if (tols[i] >= 0.05)
			assert_true(d.near[1] > tols[i] / 10 ||
				    d.near[1] <= COUNT);
		/* a narrower tolerance is never faster than the widest, and
		 * somewhere slower */
		if (i == 0)
			first = d.cycles;
		assert_true(d.cycles >= first);
		slower += d.cycles > first;
		/* never slower than stopping on every corner (G61): a wide
		 * corner is stopped on where that is faster than its blend
		 * (at P0.01 the blends took 2723 servo cycles, G61 2543) */
		assert_true(d.cycles <= g61);
	}
	assert_true(slower > 0);
}

static double max_near(const struct dev *d)
{
	double m = 0.0;
	unsigned int i;

	for (i = 0; i < NPTS; i++)
		m = fmax(m, d->near[i]);
	return m;
}

static void exact_report(const char *name, const struct dev *d)
{
	print_message("%-12s max deviation %.2f nm, corners within %.2f nm, %.2f nm past a stop, %llu servo cycles\n",
		      name, d->max * 1e6, max_near(d) * 1e6, d->past * 1e6,
		      (unsigned long long)d->cycles);
	/* every corner met to a count of the card, nothing past a stop
	 * (the card's spline stops exactly on a rest point) */
	assert_true(max_near(d) <= COUNT);
	assert_true(d->max <= COUNT);
	assert_true(d->past <= COUNT);
	assert_int_equal(d->leg, NPTS - 1);
}

static void test_exact_modes(void **s)
{
	struct dev best, path, stop, raw;

	(void)s;
	run(SH2000_PATH_BLEND, 0, 0, &best);
	run(SH2000_PATH_EXACT_PATH, 0, 0, &path);
	run(SH2000_PATH_EXACT_STOP, 0, 0, &stop);
	print_message("G64          max deviation %.4f mm, %llu servo cycles\n",
		      best.max, (unsigned long long)best.cycles);
	exact_report("G61", &path);
	exact_report("G61.1", &stop);
	run(SH2000_PATH_EXACT_PATH, 0, 1, &raw);
	exact_report("G61 raw", &raw);
	run(SH2000_PATH_EXACT_STOP, 0, 1, &raw);
	exact_report("G61.1 raw", &raw);
	/* G64 alone is the fastest and rounds the most */
	assert_true(best.cycles <= path.cycles);
	assert_true(best.max > path.max);
	assert_true(stop.cycles >= path.cycles);
}

/* Tolerances down to a nanometre keep the card's set-points within P and
 * a count: a corner too narrow to blend, taken at nanometres a period,
 * is a stop (planner.h PL_CREEP_MM; the compensated spline rang 88 nm
 * past one at P1e-7 and 0.4 um at P1e-6 before), and in raw output a
 * tolerance under a micrometre stops on every corner (PL_RAW_TOL_REST_MM). */
static void test_tiny_tolerances(void **s)
{
	static const double tols[] = { 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-9 };
	struct dev d;
	unsigned int i, raw;

	(void)s;
	for (raw = 0; raw <= 1; raw++)
		for (i = 0; i < sizeof(tols) / sizeof(tols[0]); i++) {
			run(SH2000_PATH_BLEND, tols[i], (int)raw, &d);
			print_message("G64 P%-6g %s max deviation %.2f nm, %.2f nm past a corner\n",
				      tols[i], raw ? "raw" : "compensated",
				      d.max * 1e6, d.past * 1e6);
			assert_true(d.max <= tols[i] + COUNT);
			/* raw, under a micrometre every corner is a stop, met
			 * to a count and never passed */
			if (raw && tols[i] < 1e-3) {
				assert_true(max_near(&d) <= COUNT);
				assert_true(d.past <= COUNT);
				assert_int_equal(d.leg, NPTS - 1);
			}
		}
}

/* Points a 20 mm circle of 1 degree chords takes at F6000 in a mode. */
static uint64_t polygon_points(enum sh2000_path_mode mode, double tol)
{
	struct sh2000_path_config c;
	struct sh2000_path_stats st;
	struct sh2000_path *p;
	unsigned int i;

	sh2000_path_config_default(&c);
	c.start[0] = 20.0;
	assert_int_equal(sh2000_path_create(&p, &c, discard, NULL, NULL, 0), 0);
	assert_int_equal(sh2000_path_set_mode(p, mode, tol, 0), 0);
	for (i = 1; i <= 360; i++) {
		double e[4] = { 20.0 * cos(i * M_PI / 180.0),
				20.0 * sin(i * M_PI / 180.0), 0, 0 };

		assert_int_equal(sh2000_path_line(p, e, 100), 0);
	}
	assert_int_equal(sh2000_path_finish(p), 0);
	sh2000_path_stats(p, &st);
	sh2000_path_destroy(p);
	return st.points;
}

/* A sub-micrometre tolerance still blends the small turns of a curve:
 * only corners too narrow to blend and too slow to matter are stops (a
 * rule that stopped on every corner under 1 um took a 1 degree polygon
 * at P0.0005 in 7.14 s instead of 1.70; the card's spline rounding each
 * corner within P, pl_corner_spline_vlim(), takes it from 788
 * points to 1097, 2.19 s, against G61.1's 2891). */
static void test_tiny_tolerance_curve(void **s)
{
	uint64_t fine = polygon_points(SH2000_PATH_BLEND, 0.0005);
	uint64_t g61 = polygon_points(SH2000_PATH_EXACT_STOP, 0);

	(void)s;
	print_message("1 degree polygon: G64 P0.0005 %llu points, G61.1 %llu\n",
		      (unsigned long long)fine, (unsigned long long)g61);
	assert_true(fine * 5 < g61 * 2);
}

/* G64 P Q: CAM-style tiny moves that wobble within Q of a line are taken
 * as that line (LinuxCNC's naive CAM detector), within Q of every point;
 * without Q (Q 0) each is its own block. */
static size_t naive_run(double q)
{
	struct sh2000_path_config c;
	struct sh2000_path_stats st;
	struct sh2000_path *p;
	unsigned int i;

	sh2000_path_config_default(&c);
	assert_int_equal(sh2000_path_create(&p, &c, discard, NULL, NULL, 0), 0);
	assert_int_equal(sh2000_path_set_mode(p, SH2000_PATH_BLEND, 0.01, q), 0);
	for (i = 1; i <= 400; i++) {
		/* 0.05 mm steps along X, +-2 um of Y wobble */
		double e[4] = { 0.05 * i, (i % 2 ? 0.002 : -0.002), 0, 0 };

		assert_int_equal(sh2000_path_line(p, e, 100), 0);
	}
	assert_int_equal(sh2000_path_finish(p), 0);
	sh2000_path_stats(p, &st);
	sh2000_path_destroy(p);
	return st.blocks;
}

static void test_naive_cam(void **s)
{
	size_t merged, each;

	(void)s;
	merged = naive_run(0.005);
	each = naive_run(0);
	print_message("G64 P0.01 Q0.005: 400 wobbling moves planned as %zu blocks (Q 0: %zu)\n",
		      merged, each);
	assert_true(merged < 40);
	assert_true(each >= 400);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_blend_tolerances),
		cmocka_unit_test(test_exact_modes),
		cmocka_unit_test(test_tiny_tolerances),
		cmocka_unit_test(test_tiny_tolerance_curve),
		cmocka_unit_test(test_naive_cam),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
