/* SPDX-License-Identifier: MIT */
/* first_fault.c's state: the first-fault record as last read (protocol
 * 1.4). */
#ifndef SH2000_FIRST_FAULT_STATE_H
#define SH2000_FIRST_FAULT_STATE_H

#include <stdint.h>

#include "sh2000/sh2000.h"

struct sh2000_ff_cache {
	int valid;		/* read since the faults latched */
	uint16_t cmd_ack;	/* CMD_ACK when it was read */
	struct sh2000_first_fault ff;
};

#endif /* SH2000_FIRST_FAULT_STATE_H */
