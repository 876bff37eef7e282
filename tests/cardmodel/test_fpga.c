// SPDX-License-Identifier: MIT
/* FPGA register semantics, the 10-bit address counter, port-cycle counts
 * and the 28-bit encoder counter's wrap. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "card_internal.h"

static void registers(void **state)
{
	static uint16_t ram[SH2000_RAM_WORDS];
	struct sh2000_fpga f;
	unsigned int i;

	(void)state;
	sh2000_fpga_init(&f, ram);
	sh2000_fpga_out(&f, SH2000_REG_ADDR_CLEAR, 0x1234);
	sh2000_fpga_out(&f, SH2000_REG_DATA, 0xbeef);
	assert_int_equal(ram[0], 0xbeef);
	/* a data access does not move the counter */
	assert_int_equal(sh2000_fpga_in(&f, SH2000_REG_DATA), 0xbeef);
	sh2000_fpga_out(&f, SH2000_REG_DATA, 0x0001);
	assert_int_equal(ram[0], 0x0001);
	assert_int_equal(ram[1], 0);
	sh2000_fpga_out(&f, SH2000_REG_ADDR_INC, 0);
	sh2000_fpga_out(&f, SH2000_REG_DATA, 7);
	assert_int_equal(ram[1], 7);
	/* 1023 -> 0 */
	for (i = 1; i < SH2000_RAM_WORDS; i++)
		sh2000_fpga_out(&f, SH2000_REG_ADDR_INC, 0);
	assert_int_equal(f.addr, 0);
	assert_int_equal(sh2000_fpga_in(&f, SH2000_REG_DATA), 0x0001);
	/* reads of write-only registers do nothing, spare does nothing */
	assert_int_equal(sh2000_fpga_in(&f, SH2000_REG_ADDR_INC), 0xffff);
	assert_int_equal(sh2000_fpga_in(&f, SH2000_REG_ADDR_CLEAR), 0xffff);
	sh2000_fpga_out(&f, SH2000_REG_SPARE, 99);
	assert_int_equal(f.addr, 0);
	assert_int_equal(f.counters[0], 1);
	assert_int_equal(f.counters[1], SH2000_RAM_WORDS);
	assert_int_equal(f.counters[2], 2);
	assert_int_equal(f.counters[3], 3);
}

/* A board on its own RAM, the default machine started at start_mm. */
static uint16_t board_ram[SH2000_RAM_WORDS];

static struct sh2000_board *board(double start_mm)
{
	struct sh2000_sim_config cfg;
	struct sh2000_board *b;

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].start_mm = start_mm;
	assert_int_equal(sh2000_board_create(&b, board_ram, &cfg), 0);
	return b;
}

/* 100 us periods with `dac` held until `done` or 20000 periods. */
static unsigned int drive(struct sh2000_board *b, int16_t dac,
			  int (*done)(struct sh2000_board *b))
{
	unsigned int k;

	sh2000_board_write(b, 0, SH2000_HWREG_DAC, (uint16_t)dac);
	for (k = 0; k < 20000 && !done(b); k++)
		sh2000_board_run(b, 100000);
	sh2000_board_write(b, 0, SH2000_HWREG_DAC, 0);
	return k;
}

static int wrapped(struct sh2000_board *b)
{
	return sh2000_board_read(b, 0, SH2000_HWREG_COUNTER) < 1000000u;
}

/* The counter register wraps from 2^28 - 1 to 0 as the carriage moves,
 * and stays the scale's count plus the preset all the way. */
static void counter_wrap(void **state)
{
	struct sh2000_board *b = board(300.0);
	const struct sh2000_plant *pl = sh2000_board_plant(b, 0);
	int64_t scale0 = sh2000_plant_scale(pl), moved;
	uint32_t c;

	(void)state;
	assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_COUNTER), 0);
	sh2000_board_write(b, 0, SH2000_HWREG_PRESET,
			   SH2000_COUNTER_MASK - 100000u);
	assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_COUNTER),
			 SH2000_COUNTER_MASK - 100000u);
	/* presets and reads are 28 bits: the upper bits go nowhere */
	sh2000_board_write(b, 0, SH2000_HWREG_PRESET, 0xf0000000u | 5u);
	assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_COUNTER), 5u);
	sh2000_board_write(b, 0, SH2000_HWREG_PRESET,
			   SH2000_COUNTER_MASK - 100000u);
	assert_true(drive(b, 3000, wrapped) < 20000);
	c = sh2000_board_read(b, 0, SH2000_HWREG_COUNTER);
	moved = sh2000_plant_scale(pl) - scale0;
	assert_true(moved > 100000);
	assert_int_equal(c, (uint32_t)(moved - 100001));
	assert_int_equal(sh2000_counter_delta(c, SH2000_COUNTER_MASK - 100000u),
			 moved);
	sh2000_board_destroy(b);
}

static int below_zero(struct sh2000_board *b)
{
	return sh2000_plant_scale(sh2000_board_plant(b, 0)) < 30000000 - 50;
}

static void counter_negative(void **state)
{
	struct sh2000_board *b = board(300.0);
	uint32_t c;

	(void)state;
	drive(b, -3000, below_zero);
	c = sh2000_board_read(b, 0, SH2000_HWREG_COUNTER);
	assert_true(c > SH2000_COUNTER_MASK - 100000u);
	assert_int_equal(sh2000_counter_delta(c, 0),
			 sh2000_plant_scale(sh2000_board_plant(b, 0)) - 30000000);
	sh2000_board_destroy(b);
}

