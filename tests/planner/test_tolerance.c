// SPDX-License-Identifier: MIT
/*
 * The path tolerance as LinuxCNC defines it (G64 P, G61, G61.1), checked
 * where it matters: the card model's fine set-points against the exact
 * programmed polyline of a program with sharp corners. G64 P<tol> keeps
 * every set-point within tol of the path, a smaller tolerance is slower;
 * G61 visits every corner; G61.1 stops at every block end; G64 alone is
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

static const double pts[NPTS][2] = {
	{ 0, 0 }, { 3, 0 }, { 3, 3 }, { 6, 3 }, { 3, 6 }, { 6, 6 },
	{ 6, 9 }, { 9, 6 }, { 12, 6 },
};

struct dev {
	double o[4];
	double max;		/* largest distance to the polyline, mm */
	double near[NPTS];	/* closest approach to each vertex */
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
	if (memcmp(x, d->last, sizeof(d->last)))
		d->moving = 1;
	if (d->moving)
		d->cycles++;
	memcpy(d->last, x, sizeof(d->last));
}

/* Run the zigzag in a mode; the deviation and the time it took. */
static void run(enum sh2000_path_mode mode, double tol, struct dev *d)
{
	static struct plcard pc;
	struct sh2000_path_config c;
	struct sh2000_path *p;
	unsigned int i;

	memset(d, 0, sizeof(*d));
	for (i = 0; i < NPTS; i++)
		d->near[i] = INFINITY;
	sh2000_path_config_default(&c);
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
	uint64_t first = 0;
	unsigned int i;

	(void)s;
	for (i = 0; i < sizeof(tols) / sizeof(tols[0]); i++) {
		run(SH2000_PATH_BLEND, tols[i], &d);
		print_message("G64 P%-6g  max deviation %.4f mm, %llu servo cycles\n",
			      tols[i], d.max, (unsigned long long)d.cycles);
		/* within the tolerance on the card's own set-points (its spline
		 * follows a tight blend to half a micrometre) */
		assert_true(d.max <= tols[i] + 0.0005);
		/* a corner is rounded, not visited, when the tolerance allows */
		if (tols[i] >= 0.05)
			assert_true(d.near[1] > tols[i] / 10);
		/* the widest is faster than the narrowest */
		if (i == 0)
			first = d.cycles;
		else
			assert_true(d.cycles > first);
	}
}

static void test_exact_modes(void **s)
{
	struct dev best, path, stop;
	unsigned int i;

	(void)s;
	run(SH2000_PATH_BLEND, 0, &best);
	run(SH2000_PATH_EXACT_PATH, 0, &path);
	run(SH2000_PATH_EXACT_STOP, 0, &stop);
	print_message("G64         max deviation %.4f mm, %llu servo cycles\n",
		      best.max, (unsigned long long)best.cycles);
	print_message("G61         max deviation %.4f mm, %llu servo cycles\n",
		      path.max, (unsigned long long)path.cycles);
	print_message("G61.1       max deviation %.4f mm, %llu servo cycles\n",
		      stop.max, (unsigned long long)stop.cycles);
	/* G61 and G61.1 visit every corner (to the card's micrometre); G61.1
	 * stops at every block end, G61 only where it must turn */
	for (i = 0; i < NPTS; i++) {
		assert_true(path.near[i] < 0.001);
		assert_true(stop.near[i] < 0.001);
	}
	assert_true(path.max < 0.001);
	assert_true(stop.max < 0.001);
	/* G64 alone is the fastest and rounds the most */
	assert_true(best.cycles <= path.cycles);
	assert_true(best.max > path.max);
	assert_true(stop.cycles >= path.cycles);
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
		cmocka_unit_test(test_naive_cam),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
