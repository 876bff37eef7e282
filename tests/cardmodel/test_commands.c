// SPDX-License-Identifier: MIT
/* Command round trips through the RAM: results, values, validation. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "harness.h"

static uint32_t fbits(float f)
{
	uint32_t b;

	memcpy(&b, &f, sizeof(b));
	return b;
}

static void boot_words(void **state)
{
	struct harness *h = *state;

	assert_int_equal(h_word(h, SH2000_W_MAGIC), SH2000_PROTO_MAGIC);
	assert_int_equal(h_word(h, SH2000_W_VERSION), SH2000_PROTO_VERSION);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_int_equal(h_word(h, SH2000_W_SNAP_SEQ_BEGIN),
			 h_word(h, SH2000_W_SNAP_SEQ_END));
	h_cycles(h, 5);
	assert_int_equal(h_word(h, SH2000_W_HEARTBEAT), 5);
}

static void nop_round_trip(void **state)
{
	struct harness *h = *state;
	uint32_t v = 0;

	h_cycles(h, 3);
	h_cmd_post(h, SH2000_CMD_NOP, 0, 0, 0);
	/* acknowledged in the next servo cycle, not before */
	assert_int_not_equal(h_word(h, SH2000_W_CMD_ACK), h->seq);
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_CMD_ACK), h->seq);
	assert_int_equal(h_word(h, SH2000_W_CMD_RESULT), SH2000_RES_OK);
	v = h_word(h, SH2000_W_CMD_VALUE_LO);
	assert_int_equal(v, 4);	/* NOP returns the servo cycle */
}

static void bad_check(void **state)
{
	struct harness *h = *state;

	h_cmd_post(h, SH2000_CMD_ENABLE, 0, 0, 1);
	sh2000_dpram_write(h->ram, SH2000_W_CMD_CHECK,
			   (uint16_t)(h_word(h, SH2000_W_CMD_CHECK) + 1));
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_CMD_ACK), h->seq);
	assert_int_equal(h_word(h, SH2000_W_CMD_RESULT), SH2000_RES_CHECKSUM);
	/* nothing done */
	assert_int_equal(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED, 0);
}

static void bad_op_axis_param(void **state)
{
	struct harness *h = *state;

	assert_int_equal(h_cmd(h, 42, 0, 0, 0, NULL), SH2000_RES_BAD_OP);
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 4, 0, 0, NULL), SH2000_RES_BAD_AXIS);
	assert_int_equal(h_cmd(h, SH2000_CMD_SET_POSITION, 7, 0, 0, NULL), SH2000_RES_BAD_AXIS);
	assert_int_equal(h_cmd(h, SH2000_CMD_GET_PARAM, 0, 99, 0, NULL), SH2000_RES_BAD_PARAM);
	assert_int_equal(h_cmd(h, SH2000_CMD_GET_PARAM, 0, SH2000_GP_FINE_STEPS, 0, NULL),
			 SH2000_RES_BAD_AXIS);
	assert_int_equal(h_cmd(h, SH2000_CMD_GET_PARAM, SH2000_AXIS_GLOBAL, SH2000_P_KP, 0, NULL),
			 SH2000_RES_BAD_AXIS);
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 0x10, NULL), SH2000_RES_BAD_VALUE);
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, 2, NULL), SH2000_RES_BAD_VALUE);
}

