/* SPDX-License-Identifier: MIT */
/*
 * The rs274 canonical-command reader, on canned text in the format of
 * LinuxCNC's standalone interpreter (src/emc/sai/saicanon.cc: "%5d " output
 * counter, "N<n>" padded to 7 characters or "N..... ", the call with %.4f
 * numbers; ARC_FEED(first_end, second_end, first_axis, second_axis,
 * rotation, axis_end_point, a, b, c)).
 */
#include "progtest.h"

static const char job[] =
	"    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
	"    2 N..... SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
	"    3 N..... SET_G92_OFFSET(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
	"    4 N..... SET_XY_ROTATION(0.0000)\n"
	"    5 N..... SET_FEED_REFERENCE(CANON_XYZ)\n"
	"    6 N..... ON_RESET()\n"
	"    7 N..... SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.000000)\n"
	"    8 N..... SET_NAIVECAM_TOLERANCE(0.0000)\n"
	"    9 N..... SET_FEED_MODE(0, 0)\n"
	"   10 N..... SET_FEED_RATE(0.0000)\n"
	"   11 N..... STOP_SPINDLE_TURNING(0)\n"
	"   12 N..... SET_SPINDLE_MODE(0 0.0000)\n"
	"   13 N..... ENABLE_FEED_OVERRIDE()\n"
	"   14 N..... SELECT_PLANE(CANON_PLANE_XY)\n"
	"   15 N..... COMMENT(\"interpreter: (a, b) comment\")\n"
	"   16 N10    SET_FEED_RATE(600.0000)\n"
	"   17 N20    STRAIGHT_TRAVERSE(10.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)\n"
	"   18 N30    STRAIGHT_FEED(10.0000, 0.0000, 0.0000, 1.0000, 0.0000, 0.0000)\n"
	"   19 N40    ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, 1, -2.0000, 1.0000, 0.0000, 0.0000)\n"
	"   20 N50    DWELL(0.5000)\n"
	"   21 N60    PROGRAM_STOP()\n"
	"   22 N65    OPTIONAL_PROGRAM_STOP()\n"
	"   23 N70    FLOOD_OFF()\n"
	"   24 N70    PROGRAM_END()\n";

static void test_job(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_ok(CANON, job);
	assert_int_equal(D.count, 0);
	assert_int_equal(P.count, 8);
	b = &P.blocks[0];
	assert_int_equal(b->kind, SH2000_PROG_FEED);
	assert_near(b->feed, 10, 1e-12);
	assert_int_equal(b->pos.line, 16);
	assert_int_equal(b->pos.column, 14);
	b = &P.blocks[1];
	assert_int_equal(b->kind, SH2000_PROG_RAPID);
	assert_pos4(b->end, 10, 0, 5, 0);
	b = &P.blocks[2];
	assert_int_equal(b->kind, SH2000_PROG_LINE);
	assert_pos4(b->end, 10, 0, 0, 1);
	assert_near(b->feed, 10, 1e-12);
	b = &P.blocks[3];
	assert_int_equal(b->kind, SH2000_PROG_ARC);
	assert_true(b->u.arc.ccw);
	assert_int_equal(b->u.arc.turns, 1);
	assert_near(b->u.arc.sweep, M_PI / 2, 1e-9);
	assert_near(b->u.arc.r0, 10, 1e-9);
	assert_pos4(b->end, 0, 10, -2, 1);
	assert_int_equal(P.blocks[4].kind, SH2000_PROG_DWELL);
	assert_near(P.blocks[4].u.dwell_s, 0.5, 1e-12);
	assert_int_equal(P.blocks[5].kind, SH2000_PROG_PAUSE);
	assert_false(P.blocks[5].u.optional);
	assert_true(P.blocks[6].u.optional);
	assert_int_equal(P.blocks[7].kind, SH2000_PROG_END);
	assert_int_equal(P.blocks[7].pos.line, 24);
}

