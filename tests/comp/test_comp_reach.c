// SPDX-License-Identifier: MIT
/*
 * sh2000_comp_reach() and its words (libsh2000/protocol/comp_reach.c), no
 * card: how far tables move each axis inside its soft limits and where
 * the corrected position at a soft limit lies beyond it. Without soft
 * limits the range runs over the table's points and run-outs; with one
 * side off, from the other limit to the run-out; a grid over its two
 * sources' windows; a correction beyond the limit by more than half a
 * count is said, one inside it (or within half a count) is not.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include <cmocka.h>

#include "sh2000/sh2000.h"

#define SCALE	1e5	/* counts/mm on every axis */

static char path[64];

struct judged {
	struct sh2000_comp_window win;
	struct sh2000_comp_reach reach[SH2000_AXES];
	int axes;
};

/* A window with every soft limit off and the test's scale. */
static struct sh2000_comp_window all_off(void)
{
	struct sh2000_comp_window win = { 0 };

	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		win.soft_min[a] = INT32_MIN;
		win.soft_max[a] = INT32_MAX;
		win.scale[a] = SCALE;
	}
	return win;
}

/* The tables of `text` judged with window win. */
static struct judged judge(const char *text, struct sh2000_comp_window win)
{
	double scale[SH2000_AXES] = { SCALE, SCALE, SCALE, SCALE };
	struct sh2000_comp_file *f = NULL;
	struct sh2000_comp_index ix;
	struct sh2000_comp_fault why;
	struct judged j = { .win = win };
	const uint16_t *w;
	char msg[256];
	size_t n;
	FILE *fp = fopen(path, "w");

	assert_non_null(fp);
	fputs(text, fp);
	assert_int_equal(fclose(fp), 0);
	if (sh2000_comp_file_read(&f, path, scale, msg, sizeof(msg)))
		fail_msg("%s", msg);
	w = sh2000_comp_file_image(f, &n);
	assert_int_equal(sh2000_comp_parse(w, n, &ix, &why), 0);
	j.axes = sh2000_comp_reach(w, &ix, &j.win, j.reach);
	sh2000_comp_file_free(f);
	return j;
}

static void near(double got, double want, double tol, const char *what)
{
	if (!(fabs(got - want) <= tol))
		fail_msg("%s: %.3f counts, want %.3f +- %.3f", what, got, want, tol);
}

/* -0.0005 mm at -10, +0.0005 at +10: slope 5e-5; beyond each end it runs
 * out to 0 over 16 end segments (160 mm), 0.004 mm more. */
static const char slope[] = "pitch X\n-10 -0.0005\n0 0\n10 0.0005\n";

static void no_soft_limits(void **state)
{
	struct judged j;
	char msg[512];

	(void)state;
	j = judge(slope, all_off());
	assert_int_equal(j.axes, 1);
	assert_int_equal(j.reach[0].tables, 1);
	near(j.reach[0].lo, -450.0, 0.5, "lo over the run-outs");
	near(j.reach[0].hi, 450.0, 0.5, "hi over the run-outs");
	/* no limit: nothing to be beyond */
	assert_true(j.reach[0].beyond[0] == 0.0 && j.reach[0].beyond[1] == 0.0);
	for (unsigned int a = 1; a < SH2000_AXES; a++)
		assert_int_equal(j.reach[a].tables, 0);
	assert_int_equal(sh2000_comp_reach_warning(&j.win, j.reach, 0, 1, msg,
						   sizeof(msg)), 0);
	assert_string_equal(msg, "");
}

static void one_side_off(void **state)
{
	struct sh2000_comp_window win = all_off();
	struct judged j;
	char msg[512];

	(void)state;
	win.soft_min[0] = -500000;	/* -5 mm; soft_max off */
	j = judge(slope, win);
	/* from -0.00025 mm at soft_min up to the far run-out */
	near(j.reach[0].lo, -25.0, 0.01, "lo at soft_min");
	near(j.reach[0].hi, 450.0, 0.5, "hi over the run-out");
	near(j.reach[0].beyond[0], 25.0, 0.01, "beyond soft_min");
	assert_true(j.reach[0].beyond[1] == 0.0);
	assert_true(sh2000_comp_reach_warning(&j.win, j.reach, 0, 0, msg,
					      sizeof(msg)) > 0);
	assert_string_equal(msg, "axis x at its soft_min -5.000000 mm: the tables put the tool up to 0.000250 mm beyond it (at -5.000250 mm): the card judges soft limits on nominal positions, then adds the correction");
	assert_int_equal(sh2000_comp_reach_warning(&j.win, j.reach, 0, 1, msg,
						   sizeof(msg)), 0);
}

