/* SPDX-License-Identifier: MIT */
/* The built-in G-code reader: every accepted word, modal behaviour, arcs in
 * every plane, warnings once per kind, every error with its line:column. */
#include <errno.h>
#include <stdlib.h>
#include <unistd.h>

#include "progtest.h"

static void test_rapid_line_feed_end(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_ok(G, "G21 G90\nG0 X10 Y5\nG1 X20 F600\nM2\n");
	assert_int_equal(P.count, 4);
	b = &P.blocks[0];
	assert_int_equal(b->kind, SH2000_PROG_RAPID);
	assert_pos4(b->start, 0, 0, 0, 0);
	assert_pos4(b->end, 10, 5, 0, 0);
	assert_int_equal(b->pos.line, 2);
	assert_int_equal(b->pos.column, 1);
	assert_string_equal(b->pos.file, "t.ngc");
	assert_near(b->feed, 0, 0);
	b = &P.blocks[1];
	assert_int_equal(b->kind, SH2000_PROG_FEED);
	assert_near(b->u.feed_mm_min, 600, 1e-12);
	assert_near(b->feed, 10, 1e-12);
	assert_int_equal(b->pos.line, 3);
	assert_int_equal(b->pos.column, 8);
	b = &P.blocks[2];
	assert_int_equal(b->kind, SH2000_PROG_LINE);
	assert_pos4(b->start, 10, 5, 0, 0);
	assert_pos4(b->end, 20, 5, 0, 0);
	assert_near(b->feed, 10, 1e-12);
	b = &P.blocks[3];
	assert_int_equal(b->kind, SH2000_PROG_END);
	assert_int_equal(b->u.end_code, 2);
	assert_int_equal(b->pos.column, 1);
	assert_int_equal(D.count, 0);
}

static void test_modal_motion_and_axes(void **state)
{
	(void)state;
	expect_ok(G, "G1 X1 F60\nX2\nY3 Z4 A5\nG0 X0\nY1\n" "M2\n");
	assert_int_equal(count_kind(SH2000_PROG_LINE), 3);
	assert_int_equal(count_kind(SH2000_PROG_RAPID), 2);
	assert_pos4(nth(SH2000_PROG_LINE, 2)->end, 2, 3, 4, 5);
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 0, 1, 4, 5);
	/* a modal line's block points at its first word */
	assert_int_equal(nth(SH2000_PROG_LINE, 2)->pos.column, 1);
	/* G0/G1 alone set the mode and move nothing; F alone sets the feed */
	expect_ok(G, "G0\nG1 F100\n" "M2\n");
	assert_int_equal(P.count, 2);
	assert_int_equal(P.blocks[0].kind, SH2000_PROG_FEED);
	/* an unchanged F makes no feed block */
	expect_ok(G, "G1 X1 F100\nX2 F100\nX3 F200\n" "M2\n");
	assert_int_equal(count_kind(SH2000_PROG_FEED), 2);
}

static void test_distance_modes(void **state)
{
	struct sh2000_prog_options o;

	(void)state;
	expect_ok(G, "G91 G1 X1 Y1 F60\nX1 A2\nG90 X0\n" "M2\n");
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 1, 1, 0, 0);
	assert_pos4(nth(SH2000_PROG_LINE, 1)->end, 2, 1, 0, 2);
	assert_pos4(nth(SH2000_PROG_LINE, 2)->end, 0, 1, 0, 2);
	/* the machine's start position is where G91 and arcs start */
	sh2000_prog_options_default(&o);
	o.start[0] = 1;
	o.start[1] = 2;
	o.start[2] = 3;
	o.start[3] = 4;
	expect_ok_opt(G, "G91 G0 X1\nG90 Y0\n" "M2\n", &o);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->start, 1, 2, 3, 4);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 2, 2, 3, 4);
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 2, 0, 3, 4);
}

static void test_units(void **state)
{
	(void)state;
	/* axis words of a G20 line are in inches, except A, which LinuxCNC
	 * never scales: mm, with one warning */
	expect_ok(G, "G20\nG1 X1 A0.5 F10\nG21 X10\nG20 A1\n" "M2\n");
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 25.4, 0, 0, 0.5);
	assert_near(nth(SH2000_PROG_FEED, 0)->u.feed_mm_min, 254, 1e-9);
	assert_near(nth(SH2000_PROG_LINE, 0)->feed, 254.0 / 60, 1e-12);
	assert_pos4(nth(SH2000_PROG_LINE, 1)->end, 10, 0, 0, 0.5);
	assert_pos4(nth(SH2000_PROG_LINE, 2)->end, 10, 0, 0, 1);
	assert_int_equal(D.count, 1);
	assert_int_equal(D.items[0].code, SH2000_PD_ORDER);
	assert_int_equal(D.items[0].pos.line, 2);
	assert_int_equal(D.items[0].pos.column, 7);
	/* but F on the line of a units change is in the old units, as
	 * LinuxCNC sets the feed before the units; that is warned once */
	expect_ok(G, "G20 G1 X1 F10\nG21 F600 X2\nG20 F10\n" "M2\n");
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 25.4, 0, 0, 0);
	assert_near(nth(SH2000_PROG_FEED, 0)->u.feed_mm_min, 10, 1e-9);
	assert_near(nth(SH2000_PROG_FEED, 1)->u.feed_mm_min, 600 * 25.4, 1e-9);
	assert_near(nth(SH2000_PROG_FEED, 2)->u.feed_mm_min, 10, 1e-9);
	assert_int_equal(count_warnings(SH2000_PD_ORDER), 1);
	assert_int_equal(D.items[0].pos.line, 1);
	assert_int_equal(D.items[0].pos.column, 11);
	/* no warning when the line keeps the units */
	expect_ok(G, "G21 F600\n" "M2\n");
	assert_int_equal(D.count, 0);
	/* the feed in effect keeps its speed across a units change */
	expect_ok(G, "G21 F600\nG20\nG1 X1\n" "M2\n");
	assert_near(nth(SH2000_PROG_LINE, 0)->feed, 10, 1e-12);
	assert_near(nth(SH2000_PROG_LINE, 0)->end[0], 25.4, 1e-12);
	/* incremental inches */
	expect_ok(G, "G20 G91 G0 X1\nX1\n" "M2\n");
	assert_near(nth(SH2000_PROG_RAPID, 1)->end[0], 50.8, 1e-12);
}

