/* SPDX-License-Identifier: MIT */
/*
 * The soft-limit policy over a stream of records (setpoints.c): what the
 * runner and the first pass of a program apply to every point they get,
 * with the gantry pair's rule (pair.h); and the acceleration guard the
 * first pass adds.
 */
#ifndef SH2000_RUN_SETPOINTS_H
#define SH2000_RUN_SETPOINTS_H

#include <stddef.h>
#include <stdint.h>

#include "pair.h"
#include "sh2000/run.h"

struct sh2000_setpoints {
	const struct sh2000_limits *limits;	/* NULL: none */
	struct sh2000_pair_rule pair;
	double w[3][SH2000_AXES];	/* the last three records, as planned */
	double rest[SH2000_AXES];	/* where the last motion ended */
	int in_motion;			/* w holds this motion's window */
	int judge_accel;		/* sh2000_setpoints_accel() was called */
	double amax[SH2000_AXES];	/* mm/s^2, for the message */
	double per_amax[SH2000_AXES];	/* 1 / (amax T^2): |P[k-1] - 2P[k] +
					 * P[k+1]| times it, at most 1 */
	double accel_peak;		/* the most |second difference| seen,
					 * as a fraction of its axis' amax */
	unsigned int accel_axis;	/* that axis */
	double margin;			/* the plan's, for the message */
	double period_s;
	int have_rest;
	uint64_t points;		/* records seen */
};

void sh2000_setpoints_init(struct sh2000_setpoints *c,
			   const struct sh2000_limits *l);
/* Judge the points by pc's gantry pair too (sh2000_pair_rule_init). */
void sh2000_setpoints_pair(struct sh2000_setpoints *c,
			   const struct sh2000_path_config *pc);
/* Judge the set-points' acceleration too, by pc's amax, period and scale
 * (setpoints.c): a record past amax is -ERANGE; the peak is kept in
 * accel_peak, accel_axis. */
void sh2000_setpoints_accel(struct sh2000_setpoints *c,
			    const struct sh2000_path_config *pc);
/* The card rests at mm (a new plan starts there). */
void sh2000_setpoints_rest(struct sh2000_setpoints *c,
			   const double mm[SH2000_AXES]);
/*
 * The next record mm (end: the last of a motion). Checks the gantry
 * pair's rule, the card's set-points up to it (and their acceleration,
 * if asked); then puts the record on a limit it is beyond. 0, 1 (mm
 * changed), -SH2000_EGANTRY, -SH2000_ELIMIT or -ERANGE with msg.
 */
/*
 * The same limits as bounds of the planner's primitives, with the same
 * slack (sh2000_path_set_bounds()): a primitive whose end or extremes are
 * beyond them is refused when it is added, before any of its points are
 * made. l NULL: none. 0 or the planner's error.
 */
int sh2000_setpoints_bound(const struct sh2000_limits *l,
			   struct sh2000_path *p);
int sh2000_setpoints_point(struct sh2000_setpoints *c, double mm[SH2000_AXES],
			   int end, char *msg, size_t len);

#endif
