// SPDX-License-Identifier: MIT
/*
 * The controller's one-dimensional search: the highest x in [lo, hi] at
 * which a non-increasing function f is still >= 0, to within tol.
 *
 * The answer is defined by the bracket, not by the path to it: the search
 * ends with f(lo) >= 0 > f(hi) (f(hi) as given, hi - lo <= tol) and
 * returns lo, so every method that keeps such a bracket returns the same
 * point to within tol (the bisection the controller used first, the
 * false position that replaced it, this). A bisection needs
 * n = log2((hi - lo) / tol) steps (16 for the controller); this needs
 * three to five where f is smooth or piecewise straight near its zero
 * (tests/planner/test_search.c counts them), and never more than n + 6:
 *
 *  - the secant through the last two points tried, when it falls inside
 *    the bracket (superlinear from either side), else false position
 *    with the Illinois fix;
 *  - closing in: a point that would land within tol of either end is
 *    moved to 0.99 tol from it, so that once one end sits on the zero the
 *    next step ends the search (interpolation alone leaves the far end
 *    where it is; with a zero at lo itself it would never move);
 *  - the ITP method's projection (Oliveira and Takahashi, ACM TOMS 47,
 *    2020) as the safeguard: step j stays within rad_j - (hi - lo) / 2 of
 *    the middle, rad_j = tol 2^(n + 5 - j), which bounds the bracket after
 *    step j by rad_j whatever f does. Plateaus and jumps (the controller's
 *    room mixes speeds and distances) cost at most six steps more than
 *    the bisection.
 */
#include "planner.h"

/* Steps beyond the bisection's that interpolation may spend */
#define FREE_STEPS 6

/* A cap the schedule never reaches (it ends within n + FREE_STEPS);
 * only a NaN bracket could make it matter. */
#define SEARCH_STEPS 64

/* The next point to try: the secant through the last two points tried
 * when it falls inside the bracket, else false position; at least 0.99
 * tol inside the bracket, and within `room` of its middle. */
static double next_point(const double x[2], const double fx[2], double lo,
			 double hi, double flo, double fhi, double tol,
			 double room)
{
	double mid = 0.5 * (lo + hi), m = mid;

	if (fx[0] != fx[1])
		m = x[1] - fx[1] * (x[1] - x[0]) / (fx[1] - fx[0]);
	if (!(m > lo && m < hi) && flo - fhi > 0.0) {
		/* a zero at lo itself (flo = 0) gives lo: closing in then
		 * tries lo + 0.99 tol */
		m = pl_min(pl_max((lo * fhi - hi * flo) / (fhi - flo), lo), hi);
	}
	if (!(m >= lo && m <= hi))
		m = mid;
	if (m - lo < tol)
		m = lo + 0.99 * tol;
	else if (hi - m < tol)
		m = hi - 0.99 * tol;
	return pl_min(pl_max(m, mid - room), mid + room);
}

double pl_highest_pass(double (*f)(const void *ctx, double x), const void *ctx,
		       double lo, double hi, double flo, double fhi, double tol)
{
	double rad = tol, x[2] = { hi, lo }, fx[2] = { fhi, flo };
	int side = 0, it;

	/* tol 2^n >= hi - lo: n bisections would do */
	while (rad < hi - lo)
		rad *= 2.0;
	rad *= 1u << (FREE_STEPS - 1);
	/* (hi - lo) rounds: tol to 1e-9 ends the schedule's last step */
	for (it = 0; it < SEARCH_STEPS && hi - lo > tol * (1.0 + 1e-9);
	     it++, rad *= 0.5) {
		double m = next_point(x, fx, lo, hi, flo, fhi, tol,
				      pl_max(rad - 0.5 * (hi - lo), 0.0));
		double fm = f(ctx, m);

		x[0] = x[1];
		fx[0] = fx[1];
		x[1] = m;
		fx[1] = fm;
		if (fm >= 0.0) {
			lo = m;
			flo = fm;
			if (side > 0)
				fhi *= 0.5;
			side = 1;
		} else {
			hi = m;
			fhi = fm;
			if (side < 0)
				flo *= 0.5;
			side = -1;
		}
	}
	return lo;
}
