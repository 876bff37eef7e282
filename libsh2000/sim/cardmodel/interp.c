// SPDX-License-Identifier: MIT
/*
 * Fine interpolation: a 4-point window of coarse points per axis and the
 * paper's uniform cubic B-spline evaluated at N fine steps per coarse
 * period. Pushing a point shifts the window; the curve is continuous (C2)
 * across shifts because x(1) of (x0..x3) is x(0) of (x1..x4).
 */
#include "cardmodel.h"

void sh2000_interp_hold(struct sh2000_interp *ip, unsigned int axis, double x)
{
	unsigned int i;

	for (i = 0; i < 4; i++)
		ip->w[axis][i] = x;
}

void sh2000_interp_push(struct sh2000_interp *ip, unsigned int axis, double x)
{
	ip->w[axis][0] = ip->w[axis][1];
	ip->w[axis][1] = ip->w[axis][2];
	ip->w[axis][2] = ip->w[axis][3];
	ip->w[axis][3] = x;
}

double sh2000_interp_last(const struct sh2000_interp *ip, unsigned int axis)
{
	return ip->w[axis][3];
}

double sh2000_interp_jerk(const struct sh2000_interp *ip, unsigned int axis,
			  double coarse_s)
{
	const double *w = ip->w[axis];

	return (-w[0] + 3.0 * w[1] - 3.0 * w[2] + w[3]) /
	       (coarse_s * coarse_s * coarse_s);
}

void sh2000_interp_eval(const struct sh2000_interp *ip, unsigned int axis,
			double t, double coarse_s, double *x, double *v,
			double *a)
{
	const double *w = ip->w[axis];

	*x = sh2000_bspline(w[0], w[1], w[2], w[3], t);
	*v = sh2000_bspline_d1(w[0], w[1], w[2], w[3], t) / coarse_s;
	*a = sh2000_bspline_d2(w[0], w[1], w[2], w[3], t) /
	     (coarse_s * coarse_s);
}
