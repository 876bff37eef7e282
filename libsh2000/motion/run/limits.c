// SPDX-License-Identifier: MIT
/*
 * The one soft-limit policy of libsh2000-motion (docs/library.md "Soft
 * limits"), for one target (sh2000ctl's move). The runner and the first
 * pass of a program apply it to the card's fine set-points of the stream
 * (setpoints.c), with the same slack and the same message.
 *
 * Why the slack: the planner's B-spline compensation lets control points
 * overshoot the end of a motion by about 1 um, and the card checks its
 * soft limits on the records. A target exactly at a limit is legitimate,
 * so a point within SH2000_LIMIT_SLACK_MM beyond a limit is put on it (the
 * card's spline stays inside the hull of its control points: the set-point
 * never passes the limit, and the end point stays exact). Further beyond
 * is an error naming the axis, the value and the limit.
 */
#include <errno.h>
#include <stdio.h>

#include "sh2000/run.h"

int sh2000_limits_get(struct sh2000 *h, struct sh2000_limits *l)
{
	unsigned int a;
	int r;

	for (a = 0; a < SH2000_AXES; a++) {
		r = sh2000_param_get(h, (int)a, SH2000_P_SOFT_MIN, &l->lo[a]);
		if (!r)
			r = sh2000_param_get(h, (int)a, SH2000_P_SOFT_MAX,
					     &l->hi[a]);
		if (r)
			return r;
	}
	return 0;
}

int sh2000_limits_apply(const struct sh2000_limits *l,
			double mm[SH2000_AXES], char *msg, size_t len)
{
	static const char name[] = SH2000_AXIS_LETTERS;
	unsigned int a;
	int clamped = 0;

	for (a = 0; a < SH2000_AXES; a++) {
		double lim = mm[a] < l->lo[a] ? l->lo[a] :
			     mm[a] > l->hi[a] ? l->hi[a] : mm[a];

		if (lim == mm[a])
			continue;
		if (mm[a] - lim > SH2000_LIMIT_SLACK_MM ||
		    lim - mm[a] > SH2000_LIMIT_SLACK_MM) {
			if (msg && len)
				snprintf(msg, len,
					 "%c %.4f mm is beyond the soft limit %.4f mm (soft limits %.4f..%.4f mm)",
					 name[a], mm[a], lim, l->lo[a], l->hi[a]);
			return -SH2000_ELIMIT;
		}
		mm[a] = lim;
		clamped = 1;
	}
	return clamped;
}
