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
