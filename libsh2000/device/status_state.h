/* SPDX-License-Identifier: MIT */
/* status.c's state: the card heartbeat's watch and the 28-bit counters
 * extended to 64 bits. */
#ifndef SH2000_STATUS_STATE_H
#define SH2000_STATUS_STATE_H

#include <stdint.h>

#include "sh2000/sh2000.h"

/* The heartbeat watch: when the card's heartbeat last moved. */
struct sh2000_hbwatch {
	int seen;
	uint16_t last;
	uint64_t change_ns;
	uint64_t seen_ns;	/* last time the heartbeat was read */
	int unsure;		/* same value after a gap it may wrap in */
	uint64_t limit_ns;
	uint64_t limit_user;	/* set by the caller, 0: derived */
};

/* The 28-bit actual positions and the 32-bit snapshot time, extended. */
struct sh2000_ctrext {
	int act_seen;
	uint32_t act_last[SH2000_AXES];
	int64_t act_ext[SH2000_AXES];
	int cycle_seen;
	uint32_t cycle_last;
	uint64_t cycle_ext;
};

#endif /* SH2000_STATUS_STATE_H */
