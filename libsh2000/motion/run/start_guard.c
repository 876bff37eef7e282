// SPDX-License-Identifier: MIT
/*
 * The guard between a program's two passes (run.h): the plan was made from
 * where the card stood at the check, so a card that moved since (a jog from
 * another program, a carriage caught after a fault) is refused, naming the
 * axis, before anything moves.
 */
#include <ctype.h>
#include <math.h>
#include <stdio.h>

#include "sh2000/run.h"
#include "sh2000/sh2000_protocol.h"

int sh2000_run_check_start(struct sh2000 *h, struct sh2000_path_config *pc,
			   char *msg, size_t len)
{
	static const char name[] = SH2000_AXIS_LETTERS;
	struct sh2000_path_config now;
	struct sh2000_status st;
	unsigned int a;
	int e;

	e = sh2000_run_path_config(h, &now);
	if (!e)
		e = sh2000_poll(h, &st);
	if (e < 0) {
		if (msg && len)
			snprintf(msg, len, "reading where the card stands: %s",
				 sh2000_strerror(e));
		return e;
	}
	for (a = 0; a < SH2000_AXES; a++) {
		double d = fabs(now.start[a] - pc->start[a]);

		if (!(st.axis[a].state & SH2000_AXIS_ENABLED) ||
		    d <= SH2000_MOVED_TOL_MM)
			continue;
		if (msg && len)
			snprintf(msg, len,
				 "axis %c moved by %.4f mm since the program was checked",
				 tolower((unsigned char)name[a]), d);
		return -SH2000_EMOVED;
	}
	for (a = 0; a < SH2000_AXES; a++)
		if (st.axis[a].state & SH2000_AXIS_ENABLED)
			pc->start[a] = now.start[a];
	return 0;
}
