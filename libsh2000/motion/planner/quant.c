// SPDX-License-Identifier: MIT
/*
 * Transitions in whole periods of constant jerk, for the compensated
 * output's controller (control.c).
 *
 * The card's compensated spline is the C^2 cubic spline through the
 * planned points. Where the path position s(t) is itself a C^2 piecewise
 * cubic whose knots are the sample instants (one constant jerk per
 * period), the spline through its samples is s(t) again: on a line the
 * card's acceleration is then exactly the planned one, with no ringing.
 * A jerk that switches inside a period (the exact time-optimal
 * transitions of profile.c) makes the spline ring by up to 0.1 J T.
 *
 * So the controller ends its transitions with a few periods whose jerks
 * are solved to land exactly on the target: two periods to a speed with
 * zero acceleration, three to a speed with zero acceleration at a given
 * distance. The state after n periods is linear in the n jerks.
 */
#include <math.h>

#include "planner.h"

/* The state (s, v, a) after periods of jerks j[0..n-1] from (0, v, a). */
static void run_periods(double h, double v, double a, const double *j,
			unsigned int n, double out[3])
{
	double s = 0.0;
	unsigned int k;

	for (k = 0; k < n; k++)
		pl_integrate(&s, &v, &a, j[k], h);
	out[0] = s;
	out[1] = v;
	out[2] = a;
}

/* Solve the k x k system g y = b in place (partial pivoting); -1 if
 * singular. */
static int solve_small(double g[3][3], double b[3], unsigned int k)
{
	unsigned int r, c, i;

	for (c = 0; c < k; c++) {
		unsigned int piv = c;

		for (r = c + 1; r < k; r++)
			if (fabs(g[r][c]) > fabs(g[piv][c]))
				piv = r;
		if (g[piv][c] == 0.0)
			return -1;
		for (i = 0; i < k; i++) {
			double t = g[c][i];

			g[c][i] = g[piv][i];
			g[piv][i] = t;
		}
		{
			double t = b[c];

			b[c] = b[piv];
			b[piv] = t;
		}
		for (r = 0; r < k; r++) {
			double f = g[r][c] / g[c][c];

			if (r == c)
				continue;
			for (i = c; i < k; i++)
				g[r][i] -= f * g[c][i];
			b[r] -= f * b[c];
		}
	}
	for (c = 0; c < k; c++)
		b[c] /= g[c][c];
	return 0;
}

int pl_quant_solve(double h, double v, double a, unsigned int n, int dist,
		   double d, double vt, double *j)
{
	double m[3][PL_QUANT_MAX], g[3][3], y[3], base[3], col[3];
	double e[PL_QUANT_MAX] = { 0.0 }, want[3] = { d, vt, 0.0 };
	unsigned int k = dist ? 3 : 2, r0 = 3 - k, r, c, i;

	if (n < k || n > PL_QUANT_MAX)
		return -1;
	run_periods(h, v, a, e, n, base);
	for (c = 0; c < n; c++) {
		e[c] = 1.0;
		run_periods(h, 0.0, 0.0, e, n, col);
		e[c] = 0.0;
		for (r = 0; r < k; r++)
			m[r][c] = col[r + r0];
	}
	/* the least-squares jerks that land: j = M^T (M M^T)^-1 (want - base) */
	for (r = 0; r < k; r++) {
		y[r] = want[r + r0] - base[r + r0];
		for (i = 0; i < k; i++) {
			g[r][i] = 0.0;
			for (c = 0; c < n; c++)
				g[r][i] += m[r][c] * m[i][c];
		}
	}
	if (solve_small(g, y, k))
		return -1;
	for (c = 0; c < n; c++) {
		j[c] = 0.0;
		for (r = 0; r < k; r++)
			j[c] += m[r][c] * y[r];
	}
	return 0;
}

