/* SPDX-License-Identifier: MIT */
/*
 * One program through both readers: data/compare.ngc by the built-in
 * parser, and data/compare.canon, the output of LinuxCNC 2.9's standalone
 * rs274 (Debian bookworm's linuxcnc-uspace) for the same file, by the
 * canonical-command reader. They must move the same way, to rs274's 4
 * printed decimals. data/nurbs_doc.* is LinuxCNC's G5.2 example: rs274
 * prints only "NURBS_FEED(5, ...)", which the canonical reader refuses.
 * data/nurbs_*.points are the points LinuxCNC's own NURBS evaluation
 * gives for G5.2 blocks (its Python gcode module, as its preview draws
 * them: "line x y" in inches at u = k * umax / (15 * points)); the
 * built-in parser's NURBS must go through them. data/tools.ngc changes
 * tools and tool length offsets with data/tools.tbl (mm); tools.canon is
 * rs274's output for it with that table as sh2000-upload gives it to
 * rs274 (in inches, the standalone interpreter's units).
 */
#include <stdlib.h>

#include "progtest.h"

static struct sh2000_program Q;
/* the options both readers get (NULL: defaults) */
static const struct sh2000_prog_options *O;

static int rdf(struct sh2000_program *p, enum sh2000_prog_format fmt,
	       const char *name)
{
	char path[512];

	snprintf(path, sizeof(path), "%s/%s", PROGRAM_TEST_DATA, name);
	return sh2000_program_read_file(p, fmt, path, O, &D);
}

/* rs274 prints a move for G0 or G1 without axis words; this reader
 * makes none: zero-length moves (to rs274's rounding) are not compared */
static bool compared(const struct sh2000_prog_block *b)
{
	if (b->kind == SH2000_PROG_FEED)
		return false;
	if (b->kind != SH2000_PROG_RAPID && b->kind != SH2000_PROG_LINE)
		return true;
	for (int k = 0; k < 4; k++)
		if (fabs(b->end[k] - b->start[k]) > 0.003)
			return true;
	return false;
}

/* Both files read, same motion; returns the number of blocks compared. */
static size_t same_motion(const char *ngc, const char *canon)
{
	size_t i = 0, j = 0, n = 0;

	sh2000_program_init(&Q);
	assert_int_equal(rdf(&P, G, ngc), 0);
	assert_int_equal(rdf(&Q, CANON, canon), 0);
	assert_int_equal(D.errors, 0);
	for (;;) {
		const struct sh2000_prog_block *a, *b;
		double e = 0;

		while (i < P.count && !compared(&P.blocks[i]))
			i++;
		while (j < Q.count && !compared(&Q.blocks[j]))
			j++;
		if (i == P.count || j == Q.count)
			break;
		a = &P.blocks[i++];
		b = &Q.blocks[j++];
		n++;
		assert_int_equal(a->kind, b->kind);
		for (int k = 0; k < 4; k++) {
			e = fmax(e, fabs(a->start[k] - b->start[k]));
			e = fmax(e, fabs(a->end[k] - b->end[k]));
		}
		/* feeds to 4 decimals of in/min or mm/min, in mm/s */
		assert_near(a->feed, b->feed, 1e-4 * 25.4 / 60);
		switch (a->kind) {
		case SH2000_PROG_ARC:
			assert_int_equal(a->u.arc.plane, b->u.arc.plane);
			assert_int_equal(a->u.arc.ccw, b->u.arc.ccw);
			assert_int_equal(a->u.arc.turns, b->u.arc.turns);
			for (int k = 0; k < 2; k++)
				e = fmax(e, fabs(a->u.arc.centre[k] - b->u.arc.centre[k]));
			/* along the arc, to a few roundings of 4 decimals */
			if (fabs(a->u.arc.sweep - b->u.arc.sweep) * a->u.arc.r0 > 0.006)
				fail_msg("%s line %u: sweep %.9g, %s line %u: %.9g",
					 ngc, a->pos.line, a->u.arc.sweep, canon,
					 b->pos.line, b->u.arc.sweep);
			break;
		case SH2000_PROG_DWELL:
			assert_near(a->u.dwell_s, b->u.dwell_s, 1e-4);
			break;
		case SH2000_PROG_PAUSE:
			assert_int_equal(a->u.optional, b->u.optional);
			assert_int_equal(a->tool_change, b->tool_change);
			assert_int_equal(a->tool, b->tool);
			break;
		case SH2000_PROG_END:
			assert_int_equal(a->u.end_code, b->u.end_code);
			break;
		default:
			break;
		}
		/* 4 decimals of inches, before and after */
		if (e > 2 * 0.5e-4 * 25.4 + 1e-9)
			fail_msg("%s line %u and %s line %u differ by %g mm",
				 ngc, a->pos.line, canon, b->pos.line, e);
	}
	assert_int_equal(i, P.count);
	assert_int_equal(j, Q.count);
	sh2000_program_free(&Q);
	return n;
}

