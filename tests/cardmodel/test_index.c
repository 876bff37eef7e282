// SPDX-License-Identifier: MIT
/* The index latch armed by the host while the card runs a stream
 * (protocol 1.6, INDEX_ARM): which edge it takes (rising or falling,
 * masked by the home switch or its inverse), the counter and the servo
 * cycle it reports, the travel limit, aborts, and what it refuses. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>

#include "harness.h"

static struct harness hh;

/* The scale: marks 0.1 mm wide from 0.25 + k mm; the home switch is
 * active at x <= 1.0 mm; the carriage starts at 3.0 mm (counter 0). */
static struct harness *start(void)
{
	struct sh2000_sim_config cfg;

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].start_mm = 3.0;
	cfg.axis[0].home_mm = 1.0;
	cfg.axis[0].index_pos_mm = 0.25;
	cfg.axis[0].index_width_mm = 0.1;
	h_init(&hh, &cfg);
	assert_int_equal(h_cmd(&hh, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	return &hh;
}

struct result {
	uint16_t block[SH2000_INDEX_WORDS];
	uint32_t seen_cycle;	/* first cycle whose status showed LATCHED */
	uint32_t arm;		/* the command's VALUE */
};

static void read_block(struct harness *h, uint16_t *b)
{
	unsigned int i;

	for (i = 0; i < SH2000_INDEX_WORDS; i++)
		b[i] = h_word(h, SH2000_W_INDEX(0) + i);
	assert_int_equal(b[SH2000_IX_CHECK], sh2000_index_check(b));
}

/* Streams axis 0 from 3.0 mm down to 0.0 mm at 20 mm/s and arms the
 * latch with `flags` and `within` once the card runs. */
static void run(struct harness *h, uint16_t flags, uint32_t within,
		struct result *res)
{
	static double x[4096];
	unsigned int n = h_trapezoid(0, -300000, 2e6, 1e7, 0.002, x, 4096);
	unsigned int next = 0, cycles = 0;
	int armed = 0;

	res->seen_cycle = 0;
	while (cycles < 200000) {
		int32_t p[SH2000_AXES] = { 0 };

		while (next < n) {
			p[0] = (int32_t)lround(x[next]);
			if (h_push(h, p, (uint16_t)next,
				   next + 1 == n ? SH2000_REC_F_END : 0))
				break;
			next++;
		}
		h_cycles(h, 1);
		cycles++;
		if (!armed && h_word(h, SH2000_W_STATE) == SH2000_STATE_RUNNING) {
			assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 0, flags,
					       within, &res->arm), SH2000_RES_OK);
			assert_true(h_word(h, SH2000_W_AXIS_STATE(0)) &
				    SH2000_AXIS_INDEX_ARMED);
			armed = 1;
		}
		if (!res->seen_cycle &&
		    (h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_INDEX_LATCHED))
			res->seen_cycle = (uint32_t)h->fw->dsp.cycle;
		if (next == n && h_word(h, SH2000_W_STATE) == SH2000_STATE_IDLE)
			break;
	}
	assert_true(armed);
	read_block(h, res->block);
}

static int32_t latched_counts(const struct result *r)
{
	uint32_t c = (uint32_t)r->block[SH2000_IX_COUNT_LO] |
		     ((uint32_t)r->block[SH2000_IX_COUNT_HI] << 16);

	return sh2000_counter_signed(c);
}

/* Expects a latch at physical x_mm (the counter at power-up, 3.0 mm, is
 * 0), reported in the cycle whose status first showed it. */
static void expect_latch(uint16_t flags, double x_mm)
{
	struct harness *h = start();
	struct result r;
	uint32_t cyc;

	run(h, flags, 0, &r);
	assert_int_equal(r.block[SH2000_IX_STATE], SH2000_INDEX_LATCHED);
	assert_int_equal(r.block[SH2000_IX_ARM], r.arm);
	assert_true(fabs(latched_counts(&r) - (x_mm - 3.0) * 1e5) <= 1.0);
	cyc = (uint32_t)r.block[SH2000_IX_CYCLE_LO] |
	      ((uint32_t)r.block[SH2000_IX_CYCLE_HI] << 16);
	assert_int_equal(cyc, r.seen_cycle);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_INDEX_ARMED);
	h_fini(h);
}

/* Going down, a mark [0.25 + k, 0.35 + k] rises at its upper end. */
static void rising_edge(void **state)
{
	(void)state;
	expect_latch(SH2000_INDEX_F_RISING, 2.35);
}

static void falling_edge(void **state)
{
	(void)state;
	expect_latch(0, 2.25);
}

/* Masked by the home switch (x <= 1.0): the first mark on the switch. */
static void masked_by_switch(void **state)
{
	(void)state;
	expect_latch(SH2000_INDEX_F_MASK | SH2000_INDEX_F_RISING, 0.35);
}

static void masked_by_inverse(void **state)
{
	(void)state;
	expect_latch(SH2000_INDEX_F_MASK | SH2000_INDEX_F_MASK_INVERT, 2.25);
}

/* No mark within 0.5 mm of where it was armed (masked: none before 0.35). */
static void missed(void **state)
{
	struct harness *h = start();
	struct result r;

	(void)state;
	run(h, SH2000_INDEX_F_MASK, 50000, &r);
	assert_int_equal(r.block[SH2000_IX_STATE], SH2000_INDEX_MISSED);
	assert_int_equal(r.seen_cycle, 0);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) &
		     (SH2000_AXIS_INDEX_ARMED | SH2000_AXIS_INDEX_LATCHED));
	h_fini(h);
}

static void refusals_and_abort(void **state)
{
	struct harness *h = start();
	uint16_t b[SH2000_INDEX_WORDS];
	uint32_t v = 0;

	(void)state;
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 1, 0, 0, &v),
			 SH2000_RES_DISABLED);
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 4, 0, 0, &v),
			 SH2000_RES_BAD_AXIS);
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 0, 0x8, 0, &v),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 0,
			       SH2000_INDEX_F_MASK_INVERT, 0, &v),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 0, 0, 0, &v), SH2000_RES_OK);
	assert_int_equal(v, 1);
	/* the card's own homing would need the latch */
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, 0, NULL), SH2000_RES_BUSY);
	/* a second arm replaces the first */
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 0, 0, 0, &v), SH2000_RES_OK);
	assert_int_equal(v, 2);
	assert_int_equal(h_cmd(h, SH2000_CMD_DISABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	h_cycles(h, 2);
	read_block(h, b);
	assert_int_equal(b[SH2000_IX_STATE], SH2000_INDEX_ABORTED);
	assert_int_equal(b[SH2000_IX_ARM], 2);
	/* disarm: OFF, and homing may have the latch again */
	assert_int_equal(h_cmd(h, SH2000_CMD_ENABLE, 0, 0, 1, NULL), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_ARM, 0, 0, 0, &v), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_INDEX_DISARM, 0, 0, 0, NULL), SH2000_RES_OK);
	read_block(h, b);
	assert_int_equal(b[SH2000_IX_STATE], SH2000_INDEX_OFF);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_INDEX_ARMED);
	assert_int_equal(h_cmd(h, SH2000_CMD_HOME, 0, 0, 0, NULL), SH2000_RES_OK);
	h_fini(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(rising_edge),
		cmocka_unit_test(falling_edge),
		cmocka_unit_test(masked_by_switch),
		cmocka_unit_test(masked_by_inverse),
		cmocka_unit_test(missed),
		cmocka_unit_test(refusals_and_abort),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
