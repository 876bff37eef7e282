/* SPDX-License-Identifier: MIT */
/*
 * A scripted card for unit tests that need no card model: the FPGA
 * (counter, RAM) behind a handle's port backend, logging every port cycle,
 * and an optional tiny "firmware" that acknowledges commands and keeps the
 * status snapshot consistent. Lets the bus, status and command code be
 * checked cycle by cycle.
 */
#ifndef SH2000_TEST_FAKECARD_H
#define SH2000_TEST_FAKECARD_H

#include <stdint.h>

#include "sh2000/sh2000_protocol.h"

#include "sh2000_internal.h"

enum fake_op { FAKE_CLEAR, FAKE_INC, FAKE_RD, FAKE_WR };

struct fake_event {
	uint8_t op;
	uint16_t addr;	/* counter at the cycle */
};

#define FAKE_LOG_MAX	(1u << 16)

struct fakecard {
	struct sh2000 h;	/* first: the backend casts back */
	struct sh2000_backend be;
	uint16_t ram[SH2000_RAM_WORDS];
	unsigned int counter;
	unsigned int nlog;
	struct fake_event log[FAKE_LOG_MAX];
	uint64_t now_ns;
	/* firmware behaviour */
	int auto_ack;		/* answer commands with ack_result */
	uint16_t ack_result;
	uint32_t ack_value;
	unsigned int tear_polls;	/* next polls to tear (seq begin read) */
	int tear_moving;		/* each tear a new publication */
	int hb_running;		/* heartbeat +1 per 100 us of time */
	/* answer a command only at the host's first look at the ACK, after
	 * it has read the old one, and that much time later: the host was
	 * descheduled between its read and its next step */
	uint64_t late_ack_ns;
	int ack_pending;
	/* the card's process descheduled for that long right after a command
	 * was written (a served card on a loaded machine): no heartbeat, no
	 * answer until then; the answer comes in its first cycle after */
	uint64_t stall_ns;
	uint64_t stalled_until;
	int stall_pending;	/* 1 + the word written: CMD_SEQ or ESTOP_REQ */
};

struct fakecard *fakecard_new(void);
void fakecard_free(struct fakecard *f);
/* Make RAM look like an idle v1 card. */
void fakecard_boot(struct fakecard *f);
void fakecard_clear_log(struct fakecard *f);
/* Counts of the log: clears, increments, reads, writes. */
void fakecard_counts(const struct fakecard *f, unsigned int c[4]);

#endif
