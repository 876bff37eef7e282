// SPDX-License-Identifier: MIT
/*
 * The firmware's holds with compensation tables loaded: an emergency stop
 * (mid-move and at rest), a disable and a homing each hold the motor where
 * it is. The loop closes on the nominal set-point plus the table's
 * correction, so a hold that put the nominal set-point at the counter
 * would move the motor by the correction (here about 20 um, 2000 counts)
 * the cycle after; a homing that set the nominal set-point to HOME_OFFSET
 * after the counter preset would jump by it.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "harness.h"
#include "sh2000/sh2000.h"

#define MAXPTS	2000

/* X's pitch: 20 to 30 um over its travel, never zero */
static const char table[] =
	"id 0x20202020\n"
	"pitch X\n"
	"-100 0.020\n-50 0.025\n0 0.022\n50 0.030\n100 0.020\n";

static struct harness hh;
static int32_t pts[MAXPTS][SH2000_AXES];
static double xs[MAXPTS];

/* The table loaded through the harness (the library's file reader). */
static void load_table(struct harness *h)
{
	char msg[256];

	if (h_comp_load(h, table, msg, sizeof(msg)))
		fail_msg("%s", msg);
	/* the blend from no tables to these, then a settled loop */
	h_cycles(h, 20000);
	assert_int_equal(h_word(h, SH2000_W_COMP_STATUS + SH2000_CS_STATE),
			 SH2000_COMP_ACTIVE);
	assert_true(fabs(h->fw->dsp.comp.off[0]) > 1900.0);
}

static struct harness *start(double start_mm, double home_mm)
{
	struct sh2000_sim_config cfg;

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].start_mm = start_mm;
	cfg.axis[0].home_mm = home_mm;
	h_init(&hh, &cfg);
	assert_int_equal(h_cmd(&hh, SH2000_CMD_ENABLE, 0, 0, 0x3, NULL),
			 SH2000_RES_OK);
	load_table(&hh);
	return &hh;
}

static int64_t act(struct harness *h)
{
	return h->fw->dsp.ax[0].act;
}

/* The set-point X's loop closes on: nominal plus correction. */
static double corrected(struct harness *h)
{
	return h->fw->dsp.ax[0].cmd + h->fw->dsp.comp.off[0];
}

/* After a hold, the motor comes to rest at the counter it was held at:
 * over the last 1000 of `cycles` on average within a count of `held`
 * (the counter's own count: the loop dithers by one about a fractional
 * set-point), never two away. */
static void rests_at(struct harness *h, double held, unsigned int cycles,
		     const char *what)
{
	double worst = 0.0, sum = 0.0;
	unsigned int i;

	for (i = 0; i < cycles; i++) {
		h_cycles(h, 1);
		if (i < cycles - 1000)
			continue;
		sum += (double)act(h) - held;
		if (fabs((double)act(h) - held) > worst)
			worst = fabs((double)act(h) - held);
	}
	printf("# %s: at rest %.2f counts from where it was held on average, %.2f at most (correction %.0f counts)\n",
	       what, sum / 1000.0, worst, h->fw->dsp.comp.off[0]);
	assert_true(fabs(sum / 1000.0) < 1.0);
	assert_true(worst < 2.0);
	assert_true(fabs(corrected(h) - held) < 1.0);
}

static void estop_at_rest(void **state)
{
	struct harness *h = start(0.0, -1000.0);
	double here;

	(void)state;
	here = (double)act(h);
	assert_true(fabs(corrected(h) - here) < 1.0);
	sh2000_dpram_write(h->ram, SH2000_W_ESTOP_REQ, 1);
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_ESTOP);
	rests_at(h, here, 5000, "estop at rest");
	/* RESET holds where it is too */
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	rests_at(h, here, 5000, "reset at rest");
	h_fini(h);
}

static void estop_mid_move(void **state)
{
	struct harness *h = start(0.0, -1000.0);
	unsigned int n = h_trapezoid(0, 4e6, 5e6, 5e8, 0.002, xs, MAXPTS), i;
	unsigned int cruise = 100;
	double held;

	(void)state;
	for (i = 0; i < n && i <= cruise; i++) {
		pts[i][0] = (int32_t)lrint(xs[i]);
		pts[i][1] = pts[i][2] = pts[i][3] = 0;
		assert_int_equal(h_push(h, pts[i], (uint16_t)i, 0), 0);
		if (h_fill(h) > 16)
			h_cycles(h, 20);
	}
	h_cycles(h, 40);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_RUNNING);
	assert_true(fabs(h->fw->dsp.ax[0].cmd_v) > 1e6);
	sh2000_dpram_write(h->ram, SH2000_W_ESTOP_REQ, 1);
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_ESTOP);
	/* the hold is the counter sampled in the stop's cycle (the loop's
	 * set-point there, correction included): the motor brakes past it
	 * and comes back to it */
	held = (double)act(h);
	assert_true(fabs(corrected(h) - held) < 1.0);
	rests_at(h, held, 20000, "estop at 50 mm/s");
	assert_int_equal(h_word(h, SH2000_W_AXIS_FAULTS(0)), 0);
	h_fini(h);
}