static void test_units_offsets_planes(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_ok(CANON,
		  "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n"
		  "    2 N..... SET_FEED_RATE(10.0000)\n"
		  "    3 N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		  "    4 N..... SET_G5X_OFFSET(2, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		  "    5 N..... SET_G92_OFFSET(0.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		  "    6 N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		  "    7 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
		  "    8 N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n" "  999 N..... PROGRAM_END()\n");
	assert_near(nth(SH2000_PROG_FEED, 0)->u.feed_mm_min, 254, 1e-9);
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 25.4, 0, 0, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 25.4, 50.8, 0, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 26.4, 51.8, 0, 0);
	/* XZ: first is Z, second X, the axis end is Y; rotation -2 is G2 P2 */
	expect_ok(CANON,
		  "    1 N..... SET_FEED_RATE(60.0000)\n"
		  "    2 N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)\n"
		  "    3 N..... SELECT_PLANE(CANON_PLANE_XZ)\n"
		  "    4 N..... ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, 1, 3.0000, 0.0000, 0.0000, 0.0000)\n"
		  "    5 N..... SELECT_PLANE(CANON_PLANE_YZ)\n"
		  "    6 N..... ARC_FEED(-3.0000, 0.0000, 0.0000, 5.0000, -2, 10.0000, 0.0000, 0.0000, 0.0000)\n" "  999 N..... PROGRAM_END()\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_int_equal(b->u.arc.plane, SH2000_PLANE_XZ);
	assert_pos4(b->end, 10, 3, 0, 0);
	assert_near(b->u.arc.sweep, M_PI / 2, 1e-9);
	b = nth(SH2000_PROG_ARC, 1);
	assert_int_equal(b->u.arc.plane, SH2000_PLANE_YZ);
	assert_false(b->u.arc.ccw);
	assert_int_equal(b->u.arc.turns, 2);
	assert_pos4(b->end, 10, -3, 0, 0);
	/* older rs274 builds print only X Y Z */
	expect_ok(CANON, "    1 N..... SET_FEED_RATE(60.0000)\n"
			 "    2 N..... STRAIGHT_FEED(1.0000, 2.0000, 3.0000)\n" "  999 N..... PROGRAM_END()\n");
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 1, 2, 3, 0);
}

static void test_warnings(void **state)
{
	(void)state;
	expect_ok(CANON,
		  "    1 N..... SET_SPINDLE_SPEED(0, 0.0000)\n"
		  "    2 N..... SET_SPINDLE_SPEED(0, 1000.0000)\n"
		  "    3 N..... START_SPINDLE_CLOCKWISE(0)\n"
		  "    4 N..... START_SPINDLE_COUNTERCLOCKWISE(0)\n"
		  "    5 N..... FLOOD_ON()\n"
		  "    6 N..... MIST_ON()\n"
		  "    7 N..... SELECT_POCKET(1)\n"
		  "    8 N..... CHANGE_TOOL(1)\n"
		  "    9 N..... MESSAGE(\"hello, world\")\n"
		  "   10 N..... SET_SPINDLE_SPEED(0, 2000.0000)\n"
		  "   11 N..... PROGRAM_END()\n"
		  "   12 N..... ON_RESET()\n"
		  "   13 N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000)\n");
	assert_int_equal(D.errors, 0);
	assert_int_equal(count_warnings(SH2000_PD_NOT_ACTED), 5);
	assert_int_equal(count_warnings(SH2000_PD_IGNORED), 2);
	assert_true(has_message("CHANGE_TOOL (tool change) not paused at"));
	assert_true(has_message("SET_SPINDLE_SPEED(1000)"));
	assert_true(has_message("START_SPINDLE_CLOCKWISE (spindle)"));
	assert_true(has_message("FLOOD_ON (coolant)"));
	assert_true(has_message("SELECT_POCKET (tool)"));
	assert_true(has_message("after PROGRAM_END"));
}

