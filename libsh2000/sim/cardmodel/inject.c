// SPDX-License-Identifier: MIT
/*
 * Fault injection. Every fault acts on the hardware (the machine, a switch
 * input, an encoder counter, the dual-port RAM) or on the firmware's
 * scheduling (its servo interrupt), never on the firmware's own state, so
 * the firmware meets it as it would meet the real one and the host sees
 * what the firmware makes of it; docs/cardmodel.md lists both.
 */
#include "card_internal.h"

/* Default glitch: 2^20 counts, far beyond any step the counter may make. */
#define GLITCH_DEFAULT	0x100000

static int flip(struct sh2000_fw *fw, unsigned int arg)
{
	uint16_t mask = (uint16_t)(arg >> 16);

	/* one bit by default: the smallest corruption a check word must see */
	return sh2000_board_flip(fw->hw, arg & 0xffffu, mask ? mask : 0x0010u);
}

static void clear(struct sh2000_fw *fw)
{
	fw->stall_left = 0;
	sh2000_board_clear_faults(fw->hw);
}

int sh2000_fw_inject(struct sh2000_fw *fw, enum sh2000_inject what,
		     unsigned int axis, unsigned int arg)
{
	if (!fw)
		return -22;
	switch (what) {
	case SH2000_INJECT_NONE:
		return 0;
	case SH2000_INJECT_HEARTBEAT_STOP:
		/* the firmware writes it; the RAM cell does not take it */
		return sh2000_board_stick(fw->hw, SH2000_W_HEARTBEAT);
	case SH2000_INJECT_DSP_STALL:
		fw->stall_left = arg ? arg : SH2000_STALL_FOREVER;
		return 0;
	case SH2000_INJECT_RAM_FLIP:
		return flip(fw, arg);
	case SH2000_INJECT_JAM:
		return sh2000_board_jam(fw->hw, axis, 1);
	case SH2000_INJECT_LIMIT:
		return sh2000_board_force_limit(fw->hw, axis, arg ? 2u : 1u);
	case SH2000_INJECT_DROP_SEGMENT:
		sh2000_board_drop_record(fw->hw);
		return 0;
	case SH2000_INJECT_CLEAR:
		clear(fw);
		return 0;
	case SH2000_INJECT_COUNTER_GLITCH:
		return sh2000_board_glitch(fw->hw, axis,
					   arg ? (int32_t)arg : GLITCH_DEFAULT);
	default:
		return -22;
	}
}
