// SPDX-License-Identifier: MIT
/* The parameter table and names both sides share. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "sh2000/sh2000_protocol.h"

static void table(void **state)
{
	unsigned int id, n = 0;

	(void)state;
	for (id = 0; id < 64; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		if (!p)
			continue;
		n++;
		assert_int_equal(p->id, id);
		assert_non_null(p->name);
		assert_ptr_equal(sh2000_param_by_name(p->name), p);
		/* every default is valid */
		assert_int_equal(sh2000_param_in_range(p, p->def), 0);
	}
	assert_int_equal(n, SH2000_AXIS_PARAMS + SH2000_GP_END - SH2000_GP_FIRST);
	assert_null(sh2000_param_lookup(SH2000_AXIS_PARAMS));
	assert_null(sh2000_param_lookup(SH2000_GP_END));
	assert_null(sh2000_param_by_name("nope"));
}

static void ranges(void **state)
{
	const struct sh2000_param_info *scale = sh2000_param_lookup(SH2000_P_SCALE);
	const struct sh2000_param_info *kp = sh2000_param_lookup(SH2000_P_KP);
	const struct sh2000_param_info *lim = sh2000_param_lookup(SH2000_P_DAC_LIMIT);
	const struct sh2000_param_info *hv = sh2000_param_lookup(SH2000_P_HOME_VEL);

	(void)state;
	assert_int_not_equal(sh2000_param_in_range(scale, 0.0), 0);
	assert_int_not_equal(sh2000_param_in_range(scale, NAN), 0);
	assert_int_not_equal(sh2000_param_in_range(scale, INFINITY), 0);
	assert_int_equal(sh2000_param_in_range(kp, 0.0), 0);
	assert_int_not_equal(sh2000_param_in_range(kp, -0.1), 0);
	assert_int_not_equal(sh2000_param_in_range(kp, 1e-40), 0);
	assert_int_not_equal(sh2000_param_in_range(lim, 0.0), 0);
	assert_int_not_equal(sh2000_param_in_range(lim, 32768.0), 0);
	assert_int_not_equal(sh2000_param_in_range(lim, 100.5), 0);
	assert_int_equal(sh2000_param_in_range(lim, 32767.0), 0);
	assert_int_not_equal(sh2000_param_in_range(hv, 0.0), 0);
	assert_int_equal(sh2000_param_in_range(hv, -5.0), 0);
	assert_int_not_equal(sh2000_param_in_range(NULL, 1.0), 0);
}

static void names(void **state)
{
	(void)state;
	assert_string_equal(sh2000_state_name(SH2000_STATE_ESTOP), "estop");
	assert_string_equal(sh2000_state_name(99), "unknown state");
	assert_non_null(strstr(sh2000_reject_name(SH2000_REJECT_DROPPED), "dropped"));
	assert_string_equal(sh2000_result_name(SH2000_RES_OK), "ok");
	assert_string_equal(sh2000_result_name(1000), "unknown result");
	assert_string_equal(sh2000_fault_name(SH2000_FAULT_UNDERRUN), "segment underrun");
	assert_string_equal(sh2000_axis_fault_name(SH2000_AXIS_FAULT_FERR), "following error");
}

static void checks(void **state)
{
	uint16_t rec[SH2000_RECORD_WORDS] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 0, 0 };
	uint16_t c = sh2000_record_check(rec);
	unsigned int i, b;

	(void)state;
	/* any single flipped bit in any checked word changes the check */
	for (i = 0; i < SH2000_RECORD_WORDS - 1; i++)
		for (b = 0; b < 16; b++) {
			rec[i] ^= (uint16_t)(1u << b);
			assert_int_not_equal(sh2000_record_check(rec), c);
			rec[i] ^= (uint16_t)(1u << b);
		}
	/* swapped words */
	rec[0] = 2;
	rec[1] = 1;
	assert_int_not_equal(sh2000_record_check(rec), c);
	assert_int_not_equal(sh2000_cmd_check(1, 2, 3, 4, 5, 6),
			     sh2000_cmd_check(2, 2, 3, 4, 5, 6));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(table),
		cmocka_unit_test(ranges),
		cmocka_unit_test(names),
		cmocka_unit_test(checks),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