static void test_same_motion(void **state)
{
	(void)state;
	/* 23 motion and mode blocks, and G64 P0.01 as one path mode */
	assert_int_equal(same_motion("compare.ngc", "compare.canon"), 24);
	/* the F600 beside G21, read in inches by both */
	assert_near(nth(SH2000_PROG_FEED, 2)->u.feed_mm_min, 600 * 25.4, 1e-9);
}

/* Random programs (arcs in every plane and format, G20/G21, G90/G91,
 * G90.1/G91.1, P turns) that once showed a difference: full circles after
 * a units change, G0 alone, an arc right at the radius tolerance. */
static void test_random_programs(void **state)
{
	static const char *const seeds[] = {
		"4", "6", "7", "10", "20", "31", "1173",
	};
	char ngc[64], canon[64];

	(void)state;
	for (size_t k = 0; k < sizeof(seeds) / sizeof(seeds[0]); k++) {
		snprintf(ngc, sizeof(ngc), "random%s.ngc", seeds[k]);
		snprintf(canon, sizeof(canon), "random%s.canon", seeds[k]);
		assert_true(same_motion(ngc, canon) > 10);
	}
}

/* Tool changes (paused at) and tool length offsets: G43 H, G43, G43.1
 * in inches, G43.2, G49, with X and A offsets and an absolute arc
 * centre. */
static void test_tools(void **state)
{
	struct sh2000_tool_table t;
	struct sh2000_prog_options o;
	char path[512];

	(void)state;
	sh2000_tool_table_init(&t);
	snprintf(path, sizeof(path), "%s/tools.tbl", PROGRAM_TEST_DATA);
	assert_int_equal(sh2000_tool_table_read_file(&t, path, &D), 0);
	sh2000_prog_options_default(&o);
	o.tools = &t;
	o.pause_at_tool_change = true;
	O = &o;
	/* 16 motions, 3 tool changes, the path mode and the end */
	assert_int_equal(same_motion("tools.ngc", "tools.canon"), 21);
	assert_int_equal(count_kind(SH2000_PROG_PAUSE), 3);
	/* T1's Z+10: G1 Z-1 is at machine Z 9 */
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 0, 0, 9, 0);
	O = NULL;
	sh2000_tool_table_free(&t);
}

static void test_nurbs_example(void **state)
{
	const struct sh2000_prog_diag *e;

	(void)state;
	assert_int_equal(rdf(&P, G, "nurbs_doc.ngc"), 0);
	assert_int_equal(count_kind(SH2000_PROG_NURBS), 1);
	assert_int_equal(rdf(&P, CANON, "nurbs_doc.canon"), -SH2000_PROG_EINVALID);
	e = first_error();
	assert_non_null(e);
	assert_int_equal(e->code, SH2000_PD_UNSUPPORTED);
	assert_int_equal(e->pos.line, 11);
	assert_int_equal(e->pos.column, 14);
	assert_non_null(strstr(e->message, "G5.2"));
}

static void nurbs_points(const char *ngc, const char *points, int expect)
{
	const struct sh2000_nurbs *n;
	char path[512];
	FILE *f;
	double x, y, umax, q[4], worst = 0;
	int line, k = 0, div;

	assert_int_equal(rdf(&P, G, ngc), 0);
	n = &nth(SH2000_PROG_NURBS, 0)->u.nurbs;
	umax = n->knots[n->npoints];
	div = (int)n->npoints * 15;
	snprintf(path, sizeof(path), "%s/%s", PROGRAM_TEST_DATA, points);
	f = fopen(path, "r");
	assert_non_null(f);
	while (fscanf(f, "%d %lf %lf", &line, &x, &y) == 3) {
		k++;
		sh2000_nurbs_eval(n, k < div ? umax * k / div : umax, q, NULL, NULL);
		worst = fmax(worst, fmax(fabs(q[0] - x * 25.4), fabs(q[1] - y * 25.4)));
	}
	fclose(f);
	assert_int_equal(k, expect);
	assert_true(worst < 1e-9);
}

static void test_nurbs_like_linuxcnc(void **state)
{
	(void)state;
	nurbs_points("nurbs_doc.ngc", "nurbs_doc.points", 75);
	nurbs_points("nurbs_l4.ngc", "nurbs_l4.points", 91);
	assert_int_equal(nth(SH2000_PROG_NURBS, 0)->u.nurbs.degree, 3);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_same_motion, setup, teardown),
		cmocka_unit_test_setup_teardown(test_random_programs, setup, teardown),
		cmocka_unit_test_setup_teardown(test_tools, setup, teardown),
		cmocka_unit_test_setup_teardown(test_nurbs_example, setup, teardown),
		cmocka_unit_test_setup_teardown(test_nurbs_like_linuxcnc, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
