// SPDX-License-Identifier: MIT
/* Every injection surfaces through the protocol as documented in
 * docs/cardmodel.md. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "harness.h"

/* Records first..last of a slow ramp on axis 0 (none with END). */
static void push_ramp_from(struct harness *h, unsigned int first,
			   unsigned int last)
{
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };
	unsigned int i;

	for (i = first; i <= last; i++) {
		p[0] = (int32_t)(i * i * 100);
		assert_int_equal(h_push(h, p, (uint16_t)i, 0), 0);
	}
}

static void push_ramp(struct harness *h, unsigned int n)
{
	push_ramp_from(h, 1, n);
}

static void heartbeat_stop(void **state)
{
	struct harness *h = *state;
	uint16_t hb;

	h_cycles(h, 10);
	sh2000_fw_inject(h->fw, SH2000_INJECT_HEARTBEAT_STOP, 0, 0);
	hb = h_word(h, SH2000_W_HEARTBEAT);
	h_cycles(h, 200);
	assert_int_equal(h_word(h, SH2000_W_HEARTBEAT), hb);
	/* the rest of the firmware runs: commands are answered */
	assert_int_equal(h_cmd(h, SH2000_CMD_NOP, 0, 0, 0, NULL), SH2000_RES_OK);
	/* the firmware went on counting: the cell takes its next write */
	sh2000_fw_inject(h->fw, SH2000_INJECT_CLEAR, 0, 0);
	h_cycles(h, 1);
	assert_true((uint16_t)(h_word(h, SH2000_W_HEARTBEAT) - hb) > 200);
}

static void dsp_stall(void **state)
{
	struct harness *h = *state;
	uint16_t hb, snap;

	h_cycles(h, 10);
	sh2000_fw_inject(h->fw, SH2000_INJECT_DSP_STALL, 0, 0);
	hb = h_word(h, SH2000_W_HEARTBEAT);
	snap = h_word(h, SH2000_W_SNAP_SEQ_END);
	h_cmd_post(h, SH2000_CMD_NOP, 0, 0, 0);
	h_cycles(h, 200);
	assert_int_equal(h_word(h, SH2000_W_HEARTBEAT), hb);
	assert_int_equal(h_word(h, SH2000_W_SNAP_SEQ_END), snap);
	assert_int_not_equal(h_word(h, SH2000_W_CMD_ACK), h->seq);
	sh2000_fw_inject(h->fw, SH2000_INJECT_CLEAR, 0, 0);
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_CMD_ACK), h->seq);
	assert_int_equal(h_word(h, SH2000_W_HEARTBEAT), (uint16_t)(hb + 1));
}

static void ram_flip(void **state)
{
	struct harness *h = *state;
	unsigned int slot = (h->head + 5u) % SH2000_RING_RECORDS;

	push_ramp(h, 20);
	/* record seq 6 (the 6th pushed), its axis-0 position word */
	assert_int_equal(sh2000_fw_inject(h->fw, SH2000_INJECT_RAM_FLIP, 0,
					  SH2000_W_RING_BASE + slot * SH2000_RECORD_WORDS),
			 0);
	h_cycles(h, 6 * 20);
	assert_int_equal(h_word(h, SH2000_W_REJECT_SEQ), 6);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON), SH2000_REJECT_CHECKSUM);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_REJECTED);
	assert_int_equal(h_fill(h), 0);
	assert_int_equal(sh2000_fw_inject(h->fw, SH2000_INJECT_RAM_FLIP, 0, 1024), -22);
}

static void jam(void **state)
{
	struct harness *h = *state;

	push_ramp(h, 40);
	h_cycles(h, 100);
	sh2000_fw_inject(h->fw, SH2000_INJECT_JAM, 0, 0);
	h_cycles(h, 400);
	assert_true(h_word(h, SH2000_W_AXIS_FAULTS(0)) & SH2000_AXIS_FAULT_FERR);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_AXIS);
	/* the faulted axis is disabled; the other one keeps holding */
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(1)) & SH2000_AXIS_ENABLED);
	assert_int_equal(h_word(h, SH2000_W_AXIS_FAULTS(1)), 0);
	h_cycles(h, 2000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_FAULTED);
	sh2000_fw_inject(h->fw, SH2000_INJECT_CLEAR, 0, 0);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_AXIS_FAULTS(0)), 0);
	/* reset does not re-enable an axis the fault disabled */
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_OK);
}

static void limit(void **state)
{
	struct harness *h = *state;

	h_cycles(h, 10);
	sh2000_fw_inject(h->fw, SH2000_INJECT_LIMIT, 1, 1);
	h_cycles(h, 1);
	assert_true(h_word(h, SH2000_W_AXIS_FAULTS(1)) & SH2000_AXIS_FAULT_HARD_LIMIT);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(1)) & SH2000_AXIS_LIMIT_POS);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(1)) & SH2000_AXIS_ENABLED);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
	/* after reset, with the switch still active, the axis may be enabled
	 * and moved away from it, not into it */
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 2, NULL), SH2000_RES_OK);
	h_cycles(h, 10);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	sh2000_fw_inject(h->fw, SH2000_INJECT_LIMIT, 0, 0);
	h_cycles(h, 1);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_LIMIT_NEG);
	assert_true(h_word(h, SH2000_W_AXIS_FAULTS(0)) & SH2000_AXIS_FAULT_HARD_LIMIT);
}