static void test_errors(void **state)
{
	(void)state;
	expect_error(CANON, "    1 N..... NURBS_FEED(5, ...)\n", SH2000_PD_UNSUPPORTED, 1, 14);
	expect_error(CANON, "    1 N12    STRAIGHT_PROBE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n",
		     SH2000_PD_UNSUPPORTED, 1, 14);
	expect_error(CANON, "    1 N..... RIGID_TAP(1.0000, 0.0000, 0.0000)\n", SH2000_PD_UNSUPPORTED, 1, 14);
	expect_error(CANON, "    1 N..... FROBNICATE()\n", SH2000_PD_UNKNOWN, 1, 14);
	expect_error(CANON, "    1 N..... SET_XY_ROTATION(30.0000)\n", SH2000_PD_UNSUPPORTED, 1, 14);
	/* an offset on an axis the card does not have */
	expect_error(CANON, "    1 N..... USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 1.0000, 0.0000 2.0000 0.0000, 0.0000 0.0000 0.0000)\n",
		     SH2000_PD_NO_AXIS, 1, 14);
	expect_error(CANON, "    1 N..... USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 1.0000, 0.0000 0.0000 0.0000)\n",
		     SH2000_PD_SYNTAX, 1, 14);
	expect_error(CANON, "    1 N..... USE_TOOL_LENGTH_OFFSET(0.0000 x)\n",
		     SH2000_PD_SYNTAX, 1, 44);
	expect_ok(CANON, "    1 N..... USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 0.0000, 0.0000 0.0000 0.0000, 0.0000 0.0000 0.0000)\n" "  999 N..... PROGRAM_END()\n");
	expect_error(CANON, "    1 N..... SET_FEED_MODE(0, 1)\n", SH2000_PD_UNSUPPORTED, 1, 14);
	expect_error(CANON, "    1 N..... SELECT_PLANE(CANON_PLANE_UV)\n", SH2000_PD_UNSUPPORTED, 1, 14);
	/* B moves */
	expect_error(CANON, "    1 N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 2.0000, 0.0000)\n",
		     SH2000_PD_NO_AXIS, 1, 64);
	/* feed */
	expect_error(CANON, "    1 N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n",
		     SH2000_PD_FEED, 1, 14);
	expect_error(CANON, "    1 N..... SET_FEED_RATE(-1.0000)\n", SH2000_PD_RANGE, 1, 28);
	/* geometry */
	expect_error(CANON, "    1 N..... SET_FEED_RATE(60.0000)\n"
			    "    2 N..... STRAIGHT_FEED(10.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
			    "    3 N..... ARC_FEED(0.0000, 10.5000, 0.0000, 0.0000, 1, 0.0000, 0.0000, 0.0000, 0.0000)\n",
		     SH2000_PD_ARC, 3, 14);
	expect_error(CANON, "    1 N..... SET_FEED_RATE(60.0000)\n"
			    "    2 N..... ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, 0, 0.0000, 0.0000, 0.0000, 0.0000)\n",
		     SH2000_PD_RANGE, 2, 56);
	/* rs274 stops printing at an error: no PROGRAM_END, no run */
	expect_error(CANON, "    1 N..... SET_FEED_RATE(60.0000)\n"
			    "    2 N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000)\n",
		     SH2000_PD_MISSING, 2, 1);
	/* malformed lines */
	expect_error(CANON, "garbage\n", SH2000_PD_SYNTAX, 1, 1);
	expect_error(CANON, "    1 X..... DWELL(1.0)\n", SH2000_PD_SYNTAX, 1, 7);
	expect_error(CANON, "    1 N..... DWELL 1.0\n", SH2000_PD_SYNTAX, 1, 14);
	expect_error(CANON, "    1 N..... DWELL(1.0) x\n", SH2000_PD_SYNTAX, 1, 25);
	expect_error(CANON, "    1 N..... DWELL(abc)\n", SH2000_PD_SYNTAX, 1, 20);
	expect_error(CANON, "    1 N..... DWELL(1.0, 2.0)\n", SH2000_PD_SYNTAX, 1, 14);
	expect_error(CANON, "    1 N..... STRAIGHT_TRAVERSE(nan, 0.0000, 0.0000)\n", SH2000_PD_SYNTAX, 1, 32);
	expect_error(CANON, "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_FURLONG)\n", SH2000_PD_UNKNOWN, 1, 14);
}

/* the older format (saicanon before 2.6, canterp.cc's example): three or
 * six axes, no spindle numbers, SET_ORIGIN_OFFSETS; M30 prints
 * PALLET_SHUTTLE before PROGRAM_END */
/* G61, G61.1, G64 P Q as rs274 prints them; its own reset settings are
 * not the program's */
static void test_path_modes(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_ok(CANON,
		  "    1 N..... ON_RESET()\n"
		  "    2 N..... SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.000000)\n"
		  "    3 N..... SET_NAIVECAM_TOLERANCE(0.0000)\n"
		  "    4 N10    SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH, 0.000000)\n"
		  "    5 N20    SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP, 0.000000)\n"
		  "    6 N30    USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n"
		  "    7 N40    SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.001000)\n"
		  "    8 N40    SET_NAIVECAM_TOLERANCE(0.0005)\n"
		  "    9 N50    PROGRAM_END()\n");
	assert_int_equal(count_kind(SH2000_PROG_PATH_MODE), 3);
	assert_int_equal(nth(SH2000_PROG_PATH_MODE, 0)->u.path.mode,
			 SH2000_PATH_EXACT_PATH);
	assert_int_equal(nth(SH2000_PROG_PATH_MODE, 1)->u.path.mode,
			 SH2000_PATH_EXACT_STOP);
	b = nth(SH2000_PROG_PATH_MODE, 2);
	assert_int_equal(b->u.path.mode, SH2000_PATH_BLEND);
	assert_near(b->u.path.tolerance, 0.0254, 1e-12);
	assert_near(b->u.path.naive_tolerance, 0.0127, 1e-12);
	expect_error(CANON, "    1 N10    SET_MOTION_CONTROL_MODE(CANON_FAST, 0)\n",
		     SH2000_PD_UNKNOWN, 1, 14);
}

