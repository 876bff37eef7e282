/* SPDX-License-Identifier: MIT */
/*
 * The acceleration of the card's set-points over a stream of records
 * (accel.c): what the first pass of a program checks before anything
 * moves.
 */
#ifndef SH2000_RUN_ACCEL_H
#define SH2000_RUN_ACCEL_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/path.h"

struct sh2000_accel_check {
	double w[2][SH2000_AXES];	/* the two records before, mm */
	double limit[SH2000_AXES];	/* the most |P[k-1] - 2P[k] + P[k+1]| */
	double amax[SH2000_AXES];
	double period_s;
	uint64_t records;
};

/* From pc: its amax, period, scale, margin and start. */
void sh2000_accel_check_init(struct sh2000_accel_check *c,
			     const struct sh2000_path_config *pc);
/* One record (mm, as planned; end: the motion's last, after which the
 * card holds it): 0, or -ERANGE with the axis, the acceleration and when
 * it comes in err. */
int sh2000_accel_check_point(struct sh2000_accel_check *c,
			     const double mm[SH2000_AXES], int end,
			     char *err, size_t errlen);

#endif
