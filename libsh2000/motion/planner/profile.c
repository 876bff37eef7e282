// SPDX-License-Identifier: MIT
/*
 * Velocity-profile arithmetic along the path (seed 003's trapezoid and
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

void pl_integrate(double *s, double *v, double *a, double j, double dt)
{
	*s += dt * (*v + dt * (*a / 2.0 + dt * j / 6.0));
	*v += dt * (*a + dt * j / 2.0);
	*a += dt * j;
}

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
		ap = sqrt(fmax(0.0, (2.0 * J * (v1 - v) + a * a) / 2.0));
		th = 0.0;
		if (ap > A) {
			ap = A;
			th = (v1 - v - (2.0 * A * A - a * a) / (2.0 * J)) / A;
		}
		if (ap < a)
			ap = a;
		tr->dur[0] = (ap - a) / J;
		tr->jerk[0] = J;
		tr->dur[1] = fmax(th, 0.0);
		tr->jerk[1] = 0.0;
		tr->dur[2] = ap / J;
		tr->jerk[2] = -J;
	} else {
		ap = -sqrt(fmax(0.0, (2.0 * J * (v - v1) + a * a) / 2.0));
		th = 0.0;
		if (ap < -A) {
			ap = -A;
			th = (v - v1 - (2.0 * A * A - a * a) / (2.0 * J)) / A;
		}
		if (ap > a)
			ap = a;
		tr->dur[0] = (a - ap) / J;
		tr->jerk[0] = -J;
		tr->dur[1] = fmax(th, 0.0);
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

/* Length of a transition between two speeds at rest acceleration. */
static double trans_len(const struct pl_limits *lim, double v0, double v1)
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

double pl_reach_back(const struct pl_limits *lim, double v1, double L)
{
	double lo = v1, hi = sqrt(v1 * v1 + 2.0 * lim->A * L);
	int i;

	if (L <= 0.0)
		return v1;
	if (isinf(lim->J))
		return hi;
	for (i = 0; i < 48 && hi - lo > 1e-12 * hi; i++) {
		double m = 0.5 * (lo + hi);

		if (trans_len(lim, m, v1) <= L)
			lo = m;
		else
			hi = m;
	}
	return lo;
}
