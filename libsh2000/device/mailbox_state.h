/* SPDX-License-Identifier: MIT */
/* mailbox.c's state: the point mailbox (protocol 1.3) as this handle
 * last saw and wrote it. */
#ifndef SH2000_MAILBOX_STATE_H
#define SH2000_MAILBOX_STATE_H

#include <stdint.h>

#include "sh2000/sh2000.h"

struct sh2000_mbox {
	uint16_t seq;		/* MBOX_SEQ as in the RAM */
	int dirty;		/* posted since HEAD was last written */
	int ref_ok;		/* the card knows ref[] as we do */
	int running;		/* the last poll saw state RUNNING */
	int32_t ref[SH2000_AXES];	/* the last record published */
};

#endif /* SH2000_MAILBOX_STATE_H */