static void beyond_and_within(void **state)
{
	struct sh2000_comp_window win = all_off();
	struct judged j;
	char msg[512];

	(void)state;
	win.soft_min[0] = -1000000;	/* -10 mm */
	win.soft_max[0] = 1000000;	/* +10 mm */
	/* +0.5 mm everywhere: beyond soft_max, inside at soft_min */
	j = judge("pitch X\n-100 0.5\n0 0.5\n100 0.5\n", win);
	near(j.reach[0].lo, 50000.0, 0.01, "lo");
	near(j.reach[0].hi, 50000.0, 0.01, "hi");
	assert_true(j.reach[0].beyond[0] == 0.0);
	near(j.reach[0].beyond[1], 50000.0, 0.01, "beyond soft_max");
	assert_true(sh2000_comp_reach_warning(&j.win, j.reach, 0, 1, msg,
					      sizeof(msg)) > 0);
	assert_string_equal(msg, "axis x at its soft_max 10.000000 mm: the tables put the tool up to 0.500000 mm beyond it (at 10.500000 mm): the card judges soft limits on nominal positions, then adds the correction");
	/* towards the inside at both limits */
	j = judge("pitch X\n-10 0.001\n0 0\n10 -0.001\n", win);
	assert_true(j.reach[0].beyond[0] == 0.0 && j.reach[0].beyond[1] == 0.0);
	/* 0.4 of a count beyond: within the card's whole counts */
	j = judge("pitch X\n-100 0.000004\n100 0.000004\n", win);
	near(j.reach[0].hi, 0.4, 0.001, "a fraction of a count");
	assert_true(j.reach[0].beyond[1] == 0.0);
	/* a cross table: Y corrected by X, judged at Y's limit over X's window */
	win.soft_max[1] = 0;
	j = judge("cross Y X\n-10 0\n0 0.002\n10 0\n", win);
	assert_int_equal(j.reach[0].tables, 0);
	assert_int_equal(j.reach[1].tables, 1);
	near(j.reach[1].beyond[1], 200.0, 0.5, "Y beyond by X's peak");
}

/* examples/machine.comp's flatness: Z over X and Y, -0.002 mm at the
 * middle point (150, 150), 0 at the corners. */
static const char grid[] = "grid Z X Y 0 150 3 0 150 3\n"
			   "0 -0.001 0\n-0.001 -0.002 -0.001\n0 -0.001 0\n";

static void grid_table(void **state)
{
	struct sh2000_comp_window win = all_off();
	struct judged j;

	(void)state;
	win.soft_min[0] = win.soft_min[1] = 0;
	win.soft_max[0] = win.soft_max[1] = 30000000;	/* 300 mm */
	win.soft_min[2] = 0;
	j = judge(grid, win);
	assert_int_equal(j.axes, 1);
	assert_int_equal(j.reach[2].tables, 1);
	near(j.reach[2].lo, -200.0, 0.5, "the grid's low point");
	near(j.reach[2].beyond[0], 200.0, 0.5, "beyond Z's soft_min");
	assert_true(j.reach[2].beyond[1] == 0.0);	/* soft_max off */
	/* X and Y kept near the corner (0, 0): a little of the dip only */
	win.soft_max[0] = win.soft_max[1] = 1000000;	/* 10 mm */
	j = judge(grid, win);
	assert_true(j.reach[2].lo < -1.0 && j.reach[2].lo > -40.0);
	/* NULL arguments: refused */
	assert_int_equal(sh2000_comp_reach(NULL, NULL, &win, j.reach), -1);
}

/* The table file's path, made once for the group. */
static int make_path(void **state)
{
	int fd;

	(void)state;
	snprintf(path, sizeof(path), "/tmp/test_comp_reach_XXXXXX");
	fd = mkstemp(path);
	if (fd < 0)
		return -1;
	return close(fd);
}

static int drop_path(void **state)
{
	(void)state;
	return unlink(path);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(no_soft_limits),
		cmocka_unit_test(one_side_off),
		cmocka_unit_test(beyond_and_within),
		cmocka_unit_test(grid_table),
	};

	return cmocka_run_group_tests(tests, make_path, drop_path);
}
