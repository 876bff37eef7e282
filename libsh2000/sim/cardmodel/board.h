/* SPDX-License-Identifier: MIT */
/*
 * The card as its firmware sees it: the FPGA's registers on the DSP's bus
 * and the DSP's side of the dual-port RAM. Nothing else: the motors,
 * switches and scales are behind these registers (plant.h, which no
 * firmware file includes; ctest cardmodel_layers, tests/cardmodel/layers.sh,
 * checks that).
 *
 * The paper names the parts (four 28-bit encoder counters in the FPGA, the
 * DAC7744, limit and home switches); the register layout below is the
 * project's, like the host side's (sh2000_fpga.h).
 */
#ifndef SH2000_BOARD_H
#define SH2000_BOARD_H

#include <stdint.h>

struct sh2000_board;

/* Per-axis registers (sh2000_board_read/write's `reg`). */
enum sh2000_board_reg {
	SH2000_HWREG_COUNTER = 0,	/* R: encoder counter, 28 bits, wraps */
	SH2000_HWREG_PRESET,		/* W: the counter reads the value here */
	SH2000_HWREG_INPUTS,		/* R: SH2000_HWIN_* */
	SH2000_HWREG_INDEX_LATCH,	/* R: the counter at the latched mark */
	SH2000_HWREG_INDEX_ARM,		/* W: clears HWIN_INDEX, latches the
					 * next mark */
	SH2000_HWREG_DAC,		/* R/W: DAC code, int16 in bits 0..15 */
	SH2000_HWREG_DAC_RANGE,		/* R/W: enum sh2000_dac_range */
	SH2000_HWREG_INDEX_MODE,	/* R/W: SH2000_HWIDX_* (0 at power-up:
					 * every rising edge, no mask) */
};

/* SH2000_HWREG_INDEX_MODE bits: which index edges the latch takes. The
 * home switch input is the latch's mask input. */
#define SH2000_HWIDX_FALLING	0x1u	/* the falling edge, not the rising */
#define SH2000_HWIDX_MASK	0x2u	/* only while the home switch is active */
#define SH2000_HWIDX_MASK_INV	0x4u	/* (with MASK) only while inactive */
#define SH2000_HWIDX_ALL	0x7u

/* SH2000_HWREG_INPUTS bits: the switch inputs as the FPGA samples them
 * now, and the index latch's flag. */
#define SH2000_HWIN_INDEX	0x1u	/* a mark was latched since ARM */
#define SH2000_HWIN_LIMIT_NEG	0x2u
#define SH2000_HWIN_LIMIT_POS	0x4u
#define SH2000_HWIN_HOME	0x8u

/* Registers of a missing axis or register read 0; writes do nothing. */
uint32_t sh2000_board_read(struct sh2000_board *b, unsigned int axis,
			   unsigned int reg);
void sh2000_board_write(struct sh2000_board *b, unsigned int axis,
			unsigned int reg, uint32_t v);

/* The DSP's side of the dual-port RAM: 16-bit atomic accesses (the host
 * may touch the same word at the same time). */
uint16_t sh2000_board_ram_read(struct sh2000_board *b, unsigned int w);
void sh2000_board_ram_write(struct sh2000_board *b, unsigned int w,
			    uint16_t v);

#endif /* SH2000_BOARD_H */
