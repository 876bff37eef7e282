/* SPDX-License-Identifier: MIT */
/* command.c's state: the card's one command slot as this handle uses it. */
#ifndef SH2000_COMMAND_STATE_H
#define SH2000_COMMAND_STATE_H

#include <stdint.h>

struct sh2000_cmdslot {
	uint16_t seq;		/* CMD_SEQ as this handle last wrote it */
	int busy;		/* a thread of this handle holds the slot */
	int urgent;		/* atomic: an estop wants the lock */
};

#endif /* SH2000_COMMAND_STATE_H */
