// SPDX-License-Identifier: MIT
/* FPGA register semantics, the 10-bit address counter, port-cycle counts
 * and the 28-bit encoder counter's wrap. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "cardmodel.h"

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

static void counter_wrap(void **state)
{
	struct sh2000_sim_config cfg;
	struct sh2000_plant p;
	uint32_t before, after;

	(void)state;
	sh2000_sim_config_default(&cfg);
	sh2000_plant_init(&p, &cfg.axis[0]);
	assert_int_equal(sh2000_plant_counter(&p), 0);
	sh2000_plant_preset(&p, SH2000_COUNTER_MASK - 5u);
	before = sh2000_plant_counter(&p);
	assert_int_equal(before, SH2000_COUNTER_MASK - 5u);
	p.x_mm += 0.000105;	/* +10.5 counts */
	after = sh2000_plant_counter(&p);
	assert_int_equal(after, 4u);
	assert_int_equal(sh2000_counter_delta(after, before), 10);
	assert_int_equal(sh2000_counter_delta(before, after), -10);
	assert_int_equal(sh2000_counter_delta(0, 0), 0);
	assert_int_equal(sh2000_counter_delta(1u << 27, 0),
			 -(int32_t)(1u << 27));
}

static void counter_negative(void **state)
{
	struct sh2000_sim_config cfg;
	struct sh2000_plant p;

	(void)state;
	sh2000_sim_config_default(&cfg);
	sh2000_plant_init(&p, &cfg.axis[0]);
	p.x_mm -= 0.000005;	/* half a count below power-up */
	assert_int_equal(sh2000_plant_counter(&p), SH2000_COUNTER_MASK);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(registers),
		cmocka_unit_test(counter_wrap),
		cmocka_unit_test(counter_negative),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
