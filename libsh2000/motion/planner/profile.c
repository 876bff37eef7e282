// SPDX-License-Identifier: MIT
/*
 * Velocity-profile arithmetic along the path (the single-axis controller paper's [R4] trapezoid and
 * 7-phase S-curve, generalised to start from any acceleration): the
 * time-optimal transition from (v, a) to (v1, 0) under |a| <= A and
 * |jerk| <= J, its length, and the reverse question the look-ahead asks
 * (how fast may a block be entered and still slow down in time).
 *
 * A 7-phase S-curve move is two such transitions around a cruise phase;
 * a short move that never reaches cruise is the same two transitions with
 * a lower peak, which the controller finds on its own.
 */
#include <math.h>

#include "planner.h"

void pl_trans_plan(const struct pl_limits *lim, double v, double a,
		   double v1, struct pl_trans *tr)
{
	double A = lim->A, J = lim->J, ap, th, vnat;

	tr->n = 0;
	if (isinf(J)) {
		/* trapezoid: the acceleration switches at once */
		if (v1 != v) {
			tr->dur[0] = fabs(v1 - v) / A;
			tr->jerk[0] = 0.0;
			tr->acc[0] = v1 > v ? A : -A;
			tr->n = 1;
		}
		return;
	}
	vnat = v + a * fabs(a) / (2.0 * J);
	if (v1 >= vnat) {
		/* ramp a up to ap, hold, ramp down to 0:
		 * dv = (2 ap^2 - a^2) / 2J + ap th */
		ap = sqrt(pl_max((2.0 * J * (v1 - v) + a * a) / 2.0, 0.0));
		th = 0.0;
		if (ap > A) {
			ap = A;
			th = (v1 - v - (2.0 * A * A - a * a) / (2.0 * J)) / A;
		}
		if (ap < a) {
			/* above A already (a block allowing more): held
			 * there, then down to 0 */
			ap = a;
			th = (v1 - v - a * a / (2.0 * J)) / a;
		}
		tr->dur[0] = (ap - a) / J;
		tr->jerk[0] = J;
		tr->dur[1] = pl_max(th, 0.0);
		tr->jerk[1] = 0.0;
		tr->dur[2] = ap / J;
		tr->jerk[2] = -J;
	} else {
		ap = -sqrt(pl_max((2.0 * J * (v - v1) + a * a) / 2.0, 0.0));
		th = 0.0;
		if (ap < -A) {
			ap = -A;
			th = (v - v1 - (2.0 * A * A - a * a) / (2.0 * J)) / A;
		}
		if (ap > a) {
			ap = a;
			th = (v - v1 - a * a / (2.0 * J)) / -a;
		}
		tr->dur[0] = (a - ap) / J;
		tr->jerk[0] = -J;
		tr->dur[1] = pl_max(th, 0.0);
		tr->jerk[1] = 0.0;
		tr->dur[2] = -ap / J;
		tr->jerk[2] = J;
	}
	tr->acc[0] = a;
	tr->acc[1] = ap;
	tr->acc[2] = ap;
	tr->n = 3;
}

double pl_brake_dist(const struct pl_limits *lim, double v, double a,
		     double vt)
{
	struct pl_trans tr;
	double s = 0.0, vv = v, aa = a;
	int i;

	if (isinf(lim->J)) {
		if (v <= vt)
			return 0.0;
		return (v * v - vt * vt) / (2.0 * lim->A);
	}
	if (v <= vt && (a <= 0.0 || v + a * a / (2.0 * lim->J) <= vt))
		return 0.0;
	pl_trans_plan(lim, v, a, vt, &tr);
	for (i = 0; i < tr.n; i++)
		pl_integrate(&s, &vv, &aa, tr.jerk[i], tr.dur[i]);
	return s;
}

/* Length of a transition between two speeds at rest acceleration: the
 * mean speed times its time (the S-curve is symmetric). */
double pl_trans_len(const struct pl_limits *lim, double v0, double v1)
{
	double dv = fabs(v0 - v1), t;

	if (isinf(lim->J))
		t = dv / lim->A;
	else if (dv >= lim->A * lim->A / lim->J)
		t = dv / lim->A + lim->A / lim->J;
	else
		t = 2.0 * sqrt(dv / lim->J);
	return 0.5 * (v0 + v1) * t;
}

/*
 * The inverse of pl_trans_len in closed form: the start speed v1 + dv of
 * a transition of length L down to v1. Without reaching A (dv < A^2/J),
 * L = (2 v1 + dv) sqrt(dv / J): with x = sqrt(dv) the cubic
 * x^3 + 2 v1 x - L sqrt(J) = 0, whose one real root is taken in its
 * hyperbolic form (no cancellation when v1 is large). Reaching A,
 * L = (2 v1 + dv)(dv / A + A / J) / 2, a quadratic in dv.
 */
double pl_reach_back(const struct pl_limits *lim, double v1, double L)
{
	double A = lim->A, J = lim->J, p, q, x, dv, b, c;

	if (L <= 0.0)
		return v1;
	if (isinf(J))
		return sqrt(v1 * v1 + 2.0 * A * L);
	p = 2.0 * v1;
	q = L * sqrt(J);
	if (p < 1e-9 * cbrt(q * q))
		x = cbrt(q);
	else
		x = 2.0 * sqrt(p / 3.0) *
		    sinh(asinh(1.5 * q / p * sqrt(3.0 / p)) / 3.0);
	dv = x * x;
	if (dv >= A * A / J) {
		b = 2.0 * v1 + A * A / J;
		c = 2.0 * v1 * A * A / J - 2.0 * L * A;
		dv = -2.0 * c / (b + sqrt(b * b - 4.0 * c));
	}
	return v1 + dv;
}
