/* SPDX-License-Identifier: MIT */
/* bench_tune's parts: the reference circle on a card (circle.c) and the
 * exhaustive search over the gains (search.c). */
#ifndef BENCH_TUNE_H
#define BENCH_TUNE_H

#include <sh2000/sh2000.h>
#include <sh2000/sh2000_cardsim.h>

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
 * and streamed by libsh2000-motion's runner, as a user runs it), counter-
 * clockwise, the start at angle_deg on the circle (0: the centre is R
 * along -x), the following error gathered every servo cycle. x and y
 * must be enabled, the card idle. 0, or -1 with a message printed (the
 * card failed other than by a fault of the loop). */
int circle_run(struct sh2000 *h, double angle_deg, struct circle_result *res);

/* One variant of the reference move: where on the circle it starts, and
 * where within a count of the scale the carriage stands at the start. */
struct circle_variant {
	double angle_deg;
	double start_counts;	/* added to the plant's start, counts */
	double phase;		/* host time waited before, servo periods */
};

/* The circle on a fresh card of machine m with gains g on x and y:
 * variant v, or (circle_with) angle 0 from the plant's own start. */
int circle_variant_with(const struct bench_machine *m,
			const struct tune_gains *g,
			const struct circle_variant *v,
			struct circle_result *res);
int circle_with(const struct bench_machine *m, const struct tune_gains *g,
		struct circle_result *res);

/* The measure of gains (measure.c): the worst of n runs of the circle,
 * variants first..first+n-1 (circle_variant_of), each on a fresh card;
 * unstable when one is (res is then that run). The search chooses by
 * n = CIRCLE_VARIANTS from 0; the verdict compares on the others up to
 * CIRCLE_VARIANTS_ALL (8 angles x 8 start positions), runs the search
 * never saw: the least of some 400 draws of the first 8 is partly the
 * draw's luck, which runs it did not choose by do not share. */
#define CIRCLE_VARIANTS		8
#define CIRCLE_VARIANTS_ALL	64
#define CIRCLE_HELD_OUT		(CIRCLE_VARIANTS_ALL - CIRCLE_VARIANTS)
void circle_variant_of(unsigned int i, struct circle_variant *v);
int circle_measure_from(const struct bench_machine *m,
			const struct tune_gains *g, unsigned int first,
			unsigned int n, struct circle_result *res);
int circle_measure(const struct bench_machine *m, const struct tune_gains *g,
		   unsigned int n, struct circle_result *res);
/* The worst of two measures of the same gains (a, b: unstable first). */
void circle_worst(const struct circle_result *a, const struct circle_result *b,
		  struct circle_result *res);

/* Gains whose predicted phase margin (on the true plant) is below this
 * are not admissible for the tuner: the search reports its best with
 * and without them. */
#define SEARCH_MIN_PM 45.0

/* One set of gains, its figure and its predicted margins on the true
 * plant; from: how the search came to it. */
struct search_point {
	struct tune_gains g;
	struct circle_result res;
	struct tune_design_margins mg;
	const char *from;
};

struct search_best {
	struct search_point any, pm;	/* best of all / of the admissible,
					 * by the measure */
	/* the best from the tuned gains within the design's own limits
	 * (phase margin TUNE_DEFAULT_MARGIN, gain margin TUNE_MIN_GM_DB) */
	struct search_point own;
	double grid_any, grid_pm;	/* the grids' best by one run */
	unsigned int runs, unstable;	/* the grids' circles */
	unsigned int measures, measures_unstable;	/* of the measure */
};

/* The best gains by the measure (CIRCLE_VARIANTS runs of the circle),
 * every run on a fresh card (servo period 100 us, the card's default):
 * a coarse grid around the true plant's values and finer ones around its
 * best of all and its best admissible, each point by one run; the best
 * few of each measured; then a local search (refine.c) unconstrained from
 * the best of all, and within the admissible gains from the best
 * admissible and from tuned (the tuner's gains: so best45 is at least as
 * good as they are when they are admissible), and from tuned within the
 * design's own limits (sb->own: is the design the best PID it could
 * have given?). 0 or -1. */
int search_best(const struct bench_machine *m, const struct tune_gains *tuned,
		struct search_best *sb);

/* ---- the search's parts (search.c, refine.c) ---- */

/* The true plant of machine m, as the tuner's model (delay 0, 100 us). */
void search_true_plant(const struct bench_machine *m, struct tune_plant *pl);
/* The gains the card takes (kp within its range). */
int search_on_card(const struct tune_gains *g);
/* Admissible: predicted stable with the phase margin >= SEARCH_MIN_PM. */
int search_admissible(const struct tune_design_margins *mg);
/* Measure g (margins on pl) into *pt and keep it in sb when it beats
 * sb's best of all or, admissible, its best admissible: 0 or -1. */
int search_consider(const struct bench_machine *m, const struct tune_plant *pl,
		    const struct tune_gains *g, const char *from,
		    struct search_best *sb, struct search_point *pt);
/* a before b: the lower max, then the lower RMS */
int search_better(const struct circle_result *a, const struct circle_result *b);

/* The predicted margins a local search keeps to on the true plant. */
struct search_limits {
	double pm_deg, gm_db;
};

/* From *x (measured), a compass search on log kp, log 1/ti (down to none),
 * log td, kvff and kaff, within lim (stable and both margins; NULL: any
 * gains the card takes), at most budget measures; every measure goes
 * through search_consider. *x becomes the best it found. 0 or -1. */
int search_refine(const struct bench_machine *m, const struct tune_plant *pl,
		  const struct search_limits *lim, unsigned int budget,
		  const char *from, struct search_best *sb,
		  struct search_point *x);

/* ---- bench_tune's table (report.c) ---- */

struct plant_case {
	const char *name;
	double mass, friction;
};

/* What bench_tune found on one plant. */
struct row {
	struct tune_plant truth, id;	/* the true and identified plant */
	struct tune_design_margins m;	/* the tuned gains' predicted */
	struct tune_gains tuned;
	struct circle_result init, autot;	/* by the measure */
	struct search_best sb;
	/* tuned, best, best45, own on the CIRCLE_HELD_OUT runs the search
	 * did not choose by, and over all CIRCLE_VARIANTS_ALL */
	struct circle_result held[4], all[4];
	double amax, cpu_s;
};

/* The table of n plants, their gains and the verdicts, on stdout. */
void report_table(const struct plant_case *cases, const struct row *rows,
		  unsigned int n);

#endif /* BENCH_TUNE_H */
