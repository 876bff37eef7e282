// SPDX-License-Identifier: MIT
/*
 * The index latch armed by the host (protocol 1.6, INDEX_ARM; docs/
 * protocol.md 13.1): while the card runs a stream, or idles, the FPGA's
 * latch of an axis takes the next index edge the host asked for (rising
 * or falling, optionally only while the home switch is active or
 * inactive), and the card reports the counter at the mark and the servo
 * cycle that found it in the axis' index block. The card's own HOME uses
 * the same latch in its default mode; the two exclude each other.
 */
#include "cardmodel.h"

#define WR(fw, w, v)	sh2000_board_ram_write((fw)->hw, (w), (uint16_t)(v))
#define SETREG(fw, a, r, v) sh2000_board_write((fw)->hw, (a), (r), (v))

/* The block of axis a as it is now: the words, CHECK, STATE last. */
static void publish(struct sh2000_dsp *fw, unsigned int a)
{
	const struct sh2000_fw_index *ix = &fw->ax[a].ix;
	uint16_t b[SH2000_INDEX_WORDS];
	unsigned int i;

	b[SH2000_IX_STATE] = ix->state;
	b[SH2000_IX_ARM] = ix->arm;
	b[SH2000_IX_COUNT_LO] = (uint16_t)(ix->count & 0xffffu);
	b[SH2000_IX_COUNT_HI] = (uint16_t)(ix->count >> 16);
	b[SH2000_IX_CYCLE_LO] = (uint16_t)(ix->cycle & 0xffffu);
	b[SH2000_IX_CYCLE_HI] = (uint16_t)(ix->cycle >> 16);
	b[SH2000_IX_CHECK] = sh2000_index_check(b);
	for (i = SH2000_IX_ARM; i < SH2000_INDEX_WORDS; i++)
		WR(fw, SH2000_W_INDEX(a) + i, b[i]);
	WR(fw, SH2000_W_INDEX(a) + SH2000_IX_STATE, b[SH2000_IX_STATE]);
}

/* The arm is over (a mark, none, or aborted): the latch back to the
 * default mode the card's own homing uses, the state bits, the block. */
static void end(struct sh2000_dsp *fw, unsigned int a, uint16_t state)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];

	ax->ix.state = state;
	SETREG(fw, a, SH2000_HWREG_INDEX_MODE, 0);
	ax->state &= (uint16_t)~SH2000_AXIS_INDEX_ARMED;
	if (state == SH2000_INDEX_LATCHED)
		ax->state |= SH2000_AXIS_INDEX_LATCHED;
	publish(fw, a);
}

static uint32_t hw_mode(uint16_t flags)
{
	uint32_t m = 0;

	if (!(flags & SH2000_INDEX_F_RISING))
		m |= SH2000_HWIDX_FALLING;
	if (flags & SH2000_INDEX_F_MASK)
		m |= SH2000_HWIDX_MASK;
	if (flags & SH2000_INDEX_F_MASK_INVERT)
		m |= SH2000_HWIDX_MASK_INV;
	return m;
}

uint16_t sh2000_fw_index_arm(struct sh2000_dsp *fw, unsigned int axis,
			  uint16_t flags, uint32_t within, uint32_t *value)
{
	struct sh2000_fw_axis *ax;
	int bad = (flags & ~SH2000_INDEX_F_ALL) ||
		  ((flags & SH2000_INDEX_F_MASK_INVERT) && !(flags & SH2000_INDEX_F_MASK)) ||
		  (int32_t)within < 0;
	uint16_t r = sh2000_latch_cmd_check(fw, axis, bad);

	if (r != SH2000_RES_OK)
		return r;
	ax = &fw->ax[axis];
	/* the card's own homing has the latch */
	if (ax->home != HOME_NONE || fw->state == SH2000_STATE_STOPPING)
		return SH2000_RES_BUSY;
	ax->ix.arm++;
	ax->ix.state = SH2000_INDEX_ARMED;
	ax->ix.from = ax->act;
	ax->ix.within = within;
	ax->ix.count = 0;
	ax->ix.cycle = 0;
	/* a mark latched in the default mode before now is not this arm's */
	SETREG(fw, axis, SH2000_HWREG_INDEX_MODE, hw_mode(flags));
	SETREG(fw, axis, SH2000_HWREG_INDEX_ARM, 1);
	ax->index_seen = 0;
	ax->state &= (uint16_t)~SH2000_AXIS_INDEX_LATCHED;
	ax->state |= SH2000_AXIS_INDEX_ARMED;
	publish(fw, axis);
	*value = ax->ix.arm;
	return SH2000_RES_OK;
}

void sh2000_fw_index_boot(struct sh2000_dsp *fw)
{
	unsigned int a;

	/* whatever a served card's RAM held before is not this card's */
	for (a = 0; a < SH2000_AXES; a++) {
		SETREG(fw, a, SH2000_HWREG_INDEX_MODE, 0);
		publish(fw, a);
	}
}

uint16_t sh2000_fw_index_disarm(struct sh2000_dsp *fw, unsigned int axis)
{
	if (axis >= SH2000_AXES)
		return SH2000_RES_BAD_AXIS;
	if (fw->ax[axis].ix.state == SH2000_INDEX_ARMED)
		end(fw, axis, SH2000_INDEX_OFF);
	return SH2000_RES_OK;
}

/* Every cycle, after the inputs are sampled: the mark, the travel limit,
 * or the end of what the arm needs (an enabled axis, no fault). */
void sh2000_fw_index_cycle(struct sh2000_dsp *fw, unsigned int a)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];
	int64_t moved;

	if (ax->ix.state != SH2000_INDEX_ARMED)
		return;
	if (ax->index_seen) {
		ax->ix.count = ax->index_latch;
		ax->ix.cycle = (uint32_t)fw->cycle;
		end(fw, a, SH2000_INDEX_LATCHED);
		return;
	}
	if (!sh2000_axis_enabled(ax) || ax->faults || fw->faults) {
		end(fw, a, SH2000_INDEX_ABORTED);
		return;
	}
	moved = ax->act - ax->ix.from;
	if (ax->ix.within && (moved > ax->ix.within || -moved > ax->ix.within))
		end(fw, a, SH2000_INDEX_MISSED);
}
