/* SPDX-License-Identifier: MIT */
/*
 * New soft limits must not leave an enabled or homed axis outside them
 * (the card refuses every set-point outside its soft limits: an axis left
 * there could not move back). The rule itself, sh2000_soft_limits_check(),
 * on statuses built by hand: which position counts (an enabled axis' set-
 * point, a homed axis' position, none for a disabled axis never homed),
 * the edges, the scale, the wording. Then on `sim`: sh2000_param_set()
 * and sh2000_axis_params_set() refuse such limits with that wording and
 * leave the card's limits as they were, and take limits around the axis.
 */
#include <math.h>
#include <string.h>

#include "simtest.h"

#define SCALE	100000.0	/* counts/mm */

static struct sh2000_status one_axis(unsigned int a, unsigned int state,
				     int32_t cmd, int64_t pos)
{
	struct sh2000_status st;

	memset(&st, 0, sizeof(st));
	st.axis[a].state = state;
	st.axis[a].cmd_counts = cmd;
	st.axis[a].pos_counts = pos;
	return st;
}

static void test_enabled_judged_on_its_set_point(void **state)
{
	/* set-point at 10 mm, the encoder (which does not count) at 60 */
	struct sh2000_status st = one_axis(0, SH2000_AXIS_ENABLED,
					   1000000, 6000000);
	char why[400];

	(void)state;
	assert_int_equal(sh2000_soft_limits_check(&st, 0, 50, 200, SCALE, why,
						  sizeof(why)), -SH2000_EPARAM);
	assert_string_equal(why, "x soft limits 50..200 mm would leave axis x (enabled, at 10.0000 mm) outside them: the card refuses every set-point outside its soft limits, so nothing could move it back; move it inside first, or give limits around it");
	assert_int_equal(sh2000_soft_limits_check(&st, 0, 5, 15, SCALE, why,
						  sizeof(why)), 0);
	/* the edges are inside (the card takes a set-point on its limit) */
	assert_int_equal(sh2000_soft_limits_check(&st, 0, 10, 20, SCALE, NULL, 0), 0);
	assert_int_equal(sh2000_soft_limits_check(&st, 0, -20, 10, SCALE, NULL, 0), 0);
	assert_int_equal(sh2000_soft_limits_check(&st, 0, 10.00001, 20, SCALE,
						  NULL, 0), -SH2000_EPARAM);
	assert_int_equal(sh2000_soft_limits_check(&st, 0, -20, 9.99999, SCALE,
						  NULL, 0), -SH2000_EPARAM);
	/* the other axes are disabled and never homed: not judged */
	assert_int_equal(sh2000_soft_limits_check(&st, 1, 50, 200, SCALE, NULL, 0), 0);
}

static void test_homed_judged_on_its_position(void **state)
{
	struct sh2000_status st = one_axis(2, SH2000_AXIS_HOMED, 0, -500000);
	char why[400];

	(void)state;
	assert_int_equal(sh2000_soft_limits_check(&st, 2, -1, 1, SCALE, why,
						  sizeof(why)), -SH2000_EPARAM);
	assert_non_null(strstr(why, "z soft limits -1..1 mm would leave axis z (homed, at -5.0000 mm) outside them"));
	assert_int_equal(sh2000_soft_limits_check(&st, 2, -6, -4, SCALE, NULL, 0), 0);
	/* enabled and homed: the set-point counts */
	st.axis[2].state |= SH2000_AXIS_ENABLED;
	st.axis[2].cmd_counts = 300000;
	assert_int_equal(sh2000_soft_limits_check(&st, 2, -6, -4, SCALE, why,
						  sizeof(why)), -SH2000_EPARAM);
	assert_non_null(strstr(why, "(enabled, at 3.0000 mm)"));
}

static void test_disabled_never_homed_not_judged(void **state)
{
	struct sh2000_status st = one_axis(3, 0, 900000000, 900000000);

	(void)state;
	assert_int_equal(sh2000_soft_limits_check(&st, 3, -1, 1, SCALE, NULL, 0), 0);
}

static void test_limits_in_the_new_scale(void **state)
{
	/* 1000000 counts: 10 mm at 100000 counts/mm, 20 mm at 50000; the
	 * card keeps counts, so the new scale reads the position anew */
	struct sh2000_status st = one_axis(1, SH2000_AXIS_ENABLED, 1000000, 0);
	char why[400];

	(void)state;
	assert_int_equal(sh2000_soft_limits_check(&st, 1, 15, 25, SCALE / 2,
						  NULL, 0), 0);
	assert_int_equal(sh2000_soft_limits_check(&st, 1, 5, 15, SCALE / 2, why,
						  sizeof(why)), -SH2000_EPARAM);
	assert_non_null(strstr(why, "y soft limits 5..15 mm would leave axis y (enabled, at 20.0000 mm)"));
}

