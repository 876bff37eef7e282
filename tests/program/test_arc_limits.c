/* SPDX-License-Identifier: MIT */
/*
 * Arcs the geometry cannot resolve are refused by every reader with their
 * line and column: a radius or centre beyond SH2000_ARC_MAX_MM (whose
 * points would round to millimetres: R1000000000000000000 between two points 10 mm apart
 * once rounded its sweep to nothing and became a whole circle of that
 * radius), and an end so close to the start that the sweep is within the
 * rounding of the angles. The largest radius that is resolved still draws
 * the arc it was asked for. (G-code has no exponents: the reader refuses
 * R1e18, so the texts spell the numbers out.)
 */
#include "progtest.h"

static void test_radius_form(void **state)
{
	(void)state;
	expect_error(SH2000_PROG_GCODE, "G0 X10\nG2 X20 R1000000000000000000 F600\nM2\n",
		     SH2000_PD_ARC, 2, 1);
	expect_error(SH2000_PROG_GCODE, "G0 X10\nG2 X20 R100000000000000000 F600\nM2\n",
		     SH2000_PD_ARC, 2, 1);
	expect_error(SH2000_PROG_GCODE, "G0 X10\nG3 X20 R-200000000 F600\nM2\n",
		     SH2000_PD_ARC, 2, 1);
	/* a helix in another plane */
	expect_error(SH2000_PROG_GCODE,
		     "G18 G0 X10\nG2 X20 Y5 R1000000000000000000 F600\nM2\n",
		     SH2000_PD_ARC, 2, 1);
}

static void test_centre_form(void **state)
{
	(void)state;
	/* the centre 1e18 mm away: the radii agree to rounding */
	expect_error(SH2000_PROG_GCODE, "G0 X10\nG2 X20 I5 J-1000000000000000000 F600\nM2\n",
		     SH2000_PD_RANGE, 2, 1);
	expect_error(SH2000_PROG_GCODE,
		     "G0 X10\nG2 X20 Z3 I5 J-100000000000000000 F600\nM2\n",
		     SH2000_PD_RANGE, 2, 1);
	/* G90.1: the centre itself far away */
	expect_error(SH2000_PROG_GCODE,
		     "G0 X10\nG90.1 G3 X20 I15 J300000000 F600\nM2\n",
		     SH2000_PD_RANGE, 2, 7);
	/* an end 1e-8 mm from the start on a 1e7 mm radius: the two angles
	 * agree to their rounding, the sweep is a whole turn or nothing */
	expect_error(SH2000_PROG_GCODE,
		     "G0 X0 Y0\nG3 X0.00000001 I0 J10000000 F600\nM2\n",
		     SH2000_PD_ARC, 2, 1);
}

static void test_canon(void **state)
{
	(void)state;
	expect_error(SH2000_PROG_CANON,
		     "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
		     "    2 N..... SET_FEED_RATE(600.0000)\n"
		     "    3 N..... STRAIGHT_TRAVERSE(10.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
		     "    4 N..... ARC_FEED(20.0000, 0.0000, 15.0000, -1000000000000000000.0000, -1, 0.0000, 0.0000, 0.0000, 0.0000)\n",
		     SH2000_PD_RANGE, 4, 14);
}

/* Just inside the limit the arc is the one programmed: a sweep of 1e-7
 * rad between two points 10 mm apart, its centre on the bisector. */
static void test_largest_radius(void **state)
{
	const struct sh2000_prog_block *b;
	double p[SH2000_AXES];

	(void)state;
	expect_ok(SH2000_PROG_GCODE, "G0 X10\nG2 X20 R100000000 F600\nM2\n");
	b = nth(SH2000_PROG_ARC, 0);
	assert_true(fabs(b->u.arc.sweep + 1e-7) < 1e-12);
	assert_true(fabs(b->u.arc.centre[0] - 15) < 1e-6);
	sh2000_arc_point(&b->u.arc, b->start, b->end, 1.0, p);
	assert_true(fabs(p[0] - 20) < 1e-6 && fabs(p[1]) < 1e-6);
	sh2000_arc_point(&b->u.arc, b->start, b->end, 0.5, p);
	assert_true(fabs(p[0] - 15) < 1e-6 && p[1] > 0 && p[1] < 1.3e-7);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_radius_form, setup, teardown),
		cmocka_unit_test_setup_teardown(test_centre_form, setup, teardown),
		cmocka_unit_test_setup_teardown(test_canon, setup, teardown),
		cmocka_unit_test_setup_teardown(test_largest_radius, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
