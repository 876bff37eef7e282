/* SPDX-License-Identifier: MIT */
/*
 * The one user-space model of the FPGA's host side (docs/card.md): four
 * registers, the 10-bit address counter into the dual-port RAM, and
 * counters of the port cycles issued. The card model's board carries one
 * for a host in the same process (sh2000_cardsim), the sim:NAME backend
 * emulates the FPGA with it on its side of a served RAM, and the tests
 * check it. Header-only and private: it is compiled into each library that
 * needs it and exported by none. (The kernel's own model in driver/ is
 * independent, as kernel code must be.) The FPGA's DSP side (encoder
 * counters, index latches, switch inputs, DAC) is the card model's
 * alone: libsh2000/sim/cardmodel/board.h.
 *
 * The dual-port RAM is touched by both sides at once: every access is a
 * 16-bit atomic load or store, as on the real part.
 */
#ifndef SH2000_FPGA_H
#define SH2000_FPGA_H

#include <stdint.h>

#include "sh2000_hw.h"

static inline uint16_t sh2000_dpram_read(const uint16_t *ram, unsigned int w)
{
	return __atomic_load_n(&ram[w], __ATOMIC_ACQUIRE);
}

static inline void sh2000_dpram_write(uint16_t *ram, unsigned int w, uint16_t v)
{
	__atomic_store_n(&ram[w], v, __ATOMIC_RELEASE);
}

enum sh2000_fpga_counter {
	SH2000_FPGA_CLEARS,
	SH2000_FPGA_INCREMENTS,
	SH2000_FPGA_DATA_READS,
	SH2000_FPGA_DATA_WRITES,
};

struct sh2000_fpga {
	uint16_t *ram;			/* SH2000_RAM_WORDS */
	unsigned int addr;		/* 10-bit address counter */
	uint64_t counters[4];		/* enum sh2000_fpga_counter */
};

static inline void sh2000_fpga_init(struct sh2000_fpga *f, uint16_t *ram)
{
	unsigned int i;

	f->ram = ram;
	f->addr = 0;
	for (i = 0; i < 4; i++)
		f->counters[i] = 0;
}

/* One port cycle writing a register. */
static inline void sh2000_fpga_out(struct sh2000_fpga *f, unsigned int reg,
				   uint16_t v)
{
	switch (reg) {
	case SH2000_REG_ADDR_CLEAR:
		f->addr = 0;
		f->counters[SH2000_FPGA_CLEARS]++;
		break;
	case SH2000_REG_ADDR_INC:
		f->addr = (f->addr + 1u) & SH2000_ADDR_MASK;
		f->counters[SH2000_FPGA_INCREMENTS]++;
		break;
	case SH2000_REG_DATA:
		sh2000_dpram_write(f->ram, f->addr, v);
		f->counters[SH2000_FPGA_DATA_WRITES]++;
		break;
	default:	/* spare: decoded, no function */
		break;
	}
}

/* One port cycle reading a register. */
static inline uint16_t sh2000_fpga_in(struct sh2000_fpga *f, unsigned int reg)
{
	if (reg == SH2000_REG_DATA) {
		f->counters[SH2000_FPGA_DATA_READS]++;
		return sh2000_dpram_read(f->ram, f->addr);
	}
	/* Clear and increment are triggered by writes only; reading them or
	 * the spare register returns the floating ISA bus. */
	return 0xffffu;
}

#endif /* SH2000_FPGA_H */
