/* SPDX-License-Identifier: MIT */
/*
 * The card's first-fault record (protocol 1.4, docs/protocol.md 10.1):
 * which fault latched first since the last reset. It lives after the ring
 * (words 832..836), 794 port cycles beyond the status words, and
 * does not change until RESET: a poll reads it when it first finds a
 * fault latched and keeps it while the faults stay latched and no command
 * (a RESET among them) has been answered since; otherwise it costs
 * nothing.
 */
#include <string.h>

#include "sh2000_internal.h"

static int card_has_record(const struct sh2000 *h)
{
	return SH2000_PROTO_VERSION_MINOR(h->card_version) >=
	       SH2000_PROTO_MINOR_FIRST_FAULT;
}

static int any_latched(const struct sh2000_status *st)
{
	unsigned int a;

	if (st->card_faults)
		return 1;
	for (a = 0; a < SH2000_AXES; a++)
		if (st->axis[a].faults)
			return 1;
	return 0;
}

/* 1: r[] is a record (cached), 0: none (a RESET since the status words
 * were read) or torn (read again). */
static int take(struct sh2000 *h, const uint16_t *r, const uint16_t *w,
		const struct sh2000_status *st)
{
	uint32_t at = (uint32_t)r[SH2000_FF_CYCLE_LO] |
		      ((uint32_t)r[SH2000_FF_CYCLE_HI] << 16);
	uint32_t snap = (uint32_t)sh2000_w32(&w[SH2000_W_SNAP_TIME_LO]);

	if (!r[SH2000_FF_BIT] || r[SH2000_FF_CHECK] != sh2000_first_fault_check(r))
		return 0;
	h->first.ff.bit = r[SH2000_FF_BIT];
	h->first.ff.axis = r[SH2000_FF_AXIS];
	/* the card may latch it after the snapshot it published last: the
	 * signed distance from the snapshot's cycle */
	h->first.ff.cycle = st->card_cycle + (uint64_t)(int64_t)(int32_t)(at - snap);
	h->first.cmd_ack = w[SH2000_W_CMD_ACK];
	h->first.valid = 1;
	return 1;
}

int sh2000_first_fault_update(struct sh2000 *h, const uint16_t *w,
			      struct sh2000_status *st, unsigned int tries)
{
	uint16_t r[SH2000_FIRST_FAULT_WORDS];
	unsigned int i;
	int e;

	memset(&st->first_fault, 0, sizeof(st->first_fault));
	if (!card_has_record(h) || !any_latched(st)) {
		h->first.valid = 0;
		return 0;
	}
	if (h->first.valid && h->first.cmd_ack != w[SH2000_W_CMD_ACK])
		h->first.valid = 0;	/* a RESET may have come between */
	for (i = 0; !h->first.valid && i < tries; i++) {
		e = sh2000_rd(h, SH2000_W_FIRST_FAULT, SH2000_FIRST_FAULT_WORDS, r);
		if (e < 0)
			return e;
		if (!take(h, r, w, st) && !r[SH2000_FF_BIT])
			break;	/* cleared since: the next poll sees it */
	}
	if (h->first.valid)
		st->first_fault = h->first.ff;
	return 0;
}
