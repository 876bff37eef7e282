// SPDX-License-Identifier: MIT
/*
 * NURBS (sh2000/geometry.h): the structure check and the evaluation of the
 * curve and two derivatives (Piegl and Tiller, "The NURBS Book", A2.1,
 * A2.3 and A4.2), for any degree up to SH2000_NURBS_MAX_DEGREE, with the
 * work space on the stack: no allocation, no state.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sh2000/geometry.h"

#define MSG(code, ...) \
	(msg && len ? (void)snprintf(msg, len, __VA_ARGS__) : (void)0, (code))

#define Q_MAX (SH2000_NURBS_MAX_DEGREE + 1)

static double weight(const struct sh2000_nurbs *n, size_t i)
{
	return n->weights ? n->weights[i] : 1.0;
}

static int check_points(const struct sh2000_nurbs *n, char *msg, size_t len)
{
	size_t i;
	unsigned int a;

	for (i = 0; i < n->npoints; i++) {
		double w = weight(n, i);

		if (!(w > 0) || !isfinite(w))
			return MSG(-EINVAL,
				   "weights[%zu]: %g is not a positive finite weight",
				   i, w);
		for (a = 0; a < SH2000_AXES; a++)
			if (!isfinite(n->points[i][a]))
				return MSG(-ERANGE, "points[%zu][%u]: not finite",
					   i, a);
	}
	return 0;
}

static int check_knots(const struct sh2000_nurbs *n, char *msg, size_t len)
{
	size_t nk = n->npoints + n->degree + 1, mult = 1, i;

	for (i = 0; i < nk; i++) {
		if (!isfinite(n->knots[i]))
			return MSG(-ERANGE, "knots[%zu]: not finite", i);
		if (i == 0)
			continue;
		if (n->knots[i] < n->knots[i - 1])
			return MSG(-EINVAL,
				   "knots[%zu]: %g is less than knots[%zu] = %g (knots must not decrease)",
				   i, n->knots[i], i - 1, n->knots[i - 1]);
		mult = n->knots[i] == n->knots[i - 1] ? mult + 1 : 1;
		/* inside the domain a knot repeated more than degree times
		 * breaks the curve apart */
		if (mult > n->degree && i > n->degree && i < n->npoints)
			return MSG(-EINVAL,
				   "knots[%zu]: value %g repeated %zu times inside the curve's domain; at most degree (%u) times or the curve breaks",
				   i, n->knots[i], mult, n->degree);
	}
	if (!(n->knots[n->degree] < n->knots[n->npoints]))
		return MSG(-EINVAL, "knots: the domain knots[%u]..knots[%zu] is empty",
			   n->degree, n->npoints);
	return 0;
}

int sh2000_nurbs_check(const struct sh2000_nurbs *n, char *msg, size_t len)
{
	int r;

	if (n->degree < 1 || n->degree > SH2000_NURBS_MAX_DEGREE)
		return MSG(-EINVAL, "degree: %u is outside 1..%d", n->degree,
			   SH2000_NURBS_MAX_DEGREE);
	if (n->npoints < (size_t)n->degree + 1)
		return MSG(-EINVAL,
			   "points: %zu control points, a degree %u curve needs at least %u",
			   n->npoints, n->degree, n->degree + 1);
	if (!n->points || !n->knots)
		return MSG(-EINVAL, "points and knots are required");
	r = check_points(n, msg, len);
	return r ? r : check_knots(n, msg, len);
}

double sh2000_nurbs_umin(const struct sh2000_nurbs *n)
{
	return n->knots[n->degree];
}

double sh2000_nurbs_umax(const struct sh2000_nurbs *n)
{
	return n->knots[n->npoints];
}

/* The non-empty knot span [U[span], U[span+1]) holding u; the first or
 * last one at the domain's ends. */
static size_t find_span(const struct sh2000_nurbs *n, double u)
{
	const double *U = n->knots;
	size_t lo = n->degree, hi = n->npoints, mid;

	if (u >= U[hi]) {
		mid = hi - 1;
		while (mid > lo && U[mid] >= U[mid + 1])
			mid--;
		return mid;
	}
	if (u <= U[lo]) {
		mid = lo;
		while (mid + 1 < hi && U[mid] >= U[mid + 1])
			mid++;
		return mid;
	}
	while (hi - lo > 1) {
		mid = (lo + hi) / 2;
		if (u < U[mid])
			hi = mid;
		else
			lo = mid;
	}
	return lo;
}

