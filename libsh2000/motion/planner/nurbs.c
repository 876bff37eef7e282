// SPDX-License-Identifier: MIT
/*
 * A NURBS the planner holds: its own copy of the caller's curve (the
 * window may outlive the caller's arrays), evaluated by the one evaluator
 * of sh2000/geometry.h, its arc length by Gauss-Legendre, and its frame
 * (unit tangent and curvature) for the speed limits, and the parameter at
 * an arc length (entering a block, cutting one for a blend).
 */
#include <math.h>
#include <string.h>

#include "planner.h"

struct pl_nurbs *pl_nurbs_new(struct sh2000_path *p,
			      const struct sh2000_nurbs *n)
{
	size_t np = n->npoints, nk = np + n->degree + 1;
	struct pl_nurbs *nb = pl_alloc(p, sizeof(*nb));
	double (*pts)[SH2000_AXES];
	double *w, *U;

	if (!nb)
		return NULL;
	pts = pl_alloc(p, np * sizeof(*pts));
	w = pl_alloc(p, np * sizeof(*w));
	U = pl_alloc(p, nk * sizeof(*U));
	nb->bytes = np * sizeof(*pts) + np * sizeof(*w) + nk * sizeof(*U);
	nb->c.degree = n->degree;
	nb->c.npoints = np;
	nb->c.points = (const double (*)[SH2000_AXES])pts;
	nb->c.weights = w;
	nb->c.knots = U;
	nb->expanded = 1;
	nb->refs = 1;
	if (!pts || !w || !U) {
		pl_nurbs_put(p, nb);
		return NULL;
	}
	memcpy(pts, n->points, np * sizeof(*pts));
	memcpy(U, n->knots, nk * sizeof(*U));
	for (size_t i = 0; i < np; i++)
		w[i] = n->weights ? n->weights[i] : 1.0;
	nb->umin = sh2000_nurbs_umin(&nb->c);
	nb->umax = sh2000_nurbs_umax(&nb->c);
	nb->span = n->degree;
	nb->cut = NAN;
	nb->expanded = 0;
	nb->refs = 0;
	return nb;
}

void pl_nurbs_put(struct sh2000_path *p, struct pl_nurbs *nb)
{
	size_t np = nb->c.npoints, nk = np + nb->c.degree + 1;

	if (nb->refs > 0)
		nb->refs--;
	if (nb->refs > 0 || !nb->expanded)
		return;
	pl_free(p, (void *)nb->c.points, np * sizeof(*nb->c.points));
	pl_free(p, (void *)nb->c.weights, np * sizeof(double));
	pl_free(p, (void *)nb->c.knots, nk * sizeof(double));
	pl_free(p, nb, sizeof(*nb));
}

void pl_nurbs_eval(const struct pl_nurbs *nb, double u, double c[SH2000_AXES],
		   double d1[SH2000_AXES], double d2[SH2000_AXES])
{
	sh2000_nurbs_eval(&nb->c, u, c, d1, d2);
}

static double speed_at(const struct pl_nurbs *nb, double u)
{
	double c[SH2000_AXES], d[SH2000_AXES], s = 0.0;
	unsigned int ax;

	pl_nurbs_eval(nb, u, c, d, NULL);
	for (ax = 0; ax < SH2000_AXES; ax++)
		s += d[ax] * d[ax];
	return sqrt(s);
}

/* 8-point Gauss-Legendre over [u0, u1]. */
static double gauss8(const struct pl_nurbs *nb, double u0, double u1)
{
	static const double x[4] = { 0.1834346424956498, 0.5255324099163290,
				     0.7966664774136267, 0.9602898564975363 };
	static const double w[4] = { 0.3626837833783620, 0.3137066458778873,
				     0.2223810344533745, 0.1012285362903763 };
	double m = 0.5 * (u0 + u1), h = 0.5 * (u1 - u0), s = 0.0;
	unsigned int i;

	for (i = 0; i < 4; i++)
		s += w[i] * (speed_at(nb, m - h * x[i]) +
			     speed_at(nb, m + h * x[i]));
	return s * h;
}

/* Halves until the two halves agree with the whole: a heavy weight can
 * crowd most of a block's length into a sliver of its parameter, which
 * one rule of 8 points misses (a 2 mm piece came out as 0.6 mm). */
