// SPDX-License-Identifier: MIT
/*
 * The acceleration of the card's set-points, checked on the planned
 * records before anything moves.
 *
 * The card's set-point is the uniform cubic B-spline of its records
 * (sh2000/bspline.h). Its second derivative is linear over each span,
 * (1 - u)(P0 - 2P1 + P2) + u(P1 - 2P2 + P3) over T^2, so its extremes are
 * at the knots: the largest acceleration the card commands is the largest
 * second difference of the records over T^2, exactly, with no sampling.
 * A motion starts from the window [X, X, X, P1] of its rest point X and
 * ends padded with its end point E, so both count as records.
 *
 * The planner keeps every axis within its amax on that spline at the
 * limits it is measured at (docs/planner.md), but not at all limits
 * ("Known limits": up to 4 times amax at 15000 mm/s^2 and the default
 * jerk). A plan that passes an axis' amax by more than the reserve the
 * planner's margin keeps for the card (its correction tables and time
 * base take up to 4 % of amax) is refused here, in the first pass, with
 * the axis and the time, instead of being sent to the drives. Two counts
 * of rounding are allowed on top.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "accel.h"

void sh2000_accel_check_init(struct sh2000_accel_check *c,
			     const struct sh2000_path_config *pc)
{
	double T2 = pc->period_s * pc->period_s;
	unsigned int a;

	memset(c, 0, sizeof(*c));
	c->period_s = pc->period_s;
	for (a = 0; a < SH2000_AXES; a++) {
		c->w[0][a] = c->w[1][a] = pc->start[a];
		c->amax[a] = pc->amax[a];
		c->limit[a] = (2.0 - pc->margin) * pc->amax[a] * T2 +
			      2.0 / pc->counts_per_mm[a];
	}
}

static int judge(struct sh2000_accel_check *c, const double mm[SH2000_AXES],
		 char *err, size_t errlen)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		double d2 = c->w[0][a] - 2.0 * c->w[1][a] + mm[a];

		if (fabs(d2) > c->limit[a]) {
			double T2 = c->period_s * c->period_s;

			snprintf(err, errlen,
				 "axis %c: the planned set-points accelerate at %.0f mm/s^2 at %.3f s, over its amax of %.0f mm/s^2 by more than the planner's margin keeps: the planner does not hold these limits (docs/planner.md \"Known limits\")",
				 SH2000_AXIS_LETTERS[a], fabs(d2) / T2,
				 (double)c->records * c->period_s,
				 c->amax[a]);
			return -ERANGE;
		}
	}
	memcpy(c->w[0], c->w[1], sizeof(c->w[0]));
	memcpy(c->w[1], mm, sizeof(c->w[1]));
	return 0;
}

int sh2000_accel_check_point(struct sh2000_accel_check *c,
			     const double mm[SH2000_AXES], int end,
			     char *err, size_t errlen)
{
	int e;

	c->records++;
	e = judge(c, mm, err, errlen);
	/* the card pads the window with the end point: one more knot,
	 * then the rest the next motion starts from */
	if (!e && end)
		e = judge(c, mm, err, errlen);
	return e;
}
