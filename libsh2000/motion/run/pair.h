/* SPDX-License-Identifier: MIT */
/*
 * A gantry pair's sides move together (pair.c): what the runner and the
 * first pass of a program apply to every point, beside the soft limits.
 */
#ifndef SH2000_RUN_PAIR_H
#define SH2000_RUN_PAIR_H

#include <stddef.h>

#include "sh2000/path.h"

struct sh2000_pair_rule {
	int on;
	unsigned int a, b;		/* the sides' axes, a < b */
	double tol_mm;			/* how far apart they may move */
};

/* The rule of pc's gantry pair (off without one). */
void sh2000_pair_rule_init(struct sh2000_pair_rule *p,
			   const struct sh2000_path_config *pc);
/* 0, or -SH2000_EGANTRY with msg when the point mm has moved the sides
 * from rest (where the motion began) by distances that differ by more
 * than the tolerance. */
int sh2000_pair_rule_point(const struct sh2000_pair_rule *p,
			   const double rest[SH2000_AXES],
			   const double mm[SH2000_AXES], char *msg, size_t len);

#endif