static double adaptive(const struct pl_nurbs *nb, double u0, double u1,
		       double whole, unsigned int depth)
{
	double m = 0.5 * (u0 + u1), l = gauss8(nb, u0, m), r = gauss8(nb, m, u1);

	if (depth >= 24 || fabs(l + r - whole) <= 1e-9 * (l + r) + 1e-15)
		return l + r;
	return adaptive(nb, u0, m, l, depth + 1) +
	       adaptive(nb, m, u1, r, depth + 1);
}

double pl_nurbs_length(const struct pl_nurbs *nb, double u0, double u1)
{
	if (u1 <= u0)
		return 0.0;
	return adaptive(nb, u0, u1, gauss8(nb, u0, u1), 0);
}

double pl_nurbs_length_even(const struct pl_nurbs *nb, double u0, double u1)
{
	return u1 > u0 ? gauss8(nb, u0, u1) : 0.0;
}

double pl_nurbs_frame(const struct pl_nurbs *nb, double u,
		      double t[SH2000_AXES], double *kappa)
{
	double c[SH2000_AXES], d1[SH2000_AXES], d2[SH2000_AXES], n1 = 0.0, cr = 0.0;
	unsigned int ax, bx;

	pl_nurbs_eval(nb, u, c, d1, d2);
	for (ax = 0; ax < SH2000_AXES; ax++)
		n1 += d1[ax] * d1[ax];
	n1 = sqrt(n1);
	for (ax = 0; ax < SH2000_AXES; ax++)
		t[ax] = n1 > 0.0 ? d1[ax] / n1 : 0.0;
	/* |C' x C''|^2 as the sum of its 2x2 minors, written for any
	 * dimension: unlike |C'|^2 |C''|^2 - (C'.C'')^2 it does not cancel
	 * when the two are nearly parallel, so a straight curve whose |C'|
	 * goes to zero (a cusp) keeps curvature zero instead of noise / |C'|^3 */
	for (ax = 0; ax < SH2000_AXES; ax++)
		for (bx = ax + 1; bx < SH2000_AXES; bx++) {
			double m = d1[ax] * d2[bx] - d1[bx] * d2[ax];

			cr += m * m;
		}
	*kappa = (n1 > 0.0 && cr > 0.0) ? sqrt(cr) / (n1 * n1 * n1) : 0.0;
	return n1;
}

/*
 * The parameter at arc length s from u0 along [u0, u1] (whose length is L),
 * with the arc length reached in *len. The arc length from u0 grows with
 * u, so [lo, hi] with the arc short at lo and long at hi always holds the
 * answer: a Newton step is taken only where it lands inside the bracket
 * and at least halves the error of the step before, bisection otherwise
 * (a safeguarded Newton, as rtsafe in Numerical Recipes). The
 * parametrisation can be very uneven (a tiny weight puts nearly all the
 * length at one end of a span), where plain Newton steps overshoot to the
 * block's ends and a few of them left the point on a wrong parameter, far
 * from the planned distance. Lengths are measured from the bracket's low
 * end, so each integral is short.
 */
double pl_nurbs_u_at(const struct pl_nurbs *nb, double u0, double u1, double L,
		     double s, double *len)
{
	double lo = u0, hi = u1, l_lo = 0.0, u, l = 0.0, prev = INFINITY;
	unsigned int it;

	if (!(s > 0.0) || !(L > 0.0)) {
		*len = 0.0;
		return u0;
	}
	s = pl_min(s, L);
	u = lo + (hi - lo) * s / L;
	for (it = 0; it < 200; it++) {
		double f, sp, un;

		l = l_lo + pl_nurbs_length(nb, lo, u);
		f = l - s;
		if (fabs(f) <= 1e-12 * (1.0 + s))
			break;
		if (f < 0.0) {
			lo = u;
			l_lo = l;
		} else {
			hi = u;
		}
		if (hi - lo <= 1e-15 * (1.0 + fabs(hi)))
			break;
		sp = speed_at(nb, u);
		un = sp > 0.0 ? u - f / sp : NAN;
		if (!(un > lo && un < hi) || fabs(f) > 0.5 * prev)
			un = 0.5 * (lo + hi);
		prev = fabs(f);
		u = un;
	}
	*len = l;
	return u;
}