static void test_lexical(void **state)
{
	(void)state;
	/* N words, comments, lower case, blanks, tabs, CRLF, leading zeros */
	expect_ok(G, "N10 G0 X1 (a comment) ; rest\r\nn20 (only a comment)\r\n"
		     "\tg01 x 2.5 f+60.\n  N30G0Y-.5\n" "M2\n");
	assert_int_equal(count_kind(SH2000_PROG_RAPID), 2);
	assert_near(nth(SH2000_PROG_LINE, 0)->end[0], 2.5, 1e-12);
	assert_near(nth(SH2000_PROG_RAPID, 1)->end[1], -0.5, 1e-12);
	/* G1.0 is G1 */
	expect_ok(G, "G1.0 X1 F1\n" "M2\n");
	assert_int_equal(count_kind(SH2000_PROG_LINE), 1);
	/* % opens and closes a program; what follows is reported, not read */
	expect_ok(G, "%\nG0 X1\n%\nG0 X2\n");
	assert_int_equal(count_kind(SH2000_PROG_RAPID), 1);
	assert_int_equal(count_warnings(SH2000_PD_IGNORED), 1);
	expect_error(G, "G0 X1\n%\n", SH2000_PD_SYNTAX, 2, 1);
	expect_error(G, "%\nG0 X1\n", SH2000_PD_SYNTAX, 2, 1);
}

static void test_noop_and_path_codes(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_ok(G, "G17 G21 G40 G49 G54 G80 G90 G91.1 G94\nG64 P0.01\nG61\nG61.1\nG64\nG64 P0.02 Q0.005\nG20 G64 P0.001\nG0 X1\n" "M2\n");
	assert_int_equal(count_kind(SH2000_PROG_PATH_MODE), 6);
	assert_int_equal(D.warnings, 0);
	/* G64 P: blending tolerance, Q defaults to P (LinuxCNC) */
	b = nth(SH2000_PROG_PATH_MODE, 0);
	assert_int_equal(b->pos.line, 2);
	assert_int_equal(b->u.path.mode, SH2000_PATH_BLEND);
	assert_near(b->u.path.tolerance, 0.01, 1e-12);
	assert_near(b->u.path.naive_tolerance, 0.01, 1e-12);
	assert_int_equal(nth(SH2000_PROG_PATH_MODE, 1)->u.path.mode,
			 SH2000_PATH_EXACT_PATH);
	assert_int_equal(nth(SH2000_PROG_PATH_MODE, 2)->u.path.mode,
			 SH2000_PATH_EXACT_STOP);
	/* G64 alone: best speed, no tolerance */
	b = nth(SH2000_PROG_PATH_MODE, 3);
	assert_int_equal(b->u.path.mode, SH2000_PATH_BLEND);
	assert_near(b->u.path.tolerance, 0, 0);
	b = nth(SH2000_PROG_PATH_MODE, 4);
	assert_near(b->u.path.tolerance, 0.02, 1e-12);
	assert_near(b->u.path.naive_tolerance, 0.005, 1e-12);
	/* in inches */
	assert_near(nth(SH2000_PROG_PATH_MODE, 5)->u.path.tolerance, 0.0254, 1e-12);
	/* Q needs G64 and P; tolerances are not negative; P is G64's or
	 * G4's, not both */
	expect_error(G, "G61 Q0.1\nM2\n", SH2000_PD_CONFLICT, 1, 5);
	expect_error(G, "G0 X1 Q0.1\nM2\n", SH2000_PD_CONFLICT, 1, 7);
	expect_error(G, "G64 Q0.1\nM2\n", SH2000_PD_MISSING, 1, 5);
	expect_error(G, "G64 P-1\nM2\n", SH2000_PD_RANGE, 1, 5);
	expect_error(G, "G4 G64 P1\nM2\n", SH2000_PD_CONFLICT, 1, 8);
}

