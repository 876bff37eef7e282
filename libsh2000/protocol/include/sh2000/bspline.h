/* SPDX-License-Identifier: MIT */
/*
 * The card paper's fine interpolation: the uniform cubic B-spline over four
 * consecutive coarse points, evaluated at 0 <= t <= 1. The card model and
 * the planner share this one copy so that a planner can predict exactly
 * where the card's set-point will be.
 *
 * x(t) = (x0+4x1+x2)/6 + (-x0+x2)/2 t + (x0-2x1+x2)/2 t^2
 *        + (-x0+3x1-3x2+x3)/6 t^3
 *
 * Properties the protocol relies on: x(1) of window (x0..x3) equals x(0) of
 * the next window (x1..x4), with matching first and second derivatives, and
 * four equal points give that point exactly (END padding).
 */
#ifndef SH2000_BSPLINE_H
#define SH2000_BSPLINE_H

static inline double sh2000_bspline(double x0, double x1, double x2,
				    double x3, double t)
{
	/* Horner form of the paper's polynomial. */
	double c0 = (x0 + 4.0 * x1 + x2) / 6.0;
	double c1 = (x2 - x0) / 2.0;
	double c2 = (x0 - 2.0 * x1 + x2) / 2.0;
	double c3 = (-x0 + 3.0 * x1 - 3.0 * x2 + x3) / 6.0;

	return c0 + t * (c1 + t * (c2 + t * c3));
}

/* First derivative with respect to t (per coarse period). */
static inline double sh2000_bspline_d1(double x0, double x1, double x2,
				       double x3, double t)
{
	double c1 = (x2 - x0) / 2.0;
	double c2 = (x0 - 2.0 * x1 + x2) / 2.0;
	double c3 = (-x0 + 3.0 * x1 - 3.0 * x2 + x3) / 6.0;

	return c1 + t * (2.0 * c2 + t * 3.0 * c3);
}

/* Second derivative with respect to t (per coarse period squared). */
static inline double sh2000_bspline_d2(double x0, double x1, double x2,
				       double x3, double t)
{
	double c2 = (x0 - 2.0 * x1 + x2) / 2.0;
	double c3 = (-x0 + 3.0 * x1 - 3.0 * x2 + x3) / 6.0;

	return 2.0 * c2 + t * 6.0 * c3;
}

#endif /* SH2000_BSPLINE_H */
