// SPDX-License-Identifier: MIT
/*
 * Soft limits judged on the card's fine set-points, not on its records.
 *
 * The card's set-point is the uniform cubic B-spline of its records
 * (sh2000/bspline.h), starting from the window [X, X, X, P1] of the rest
 * point X and padded with the end point E after END. The planner's
 * B-spline compensation (docs/planner.md) chooses the records so that this
 * spline passes through the planned points: where the path turns near a
 * limit (a circle tangent to it, a reversal) the records lie beyond the
 * path by up to about a T^2 / 6 (6 um for 9000 mm/s^2 at T = 2 ms) while
 * the set-points stay on it. Judging the records would refuse such paths.
 *
 * So the policy is: the set-points of the planned records, evaluated span
 * by span with their extremes between the knots, must stay within
 * SH2000_LIMIT_SLACK_MM of the limits (-SH2000_ELIMIT otherwise, naming
 * the set-point); and a record beyond a limit is put on it, because the
 * card refuses records outside its soft limits. Moving records inwards
 * keeps the card's set-points inside, since a B-spline stays in the hull
 * of its control points, and moves them by no more than the records moved.
 *
 * The ends and extremes of the primitives are known when they are added:
 * the planner refuses one beyond the limits and their slack then
 * (sh2000_setpoints_bound()), before any of it is queued, while this
 * check, a ring ahead of the card, stays the guard for what only the
 * points show (blends, the compensation, what a NURBS sample missed).
 *
 * A span is known once its fourth record is: the check of a record's
 * neighbourhood ends two records after it (or at END), so a runner may
 * have pushed the records before; those are inside the limits all the
 * same. The first pass of a program checks everything before anything
 * moves.
 *
 * The first pass also judges the acceleration of the same set-points
 * (sh2000_setpoints_accel()). The spline's second derivative is linear
 * over each span, (1 - u)(P0 - 2P1 + P2) + u(P1 - 2P2 + P3) over T^2, so
 * its extremes are at the knots: the largest acceleration the card
 * commands is the largest second difference of the records over T^2,
 * exactly, with no sampling. The planner plans within its margin of every
 * amax (0.95), which leaves the card's correction tables and time base
 * their reserve (up to 4 % of amax); on that spline it keeps within amax
 * at the limits it is measured at (docs/planner.md), but not at all limits
 * ("Known limits"). A plan whose records pass an axis' amax is refused
 * with the axis and the time instead of being sent to the drives, and
 * sh2000_program_check() plans it again with a smaller margin. The runner
 * does not judge it: a live override changes the plan the first pass
 * judged.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "setpoints.h"
#include "sh2000/bspline.h"

void sh2000_setpoints_init(struct sh2000_setpoints *c,
			   const struct sh2000_limits *l)
{
	memset(c, 0, sizeof(*c));
	c->limits = l;
}

void sh2000_setpoints_pair(struct sh2000_setpoints *c,
			   const struct sh2000_path_config *pc)
{
	sh2000_pair_rule_init(&c->pair, pc);
}

void sh2000_setpoints_rest(struct sh2000_setpoints *c,
			   const double mm[SH2000_AXES])
{
	memcpy(c->rest, mm, sizeof(c->rest));
	c->have_rest = 1;
	c->in_motion = 0;
}

int sh2000_setpoints_bound(const struct sh2000_limits *l,
			   struct sh2000_path *p)
{
	double lo[SH2000_AXES], hi[SH2000_AXES];
	unsigned int a;

	if (!l)
		return sh2000_path_set_bounds(p, NULL, NULL);
	for (a = 0; a < SH2000_AXES; a++) {
		lo[a] = l->lo[a] - SH2000_LIMIT_SLACK_MM;
		hi[a] = l->hi[a] + SH2000_LIMIT_SLACK_MM;
	}
	return sh2000_path_set_bounds(p, lo, hi);
}

/* Lowest and highest value of the span's cubic on 0 <= t <= 1. */
static void span_range(const double w[4], double *lo, double *hi)
{
	double c1 = (w[2] - w[0]) / 2.0;
	double c2 = (w[0] - 2.0 * w[1] + w[2]) / 2.0;
	double c3 = (-w[0] + 3.0 * w[1] - 3.0 * w[2] + w[3]) / 6.0;
	double t[4], x;
	unsigned int n = 2, i;

	t[0] = 0.0;
	t[1] = 1.0;
	/* x'(t) = c1 + 2 c2 t + 3 c3 t^2 = 0 */
	if (fabs(c3) > 1e-300) {
		double d = 4.0 * c2 * c2 - 12.0 * c3 * c1;

		if (d >= 0.0) {
			t[n++] = (-2.0 * c2 + sqrt(d)) / (6.0 * c3);
			t[n++] = (-2.0 * c2 - sqrt(d)) / (6.0 * c3);
		}
	} else if (fabs(c2) > 1e-300) {
		t[n++] = -c1 / (2.0 * c2);
	}
	*lo = INFINITY;
	*hi = -INFINITY;
	for (i = 0; i < n; i++) {
		if (!(t[i] >= 0.0 && t[i] <= 1.0))
			continue;
		x = sh2000_bspline(w[0], w[1], w[2], w[3], t[i]);
		if (x < *lo)
			*lo = x;
		if (x > *hi)
			*hi = x;
	}
}

/* The span of window (a, b, c, d): the set-points between the knots of b
 * and c. */
