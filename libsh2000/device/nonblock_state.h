/* SPDX-License-Identifier: MIT */
/* nonblock.c's state: the real-time calls' view of the card between ticks. */
#ifndef SH2000_NONBLOCK_STATE_H
#define SH2000_NONBLOCK_STATE_H

#include <stdint.h>

struct sh2000_nb {
	int active;		/* in one (or index.c's): locks, the
				 * arbiter's bus lock too, tried once */
	int tail_seen;		/* a poll has read TAIL */
	uint16_t tail;		/* TAIL as the last poll read it */
	uint16_t estop_ack_seen;	/* ESTOP_ACK as the last poll read it */
	struct {		/* the command started and not yet answered */
		int busy;	/* started, not yet completed */
		int motion;	/* took the motion lock shared */
		int fresh;	/* ack[] read by a poll since the start */
		uint16_t seq;
		uint16_t ack[4];	/* CMD_ACK, RESULT, VALUE_LO/HI */
		uint64_t t0;
		unsigned int op;
	} cmd;
};

#endif /* SH2000_NONBLOCK_STATE_H */