/* The same through the streaming reader, which hands each line's blocks
 * out before it reads the next: SET_NAIVECAM_TOLERANCE after the mode's
 * line still reaches the planner (the mode is given again with it). */
static void test_path_modes_streamed(void **state)
{
	static const char text[] =
		"    1 N..... ON_RESET()\n"
		"    2 N..... SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.000000)\n"
		"    3 N..... SET_NAIVECAM_TOLERANCE(0.0000)\n"
		"    4 N10    USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n"
		"    5 N20    SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.001000)\n"
		"    6 N20    SET_NAIVECAM_TOLERANCE(0.0005)\n"
		"    7 N30    SET_FEED_RATE(10.0000)\n"
		"    8 N30    STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		"    9 N40    PROGRAM_END()\n";
	struct sh2000_prog_diags diags;
	struct sh2000_prog_reader *r;
	const struct sh2000_prog_block *b;
	struct sh2000_prog_block last = { 0 };
	unsigned int modes = 0;

	(void)state;
	sh2000_prog_diags_init(&diags);
	assert_int_equal(sh2000_prog_reader_open_text(&r, SH2000_PROG_CANON, "t",
						      text, strlen(text), NULL,
						      &diags), 0);
	while (sh2000_prog_reader_next(r, &b) == 1) {
		if (b->kind != SH2000_PROG_PATH_MODE)
			continue;
		last = *b;
		modes++;
	}
	assert_int_equal(sh2000_prog_reader_errors(r), 0);
	sh2000_prog_reader_close(r);
	sh2000_prog_diags_free(&diags);
	assert_true(modes >= 1);
	assert_int_equal(last.u.path.mode, SH2000_PATH_BLEND);
	assert_near(last.u.path.tolerance, 0.0254, 1e-12);
	assert_near(last.u.path.naive_tolerance, 0.0127, 1e-12);
}

static void test_older_format(void **state)
{
	(void)state;
	expect_ok(CANON,
		  "1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
		  "2 N..... SET_ORIGIN_OFFSETS(1.0000, 0.0000, 0.0000)\n"
		  "3 N..... SET_FEED_REFERENCE(CANON_XYZ)\n"
		  "7 N..... COMMENT(\"Assumes 4\"x4\"x2\" finished stock)\")\n"
		  "10 N0080  MIST_OFF()\n"
		  "12 N0090  USE_TOOL_LENGTH_OFFSET(0.0000)\n"
		  "13 N0110  STRAIGHT_TRAVERSE(0.0000, 0.0000, 3.0000)\n"
		  "14 N0140  SET_FEED_RATE(16.0000)\n"
		  "15 N0140  SET_SPINDLE_SPEED(3500.0000)\n"
		  "16 N0140  START_SPINDLE_CLOCKWISE()\n"
		  "21 N0180  STRAIGHT_FEED(0.0000, 3.9150, 1.6875)\n"
		  "281 N..... STOP_SPINDLE_TURNING()\n"
		  "282 N..... SET_ORIGIN_OFFSETS(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		  "285 N..... PALLET_SHUTTLE()\n"
		  "286 N..... PROGRAM_END()\n");
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 1, 0, 3, 0);
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 1, 3.915, 1.6875, 0);
	assert_int_equal(nth(SH2000_PROG_END, 0)->u.end_code, 30);
	assert_int_equal(count_warnings(SH2000_PD_NOT_ACTED), 2);
	/* the older form's one number is the Z offset */
	expect_ok(CANON, "1 N..... USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n"
			 "12 N0090  USE_TOOL_LENGTH_OFFSET(1.0000)\n"
			 "13 N0110  STRAIGHT_TRAVERSE(0.0000, 0.0000, 3.0000)\n"
			 "14 N..... PROGRAM_END()\n");
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 4 * 25.4, 0);
	expect_error(CANON, "    1 N..... DWELL(1.0\n", SH2000_PD_SYNTAX, 1, 19);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_job, setup, teardown),
		cmocka_unit_test_setup_teardown(test_units_offsets_planes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_warnings, setup, teardown),
		cmocka_unit_test_setup_teardown(test_errors, setup, teardown),
		cmocka_unit_test_setup_teardown(test_older_format, setup, teardown),
		cmocka_unit_test_setup_teardown(test_path_modes, setup, teardown),
		cmocka_unit_test(test_path_modes_streamed),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