/* The host's next record write does not reach the RAM: the slot keeps
 * its old words, and the firmware finds the gap in the SEQ numbers. */
static void drop(void **state)
{
	struct harness *h = *state;
	unsigned int slot = (h->head + 5u) % SH2000_RING_RECORDS;
	unsigned int seq_w = SH2000_W_RING_BASE + slot * SH2000_RECORD_WORDS +
			     SH2000_REC_SEQ;

	push_ramp(h, 5);
	h_cycles(h, 3 * 20);
	sh2000_fw_inject(h->fw, SH2000_INJECT_DROP_SEGMENT, 0, 0);
	push_ramp_from(h, 6, 20);
	h_cycles(h, 4 * 20);
	assert_int_equal(h_word(h, SH2000_W_REJECT_SEQ), 6);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON), SH2000_REJECT_DROPPED);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_REJECTED);
	assert_int_equal(h_fill(h), 0);
	/* the RAM holds what it held before: record 6 never arrived */
	assert_int_not_equal(h_word(h, seq_w), 6);
}

/* Records first..last at 100 counts a coarse period, waiting for room. */
static void push_slow(struct harness *h, unsigned int first,
		      unsigned int last)
{
	unsigned int i;

	for (i = first; i <= last; i++) {
		int32_t p[SH2000_AXES] = { (int32_t)(i * 100), 0, 0, 0 };

		while (h_push(h, p, (uint16_t)i, 0))
			h_cycles(h, 1);
	}
}

/* Once the ring has gone round, the lost write leaves a valid record 64
 * numbers older in the slot: its check word passes, its SEQ does not. */
static void drop_stale(void **state)
{
	struct harness *h = *state;

	push_slow(h, 1, 70);
	sh2000_fw_inject(h->fw, SH2000_INJECT_DROP_SEGMENT, 0, 0);
	push_slow(h, 71, 75);
	h_cycles(h, 70 * 20);
	assert_int_equal(h_word(h, SH2000_W_REJECT_SEQ), 71);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON), SH2000_REJECT_DROPPED);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_REJECTED);
}

static void counter_glitch(void **state)
{
	struct harness *h = *state;
	uint32_t c0;

	h_cycles(h, 10);
	c0 = sh2000_board_read(h->fw->hw, 0, SH2000_HWREG_COUNTER);
	sh2000_fw_inject(h->fw, SH2000_INJECT_COUNTER_GLITCH, 0, 0);
	/* 2^20 counts in the register, wrapped to 28 bits */
	assert_int_equal(sh2000_board_read(h->fw->hw, 0, SH2000_HWREG_COUNTER),
			 (c0 + 0x100000u) & SH2000_COUNTER_MASK);
	h_cycles(h, 1);
	assert_true(h_word(h, SH2000_W_AXIS_FAULTS(0)) & SH2000_AXIS_FAULT_COUNTER);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
}

static void dac_saturation(void **state)
{
	struct harness *h = *state;
	unsigned int i;

	assert_int_equal(h_set_i(h, 0, SH2000_P_DAC_LIMIT, 50), SH2000_RES_OK);
	assert_int_equal(h_set_i(h, 0, SH2000_P_FERR_LIMIT, 100000000), SH2000_RES_OK);
	push_ramp(h, 40);
	for (i = 0; i < 800 && !h_word(h, SH2000_W_AXIS_FAULTS(0)); i++)
		h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_AXIS_FAULTS(0)), SH2000_AXIS_FAULT_DAC_SAT);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
}

static void soft_limit(void **state)
{
	struct harness *h = *state;
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };
	unsigned int i;

	assert_int_equal(h_set_i(h, 0, SH2000_P_SOFT_MAX, 200000), SH2000_RES_OK);
	for (i = 1; i <= 10; i++) {
		p[0] = (int32_t)(i * 20000);	/* 100 mm/s up to the limit */
		h_push(h, p, (uint16_t)i, 0);
	}
	/* no END: the underrun stop runs past the soft limit */
	h_cycles(h, 2000);
	assert_true(h_word(h, SH2000_W_AXIS_FAULTS(0)) & SH2000_AXIS_FAULT_SOFT_LIMIT);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_UNDERRUN);
	assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
}

/* A jammed carriage stops the scale: the counter register freezes, the
 * firmware's following error (set-point minus encoder) grows with the
 * set-point and FERR fires when it crosses FERR_LIMIT, not before. */
