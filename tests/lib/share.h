/* SPDX-License-Identifier: MIT */
/*
 * Several programs on one card, as checks that need no test framework:
 * test_share.c runs them on a served card (sim:NAME) under cmocka, and
 * sh2000-share (share_main.c) runs them in the VM suite on /dev/sh2000-0
 * with the card model attached (tests/kernel).
 */
#ifndef SH2000_TEST_SHARE_H
#define SH2000_TEST_SHARE_H

#include <stddef.h>

#include "sh2000/sh2000.h"

struct share_tally {
	unsigned int done, wrong, errors;
	double max_ms;		/* slowest command, waiting included */
	int first_error;
	char msg[200];
};

double share_now_ms(void);

/* Open dev with a heartbeat limit for a loaded machine; NULL and msg on
 * failure. */
struct sh2000 *share_open(const char *dev, char *msg, size_t len);

/*
 * procs processes (forked) x commands mixed commands each on dev: set and
 * get of a parameter no other process touches (kp of axis c for c < 4, td
 * of axis c - 4 else; the value read must be the value this process set,
 * float32-rounded), nop, enable/disable of an axis no other process
 * touches (nop for c >= 4). Sums the processes' tallies into *sum.
 * 0, or -1 with a message in sum->msg if a process did not report.
 */
int share_many(const char *dev, unsigned int procs, unsigned int commands,
	       struct share_tally *sum);

/* The card's lock file (the library's rule: $SH2000_LOCK_DIR, /run/lock
 * or /tmp; sh2000-shm-NAME.lock or sh2000-dev-MAJOR-MINOR.lock). */
int share_lock_path(const char *dev, char *buf, size_t len);

/* Is the command lock (byte 0 of the lock file) held by anyone? */
int share_cmd_lock_held(const char *path);

/*
 * Up to `rounds` times: a process sends nop after nop, is killed with
 * SIGKILL once the command lock is held (by it: it is the only user),
 * then a new handle's nop and parameter set must be answered. *held:
 * rounds killed with the lock held; *worst_ms: the slowest recovery.
 * 0, or negative with msg when a command failed.
 */
int share_killed_in_command(const char *dev, unsigned int rounds,
			    unsigned int *held, double *worst_ms, char *msg,
			    size_t len);

/* A child that claims the motion on dev, then waits to be killed. Its
 * pid; *claimed tells whether the claim succeeded. */
int share_spawn_holder(const char *dev, int *claimed);

#endif /* SH2000_TEST_SHARE_H */
