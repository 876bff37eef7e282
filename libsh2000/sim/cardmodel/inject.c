// SPDX-License-Identifier: MIT
/*
 * Fault injection. Each injection acts where the real fault would (the
 * firmware, the RAM, the mechanics, a switch) so that it surfaces through
 * the protocol exactly as the real fault would; docs/cardmodel.md lists
 * what the host sees for each.
 */
#include "cardmodel.h"

int sh2000_fw_inject(struct sh2000_fw *fw, enum sh2000_inject what,
		     unsigned int axis, unsigned int arg)
{
	unsigned int a;

	if (!fw)
		return -22;
	switch (what) {
	case SH2000_INJECT_NONE:
		return 0;
	case SH2000_INJECT_HEARTBEAT_STOP:
		fw->hb_frozen = 1;
		return 0;
	case SH2000_INJECT_DSP_STALL:
		fw->stalled = 1;
		return 0;
	case SH2000_INJECT_RAM_FLIP:
		if (arg >= SH2000_RAM_WORDS)
			return -22;
		/* one bit: the smallest corruption the check word must see */
		sh2000_dpram_write(fw->ram, arg,
				   (uint16_t)(sh2000_dpram_read(fw->ram, arg) ^
					      0x0010u));
		return 0;
	case SH2000_INJECT_JAM:
		if (axis >= SH2000_AXES)
			return -22;
		fw->ax[axis].plant.jammed = 1;
		return 0;
	case SH2000_INJECT_LIMIT:
		if (axis >= SH2000_AXES)
			return -22;
		fw->ax[axis].plant.force_limit |= arg ? 2 : 1;
		return 0;
	case SH2000_INJECT_DROP_SEGMENT:
		fw->drop_next = 1;
		return 0;
	case SH2000_INJECT_CLEAR:
		fw->hb_frozen = 0;
		fw->stalled = 0;
		fw->drop_next = 0;
		for (a = 0; a < SH2000_AXES; a++) {
			fw->ax[a].plant.jammed = 0;
			fw->ax[a].plant.force_limit = 0;
		}
		return 0;
	case SH2000_INJECT_COUNTER_GLITCH:
		if (axis >= SH2000_AXES)
			return -22;
		/* the FPGA counter jumps, as after a lost scale signal */
		sh2000_plant_preset(&fw->ax[axis].plant,
				    sh2000_plant_counter(&fw->ax[axis].plant) +
					    (arg ? arg : 0x100000u));
		return 0;
	default:
		return -22;
	}
}
