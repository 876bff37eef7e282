/* SPDX-License-Identifier: MIT */
/* bench_tune's parts: the reference circle on a card (circle.c) and the
 * exhaustive search over the gains (search.c). */
#ifndef BENCH_TUNE_H
#define BENCH_TUNE_H

#include <sh2000/sh2000.h>

#include "autotune.h"

#define CIRCLE_R_MM	5.0
#define CIRCLE_FEED	300.0	/* mm/s asked */

/* What one run of the circle gave. */
struct circle_result {
	double max_ferr, rms_ferr;	/* |(ex, ey)|, counts, whole record */
	double feed;		/* the fastest the set-point went, mm/s */
	int unstable;		/* a fault (following error, DAC), or an
				 * oscillation growing after the motion */
	char why[160];		/* what made it unstable */
};

/* A machine: its plant (every axis) and the amax the planner may use. */
struct bench_machine {
	struct sh2000_sim_config cfg;
	double amax;		/* mm/s^2 */
	double ferr_limit;	/* mm */
};

/* A fresh card of machine m (in-process `sim`, virtual time): amax on
 * every axis, the following-error limit, gains g on x and y (NULL: the
 * card's), x and y enabled. 0, or -1 with a message printed. */
int bench_card_open(struct sh2000 **h, const struct bench_machine *m,
		    const struct tune_gains *g);

/* The R 5 mm circle at 300 mm/s in XY from the card's position (planned
 * and streamed by libsh2000-motion's runner, as a user runs it), the
 * following error gathered every servo cycle. x and y must be enabled,
 * the card idle. 0, or -1 with a message printed (the card failed other
 * than by a fault of the loop). */
int circle_run(struct sh2000 *h, struct circle_result *res);

/* The circle on a fresh card of machine m with gains g on x and y. */
int circle_with(const struct bench_machine *m, const struct tune_gains *g,
		struct circle_result *res);

/* Gains whose predicted phase margin (on the true plant) is below this
 * are not admissible for the tuner: the search reports its best with
 * and without them. */
#define SEARCH_MIN_PM 45.0

struct search_best {
	struct circle_result any, pm;	/* best of all / of the admissible */
	struct tune_gains any_gains, pm_gains;
	struct tune_design_margins any_margins, pm_margins;
	unsigned int runs, unstable;
};

/* The best gains by the circle's max following error: a coarse grid
 * around the true plant's values, then finer ones around the best of all
 * and around the best admissible, every run on a fresh card (servo period
 * 100 us, the card's default). 0 or -1. */
int search_best(const struct bench_machine *m, struct search_best *sb);

#endif /* BENCH_TUNE_H */
