/* SPDX-License-Identifier: MIT */
/*
 * A card on a RAM (the public struct sh2000_fw): the board and the
 * firmware that runs on its DSP, plus what schedules the firmware (the
 * servo interrupt, which an injected stall withholds) and the card's
 * clock. Internal: for card.c, inject.c, cardsim.c, server.c and tests.
 */
#ifndef SH2000_CARD_INTERNAL_H
#define SH2000_CARD_INTERNAL_H

#include <stdint.h>

#include "board_sim.h"
#include "cardmodel.h"
#include "sh2000/sh2000_cardsim.h"

#define SH2000_STALL_FOREVER	UINT64_MAX

struct sh2000_fw {
	struct sh2000_board *hw;
	struct sh2000_dsp dsp;
	uint64_t stall_left;	/* interrupts still withheld */
	uint64_t time_ns;	/* card time (its own clock) */
	sh2000_fw_observer observer;
	void *observer_ctx;
};

/* One servo interrupt (unless stalled), then the board runs to the next
 * one. Returns how long that was in host time. */
uint64_t sh2000_card_cycle(struct sh2000_fw *fw);

#endif /* SH2000_CARD_INTERNAL_H */
