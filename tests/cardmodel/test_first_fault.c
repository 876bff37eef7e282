// SPDX-License-Identifier: MIT
/*
 * The first-fault record (protocol 1.4): written in the cycle the first
 * fault latches (the cycle whose end publishes it in FAULTS); not touched by the faults after
 * it (another axis, a rejected record, the emergency stop); cleared by
 * RESET; and the next fault after RESET is recorded afresh. Every fault
 * path of the firmware writes it: an axis fault, a rejected record, the
 * host's emergency stop, the host timeout.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "harness.h"

static void record(struct harness *h, uint16_t r[SH2000_FIRST_FAULT_WORDS])
{
	unsigned int i;

	for (i = 0; i < SH2000_FIRST_FAULT_WORDS; i++)
		r[i] = h_word(h, SH2000_W_FIRST_FAULT + i);
}

/* The record says (axis, bit), checks, and latched in the cycle before
 * now (the harness has run the cycle that latched it). */
static void assert_record(struct harness *h, unsigned int axis,
			  unsigned int bit, uint64_t cycle)
{
	uint16_t r[SH2000_FIRST_FAULT_WORDS];

	record(h, r);
	assert_int_equal(r[SH2000_FF_BIT], bit);
	assert_int_equal(r[SH2000_FF_AXIS], axis);
	assert_int_equal(r[SH2000_FF_CHECK], sh2000_first_fault_check(r));
	assert_int_equal((uint32_t)r[SH2000_FF_CYCLE_LO] |
			 ((uint32_t)r[SH2000_FF_CYCLE_HI] << 16),
			 (uint32_t)cycle);
}

static void assert_cleared(struct harness *h)
{
	uint16_t r[SH2000_FIRST_FAULT_WORDS];
	unsigned int i;

	record(h, r);
	for (i = 0; i < SH2000_FIRST_FAULT_WORDS; i++)
		assert_int_equal(r[i], 0);
}

/* One cycle until `word` shows a bit, at most n; the firmware's cycle
 * that latched it. */
static uint64_t cycles_until(struct harness *h, unsigned int word,
			     unsigned int n)
{
	while (n--) {
		h_cycles(h, 1);
		if (h_word(h, word))
			return h->fw->dsp.cycle;
	}
	fail_msg("word %u shows no fault", word);
	return 0;
}

static void written_once_cleared_by_reset(void **state)
{
	struct harness *h = *state;
	uint16_t first[SH2000_FIRST_FAULT_WORDS], now[SH2000_FIRST_FAULT_WORDS];
	const int32_t far[SH2000_AXES] = { 0 };
	uint64_t at;

	h_cycles(h, 10);
	assert_cleared(h);
	/* Y at its + limit switch: the first fault */
	sh2000_fw_inject(h->fw, SH2000_INJECT_LIMIT, 1, 1);
	at = cycles_until(h, SH2000_W_AXIS_FAULTS(1), 5);
	assert_record(h, 1, SH2000_AXIS_FAULT_HARD_LIMIT, at);
	record(h, first);
	/* then X's counter jumps, a record is refused, the host stops it */
	h_cycles(h, 50);
	sh2000_fw_inject(h->fw, SH2000_INJECT_COUNTER_GLITCH, 0, 0);
	cycles_until(h, SH2000_W_AXIS_FAULTS(0), 5);
	h_push(h, far, 1, 0);
	h_cycles(h, 2);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON), SH2000_REJECT_STATE);
	sh2000_dpram_write(h->ram, SH2000_W_ESTOP_REQ, 3);
	h_cycles(h, 2);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_ESTOP);
	record(h, now);
	assert_memory_equal(first, now, sizeof(first));
	/* RESET clears it; nothing is written while nothing latches */
	sh2000_fw_inject(h->fw, SH2000_INJECT_CLEAR, 0, 0);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_cleared(h);
	h_cycles(h, 100);
	assert_cleared(h);
	/* the next first fault after RESET: the host's emergency stop */
	sh2000_dpram_write(h->ram, SH2000_W_ESTOP_REQ, 4);
	at = cycles_until(h, SH2000_W_FAULTS, 2);
	assert_record(h, SH2000_AXIS_GLOBAL, SH2000_FAULT_ESTOP, at);
}

static void rejected_record_first(void **state)
{
	struct harness *h = *state;
	int32_t p[SH2000_AXES] = { 0 };
	uint64_t at;

	/* a record far beyond one step at VMAX: REJECT_VELOCITY */
	p[0] = 100000000;
	h_push(h, p, 0, 0);
	at = cycles_until(h, SH2000_W_FAULTS, 3);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), SH2000_FAULT_REJECTED);
	assert_record(h, SH2000_AXIS_GLOBAL, SH2000_FAULT_REJECTED, at);
}

static void host_timeout_first(void **state)
{
	struct harness *h = *state;
	int32_t p[SH2000_AXES] = { 0 };
	unsigned int i;
	uint64_t at;

	/* a motion the host leaves: 64 records standing still, then no
	 * heartbeat; the card times out (100 ms) before the ring runs dry */
	for (i = 0; i < SH2000_RING_RECORDS; i++)
		h_push(h, p, (uint16_t)i, 0);
	h_cycles(h, 2);
	h->host_alive = 0;
	at = cycles_until(h, SH2000_W_FAULTS, 2000);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), SH2000_FAULT_HOST_TIMEOUT);
	assert_record(h, SH2000_AXIS_GLOBAL, SH2000_FAULT_HOST_TIMEOUT, at);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(written_once_cleared_by_reset,
						h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(rejected_record_first,
						h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(host_timeout_first,
						h_setup_enabled, h_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
