// SPDX-License-Identifier: MIT
/*
 * Homing one axis to the end, with the runner's rules for how it ended:
 * the card's homing sequence runs on the card (HOME command); a STOP from
 * another program ends it as it ends a streamed run (-SH2000_ESTOPPED,
 * nothing latched), a latched fault with its own error.
 */
#include <errno.h>
#include <stdio.h>

#include "sh2000/run.h"

int sh2000_run_home(struct sh2000 *h, unsigned int axis, unsigned int flags,
		    int timeout_ms, char *msg, size_t len)
{
	struct sh2000_status st;
	int r;

	r = sh2000_home(h, axis, flags);
	if (!r)
		r = sh2000_wait_idle(h, timeout_ms);
	if (!r)
		r = sh2000_poll(h, &st);
	if (r < 0) {
		if (msg && len)
			snprintf(msg, len, "%s", sh2000_last_error(h));
		return r;
	}
	if (st.axis[axis].state & SH2000_AXIS_HOMED)
		return 0;
	r = sh2000_status_error(h, &st);
	if (r < 0) {
		if (msg && len)
			snprintf(msg, len, "%s", sh2000_last_error(h));
		return r;
	}
	/* idle, not homed, nothing latched: a STOP ended the homing */
	if (msg && len)
		snprintf(msg, len,
			 "%s: axis %u: homing stopped before the home point (a STOP from another program?)",
			 sh2000_device(h), axis);
	return -SH2000_ESTOPPED;
}