static void test_arc_xy(void **state)
{
	const struct sh2000_prog_block *b;
	double p[4];

	(void)state;
	expect_ok(G, "G0 X10 Y0\nG3 X0 Y10 I-10 J0 F60\nG2 X10 Y0 I0 J-10\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_int_equal(b->u.arc.plane, SH2000_PLANE_XY);
	assert_true(b->u.arc.ccw);
	assert_int_equal(b->u.arc.turns, 1);
	assert_near(b->u.arc.centre[0], 0, 1e-12);
	assert_near(b->u.arc.centre[1], 0, 1e-12);
	assert_near(b->u.arc.r0, 10, 1e-12);
	assert_near(b->u.arc.sweep, M_PI / 2, 1e-12);
	assert_near(b->feed, 1, 1e-12);
	assert_int_equal(b->pos.line, 2);
	assert_int_equal(b->pos.column, 1);
	assert_int_equal(sh2000_prog_block_point(b, 0.5, p), 0);
	assert_near(p[0], 10 / M_SQRT2, 1e-9);
	assert_near(p[1], 10 / M_SQRT2, 1e-9);
	b = nth(SH2000_PROG_ARC, 1);
	assert_false(b->u.arc.ccw);
	assert_near(b->u.arc.sweep, -M_PI / 2, 1e-12);
	assert_pos4(b->end, 10, 0, 0, 0);
	/* I alone: J is 0 in incremental centre mode */
	expect_ok(G, "G0 X10\nG2 X-10 I-10 F1\n" "M2\n");
	assert_near(nth(SH2000_PROG_ARC, 0)->u.arc.sweep, -M_PI, 1e-12);
	/* the long way round */
	expect_ok(G, "G0 X10\nG2 X0 Y10 I-10 F1\n" "M2\n");
	assert_near(nth(SH2000_PROG_ARC, 0)->u.arc.sweep, -3 * M_PI / 2, 1e-12);
}

static void test_full_circles_and_helix(void **state)
{
	const struct sh2000_prog_block *b;
	double p[4];

	(void)state;
	expect_ok(G, "G0 X10\nG2 I-10 F60\nG2 I-10 P3\nG3 X10 Y0 Z-5 A2 I-10 J0 P2\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_near(b->u.arc.sweep, -2 * M_PI, 1e-12);
	assert_pos4(b->end, 10, 0, 0, 0);
	b = nth(SH2000_PROG_ARC, 1);
	assert_int_equal(b->u.arc.turns, 3);
	assert_near(b->u.arc.sweep, -6 * M_PI, 1e-12);
	b = nth(SH2000_PROG_ARC, 2);
	assert_true(b->u.arc.ccw);
	assert_int_equal(b->u.arc.turns, 2);
	assert_near(b->u.arc.sweep, 4 * M_PI, 1e-12);
	assert_pos4(b->end, 10, 0, -5, 2);
	assert_near(b->start[b->u.arc.normal], 0, 1e-12);
	assert_int_equal(b->u.arc.normal, SH2000_PROG_Z);
	/* a quarter of the way: one half turn, z and a a quarter down */
	sh2000_prog_block_point(b, 0.25, p);
	assert_near(p[0], -10, 1e-9);
	assert_near(p[1], 0, 1e-9);
	assert_near(p[2], -1.25, 1e-12);
	assert_near(p[3], 0.5, 1e-12);
}

static void test_arc_xz_yz(void **state)
{
	const struct sh2000_prog_block *b;
	double p[4];

	(void)state;
	/* G18: axis1 Z, axis2 X; G3 turns from +Z towards +X (seen from +Y) */
	expect_ok(G, "G0 Z10\nG18 G3 X10 Z0 I0 K-10 F60\nG0 Z10 X0\nG2 X10 Z0 K-10\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_int_equal(b->u.arc.plane, SH2000_PLANE_XZ);
	assert_int_equal(b->u.arc.first, SH2000_PROG_Z);
	assert_int_equal(b->u.arc.second, SH2000_PROG_X);
	assert_int_equal(b->u.arc.normal, SH2000_PROG_Y);
	assert_near(b->u.arc.sweep, M_PI / 2, 1e-12);
	sh2000_prog_block_point(b, 0.5, p);
	assert_near(p[0], 10 / M_SQRT2, 1e-9);
	assert_near(p[2], 10 / M_SQRT2, 1e-9);
	assert_near(nth(SH2000_PROG_ARC, 1)->u.arc.sweep, -3 * M_PI / 2, 1e-12);
	/* helix along Y in G18 */
	expect_ok(G, "G0 Z10\nG18 G3 X10 Z0 Y7 I0 K-10 F60\n" "M2\n");
	assert_pos4(nth(SH2000_PROG_ARC, 0)->end, 10, 7, 0, 0);
	/* G19: axis1 Y, axis2 Z */
	expect_ok(G, "G0 Y10\nG19 G3 Y0 Z10 J-10 K0 X3 F60\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_int_equal(b->u.arc.plane, SH2000_PLANE_YZ);
	assert_int_equal(b->u.arc.normal, SH2000_PROG_X);
	assert_near(b->u.arc.sweep, M_PI / 2, 1e-12);
	assert_pos4(b->end, 3, 0, 10, 0);
	/* full circles and helices in G18 and G19 */
	expect_ok(G, "G0 X10\nG18 G2 I-10 Y4 P2 F60\nG19 G0 X0 Y10\nG3 J-10 X-3\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_near(b->u.arc.sweep, -4 * M_PI, 1e-12);
	assert_pos4(b->end, 10, 4, 0, 0);
	sh2000_prog_block_point(b, 0.125, p);	/* a quarter turn, from +X */
	/* G2 seen from +Y (Z right, X up): clockwise, +X towards +Z */
	assert_near(p[2], 10, 1e-9);
	assert_near(p[0], 0, 1e-9);
	assert_near(p[1], 0.5, 1e-12);
	b = nth(SH2000_PROG_ARC, 1);
	assert_near(b->u.arc.sweep, 2 * M_PI, 1e-12);
	assert_pos4(b->end, -3, 10, 0, 0);
	sh2000_prog_block_point(b, 0.25, p);	/* from +Y towards +Z */
	assert_near(p[1], 0, 1e-9);
	assert_near(p[2], 10, 1e-9);
	/* the word for the normal axis' centre is an error */
	expect_error(G, "G17 G2 X1 I1 K1 F1\n", SH2000_PD_CONFLICT, 1, 14);
	expect_error(G, "G18 G2 X1 I1 J1 F1\n", SH2000_PD_CONFLICT, 1, 14);
	expect_error(G, "G19 G2 Y1 I1 J1 F1\n", SH2000_PD_CONFLICT, 1, 11);
}

static void test_arc_centre_modes(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_ok(G, "G0 X10 Y10\nG90.1 G3 X0 Y20 I0 J10 F60\nG91.1 G2 X10 Y10 I0 J-10\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_near(b->u.arc.centre[0], 0, 1e-12);
	assert_near(b->u.arc.centre[1], 10, 1e-12);
	b = nth(SH2000_PROG_ARC, 1);
	assert_near(b->u.arc.centre[0], 0, 1e-12);
	assert_near(b->u.arc.centre[1], 10, 1e-12);
	/* absolute centres in inches */
	expect_ok(G, "G20 G0 X1\nG90.1 G3 X0 Y1 I0 J0 F1\n" "M2\n");
	assert_near(nth(SH2000_PROG_ARC, 0)->u.arc.r0, 25.4, 1e-12);
	/* G90.1 needs both centre words */
	expect_error(G, "G0 X1\nG90.1 G3 X0 Y1 I0 F1\n", SH2000_PD_MISSING, 2, 7);
}

static void test_arc_r_format(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_ok(G, "G1 F1\nG2 X10 Y0 R5\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_near(b->u.arc.centre[0], 5, 1e-9);
	assert_near(b->u.arc.centre[1], 0, 1e-9);
	assert_near(b->u.arc.sweep, -M_PI, 1e-9);
	expect_ok(G, "G1 F1\nG2 X10 Y10 R10\nG0 X0 Y0\nG2 X10 Y10 R-10\nG0 X0 Y0\nG3 X10 Y10 R10\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_near(b->u.arc.centre[0], 10, 1e-9);
	assert_near(b->u.arc.centre[1], 0, 1e-9);
	assert_near(b->u.arc.sweep, -M_PI / 2, 1e-9);
	b = nth(SH2000_PROG_ARC, 1);
	assert_near(b->u.arc.centre[0], 0, 1e-9);
	assert_near(b->u.arc.centre[1], 10, 1e-9);
	assert_near(b->u.arc.sweep, -3 * M_PI / 2, 1e-9);
	b = nth(SH2000_PROG_ARC, 2);
	assert_near(b->u.arc.centre[0], 0, 1e-9);
	assert_near(b->u.arc.centre[1], 10, 1e-9);
	assert_near(b->u.arc.sweep, M_PI / 2, 1e-9);
	/* cannot reach; no end; no plane axis word */
	expect_error(G, "G1 F1\nG2 X10 Y0 R4.99\n", SH2000_PD_ARC, 2, 1);
	expect_error(G, "G1 F1\nG2 X0 Y0 R4\n", SH2000_PD_ARC, 2, 1);
	expect_error(G, "G1 F1\nG2 Z1 R4\n", SH2000_PD_MISSING, 2, 1);
	/* R and I/J together, neither */
	expect_error(G, "G1 F1\nG2 X1 R4 I1\n", SH2000_PD_CONFLICT, 2, 7);
	expect_error(G, "G1 F1\nG2 X1\n", SH2000_PD_MISSING, 2, 1);
}

static void test_arc_radius_tolerance(void **state)
{
	struct sh2000_prog_options o;
	const struct sh2000_prog_block *b;

	(void)state;
	/* within 0.0283 mm and 0.1 % */
	expect_ok(G, "G0 X10\nG3 X0 Y10.005 I-10 F1\n" "M2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_near(b->u.arc.r1, 10.005, 1e-12);
	/* the fitted circle goes through both ends, near the centre */
	assert_near(hypot(10 - b->u.arc.fit_centre[0], 0 - b->u.arc.fit_centre[1]),
		    b->u.arc.fit_radius, 1e-12);
	assert_near(hypot(0 - b->u.arc.fit_centre[0], 10.005 - b->u.arc.fit_centre[1]),
		    b->u.arc.fit_radius, 1e-12);
	assert_true(hypot(b->u.arc.fit_centre[0], b->u.arc.fit_centre[1]) < 0.005);
	/* LinuxCNC 2.9's rule (each case checked with Debian's rs274): an
	 * error past 0.0283 mm and 0.1 % of the radius at once ... */
	expect_ok(G, "G0 X10\nG3 X0 Y10.025 I-10 F1\nM2\n");
	expect_error(G, "G0 X10\nG3 X0 Y10.03 I-10 F1\nM2\n", SH2000_PD_ARC, 2, 1);
	expect_ok(G, "G0 X100\nG3 X0 Y100.05 I-100 F1\nM2\n");
	expect_error(G, "G0 X100\nG3 X0 Y100.2 I-100 F1\nM2\n", SH2000_PD_ARC, 2, 1);
	/* ... or past 100 times 0.0283 mm */
	expect_ok(G, "G0 X10000\nG3 X0 Y10002.8 I-10000 F1\nM2\n");
	expect_error(G, "G0 X10000\nG3 X0 Y10002.9 I-10000 F1\nM2\n", SH2000_PD_ARC, 2, 1);
	/* in inches the tolerance is 0.0028 in */
	expect_ok(G, "G20 G0 X1\nG3 X0 Y1.0027 I-1 F1\nM2\n");
	expect_error(G, "G20 G0 X1\nG3 X0 Y1.003 I-1 F1\nM2\n", SH2000_PD_ARC, 2, 1);
	expect_ok(G, "G20 G0 X10\nG3 X0 Y10.004 I-10 F1\nM2\n");
	/* a caller's tolerance */
	sh2000_prog_options_default(&o);
	o.arc_tolerance_mm = 0.001;
	expect_ok(G, "G0 X10\nG3 X0 Y10.015 I-10 F1\nM2\n");
	assert_int_equal(rd_opt(G, "G0 X10\nG3 X0 Y10.015 I-10 F1\nM2\n", &o),
			 -SH2000_PROG_EINVALID);
	/* zero radius */
	expect_error(G, "G0 X1\nG2 I0.0001 J0 F1\n", SH2000_PD_ARC, 2, 1);
}

static void test_arc_words(void **state)
{
	(void)state;
	/* P turns */
	expect_error(G, "G2 I1 P1.5 F1\n", SH2000_PD_RANGE, 1, 7);
	expect_error(G, "G2 I1 P0 F1\n", SH2000_PD_RANGE, 1, 7);
	/* feed */
	expect_error(G, "G2 I1\n", SH2000_PD_FEED, 1, 1);
	expect_error(G, "G1 X1 F0\nG3 I1\n", SH2000_PD_FEED, 1, 1);
	/* modal arc with axis words, and a full circle needs its G word */
	expect_ok(G, "G0 X10\nG3 X0 Y10 I-10 F1\nX-10 Y0 J-10\n" "M2\n");
	assert_int_equal(count_kind(SH2000_PROG_ARC), 2);
	expect_error(G, "G0 X10\nG3 X0 Y10 I-10 F1\nI5\n", SH2000_PD_CONFLICT, 3, 1);
}

static void test_dwell_pause_end(void **state)
{
	(void)state;
	expect_ok(G, "G4 P1.5\nG1 X1 F60 M0\nM1\nG0 X0 M30\nG0 X5\n");
	assert_near(nth(SH2000_PROG_DWELL, 0)->u.dwell_s, 1.5, 1e-12);
	assert_int_equal(P.blocks[2].kind, SH2000_PROG_LINE);
	assert_int_equal(P.blocks[3].kind, SH2000_PROG_PAUSE);
	assert_false(P.blocks[3].u.optional);
	assert_int_equal(P.blocks[3].pos.column, 11);
	assert_true(nth(SH2000_PROG_PAUSE, 1)->u.optional);
	assert_int_equal(nth(SH2000_PROG_END, 0)->u.end_code, 30);
	assert_pos4(nth(SH2000_PROG_END, 0)->start, 0, 0, 0, 0);
	/* the line after M30 is not read, and that is said */
	assert_int_equal(count_kind(SH2000_PROG_RAPID), 1);
	assert_int_equal(count_warnings(SH2000_PD_IGNORED), 1);
	assert_int_equal(D.items[0].pos.line, 5);
	/* G4 with a move: dwell first */
	expect_ok(G, "G4 P1 G0 X1\n" "M2\n");
	assert_int_equal(P.blocks[0].kind, SH2000_PROG_DWELL);
	expect_error(G, "G4\n", SH2000_PD_MISSING, 1, 1);
	expect_error(G, "G4 P-1\n", SH2000_PD_RANGE, 1, 4);
	expect_error(G, "G4 G2 I1 P1 F1\n", SH2000_PD_CONFLICT, 1, 10);
}

static void test_warnings_once_per_kind(void **state)
{
	(void)state;
	expect_ok(G, "S1000 M3\nG0 X1\nS2000 M4\nM5\nT1 M6\nT2 M6\nM8\nM7\nM9\nM2\n");
	assert_int_equal(D.errors, 0);
	assert_int_equal(D.warnings, 5);
	assert_int_equal(count_warnings(SH2000_PD_NOT_ACTED), 5);
	assert_true(has_message("S1000 (spindle speed) not acted on"));
	assert_true(has_message("M3 (spindle clockwise) not acted on"));
	assert_true(has_message("T1 (tool select) not acted on"));
	assert_true(has_message("M6 (tool change) not paused at"));
	assert_true(has_message("M8 (coolant flood) not acted on"));
	/* positions of the first of each kind */
	for (size_t i = 0; i < D.count; i++) {
		const struct sh2000_prog_diag *g = &D.items[i];

		if (strstr(g->message, "S1000"))
			assert_true(g->pos.line == 1 && g->pos.column == 1);
		if (strstr(g->message, "M3 "))
			assert_true(g->pos.line == 1 && g->pos.column == 7);
		if (strstr(g->message, "T1 (tool select)"))
			assert_true(g->pos.line == 5 && g->pos.column == 1);
		if (strstr(g->message, "M6 (tool change)"))
			assert_true(g->pos.line == 5 && g->pos.column == 4);
		if (strstr(g->message, "M8"))
			assert_true(g->pos.line == 7 && g->pos.column == 1);
	}
	assert_int_equal(count_kind(SH2000_PROG_RAPID), 1);
	assert_int_equal(count_kind(SH2000_PROG_END), 1);
	/* a message comment is read as a comment, with one warning */
	expect_ok(G, "(MSG, hello)\n(msg,again)\n(DEBUG, x)\n" "M2\n");
	assert_int_equal(count_warnings(SH2000_PD_IGNORED), 1);
}

static void test_modal_group_conflicts(void **state)
{
	(void)state;
	expect_error(G, "G0 G1 X1\n", SH2000_PD_CONFLICT, 1, 4);
	expect_error(G, "G1 G2 X1\n", SH2000_PD_CONFLICT, 1, 4);
	expect_error(G, "G5.2 G1 X1 Y1\n", SH2000_PD_CONFLICT, 1, 6);
	expect_error(G, "G17 G18\n", SH2000_PD_CONFLICT, 1, 5);
	expect_error(G, "G20 G21\n", SH2000_PD_CONFLICT, 1, 5);
	expect_error(G, "G90 G91\n", SH2000_PD_CONFLICT, 1, 5);
	expect_error(G, "G90.1 G91.1\n", SH2000_PD_CONFLICT, 1, 7);
	expect_error(G, "G61 G64\n", SH2000_PD_CONFLICT, 1, 5);
	expect_error(G, "M3 M5\n", SH2000_PD_CONFLICT, 1, 4);
	expect_error(G, "M0 M2\n", SH2000_PD_CONFLICT, 1, 4);
	expect_error(G, "M8 M9\n", SH2000_PD_CONFLICT, 1, 4);
	/* LinuxCNC's manual allows M7 with M8; its 2.9 interpreter does not */
	expect_error(G, "M7 M8\n", SH2000_PD_CONFLICT, 1, 4);
	expect_error(G, "G1 X1 X2 F1\n", SH2000_PD_CONFLICT, 1, 7);
	expect_error(G, "G1 X1 F1 F2\n", SH2000_PD_CONFLICT, 1, 10);
	/* words without a user */
	expect_error(G, "G1 X1 P2 F1\n", SH2000_PD_CONFLICT, 1, 7);
	expect_error(G, "G1 X1 I2 F1\n", SH2000_PD_CONFLICT, 1, 7);
	expect_error(G, "G1 X1 R2 F1\n", SH2000_PD_CONFLICT, 1, 7);
	expect_error(G, "G1 X1 L2 F1\n", SH2000_PD_CONFLICT, 1, 7);
	/* axis words need a motion mode */
	expect_error(G, "X1\n", SH2000_PD_MISSING, 1, 1);
	expect_error(G, "G0 X1\nG80\nY1\n", SH2000_PD_MISSING, 3, 1);
	expect_error(G, "G80 X1\n", SH2000_PD_CONFLICT, 1, 1);
}

static void test_unknown_and_unsupported(void **state)
{
	(void)state;
	expect_error(G, "G0 X1\nG12 X1\n", SH2000_PD_UNKNOWN, 2, 1);
	expect_error(G, "G1.5\n", SH2000_PD_UNKNOWN, 1, 1);
	expect_error(G, "G0 X1 G41\n", SH2000_PD_UNSUPPORTED, 1, 7);
	expect_error(G, "G38.2 Z-1\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "G5.1 X1 Y1 I1\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "G81 Z-1 R1\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "G93\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "G92 X0\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "M98\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "M60\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "M55\n", SH2000_PD_UNKNOWN, 1, 1);
	expect_error(G, "M1.5\n", SH2000_PD_UNKNOWN, 1, 1);
	expect_error(G, "G0 B1\n", SH2000_PD_NO_AXIS, 1, 4);
	expect_error(G, "G0 X1 C1\n", SH2000_PD_NO_AXIS, 1, 7);
	expect_error(G, "G0 U1\n", SH2000_PD_NO_AXIS, 1, 4);
	expect_error(G, "G41 D1\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "G0 X1 H1\n", SH2000_PD_CONFLICT, 1, 7);
	expect_error(G, "#1=5\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "G0 X#1\n", SH2000_PD_UNSUPPORTED, 1, 5);
	expect_error(G, "G0 X[1+2]\n", SH2000_PD_UNSUPPORTED, 1, 5);
	expect_error(G, "O100 sub\n", SH2000_PD_UNSUPPORTED, 1, 1);
	expect_error(G, "/G0 X1\n", SH2000_PD_UNSUPPORTED, 1, 1);
}

/* An exponent right after a number: refused at the E, the number written
 * out where that is short. */
static void exponent(const char *text, unsigned int col, const char *words)
{
	expect_error(G, text, SH2000_PD_UNSUPPORTED, 1, col);
	if (!strstr(first_error()->message, words))
		fail_msg("\"%s\" for %s", first_error()->message, text);
}

static void test_syntax_errors(void **state)
{
	(void)state;
	expect_error(G, "G0 X\n", SH2000_PD_SYNTAX, 1, 4);
	expect_error(G, "G0 X-\n", SH2000_PD_SYNTAX, 1, 4);
	expect_error(G, "G0 X1 $\n", SH2000_PD_SYNTAX, 1, 7);
	expect_error(G, "G0 X1 \x01\n", SH2000_PD_SYNTAX, 1, 7);
	expect_error(G, "G0 X1 (unclosed\n", SH2000_PD_SYNTAX, 1, 7);
	expect_error(G, "(a (b) )\n", SH2000_PD_SYNTAX, 1, 4);
	expect_error(G, "G0 N5 X1\n", SH2000_PD_SYNTAX, 1, 4);
	expect_error(G, "G0 X1e3\n", SH2000_PD_UNSUPPORTED, 1, 6);
	assert_string_equal(first_error()->message,
			    "numbers take no exponent (1e3): write 1000");
	expect_error(G, "G0 X1 E3\n", SH2000_PD_UNSUPPORTED, 1, 7);
	assert_true(has_message("E word is not in the built-in parser's subset"));
	expect_error(G, "G0 X1e\n", SH2000_PD_SYNTAX, 1, 6);
	assert_true(has_message("E word without a number"));
	exponent("G0 X-1.5E-3\n", 9, "(-1.5E-3): write -0.0015");
	exponent("G0 X+.5e+1\n", 8, "(+.5e+1): write 5");
	exponent("G0 X0012.50e1\n", 12, "(0012.50e1): write 125");
	exponent("G0 X0.0e5\n", 8, "(0.0e5): write 0");
	exponent("G0 X5.e-1\n", 7, "(5.e-1): write 0.5");
	exponent("G0 X1e-30\n", 6, "(1e-30): write 0.000000000000000000000000000001");
	exponent("G0 X1e99\n", 6, "numbers take no exponent (1e99)");
	assert_false(has_message("write"));
	exponent("G0 X1e-99999999999999999999\n", 6, "(1e-99999999999999999999)");
	assert_false(has_message("write"));
	/* more digits than are written out; the message shows 60 bytes */
	exponent("G0 X1234567890123456789012345678901234567890123456789012345678901234e1\n",
		 69, "(123456789012345678901234567890123456789012345678901234567890)");
	assert_false(has_message("write"));
	expect_error(G, "G1 X1 F-5\n", SH2000_PD_RANGE, 1, 7);
	expect_error(G, "G1 X1\n", SH2000_PD_FEED, 1, 1);
	{
		/* a number too large for a double */
		char text[700] = "G0 X";

		memset(text + 4, '9', 400);
		strcpy(text + 404, "\n");
		expect_error(G, text, SH2000_PD_RANGE, 1, 4);
	}
}

static void test_errors_everywhere_nothing_moves(void **state)
{
	char text[2000] = "";

	(void)state;
	/* every bad line is reported, with its line */
	assert_int_equal(rd(G, "G0 X1\nG0 B1\nG0 X2\nG0 Q1\nM2\n"), -SH2000_PROG_EINVALID);
	assert_int_equal(D.errors, 2);
	assert_int_equal(D.items[0].pos.line, 2);
	assert_int_equal(D.items[1].pos.line, 4);
	assert_int_equal(P.count, 0);
	/* and reading stops after max_errors */
	for (int i = 0; i < 30; i++)
		strcat(text, "G0 B1\n");
	assert_int_equal(rd(G, text), -SH2000_PROG_EINVALID);
	assert_int_equal(D.errors, 21);
	assert_int_equal(D.items[20].code, SH2000_PD_LIMIT);
	/* an arc error leaves the position at the programmed end */
	assert_int_equal(rd(G, "G0 X10\nG3 X0 Y10.5 I-10 F1\nG3 X-10.5 Y0 J-10.5\n" "M2\n"),
			 -SH2000_PROG_EINVALID);
	assert_int_equal(D.errors, 1);	/* the next arc starts at Y10.5 */
	/* a file that stops without M2/M30 may be cut short: as LinuxCNC */
	expect_error(G, "G0 X1\nG0 X2\n", SH2000_PD_MISSING, 2, 1);
	expect_error(G, "", SH2000_PD_MISSING, 1, 1);
}

static void test_diag_format_and_files(void **state)
{
	char buf[256];
	int ret;

	(void)state;
	expect_error(G, "G0 X1\nG0 B1\n", SH2000_PD_NO_AXIS, 2, 4);
	sh2000_prog_diag_format(first_error(), buf, sizeof(buf));
	assert_string_equal(buf, "t.ngc:2:4: error: the SH-2000TH has no B axis (its axes are X, Y, Z and the linear A)");
	/* files */
	sh2000_prog_diags_free(&D);
	ret = sh2000_program_read_file(&P, SH2000_PROG_AUTO, "/nonexistent/x.ngc",
				       NULL, &D);
	assert_int_equal(ret, -ENOENT);
	assert_int_equal(D.errors, 1);
	sh2000_prog_diag_format(&D.items[0], buf, sizeof(buf));
	assert_string_equal(buf, "/nonexistent/x.ngc: error: cannot read: No such file or directory");
	{
		char path[] = "/tmp/sh2000-prog-XXXXXX.ngc";
		int fd = mkstemps(path, 4);
		FILE *f = fdopen(fd, "w");

		assert_non_null(f);
		fputs("G0 X3\nM2\n", f);
		fclose(f);
		sh2000_prog_diags_free(&D);
		assert_int_equal(sh2000_program_read_file(&P, SH2000_PROG_AUTO, path,
							  NULL, &D), 0);
		assert_int_equal(P.count, 2);
		assert_string_equal(P.blocks[0].pos.file, path);
		unlink(path);
	}
	{
		/* the diagnostics as a tool prints them */
		char *text = NULL;
		size_t len = 0;
		FILE *m = open_memstream(&text, &len);

		rd(G, "S1\nG0 B1\nM2\n");
		assert_int_equal(sh2000_prog_diags_print(&D, m), 2);
		fclose(m);
		assert_string_equal(text,
			"t.ngc:1:1: warning: S1 (spindle speed) not acted on: the SH-2000TH has no spindle output; later S words are not reported\n"
			"t.ngc:2:4: error: the SH-2000TH has no B axis (its axes are X, Y, Z and the linear A)\n");
		free(text);
	}
	assert_int_equal(sh2000_prog_format_guess("a/b.NGC"), SH2000_PROG_GCODE);
	assert_int_equal(sh2000_prog_format_guess("x.canon"), SH2000_PROG_CANON);
	assert_int_equal(sh2000_prog_format_guess("x.csv"), SH2000_PROG_CSV);
	assert_int_equal(sh2000_prog_format_guess("x.json"), SH2000_PROG_NURBS_JSON);
	assert_int_equal(sh2000_prog_format_guess("x.d/noext"), SH2000_PROG_AUTO);
	sh2000_prog_diags_free(&D);
	assert_int_equal(sh2000_program_read(&P, SH2000_PROG_AUTO, "noext", "", 0,
					     NULL, &D), -SH2000_PROG_EFORMAT);
	assert_string_equal(sh2000_prog_strerror(-SH2000_PROG_EINVALID),
			    "the program has errors");
	assert_string_equal(sh2000_prog_strerror(-ENOMEM), strerror(ENOMEM));
	/* one error space: the library's own names */
	assert_int_equal(SH2000_PROG_EINVALID, SH2000_EPROGRAM);
	assert_string_equal(sh2000_strerror(-SH2000_EFORMAT),
			    "unknown program format");
}

/* Read a whole program with r: the blocks handed out (up to its END),
 * and the diagnostics its reading added to d. */
static unsigned int read_all(struct sh2000_prog_reader *r,
			     const struct sh2000_prog_diags *d, size_t *diags)
{
	const struct sh2000_prog_block *b;
	unsigned int n = 0;
	size_t before = d->count;

	while (sh2000_prog_reader_next(r, &b) == 1 &&
	       b->kind != SH2000_PROG_END)
		n++;
	*diags = d->count - before;
	return n;
}

/*
 * The axes a program moves (sh2000_prog_reader_axes): both axes of an
 * arc's plane, every axis an end leaves the start on, nothing after the
 * program's end. The scan says nothing and leaves the reader as it found
 * it: a fresh one gives its warning and its error on the next read as if
 * just opened, a read one (a replay) gives no warning twice.
 */
static void test_reader_axes(void **state)
{
	static const char text[] =
		"G21 G90 G17 F600\n"
		"S1000 M3\n"
		"G1 X10 Y5\n"
		"G18 G2 X20 Z0 I5 K0\n"
		"G1 X0 Y0\n"
		"M2\n"
		"G1 A5\n";
	static const char bad[] = "G21 G90 F600\nG1 X10\nG1 Y\nM2\n";
	const double at[SH2000_AXES] = { 0, 0, 0, 0 };
	struct sh2000_prog_diags d;
	struct sh2000_prog_reader *r;
	unsigned int moves, blocks;
	size_t diags;

	(void)state;
	sh2000_prog_diags_init(&d);
	assert_int_equal(sh2000_prog_reader_open_text(&r, SH2000_PROG_GCODE, "t.ngc",
						      text, strlen(text), NULL,
						      &d), 0);
	assert_int_equal(sh2000_prog_reader_axes(r, at, &moves), 0);
	assert_int_equal(moves, 0x7);
	assert_int_equal(d.count, 0);
	blocks = read_all(r, &d, &diags);
	assert_int_equal(diags, 2);	/* S and M3, one warning each */
	assert_int_equal(d.warnings, 2);
	/* read, then scanned: the next read is a replay, as after a rewind */
	assert_int_equal(sh2000_prog_reader_axes(r, at, &moves), 0);
	assert_int_equal(moves, 0x7);
	assert_int_equal(read_all(r, &d, &diags), blocks);
	assert_int_equal(diags, 0);
	/* axes standing at X10 Y5: the first move ends there and moves
	 * nothing, the last leaves it on both */
	{
		const double at2[SH2000_AXES] = { 10, 5, 0, 0 };

		assert_int_equal(sh2000_prog_reader_axes(r, at2, &moves), 0);
		assert_int_equal(moves, 0x7);
	}
	sh2000_prog_reader_close(r);
	/* an error: found by the read after the scan, with its position */
	assert_int_equal(sh2000_prog_reader_open_text(&r, SH2000_PROG_GCODE, "t.ngc",
						      bad, strlen(bad), NULL,
						      &d), 0);
	diags = d.count;
	assert_int_equal(sh2000_prog_reader_axes(r, at, &moves), 0);
	assert_int_equal(moves, 0x1);
	assert_int_equal(d.count, diags);
	read_all(r, &d, &diags);
	assert_int_equal(diags, 1);
	assert_int_equal(sh2000_prog_reader_errors(r), 1);
	assert_int_equal(d.items[d.count - 1].pos.line, 3);
	sh2000_prog_reader_close(r);
	sh2000_prog_diags_free(&d);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_rapid_line_feed_end, setup, teardown),
		cmocka_unit_test(test_reader_axes),
		cmocka_unit_test_setup_teardown(test_modal_motion_and_axes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_distance_modes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_units, setup, teardown),
		cmocka_unit_test_setup_teardown(test_lexical, setup, teardown),
		cmocka_unit_test_setup_teardown(test_noop_and_path_codes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_arc_xy, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_circles_and_helix, setup, teardown),
		cmocka_unit_test_setup_teardown(test_arc_xz_yz, setup, teardown),
		cmocka_unit_test_setup_teardown(test_arc_centre_modes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_arc_r_format, setup, teardown),
		cmocka_unit_test_setup_teardown(test_arc_radius_tolerance, setup, teardown),
		cmocka_unit_test_setup_teardown(test_arc_words, setup, teardown),
		cmocka_unit_test_setup_teardown(test_dwell_pause_end, setup, teardown),
		cmocka_unit_test_setup_teardown(test_warnings_once_per_kind, setup, teardown),
		cmocka_unit_test_setup_teardown(test_modal_group_conflicts, setup, teardown),
		cmocka_unit_test_setup_teardown(test_unknown_and_unsupported, setup, teardown),
		cmocka_unit_test_setup_teardown(test_syntax_errors, setup, teardown),
		cmocka_unit_test_setup_teardown(test_errors_everywhere_nothing_moves, setup, teardown),
		cmocka_unit_test_setup_teardown(test_diag_format_and_files, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
