// SPDX-License-Identifier: MIT
/* Homing on the switch with debounce, optionally on the index; limit
 * switch during homing. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>

#include "harness.h"

static struct harness hh;

static double bounce_mm;

static struct harness *start(double start_mm, double home_mm)
{
	struct sh2000_sim_config cfg;

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].home_bounce_mm = bounce_mm;
	cfg.axis[0].start_mm = start_mm;
	cfg.axis[0].home_mm = home_mm;
	h_init(&hh, &cfg);
	assert_int_equal(h_cmd(&hh, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	return &hh;
}

static unsigned int home(struct harness *h, uint32_t flags)
{
	unsigned int n = 0;

	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, flags, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_HOMING);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_HOMING);
	while (h_word(h, SH2000_W_STATE) == SH2000_STATE_HOMING && n < 100000) {
		h_cycles(h, 1);
		n++;
	}
	return n;
}

static double deepest;

static void track(void *ctx, const struct sh2000_probe *p)
{
	(void)ctx;
	if (p->axis[0].fine_cmd < deepest)
		deepest = p->axis[0].fine_cmd;
}

/* Homes with `debounce`; returns the physical reference point (mm) and
 * how far past it the axis went (mm). */
static double switch_point(unsigned int debounce, double *overrun)
{
	struct harness *h = start(3.0, 0.0);
	int32_t cmd[SH2000_AXES];
	uint32_t act[SH2000_AXES];
	double x;

	assert_int_equal(h_set_i(h, 0, SH2000_P_HOME_OFFSET, 12345), SH2000_RES_OK);
	assert_int_equal(h_set_i(h, 0, SH2000_P_HOME_DEBOUNCE, (int32_t)debounce),
			 SH2000_RES_OK);
	deepest = 1e18;
	sh2000_fw_set_observer(h->fw, track, NULL);
	home(h, 0);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_HOMED);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_HOMING);
	h_cycles(h, 500);
	h_snapshot(h, cmd, act);
	/* the reference point is HOME_OFFSET and the axis rests on it */
	assert_int_equal(cmd[0], 12345);
	assert_true(abs(sh2000_counter_delta(act[0], 12345)) <= 2);
	x = sh2000_board_plant(h->fw->hw, 0)->x_mm;
	/* deepest set-point in the old coordinates, relative to the latch */
	*overrun = (h->fw->dsp.ax[0].home_latch - deepest) / 1e5;
	h_fini(h);
	return x;
}

static void debounce(void **state)
{
	double o10, o100, x10 = switch_point(10, &o10), x100 = switch_point(100, &o100);

	(void)state;
	/* the reference is the switch edge, whatever the debounce */
	assert_true(x10 <= 0.0 && x10 > -0.003);
	assert_true(fabs(x10 - x100) < 0.003);
	/* confirmation needs N consecutive active cycles: at 20 mm/s that is
	 * 2 um per cycle past the edge before the axis brakes */
	assert_true(fabs((o100 - o10) - 90 * 0.002) < 0.005);
}

static void chattering_switch(void **state)
{
	double o, x1, x10;

	(void)state;
	bounce_mm = 0.05;
	/* debounce 1 takes the first chatter, 50 um before the switch point */
	x1 = switch_point(1, &o);
	/* debounce 10 ignores the chatter (runs of 3) and takes the edge of
	 * the first steady run, at the far side of the chatter band */
	x10 = switch_point(10, &o);
	bounce_mm = 0.0;
	assert_true(x1 > 0.04 && x1 < 0.0501);
	assert_true(x10 < -0.045 && x10 > -0.053);
}

static void index_pulse(void **state)
{
	struct harness *h = start(3.0, 0.0);
	int32_t cmd[SH2000_AXES];
	uint32_t act[SH2000_AXES];

	(void)state;
	home(h, SH2000_HOME_F_INDEX);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_HOMED);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_INDEX);
	h_cycles(h, 500);
	h_snapshot(h, cmd, act);
	assert_int_equal(cmd[0], 0);
	/* the index mark below the switch point is at -1 mm */
	assert_true(fabs(sh2000_board_plant(h->fw->hw, 0)->x_mm + 1.0) < 0.0001);
	h_fini(h);
}

static void starts_on_switch(void **state)
{
	struct harness *h = start(-1.5, 0.0);	/* on the switch */
	double x_ref;

	(void)state;
	home(h, 0);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_HOMED);
	x_ref = sh2000_board_plant(h->fw->hw, 0)->x_mm;
	h_fini(h);
	/* the same reference as when starting off the switch */
	h = start(3.0, 0.0);
	home(h, 0);
	assert_true(fabs(sh2000_board_plant(h->fw->hw, 0)->x_mm - x_ref) < 0.003);
	h_fini(h);
}

static void limit_during_homing(void **state)
{
	struct harness *h = start(-3.0, -100.0);	/* switch never found */

	(void)state;
	home(h, 0);
	assert_true(h_word(h, SH2000_W_AXIS_FAULTS(0)) & SH2000_AXIS_FAULT_HOME);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_AXIS);
	h_cycles(h, 2000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_HOMED);
	h_fini(h);
}

static void stop_aborts(void **state)
{
	struct harness *h = start(3.0, 0.0);

	(void)state;
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, 0, NULL), SH2000_RES_BUSY);
	h_cycles(h, 100);
	assert_int_equal(h_cmd(h, SH2000_CMD_STOP, 0, 0, 0, NULL), SH2000_RES_OK);
	h_cycles(h, 1000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) &
		     (SH2000_AXIS_HOMED | SH2000_AXIS_HOMING));
	h_fini(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(debounce),
		cmocka_unit_test(chattering_switch),
		cmocka_unit_test(index_pulse),
		cmocka_unit_test(starts_on_switch),
		cmocka_unit_test(limit_during_homing),
		cmocka_unit_test(stop_aborts),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