/* The triangle of basis functions and knot differences (A2.2's ndu). */
static void basis_table(const double *U, unsigned int p, size_t span,
			double u, double ndu[Q_MAX][Q_MAX])
{
	double left[Q_MAX], right[Q_MAX];
	unsigned int j, r;

	ndu[0][0] = 1.0;
	for (j = 1; j <= p; j++) {
		double saved = 0.0;

		left[j] = u - U[span + 1 - j];
		right[j] = U[span + j] - u;
		for (r = 0; r < j; r++) {
			double temp;

			ndu[j][r] = right[r + 1] + left[j - r];
			temp = ndu[r][j - 1] / ndu[j][r];
			ndu[r][j] = saved + right[r + 1] * temp;
			saved = left[j - r] * temp;
		}
		ndu[j][j] = saved;
	}
}

/* ders[k][j]: the k-th derivative (k <= nd) of basis function
 * N[span - p + j] at u (A2.3). */
static void basis_ders(const double *U, unsigned int p, size_t span,
		       double u, unsigned int nd, double ders[3][Q_MAX])
{
	double ndu[Q_MAX][Q_MAX], a[2][Q_MAX];
	unsigned int j, r, k, s1, s2;

	basis_table(U, p, span, u, ndu);
	for (j = 0; j <= p; j++)
		ders[0][j] = ndu[j][p];
	for (r = 0; r <= p; r++) {
		s1 = 0;
		s2 = 1;
		a[0][0] = 1.0;
		for (k = 1; k <= nd; k++) {
			int rk = (int)r - (int)k, pk = (int)p - (int)k;
			int j1 = rk >= -1 ? 1 : -rk;
			int j2 = ((int)r - 1 <= pk) ? (int)k - 1 : (int)p - (int)r;
			double d = 0.0;
			int jj;

			if (rk >= 0) {
				a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
				d = a[s2][0] * ndu[rk][pk];
			}
			for (jj = j1; jj <= j2; jj++) {
				a[s2][jj] = (a[s1][jj] - a[s1][jj - 1]) /
					    ndu[pk + 1][rk + jj];
				d += a[s2][jj] * ndu[rk + jj][pk];
			}
			if ((int)r <= pk) {
				a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
				d += a[s2][k] * ndu[r][pk];
			}
			ders[k][r] = d;
			j = s1;
			s1 = s2;
			s2 = j;
		}
	}
	r = p;
	for (k = 1; k <= nd; k++) {
		for (j = 0; j <= p; j++)
			ders[k][j] *= r;
		r *= p - k;
	}
}

void sh2000_nurbs_eval(const struct sh2000_nurbs *n, double u,
		       double c[SH2000_AXES], double d1[SH2000_AXES],
		       double d2[SH2000_AXES])
{
	unsigned int p = n->degree, nd = d2 ? 2 : d1 ? 1 : 0, j, k, ax;
	double ders[3][Q_MAX], A[3][SH2000_AXES + 1];
	size_t span;

	u = fmin(fmax(u, sh2000_nurbs_umin(n)), sh2000_nurbs_umax(n));
	span = find_span(n, u);
	basis_ders(n->knots, p, span, u, nd < p ? nd : p, ders);
	for (k = p < nd ? p + 1 : nd + 1; k <= nd; k++)
		for (j = 0; j <= p; j++)
			ders[k][j] = 0.0;	/* above the degree */
	memset(A, 0, sizeof(A));
	for (j = 0; j <= p; j++) {
		size_t i = span - p + j;
		double w = weight(n, i);

		for (k = 0; k <= nd; k++) {
			double f = ders[k][j] * w;

			for (ax = 0; ax < SH2000_AXES; ax++)
				A[k][ax] += f * n->points[i][ax];
			A[k][SH2000_AXES] += f;
		}
	}
	/* the quotient rule for C = A / w (A4.2) */
	for (ax = 0; ax < SH2000_AXES; ax++) {
		double w = A[0][SH2000_AXES], x = A[0][ax] / w, x1 = 0.0;

		c[ax] = x;
		if (nd >= 1) {
			x1 = (A[1][ax] - A[1][SH2000_AXES] * x) / w;
			if (d1)
				d1[ax] = x1;
		}
		if (d2)
			d2[ax] = (A[2][ax] - 2.0 * A[1][SH2000_AXES] * x1 -
				  A[2][SH2000_AXES] * x) / w;
	}
}
