// SPDX-License-Identifier: MIT
/*
 * Homing one axis to the end, with the runner's rules for how it ended:
 * the card's homing sequence runs on the card (HOME command); a STOP from
 * another program ends it as it ends a streamed run (-SH2000_ESTOPPED,
 * nothing latched), a latched fault with its own error.
 *
 * The caller's end (its timeout, or its stop check: a signal) ends it with
 * a controlled STOP and a wait for rest, never by going away: the card
 * needs a polling host while it homes, and a host that just left would
 * have it latch a host heartbeat timeout.
 */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>

#include "sh2000/run.h"

/* How often the wait looks at the caller's stop check and the clock. */
#define HOME_SLICE_MS	20
/* The controlled stop's longest way to rest. */
#define HOME_REST_MS	10000

/* The axis as the messages name it: x y z a. */
static char letter(unsigned int axis)
{
	return axis < SH2000_AXES ?
	       (char)tolower((unsigned char)SH2000_AXIS_LETTERS[axis]) : '?';
}

static int fail(struct sh2000 *h, int r, char *msg, size_t len)
{
	if (msg && len)
		snprintf(msg, len, "%s", sh2000_last_error(h));
	return r;
}

/* The caller ended the homing: a STOP, then the card at rest. */
static int stop_to_rest(struct sh2000 *h, char *msg, size_t len)
{
	int r = sh2000_stop(h);

	if (r >= 0)
		r = sh2000_wait_rest(h, HOME_REST_MS);
	return r < 0 ? fail(h, r, msg, len) : 0;
}

/* The card ended the homing by itself: homed, stopped, or faulted. */
static int how_it_ended(struct sh2000 *h, unsigned int axis, char *msg,
			size_t len)
{
	struct sh2000_status st;
	int r = sh2000_poll(h, &st);

	if (r < 0)
		return fail(h, r, msg, len);
	if (st.axis[axis].state & SH2000_AXIS_HOMED)
		return 0;
	r = sh2000_status_error(h, &st);
	if (r < 0)
		return fail(h, r, msg, len);
	/* idle, not homed, nothing latched: a STOP ended the homing */
	if (msg && len)
		snprintf(msg, len,
			 "%s: axis %c: homing stopped before the home point by a STOP from another program; the card is at rest",
			 sh2000_device(h), letter(axis));
	return -SH2000_ESTOPPED;
}

int sh2000_run_home_until(struct sh2000 *h, unsigned int axis,
			  unsigned int flags, int timeout_ms,
			  int (*stop_asked)(void *ctx), void *ctx,
			  char *msg, size_t len)
{
	uint64_t end;
	int r, asked;

	r = sh2000_home(h, axis, flags);
	if (r < 0)
		return fail(h, r, msg, len);
	end = sh2000_now_ns(h) + (uint64_t)(timeout_ms < 0 ? 0 : timeout_ms) * 1000000ull;
	for (;;) {
		r = sh2000_wait_idle(h, HOME_SLICE_MS);
		if (r != -SH2000_ETIMEOUT) {
			if (r < 0 && r != -SH2000_ESTOPPED)
				return fail(h, r, msg, len);
			return how_it_ended(h, axis, msg, len);
		}
		asked = stop_asked && stop_asked(ctx);
		if (asked || sh2000_now_ns(h) > end)
			break;
	}
	r = stop_to_rest(h, msg, len);
	if (r < 0)
		return r;
	if (msg && len)
		snprintf(msg, len, asked ?
			 "%s: interrupted: homing stopped, card at rest" :
			 "%s: axis %c: not homed after %g s: homing stopped, card at rest",
			 sh2000_device(h), letter(axis), timeout_ms / 1e3);
	return asked ? -ECANCELED : -SH2000_ETIMEOUT;
}

int sh2000_run_home(struct sh2000 *h, unsigned int axis, unsigned int flags,
		    int timeout_ms, char *msg, size_t len)
{
	return sh2000_run_home_until(h, axis, flags, timeout_ms, NULL, NULL,
				     msg, len);
}
