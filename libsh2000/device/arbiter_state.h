/* SPDX-License-Identifier: MIT */
/* arbiter.c's state: the locks shared with other processes using the card. */
#ifndef SH2000_ARBITER_STATE_H
#define SH2000_ARBITER_STATE_H

#include <stdint.h>

struct sh2000_arb {
	int fd;			/* the card's lock file, -1: none (sim) */
	int motion;		/* this handle holds the motion lock */
	uint64_t token;		/* this handle's mark as last slot user */
	uint64_t dropped_ns;	/* when it last released the command lock */
	char path[256];
};

#define SH2000_ARB_CMD		0u	/* one command exchange */
#define SH2000_ARB_MOTION	1u	/* one program controls the motion */
#define SH2000_ARB_BUS		2u	/* io: one port sequence */
/* Longest wait for another program's command or port sequence. */
#define SH2000_ARB_WAIT_MS	5000

#endif /* SH2000_ARBITER_STATE_H */