static void test_bad_arguments(void **state)
{
	struct sh2000_status st = one_axis(0, SH2000_AXIS_ENABLED, 0, 0);
	char why[400];

	(void)state;
	assert_int_equal(sh2000_soft_limits_check(&st, SH2000_AXES, -1, 1, SCALE,
						  why, sizeof(why)), -SH2000_EPARAM);
	assert_non_null(strstr(why, "no axis 4"));
	assert_int_equal(sh2000_soft_limits_check(NULL, 0, -1, 1, SCALE, NULL, 0),
			 -SH2000_EPARAM);
	assert_int_equal(sh2000_soft_limits_check(&st, 0, NAN, 1, SCALE, NULL, 0),
			 -SH2000_EPARAM);
	assert_int_equal(sh2000_soft_limits_check(&st, 0, -1, 1, 0.0, why,
						  sizeof(why)), -SH2000_EPARAM);
	assert_non_null(strstr(why, "scale above 0"));
}

static void limits(struct sh2000 *h, unsigned int a, double *lo, double *hi)
{
	CHECK(sh2000_param_get(h, (int)a, SH2000_P_SOFT_MIN, lo));
	CHECK(sh2000_param_get(h, (int)a, SH2000_P_SOFT_MAX, hi));
}

static void refused(struct sh2000 *h, unsigned int id, double v,
		    const char *needle)
{
	double lo0, hi0, lo, hi;

	limits(h, 0, &lo0, &hi0);
	assert_int_equal(sh2000_param_set(h, 0, id, v), -SH2000_EPARAM);
	if (!strstr(sh2000_last_error(h), needle))
		fail_msg("message \"%s\" lacks \"%s\"", sh2000_last_error(h), needle);
	limits(h, 0, &lo, &hi);
	assert_true(lo == lo0 && hi == hi0);
}

static void test_param_set_refuses_on_sim(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_axis_params ap, back;
	double lo, hi;

	(void)state;
	CHECK(sh2000_param_set(h, 0, SH2000_P_SOFT_MIN, -100));
	CHECK(sh2000_param_set(h, 0, SH2000_P_SOFT_MAX, 200));
	CHECK(sh2000_enable(h, 0x1));
	CHECK(sh2000_set_position(h, 0, 10.0));
	refused(h, SH2000_P_SOFT_MIN, 50,
		"axis x parameter soft_min: x soft limits 50..200 mm would leave axis x (enabled, at 10.0000 mm) outside them: the card refuses every set-point outside its soft limits");
	refused(h, SH2000_P_SOFT_MAX, 5,
		"axis x parameter soft_max: x soft limits -100..5 mm would leave axis x (enabled, at 10.0000 mm) outside them");
	/* a whole axis: refused before anything is sent */
	CHECK(sh2000_axis_params_get(h, 0, &ap));
	ap.v[SH2000_P_KP] = ap.v[SH2000_P_KP] / 2;
	ap.v[SH2000_P_SOFT_MIN] = 20;
	ap.v[SH2000_P_SOFT_MAX] = 30;
	assert_int_equal(sh2000_axis_params_set(h, 0, &ap), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h),
			       "axis x parameters: x soft limits 20..30 mm would leave axis x (enabled, at 10.0000 mm)"));
	CHECK(sh2000_axis_params_get(h, 0, &back));
	assert_true(back.v[SH2000_P_KP] != ap.v[SH2000_P_KP]);
	assert_true(back.v[SH2000_P_SOFT_MIN] == -100 &&
		    back.v[SH2000_P_SOFT_MAX] == 200);
	/* limits around it, up to it, and a new scale are taken */
	CHECK(sh2000_param_set(h, 0, SH2000_P_SOFT_MIN, 10));
	CHECK(sh2000_param_set(h, 0, SH2000_P_SOFT_MAX, 10.5));
	ap.v[SH2000_P_SOFT_MIN] = 5;
	ap.v[SH2000_P_SOFT_MAX] = 15;
	CHECK(sh2000_axis_params_set(h, 0, &ap));
	CHECK(sh2000_param_set(h, 0, SH2000_P_SCALE, SCALE / 4));
	limits(h, 0, &lo, &hi);
	assert_true(fabs(lo - 20) < 1e-9 && fabs(hi - 60) < 1e-9);
	/* a disabled axis never homed is not judged */
	CHECK(sh2000_param_set(h, 1, SH2000_P_SOFT_MIN, 50));
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_enabled_judged_on_its_set_point),
		cmocka_unit_test(test_homed_judged_on_its_position),
		cmocka_unit_test(test_disabled_never_homed_not_judged),
		cmocka_unit_test(test_limits_in_the_new_scale),
		cmocka_unit_test(test_bad_arguments),
		cmocka_unit_test(test_param_set_refuses_on_sim),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