static void jam_through_encoder(void **state)
{
	struct harness *h = *state;
	struct sh2000_board *b = h->fw->hw;
	double limit = h->fw->dsp.ax[0].prm.ferr_limit, err = 0.0;
	unsigned int k;
	uint32_t c0;

	push_ramp(h, 40);
	h_cycles(h, 200);
	sh2000_fw_inject(h->fw, SH2000_INJECT_JAM, 0, 0);
	h_cycles(h, 1);
	c0 = sh2000_board_read(b, 0, SH2000_HWREG_COUNTER);
	h_trace(h, 4000);
	for (k = 0; k < 4000; k++) {
		h_cycles(h, 1);
		assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_COUNTER), c0);
		if (h_word(h, SH2000_W_AXIS_FAULTS(0)))
			break;
		err = h->trace[h->trace_len - 1].axis[0].fine_cmd -
		      h->trace[h->trace_len - 1].axis[0].actual;
		assert_true(fabs(err) <= limit);
	}
	assert_int_equal(h_word(h, SH2000_W_AXIS_FAULTS(0)), SH2000_AXIS_FAULT_FERR);
	/* the last cycle before the fault was within one set-point step of
	 * the limit: the error grew to it */
	printf("# jam: FERR %u cycles after the carriage stopped, error %.0f counts the cycle before (limit %.0f)\n",
	       k + 1, err, limit);
	assert_true(fabs(err) > limit - 500.0);
}

/* A glitch below the counter-jump check is taken for motion: the counter
 * register jumps by exactly N, the firmware's position with it, and the
 * loop drives the carriage N counts the other way (a position lost that
 * only the machine knows). */
static void glitch_small(void **state)
{
	struct harness *h = *state;
	struct sh2000_board *b = h->fw->hw;
	const struct sh2000_plant *pl = sh2000_board_plant(b, 1);
	const int32_t n[2] = { 300, -700 };
	unsigned int i;

	h_cycles(h, 100);
	for (i = 0; i < 2; i++) {
		uint32_t c0 = sh2000_board_read(b, 1, SH2000_HWREG_COUNTER);
		int64_t s0 = sh2000_plant_scale(pl), act0 = h->fw->dsp.ax[1].act;

		assert_int_equal(sh2000_fw_inject(h->fw, SH2000_INJECT_COUNTER_GLITCH,
						  1, (unsigned int)n[i]), 0);
		assert_int_equal(sh2000_counter_delta(sh2000_board_read(b, 1,
						SH2000_HWREG_COUNTER), c0), n[i]);
		h_cycles(h, 1);
		assert_true(h->fw->dsp.ax[1].act == act0 + n[i]);
		h_cycles(h, 2000);
		assert_int_equal(h_word(h, SH2000_W_AXIS_FAULTS(1)), 0);
		assert_true(llabs(sh2000_plant_scale(pl) - s0 + n[i]) <= 2);
	}
	assert_int_equal(sh2000_fw_inject(h->fw, SH2000_INJECT_COUNTER_GLITCH,
					  SH2000_AXES, 1), -22);
}

/* A stall of N interrupts: nothing the firmware writes changes for N
 * cycles, then it goes on by itself; the card's clock kept running. */
static void stall_n(void **state)
{
	struct harness *h = *state;
	struct sh2000_probe p0, p1;
	uint16_t hb;

	h_cycles(h, 10);
	sh2000_fw_probe(h->fw, &p0);
	hb = h_word(h, SH2000_W_HEARTBEAT);
	sh2000_fw_inject(h->fw, SH2000_INJECT_DSP_STALL, 0, 50);
	h_cycles(h, 50);
	assert_int_equal(h_word(h, SH2000_W_HEARTBEAT), hb);
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_HEARTBEAT), (uint16_t)(hb + 1));
	sh2000_fw_probe(h->fw, &p1);
	assert_int_equal(p1.servo_cycle - p0.servo_cycle, 1);
	assert_int_equal(p1.time_ns - p0.time_ns, 51 * 100000);
}

/* RAM_FLIP's mask in arg's upper half; 0x0010 when it is 0. */
static void flip_mask(void **state)
{
	struct harness *h = *state;
	unsigned int w = SH2000_W_RING_BASE + 5;
	uint16_t v = h_word(h, w);

	assert_int_equal(sh2000_fw_inject(h->fw, SH2000_INJECT_RAM_FLIP, 0,
					  w | 0x8300u << 16), 0);
	assert_int_equal(h_word(h, w), v ^ 0x8300u);
	assert_int_equal(sh2000_fw_inject(h->fw, SH2000_INJECT_RAM_FLIP, 0, w), 0);
	assert_int_equal(h_word(h, w), v ^ 0x8310u);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(heartbeat_stop, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(dsp_stall, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(ram_flip, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(jam, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(limit, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(drop, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(drop_stale, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(counter_glitch, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(dac_saturation, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(soft_limit, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(jam_through_encoder, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(glitch_small, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(stall_n, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(flip_mask, h_setup_enabled, h_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