static int check_span(const struct sh2000_setpoints *c, const double *a,
		      const double *b, const double *cc, const double *d,
		      uint64_t first, char *msg, size_t len)
{
	static const char name[] = SH2000_AXIS_LETTERS;
	unsigned int ax;

	for (ax = 0; ax < SH2000_AXES; ax++) {
		const double w[4] = { a[ax], b[ax], cc[ax], d[ax] };
		double lo, hi, x, lim;

		span_range(w, &lo, &hi);
		if (lo < c->limits->lo[ax] - SH2000_LIMIT_SLACK_MM) {
			x = lo;
			lim = c->limits->lo[ax];
		} else if (hi > c->limits->hi[ax] + SH2000_LIMIT_SLACK_MM) {
			x = hi;
			lim = c->limits->hi[ax];
		} else {
			continue;
		}
		if (msg && len)
			snprintf(msg, len,
				 "%c %.4f mm is beyond the soft limit %.4f mm (soft limits %.4f..%.4f mm; the card's set-point near record %llu)",
				 name[ax], x, lim, c->limits->lo[ax],
				 c->limits->hi[ax], (unsigned long long)first);
		return -SH2000_ELIMIT;
	}
	return 0;
}

/* Put the record on the limits it is beyond: 1 if it moved. */
static int clamp(const struct sh2000_limits *l, double mm[SH2000_AXES])
{
	unsigned int a;
	int moved = 0;

	for (a = 0; a < SH2000_AXES; a++) {
		double v = mm[a] < l->lo[a] ? l->lo[a] :
			   mm[a] > l->hi[a] ? l->hi[a] : mm[a];

		moved |= v != mm[a];
		mm[a] = v;
	}
	return moved;
}

/* The second difference of three consecutive records over T^2, the
 * spline's acceleration at the middle one's knot: kept as the peak, and
 * judged against amax. */
static int check_accel(struct sh2000_setpoints *c, const double *a,
		       const double *b, const double *cc, uint64_t n,
		       char *msg, size_t len)
{
	static const char name[] = SH2000_AXIS_LETTERS;
	double T2 = c->period_s * c->period_s;
	unsigned int ax;

	for (ax = 0; ax < SH2000_AXES; ax++) {
		double d2 = fabs(a[ax] - 2.0 * b[ax] + cc[ax]);
		double f = d2 * c->per_amax[ax];

		if (f > c->accel_peak) {
			c->accel_peak = f;
			c->accel_axis = ax;
		}
		/* the records as planned, before the card rounds them to
		 * counts (which moves a second difference by two counts at
		 * most: 5 mm/s^2 at 10 nm and 2 ms); an ulp's slack */
		if (f <= 1.0 + 1e-9)
			continue;
		if (msg && len)
			snprintf(msg, len,
				 "axis %c: the planned set-points accelerate at %.0f mm/s^2 at %.3f s, over its amax of %.0f mm/s^2 (planned with the margin %.3f: the planner does not hold these limits there, docs/planner.md \"Known limits\")",
				 name[ax], d2 / T2, (double)n * c->period_s,
				 c->amax[ax], c->margin);
		return -ERANGE;
	}
	return 0;
}

void sh2000_setpoints_accel(struct sh2000_setpoints *c,
			    const struct sh2000_path_config *pc)
{
	double T2 = pc->period_s * pc->period_s;
	unsigned int a;

	c->judge_accel = 1;
	c->period_s = pc->period_s;
	c->margin = pc->margin;
	for (a = 0; a < SH2000_AXES; a++) {
		c->amax[a] = pc->amax[a];
		c->per_amax[a] = 1.0 / (pc->amax[a] * T2);
	}
}

/* Record mm's spans (and after END, the padded ones): their set-points
 * within the limits, their acceleration within the guard's. */
static int check_record(struct sh2000_setpoints *c, const double *mm,
			uint64_t k, int end, char *msg, size_t len)
{
	const double (*w)[SH2000_AXES] = c->w;
	int e = 0;

	if (c->judge_accel)
		e = check_accel(c, w[1], w[2], mm, k + 1, msg, len);
	if (!e && c->judge_accel && end)
		e = check_accel(c, w[2], mm, mm, k + 2, msg, len);
	if (!c->limits || e)
		return e;
	e = check_span(c, w[0], w[1], w[2], mm, k ? k - 1 : 0, msg, len);
	/* after END the card pads with the end point */
	if (!e && end)
		e = check_span(c, w[1], w[2], mm, mm, k, msg, len);
	if (!e && end)
		e = check_span(c, w[2], mm, mm, mm, k, msg, len);
	return e;
}

int sh2000_setpoints_point(struct sh2000_setpoints *c, double mm[SH2000_AXES],
			   int end, char *msg, size_t len)
{
	uint64_t k = c->points++;
	const double *x;
	/* the motion began at rest (the planner's start, as the card's) */
	int e = sh2000_pair_rule_point(&c->pair, c->have_rest ? c->rest : mm,
				       mm, msg, len);

	if (e)
		return e;
	if (!c->in_motion) {
		/* the card starts from its rest point (the planner's start
		 * is within a micrometre of the first record) */
		x = c->have_rest ? c->rest : mm;
		memcpy(c->w[0], x, sizeof(c->w[0]));
		memcpy(c->w[1], x, sizeof(c->w[1]));
		memcpy(c->w[2], x, sizeof(c->w[2]));
		c->in_motion = 1;
	}
	e = check_record(c, mm, k, end, msg, len);
	if (e)
		return e;
	memmove(c->w[0], c->w[1], 2 * sizeof(c->w[0]));
	memcpy(c->w[2], mm, sizeof(c->w[2]));
	if (end)
		sh2000_setpoints_rest(c, mm);
	return c->limits ? clamp(c->limits, mm) : 0;
}
