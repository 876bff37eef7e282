/* SPDX-License-Identifier: MIT */
/*
 * The search's local refinement: a compass search from a measured point
 * on five coordinates, log kp, log(1/ti), log td, kvff and kaff (the last
 * two in steps of the plant's exact inverse, which the search knows).
 * Each pass tries both directions of each coordinate, the one that worked
 * last first, and keeps going while a step improves; after a pass that
 * improves nothing the steps halve, down to MIN_STEP of their start. The
 * integral may leave (ti beyond TI_NONE: none) and come back (from none:
 * TI_FROM_NONE). A point is measured only when the card takes it and,
 * constrained, when its predicted margins on the true plant keep to the
 * limits. Unstable runs never win. Noise: the measure is the worst
 * of CIRCLE_VARIANTS runs, so a step must win on all of them.
 */
#include <math.h>
#include <string.h>

#include "bench_tune.h"

#define NCOORD 5
#define MIN_STEP (1.0 / 32)
#define TI_NONE 1.0		/* s: an integral this slow is none */
#define TI_FROM_NONE 0.1	/* s */
#define TD_FROM_NONE 1e-5	/* s */

struct walk {
	const struct bench_machine *m;
	const struct tune_plant *pl;
	const struct search_limits *lim;	/* NULL: none */
	unsigned int left;	/* measures still allowed */
	const char *from;
	struct search_best *sb;
	double step[NCOORD];
	int dir[NCOORD];	/* the direction that worked last */
};

/* x moved by dir steps along coordinate c. */
static struct tune_gains moved(const struct walk *w, const struct tune_gains *x,
			       int c, int dir)
{
	struct tune_gains g = *x;
	double s = dir * w->step[c];
	/* the feed-forward's unit: the plant's exact inverse (kvff: a
	 * tenth of 1/g's when the plant has no friction) */
	double uv = w->pl->p > 0 ? w->pl->p / w->pl->g : 0.1 / w->pl->g;

	switch (c) {
	case 0:
		g.kp *= exp(s);
		break;
	case 1:		/* 1/ti up by e^s */
		g.ti = g.ti > 0 ? g.ti * exp(-s) : (dir > 0 ? TI_FROM_NONE : 0);
		if (g.ti > TI_NONE)
			g.ti = 0;
		break;
	case 2:
		g.td = g.td > 0 ? g.td * exp(s) : (dir > 0 ? TD_FROM_NONE : 0);
		break;
	case 3:
		g.kvff = fmax(0, g.kvff + s * uv);
		break;
	default:
		g.kaff = fmax(0, g.kaff + s / w->pl->g);
		break;
	}
	return g;
}

/* Measure g when it may be and is new; 1 when it beats *x (then *x is
 * it), 0 when not, -1 on a failure of the card. */
static int try_point(struct walk *w, const struct tune_gains *g,
		     struct search_point *x)
{
	struct search_point p;
	struct tune_design_margins mg;

	if (!memcmp(g, &x->g, sizeof(*g)) || !search_on_card(g) || !w->left)
		return 0;
	if (w->lim) {
		tune_margins_of(w->pl, g, &mg);
		if (!mg.stable || mg.pm_deg < w->lim->pm_deg ||
		    mg.gm_db < w->lim->gm_db)
			return 0;
	}
	w->left--;
	if (search_consider(w->m, w->pl, g, w->from, w->sb, &p) < 0)
		return -1;
	if (p.res.unstable || !search_better(&p.res, &x->res))
		return 0;
	*x = p;
	return 1;
}

/* Along coordinate c: the last good direction first, then the other;
 * on while it improves. 1 if *x moved, 0 if not, -1 on failure. */
static int line(struct walk *w, int c, struct search_point *x)
{
	for (int k = 0; k < 2; k++) {
		int dir = k ? -w->dir[c] : w->dir[c], r, n = 0;
		struct tune_gains g;

		do {
			g = moved(w, &x->g, c, dir);
			r = try_point(w, &g, x);
			n += r > 0;
		} while (r > 0);
		if (r < 0)
			return -1;
		if (n) {
			w->dir[c] = dir;
			return 1;
		}
	}
	return 0;
}

int search_refine(const struct bench_machine *m, const struct tune_plant *pl,
		  const struct search_limits *lim, unsigned int budget,
		  const char *from, struct search_best *sb,
		  struct search_point *x)
{
	struct walk w = {
		.m = m, .pl = pl, .lim = lim, .left = budget,
		.from = from, .sb = sb,
		/* x 1.3 on kp and td, x 1.65 on 1/ti, 4 % of the inverse */
		.step = { 0.25, 0.5, 0.25, 0.04, 0.04 },
		.dir = { 1, 1, 1, 1, 1 },
	};
	double scale = 1;

	while (w.left && scale >= MIN_STEP) {
		int moved_any = 0;

		for (int c = 0; c < NCOORD; c++) {
			int r = line(&w, c, x);

			if (r < 0)
				return -1;
			moved_any |= r;
		}
		if (!moved_any) {
			scale /= 2;
			for (int c = 0; c < NCOORD; c++)
				w.step[c] /= 2;
		}
	}
	return 0;
}