static int index_flag(struct sh2000_board *b)
{
	return (sh2000_board_read(b, 0, SH2000_HWREG_INPUTS) &
		SH2000_HWIN_INDEX) != 0;
}

static int past_302(struct sh2000_board *b)
{
	return sh2000_board_plant(b, 0)->x_mm > 302.2;
}

/* The first mark after ARM is latched (its counter value, exactly); the
 * flag stays until the next ARM and later marks do not overwrite it. */
static void index_latch(void **state)
{
	struct sh2000_board *b = board(300.0);
	int64_t at_preset, mark;

	(void)state;
	assert_false(index_flag(b));
	drive(b, 2000, index_flag);
	/* mark at 301 mm: 1 mm = 100000 counts from power-up */
	assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_INDEX_LATCH),
			 100000u);
	assert_true(sh2000_board_read(b, 0, SH2000_HWREG_COUNTER) >= 100000u);
	drive(b, 2000, past_302);
	assert_true(index_flag(b));
	assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_INDEX_LATCH),
			 100000u);
	/* armed again, after a preset: the next mark (302 mm, going back)
	 * in the new coordinates */
	sh2000_board_write(b, 0, SH2000_HWREG_INDEX_ARM, 1);
	assert_false(index_flag(b));
	sh2000_board_write(b, 0, SH2000_HWREG_PRESET, 0);
	at_preset = sh2000_plant_scale(sh2000_board_plant(b, 0));
	drive(b, -2000, index_flag);
	/* still coasting forwards or already back: the mark it met, to the
	 * count, in the preset's coordinates */
	mark = sh2000_counter_delta(sh2000_board_read(b, 0,
						      SH2000_HWREG_INDEX_LATCH),
				    0) + at_preset;
	assert_int_equal(mark % 100000, 0);
	assert_true(mark >= 30200000 && mark <= 30500000);
	sh2000_board_destroy(b);
}

static int home_on(struct sh2000_board *b)
{
	return (sh2000_board_read(b, 0, SH2000_HWREG_INPUTS) &
		SH2000_HWIN_HOME) != 0;
}

static int limit_neg(struct sh2000_board *b)
{
	return (sh2000_board_read(b, 0, SH2000_HWREG_INPUTS) &
		SH2000_HWIN_LIMIT_NEG) != 0;
}

static int limit_pos(struct sh2000_board *b)
{
	return (sh2000_board_read(b, 0, SH2000_HWREG_INPUTS) &
		SH2000_HWIN_LIMIT_POS) != 0;
}

/* The switch inputs follow the carriage: home at x <= 0, limits at -5 and
 * 605 mm (the defaults); a forced input reads active wherever it is. */
static void switches(void **state)
{
	struct sh2000_board *b = board(0.5);
	const struct sh2000_plant *pl = sh2000_board_plant(b, 0);

	(void)state;
	assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_INPUTS), 0);
	drive(b, -2000, home_on);
	assert_true(pl->x_mm <= 0.0 && pl->x_mm > -0.1);
	assert_false(limit_neg(b));
	drive(b, -3000, limit_neg);
	assert_true(pl->x_mm <= -5.0 && pl->x_mm > -5.2);
	assert_true(home_on(b));
	sh2000_board_destroy(b);
	b = board(604.5);
	pl = sh2000_board_plant(b, 0);
	assert_false(limit_pos(b));
	drive(b, 2000, limit_pos);
	assert_true(pl->x_mm >= 605.0 && pl->x_mm < 605.1);
	assert_int_equal(sh2000_board_force_limit(b, 0, 1), 0);
	assert_true(limit_neg(b) && limit_pos(b));
	sh2000_board_clear_faults(b);
	assert_false(limit_neg(b));
	assert_int_equal(sh2000_board_force_limit(b, SH2000_AXES, 1), -22);
	sh2000_board_destroy(b);
}

/* The DAC register keeps a 16-bit two's complement code; the range takes
 * only the DAC7744's four; a missing axis reads 0. */
static void dac_register(void **state)
{
	struct sh2000_board *b = board(300.0);

	(void)state;
	assert_int_equal(sh2000_board_read(b, 0, SH2000_HWREG_DAC_RANGE),
			 SH2000_DAC_PM10V);
	sh2000_board_write(b, 1, SH2000_HWREG_DAC, 0x18000u);
	assert_int_equal(sh2000_board_read(b, 1, SH2000_HWREG_DAC), 0x8000u);
	sh2000_board_write(b, 1, SH2000_HWREG_DAC_RANGE, SH2000_DAC_0_5V);
	sh2000_board_write(b, 1, SH2000_HWREG_DAC_RANGE, 7);
	assert_int_equal(sh2000_board_read(b, 1, SH2000_HWREG_DAC_RANGE),
			 SH2000_DAC_0_5V);
	assert_int_equal(sh2000_board_read(b, SH2000_AXES,
					   SH2000_HWREG_COUNTER), 0);
	/* -32768 codes at 0..5 V: the carriage moves backwards */
	sh2000_board_run(b, 1000000);
	assert_true(sh2000_board_plant(b, 1)->v_mm_s < 0.0);
	assert_true(sh2000_board_plant(b, 0)->v_mm_s == 0.0);
	sh2000_board_destroy(b);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(registers),
		cmocka_unit_test(counter_wrap),
		cmocka_unit_test(counter_negative),
		cmocka_unit_test(index_latch),
		cmocka_unit_test(switches),
		cmocka_unit_test(dac_register),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
