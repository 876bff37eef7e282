// SPDX-License-Identifier: MIT
/*
 * Latching a fault, the one place every fault path of the firmware goes
 * through (an axis check, a rejected record, the host's emergency stop,
 * the host timeout, an underrun, a protocol fault): the bit, and, for the
 * first fault since RESET, the first-fault record (protocol 1.4,
 * docs/protocol.md 10.1). FAULTS and AXIS_FAULTS(a) are bit sets and keep
 * no order; the record is what tells the host which came first.
 */
#include "cardmodel.h"

#define WR(fw, w, v)	sh2000_board_ram_write((fw)->hw, (w), (uint16_t)(v))

/* The record in the cycle the first fault latches: AXIS, CYCLE and CHECK
 * first and BIT last, all before the end of the cycle publishes the bit
 * itself in FAULTS or AXIS_FAULTS(a). */
static void write_first(struct sh2000_dsp *fw, unsigned int axis,
			uint16_t bit)
{
	uint16_t r[SH2000_FIRST_FAULT_WORDS];
	unsigned int i;

	r[SH2000_FF_BIT] = bit;
	r[SH2000_FF_AXIS] = (uint16_t)axis;
	r[SH2000_FF_CYCLE_LO] = (uint16_t)(fw->cycle & 0xffffu);
	r[SH2000_FF_CYCLE_HI] = (uint16_t)((fw->cycle >> 16) & 0xffffu);
	r[SH2000_FF_CHECK] = sh2000_first_fault_check(r);
	for (i = SH2000_FF_AXIS; i < SH2000_FIRST_FAULT_WORDS; i++)
		WR(fw, SH2000_W_FIRST_FAULT + i, r[i]);
	WR(fw, SH2000_W_FIRST_FAULT + SH2000_FF_BIT, bit);
	fw->first_fault = 1;
}

void sh2000_fw_latch(struct sh2000_dsp *fw, unsigned int axis, uint16_t bit)
{
	if (!fw->first_fault)
		write_first(fw, axis, bit);
	if (axis < SH2000_AXES)
		fw->ax[axis].faults |= bit;
	else
		fw->faults |= bit;
}

void sh2000_fw_first_fault_clear(struct sh2000_dsp *fw)
{
	unsigned int i;

	/* BIT first: a host never takes a half-cleared record for one */
	for (i = 0; i < SH2000_FIRST_FAULT_WORDS; i++)
		WR(fw, SH2000_W_FIRST_FAULT + i, 0);
	fw->first_fault = 0;
}
