/* SPDX-License-Identifier: GPL-2.0 OR MIT */
/*
 * How to move the card's address counter to a word: the one seek logic that
 * the kernel driver and libsh2000's direct-port and simulated backends share.
 *
 * The counter can only be cleared to 0 or incremented by one (wrapping from
 * 1023 to 0), each costing one port cycle. From a known position p the target
 * t is reached either by (t - p) mod 1024 increments (which covers going
 * through the wrap) or by a clear and t increments; the cheaper wins and a
 * tie keeps the counter (no clear). From an unknown position only
 * clear-then-increment is possible.
 *
 * Transfers are lazy: after the last word of a transfer no increment is
 * issued, so a transfer of n words streamed from the counter position costs
 * n data cycles and n - 1 increments, the floor.
 */
#ifndef SH2000_SEEK_H
#define SH2000_SEEK_H

#include "sh2000_hw.h"

/* A counter position that is not known (after load, or after a reset). */
#define SH2000_SEEK_UNKNOWN	0xffffffffU

/**
 * struct sh2000_seek - the cheapest way to one address
 * @clear:	1 if the counter must be cleared first
 * @increments:	increments to issue after the (optional) clear
 */
struct sh2000_seek {
	unsigned int clear;
	unsigned int increments;
};

/**
 * sh2000_seek_plan() - plan the cheapest move of the address counter
 * @pos:	current counter position, or SH2000_SEEK_UNKNOWN
 * @target:	word address to reach (0..SH2000_RAM_WORDS - 1)
 *
 * Return: the plan; its cost is clear + increments port cycles.
 */
static inline struct sh2000_seek sh2000_seek_plan(unsigned int pos,
						  unsigned int target)
{
	struct sh2000_seek s = { 1, target & SH2000_ADDR_MASK };
	unsigned int forward;

	if (pos == SH2000_SEEK_UNKNOWN)
		return s;
	forward = (target - pos) & SH2000_ADDR_MASK;
	if (forward <= s.clear + s.increments) {
		s.clear = 0;
		s.increments = forward;
	}
	return s;
}

/* Cost in port cycles of the plan sh2000_seek_plan() returns. */
static inline unsigned int sh2000_seek_cost(unsigned int pos,
					    unsigned int target)
{
	struct sh2000_seek s = sh2000_seek_plan(pos, target);

	return s.clear + s.increments;
}

#endif /* SH2000_SEEK_H */
