// SPDX-License-Identifier: MIT
/*
 * The FPGA as the host sees it: four registers, a 10-bit address counter
 * into the dual-port RAM, and counters of the port cycles issued (for
 * tests and the benchmark). The encoder counters live in plant.c because
 * their input is the plant.
 */
#include "cardmodel.h"

void sh2000_fpga_init(struct sh2000_fpga *f, uint16_t *ram)
{
	unsigned int i;

	f->ram = ram;
	f->addr = 0;
	for (i = 0; i < 4; i++)
		f->counters[i] = 0;
}

void sh2000_fpga_out(struct sh2000_fpga *f, unsigned int reg, uint16_t v)
{
	switch (reg) {
	case SH2000_REG_ADDR_CLEAR:
		f->addr = 0;
		f->counters[0]++;
		break;
	case SH2000_REG_ADDR_INC:
		f->addr = (f->addr + 1u) & SH2000_ADDR_MASK;
		f->counters[1]++;
		break;
	case SH2000_REG_DATA:
		sh2000_dpram_write(f->ram, f->addr, v);
		f->counters[3]++;
		break;
	default:	/* spare: decoded, no function */
		break;
	}
}

uint16_t sh2000_fpga_in(struct sh2000_fpga *f, unsigned int reg)
{
	if (reg == SH2000_REG_DATA) {
		f->counters[2]++;
		return sh2000_dpram_read(f->ram, f->addr);
	}
	/* Clear and increment are triggered by writes only; reading them or
	 * the spare register returns the floating ISA bus. */
	return 0xffffu;
}

int32_t sh2000_counter_delta(uint32_t now, uint32_t before)
{
	uint32_t d = (now - before) & SH2000_COUNTER_MASK;

	if (d & (1u << (SH2000_COUNTER_BITS - 1u)))
		return (int32_t)d - (int32_t)(1u << SH2000_COUNTER_BITS);
	return (int32_t)d;
}
