/* SPDX-License-Identifier: MIT */
/*
 * The free-form curves the feed test (test_feed.c) and the feed benchmark
 * (bench/feed) run, defined once:
 *
 *  - the free-form NURBS of the planner's tests: cubic, 8 control points,
 *    uneven weights, 32 mm across in x and 44.7 mm long;
 *  - a butterfly: cubic, 50 control points sampled from Fay's butterfly
 *    without its slow term, r(t) = e^cos t - 2 cos 4t, x = s r sin t,
 *    y = s r cos t, t over one turn (the first and last point are both
 *    t = 0), s = 12 mm (68 x 57 mm, 407 mm long); clamped uniform knots;
 *    weight 5 at the tips of the upper wings and 3 at those of the lower
 *    ones, 1 elsewhere. Our own curve, of the class the NURBS-interpolation
 *    literature tests with (about 50 points, uneven weights, tight turns);
 *    not any paper's data. Its tightest turns: the two small loops beside
 *    the body (R 0.22 mm), the head (R 0.72), the wing tips (R 0.74 and
 *    1.0). Its derivative never vanishes (|C'(u)| >= 54 mm) and it has no
 *    cusp (test_feed's test_butterfly_shape).
 *
 * Both are translated so that they start at a given point (the card's
 * set-point). Header-only.
 */
#ifndef SH2000_CURVES_H
#define SH2000_CURVES_H

#include <math.h>

#include "sh2000/geometry.h"

/* ---- the free-form NURBS of the planner's tests ------------------------- */

#define FF_NPTS 8

static const double ff_ctrl[FF_NPTS][4] = {
	{ 0, 0, 0, 0 }, { 5, 10, 0, 0 }, { 10, -5, 1, 0 }, { 15, 8, 2, 0 },
	{ 20, 0, 2, 0 }, { 22, 12, 1, 0 }, { 30, 5, 0, 0 }, { 32, 0, 0, 0 },
};
static const double ff_w[FF_NPTS] = { 1, 2, 0.5, 1, 3, 1, 1, 1 };
static const double ff_k[FF_NPTS + 4] = { 0, 0, 0, 0, 0.2, 0.4, 0.5, 0.8,
					  1, 1, 1, 1 };

/* The free-form curve starting at o, its points in pts. */
static inline struct sh2000_nurbs ff_nurbs(double pts[FF_NPTS][4],
					   const double o[4])
{
	struct sh2000_nurbs n = { 3, FF_NPTS, (const double (*)[4])pts, ff_w,
				  ff_k };

	for (unsigned int i = 0; i < FF_NPTS; i++)
		for (unsigned int a = 0; a < 4; a++)
			pts[i][a] = o[a] + ff_ctrl[i][a];
	return n;
}

/* ---- the butterfly ------------------------------------------------------- */

#define BFLY_NPTS 50
#define BFLY_SCALE 12.0		/* mm */

struct bfly {
	double pts[BFLY_NPTS][4];
	double w[BFLY_NPTS];
	double k[BFLY_NPTS + 4];
};

/* The butterfly starting at o, its arrays in b. */
static inline struct sh2000_nurbs bfly_nurbs(struct bfly *b, const double o[4])
{
	struct sh2000_nurbs n = { 3, BFLY_NPTS, (const double (*)[4])b->pts,
				  b->w, b->k };
	double x0 = 0, y0 = 0;

	for (unsigned int i = 0; i < BFLY_NPTS; i++) {
		double t = 2 * M_PI * i / (BFLY_NPTS - 1);
		double r = BFLY_SCALE * (exp(cos(t)) - 2 * cos(4 * t));

		if (!i) {
			x0 = r * sin(t);
			y0 = r * cos(t);
		}
		b->pts[i][0] = o[0] + r * sin(t) - x0;
		b->pts[i][1] = o[1] + r * cos(t) - y0;
		b->pts[i][2] = o[2];
		b->pts[i][3] = o[3];
		/* the wing tips: the points where r peaks (cos 4t = -1) */
		b->w[i] = (i == 6 || i == 43) ? 5 : (i == 18 || i == 31) ? 3 : 1;
	}
	/* clamped, uniform inside */
	for (unsigned int k = 0; k < BFLY_NPTS + 4; k++)
		b->k[k] = k < 4 ? 0 : k >= BFLY_NPTS ? 1 :
			  (double)(k - 3) / (BFLY_NPTS - 3);
	return n;
}

#endif /* SH2000_CURVES_H */