static void disable_at_rest(void **state)
{
	struct harness *h = start(0.0, -1000.0);
	double here;

	(void)state;
	here = (double)act(h);
	assert_int_equal(h_cmd(h, SH2000_CMD_DISABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
	rests_at(h, here, 5000, "disabled at rest");
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
	rests_at(h, here, 5000, "enabled again at rest");
	h_fini(h);
}

/* How far the DAC swings from `from` over `cycles` cycles. */
static double dac_swing(struct harness *h, int16_t from, unsigned int cycles)
{
	double swing = fabs((double)h->fw->dsp.ax[0].dac - from);
	unsigned int i;

	for (i = 0; i < cycles; i++) {
		h_cycles(h, 1);
		swing = fmax(swing, fabs((double)h->fw->dsp.ax[0].dac - from));
	}
	return swing;
}

/* The host's SET_POSITION at rest, to 50 mm where the table corrects 8 um
 * more than where the motor is: the motor stays, held at the new count,
 * and the step the preset makes in the correction is not fed forward
 * (that swung the DAC from one end to the other). */
static void set_position_at_rest(void **state)
{
	struct harness *h = start(0.0, -1000.0);
	int16_t dac = h->fw->dsp.ax[0].dac;
	double swing;

	(void)state;
	assert_int_equal(h_cmd(h, SH2000_CMD_SET_POSITION, 0, 0, 5000000, NULL),
			 SH2000_RES_OK);
	swing = dac_swing(h, dac, 300);
	printf("# SET_POSITION: the DAC swung by %.0f\n", swing);
	assert_true(swing < 4096.0);
	rests_at(h, 5000000.0, 5000, "after SET_POSITION");
	h_fini(h);
}

/* Homing on the switch with the table loaded: from HOMED on the motor
 * stays where the homing left it, in the preset counter's frame. The
 * reference is 50 mm (HOME_OFFSET) from the switch, where the table
 * corrects 8 um more than at the switch: a set-point put at HOME_OFFSET
 * in nominal counts would jump by that difference. The homing's return
 * move ends with its own following error (some 10 to 30 counts, by how
 * its last ramp falls), which the preset keeps: the set-point's distance
 * from the counter changes from the cycle before the preset to the one
 * after by the move's last step to its target (the set-point is put on
 * it when within AMAX T^2 + 0.5, some 10 counts) and one cycle of the
 * loop, far less than a correction's step. Nor may the preset's step in
 * the correction (8 um) be fed forward as one cycle's velocity: that
 * slammed the DAC from one end to the other (a swing of 65534); the
 * settling after the return swings it by some 600. */
static void homing_no_jump(void **state)
{
	struct harness *h = start(3.0, 0.0);
	unsigned int n = 0;
	double before = 0.0, after, swing;

	(void)state;
	assert_int_equal(h_set_i(h, 0, SH2000_P_HOME_OFFSET, 5000000), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, 0, NULL), SH2000_RES_OK);
	while (h_word(h, SH2000_W_STATE) == SH2000_STATE_HOMING && n++ < 200000) {
		before = corrected(h) - (double)act(h);
		h_cycles(h, 1);
	}
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_HOMED);
	after = corrected(h) - (double)act(h);
	printf("# homed: set-point %.2f counts from the counter, %.2f the cycle before\n",
	       after, before);
	assert_true(fabs(after - before) < 20.0);
	swing = dac_swing(h, h->fw->dsp.ax[0].dac, 300);
	printf("# the DAC swung by %.0f in the 300 cycles after the preset\n", swing);
	assert_true(swing < 4096.0);
	rests_at(h, corrected(h), 5000, "after homing");
	/* at rest on the reference: the counter reads HOME_OFFSET on the
	 * switch's edge, give or take the following error the preset kept
	 * (the return went to the latch's nominal position, not the latch's
	 * count: that would be the correction at the switch, 22 um, away) */
	printf("# at rest %.0f counts from HOME_OFFSET\n", (double)act(h) - 5000000.0);
	assert_true(fabs((double)act(h) - 5000000.0) < 50.0);
	h_fini(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(estop_at_rest),
		cmocka_unit_test(estop_mid_move),
		cmocka_unit_test(disable_at_rest),
		cmocka_unit_test(set_position_at_rest),
		cmocka_unit_test(homing_no_jump),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