static void params(void **state)
{
	struct harness *h = *state;
	uint32_t v;

	assert_int_equal(h_cmd(h, SH2000_CMD_GET_PARAM, 1, SH2000_P_SCALE, 0, &v), SH2000_RES_OK);
	assert_int_equal(v, fbits(100000.0f));
	assert_int_equal(h_set_f(h, 1, SH2000_P_KP, 0.75), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_GET_PARAM, 1, SH2000_P_KP, 0, &v), SH2000_RES_OK);
	assert_int_equal(v, fbits(0.75f));
	/* invalid values change nothing */
	assert_int_equal(h_set_f(h, 1, SH2000_P_KP, -1.0), SH2000_RES_BAD_VALUE);
	assert_int_equal(h_cmd(h, SH2000_CMD_SET_PARAM, 1, SH2000_P_KP, fbits(NAN), NULL),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(h_cmd(h, SH2000_CMD_SET_PARAM, 1, SH2000_P_KP, fbits(INFINITY), NULL),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(h_cmd(h, SH2000_CMD_GET_PARAM, 1, SH2000_P_KP, 0, &v), SH2000_RES_OK);
	assert_int_equal(v, fbits(0.75f));
	assert_int_equal(h_set_i(h, 1, SH2000_P_DAC_LIMIT, 0), SH2000_RES_BAD_VALUE);
	assert_int_equal(h_set_i(h, 1, SH2000_P_DAC_LIMIT, 40000), SH2000_RES_BAD_VALUE);
	assert_int_equal(h_set_i(h, 1, SH2000_P_DAC_RANGE, 4), SH2000_RES_BAD_VALUE);
	assert_int_equal(h_set_f(h, 1, SH2000_P_HOME_VEL, 0.0), SH2000_RES_BAD_VALUE);
	/* soft limits stay ordered */
	assert_int_equal(h_set_i(h, 1, SH2000_P_SOFT_MAX, 1000), SH2000_RES_OK);
	assert_int_equal(h_set_i(h, 1, SH2000_P_SOFT_MIN, 1000), SH2000_RES_BAD_VALUE);
	assert_int_equal(h_set_i(h, 1, SH2000_P_SOFT_MIN, -1000), SH2000_RES_OK);
	assert_int_equal(h_set_i(h, 1, SH2000_P_SOFT_MAX, -1000), SH2000_RES_BAD_VALUE);
	/* timing: the coarse period must divide into whole ns servo periods
	 * of at least 10 us */
	assert_int_equal(h_set_i(h, SH2000_AXIS_GLOBAL, SH2000_GP_FINE_STEPS, 300),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(h_set_i(h, SH2000_AXIS_GLOBAL, SH2000_GP_FINE_STEPS, 201),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(h_set_i(h, SH2000_AXIS_GLOBAL, SH2000_GP_FINE_STEPS, 10),
			 SH2000_RES_OK);
	assert_int_equal(sh2000_fw_servo_period_ns(h->fw), 200000);
	assert_int_equal(h_set_i(h, SH2000_AXIS_GLOBAL, SH2000_GP_COARSE_PERIOD_US, 99),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(h_cmd(h, SH2000_CMD_GET_PARAM, SH2000_AXIS_GLOBAL,
			       SH2000_GP_HOST_TIMEOUT_MS, 0, &v), SH2000_RES_OK);
	assert_int_equal(v, 100);
}

static void enable_disable(void **state)
{
	struct harness *h = *state;

	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 0x5, NULL), SH2000_RES_OK);
	h_cycles(h, 1);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(1)) & SH2000_AXIS_ENABLED);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(2)) & SH2000_AXIS_ENABLED);
	h_cycles(h, 500);
	/* holding still: no fault, small error */
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_int_equal(h_cmd(h, SH2000_CMD_DISABLE, 0, 0, 0x4, NULL), SH2000_RES_OK);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(2)) & SH2000_AXIS_ENABLED);
	assert_int_equal(h_cmd(h, SH2000_CMD_DISABLE, 0, 0, 0x100, NULL), SH2000_RES_BAD_VALUE);
}

static void set_position(void **state)
{
	struct harness *h = *state;
	int32_t cmd[SH2000_AXES];
	uint32_t act[SH2000_AXES];

	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_SET_POSITION, 0, 0, (uint32_t)-5000, NULL),
			 SH2000_RES_OK);
	h_cycles(h, 20);
	h_snapshot(h, cmd, act);
	assert_int_equal(cmd[0], -5000);
	/* the 28-bit counter: -5000 wraps */
	assert_true(abs(sh2000_counter_delta(act[0], (uint32_t)-5000 & SH2000_COUNTER_MASK)) < 3);
}

static void busy_and_faulted(void **state)
{
	struct harness *h = *state;
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };
	unsigned int i;

	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	for (i = 1; i <= 40; i++) {
		p[0] = (int32_t)(i * 2000);
		assert_int_equal(h_push(h, p, (uint16_t)i, 0), 0);
	}
	h_cycles(h, 5);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_RUNNING);
	/* gains may change in motion, scale and timing may not */
	assert_int_equal(h_set_f(h, 0, SH2000_P_KP, 0.5), SH2000_RES_OK);
	assert_int_equal(h_set_f(h, 0, SH2000_P_SCALE, 1000.0), SH2000_RES_BUSY);
	assert_int_equal(h_set_i(h, SH2000_AXIS_GLOBAL, SH2000_GP_FINE_STEPS, 10),
			 SH2000_RES_BUSY);
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 2, NULL), SH2000_RES_BUSY);
	assert_int_equal(h_cmd(h, SH2000_CMD_SET_POSITION, 0, 0, 0, NULL), SH2000_RES_BUSY);
	/* stop: decelerates, then idle */
	assert_int_equal(h_cmd(h, SH2000_CMD_STOP, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_STOPPING);
	h_cycles(h, 2000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_int_equal(h_fill(h), 0);
	/* a latched fault forbids enable and homing until reset */
	sh2000_dpram_write(h->ram, SH2000_W_ESTOP_REQ, 1);
	h_cycles(h, 1);
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 2, NULL), SH2000_RES_FAULTED);
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, 0, NULL), SH2000_RES_FAULTED);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	/* axes stay enabled through a reset */
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 2, NULL), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 3, 0, 0, NULL), SH2000_RES_DISABLED);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(boot_words, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(nop_round_trip, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(bad_check, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(bad_op_axis_param, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(params, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(enable_disable, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(set_position, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(busy_and_faulted, h_setup, h_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