/*
 * The landing on a lower speed vt at distance d in the fewest whole
 * periods, however many (the least-squares jerks above take up to
 * PL_QUANT_MAX and give a smooth profile, not the fastest). With one jerk
 * a period the acceleration is piecewise linear between its values a_k at
 * the period ends, a_0 now and a_n = 0 at the landing, and the state
 * there is linear in them:
 *
 *   v_n = v0 + h (a_0 / 2 + sum a_k)
 *   s_n = v0 n h + h^2 (a_0 (n / 2 - 1/6) + sum (n - k) a_k),  k = 1..n-1.
 *
 * Braking, b_k = -a_k in [0, A] (the first within the jerk from a_0):
 * two sums are given, sum b_k = B and sum (n - k) b_k = W. For a given B,
 * W is the largest with the braking as early as the caps allow and the
 * least with it as late; every W between is a mix of the two, and a mix
 * keeps every cap and every jerk (|a_k - a_k-1| <= A <= J h: the caller
 * holds one jerk a period only where J h >= A). The fewest n is the
 * first whose latest braking covers d. Where the allowed acceleration
 * drops at d (a line into a blend that allows less), the last knots'
 * cap is the lower one, which holds the braking within it over the
 * periods before the drop (control.c, drop_room()); the early and the
 * late fill are still the extremes of W, so a mix still lands.
 */

/* The knots b_k (k = 1..n-1, cap A, Aend on the last PL_LAND_END, and
 * c1 on the first) filled up to B, from the first knot (early) or from
 * the last: the weighted sum W and the first knot's b, in w[0] and w[1];
 * -1 if the caps cannot hold B. */
static int fill(unsigned int n, double B, const double cap[2], double c1,
		int early, double tol, double w[2])
{
	double left = B;
	unsigned int i;

	w[0] = w[1] = 0.0;
	for (i = 1; i < n && left > 0.0; i++) {
		unsigned int k = early ? i : n - i;
		double x = cap[k + PL_LAND_END >= n];

		x = pl_min(k == 1 ? pl_min(c1, x) : x, left);
		left -= x;
		w[0] += (double)(n - k) * x;
		if (k == 1)
			w[1] = x;
	}
	return left > tol ? -1 : 0;
}

int pl_quant_land(double h, double v0, double a0, double vt, double d,
		  double A, double Aend, double J, int strict,
		  unsigned int nmax, unsigned int *n_out, double *a1)
{
	const double cap[2] = { A, pl_min(A, Aend) };
	double B = (v0 - vt) / h + a0 / 2.0, c1 = pl_min(A, J * h - a0);
	double rate = v0 / h + a0 / 2.0, late = 0.0, left = B, tol, over;
	unsigned int n, k;

	if (!(d > 0.0) || !(A > 0.0) || B < -1e-9 * (rate + A) || c1 < 0.0 ||
	    J * h < A)
		return -1;
	tol = 1e-9 * (pl_max(rate, 0.0) + d / (h * h) + A);
	/* strict: only where there is room to spare (rounding in the
	 * periods of the landing must not take it past the earliest braking) */
	over = (strict ? -1e-6 : 1e-6) * (pl_max(rate, 0.0) + d / (h * h) + A);
	/* the latest braking far from the first knot weighs W_late (the
	 * knots from the last: 1, 2, ...), and W grows by rate a period:
	 * start just below where it covers d */
	for (k = 1; left > 0.0; k++) {
		double x = pl_min(A, left);

		late += (double)k * x;
		left -= x;
	}
	n = 1;
	if (rate > tol)	/* else the speed is all but lost: from 1 */
		n = (unsigned int)pl_max(1.0, pl_min((double)nmax, floor(
			(late + d / (h * h) + a0 / 6.0) / rate) - 1.0));
	for (; n <= nmax; n++) {
		double W = (v0 * n * h - d) / (h * h) + a0 * (n / 2.0 - 1.0 / 6.0);
		double we[2], wl[2], f;

		if (fill(n, B, cap, c1, 0, tol, wl))
			continue;	/* too few periods to lose the speed */
		if (W < wl[0] - tol * n) {
			/* the latest braking stops short, by h^2 (wl - W):
			 * on a speed above zero, cruising at it the rest
			 * passes d within a period, sooner than the landing
			 * in n + 1 */
			if (vt > 0.0 && h * h * (wl[0] - W) < vt * h) {
				*n_out = n;
				*a1 = n > 1 ? -wl[1] : 0.0;
				return 1;
			}
			continue;
		}
		if (fill(n, B, cap, c1, 1, tol, we) || W > we[0] + over)
			return -2;	/* overshoots: more periods only more */
		f = we[0] > wl[0] ? (W - wl[0]) / (we[0] - wl[0]) : 0.0;
		f = pl_min(1.0, pl_max(0.0, f));
		*n_out = n;
		*a1 = n > 1 ? -((1.0 - f) * wl[1] + f * we[1]) : 0.0;
		return 0;
	}
	return -1;
}
