/* SPDX-License-Identifier: MIT */
/*
 * Which axes a run's records move (moved.c): what the runner adds to the
 * card's REJECT_DISABLED, which names a record but not the axis.
 */
#ifndef SH2000_RUN_MOVED_H
#define SH2000_RUN_MOVED_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/sh2000.h"

struct sh2000_moved {
	int32_t lo[SH2000_AXES], hi[SH2000_AXES];	/* counts */
	int have;
};

/* A record of the run (counts). */
void sh2000_moved_add(struct sh2000_moved *m,
		      const int32_t counts[SH2000_AXES]);
/*
 * After a rejection: when st says REJECT_DISABLED, appends to msg (a
 * string of len bytes) each axis st shows disabled that the records
 * moved, with how far (scale: counts per mm). Else leaves msg as it is.
 */
void sh2000_moved_note(const struct sh2000_moved *m,
		       const struct sh2000_status *st,
		       const double scale[SH2000_AXES], char *msg, size_t len);

#endif
