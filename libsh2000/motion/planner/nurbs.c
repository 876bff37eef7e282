// SPDX-License-Identifier: MIT
/*
 * NURBS evaluation (points and two derivatives, any degree, Piegl and
 * Tiller's basis-function derivatives), arc length by Gauss-Legendre, and
 * the expansion of a curve into planner blocks: each knot span is cut into
 * PL_NURBS_SUBDIV blocks whose speed limit comes from the curvature there,
 * so the look-ahead sees the curve's slow parts before it reaches them.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

static unsigned int find_span(const struct pl_nurbs *nb, double u)
{
	unsigned int lo = nb->p, hi = nb->n, mid;

	if (u >= nb->U[nb->n]) {
		/* the last non-empty span */
		mid = nb->n - 1;
		while (mid > nb->p && nb->U[mid] >= nb->U[mid + 1])
			mid--;
		return mid;
	}
	if (u <= nb->U[nb->p]) {
		mid = nb->p;
		while (mid + 1 < nb->n && nb->U[mid] >= nb->U[mid + 1])
			mid++;
		return mid;
	}
	/* U[lo] <= u < U[hi] */
	while (hi - lo > 1) {
		mid = (lo + hi) / 2;
		if (u < nb->U[mid])
			hi = mid;
		else
			lo = mid;
	}
	return lo;
}

/* ders[k][j], k = 0..2: k-th derivative of the p+1 non-zero basis
 * functions N[span-p+j] at u. */
static void ders_basis(const struct pl_nurbs *nb, unsigned int span, double u,
		       double *ders)
{
	unsigned int p = nb->p, q = p + 1, w = (p > 2 ? p : 2) + 1;
	double *ndu = nb->scratch;		/* q * q */
	double *left = ndu + q * q;		/* q */
	double *right = left + q;		/* q */
	double *a = right + q;			/* 2 * w */
	unsigned int j, r, k, nd = p < 2 ? p : 2;
	const double *U = nb->U;

	ndu[0] = 1.0;
	for (j = 1; j <= p; j++) {
		double saved = 0.0;

		left[j] = u - U[span + 1 - j];
		right[j] = U[span + j] - u;
		for (r = 0; r < j; r++) {
			double temp;

			ndu[j * q + r] = right[r + 1] + left[j - r];
			temp = ndu[r * q + j - 1] / ndu[j * q + r];
			ndu[r * q + j] = saved + right[r + 1] * temp;
			saved = left[j - r] * temp;
		}
		ndu[j * q + j] = saved;
	}
	for (j = 0; j <= p; j++) {
		ders[j] = ndu[j * q + p];
		ders[q + j] = 0.0;
		ders[2 * q + j] = 0.0;
	}
	for (r = 0; r <= p; r++) {
		unsigned int s1 = 0, s2 = 1;

		a[0] = 1.0;
		for (k = 1; k <= nd; k++) {
			double d = 0.0;
			int rk = (int)r - (int)k, pk = (int)p - (int)k;
			int j1, j2, jj;

			if (rk >= 0) {
				a[s2 * w] = a[s1 * w] / ndu[(pk + 1) * q + rk];
				d = a[s2 * w] * ndu[rk * q + pk];
			}
			j1 = rk >= -1 ? 1 : -rk;
			j2 = ((int)r - 1 <= pk) ? (int)k - 1 : (int)p - (int)r;
			for (jj = j1; jj <= j2; jj++) {
				a[s2 * w + jj] = (a[s1 * w + jj] -
						  a[s1 * w + jj - 1]) /
						 ndu[(pk + 1) * q + rk + jj];
				d += a[s2 * w + jj] * ndu[(rk + jj) * q + pk];
			}
			if ((int)r <= pk) {
				a[s2 * w + k] = -a[s1 * w + k - 1] /
						ndu[(pk + 1) * q + r];
				d += a[s2 * w + k] * ndu[r * q + pk];
			}
			ders[k * q + r] = d;
			j = s1;
			s1 = s2;
			s2 = j;
		}
	}
	r = p;
	for (k = 1; k <= nd; k++) {
		for (j = 0; j <= p; j++)
			ders[k * q + j] *= r;
		r *= p - k;
	}
}

void pl_nurbs_eval(struct pl_nurbs *nb, double u, double c[SH2000_AXES],
		   double d1[SH2000_AXES], double d2[SH2000_AXES])
{
	unsigned int q = nb->p + 1, span, j, k, ax;
	double *ders = nb->scratch + q * q + 2 * q + 2 * ((nb->p > 2 ? nb->p : 2) + 1);
	double A[3][SH2000_AXES + 1];

	if (u < nb->umin)
		u = nb->umin;
	if (u > nb->umax)
		u = nb->umax;
	span = find_span(nb, u);
	ders_basis(nb, span, u, ders);
	memset(A, 0, sizeof(A));
	for (j = 0; j <= nb->p; j++) {
		const double *pw = nb->Pw + 5 * (span - nb->p + j);

		for (k = 0; k < 3; k++)
			for (ax = 0; ax <= SH2000_AXES; ax++)
				A[k][ax] += ders[k * q + j] * pw[ax];
	}
	for (ax = 0; ax < SH2000_AXES; ax++) {
		double w = A[0][SH2000_AXES], w1 = A[1][SH2000_AXES], w2 = A[2][SH2000_AXES];
		double x = A[0][ax] / w;
		double x1 = (A[1][ax] - w1 * x) / w;

		c[ax] = x;
		if (d1)
			d1[ax] = x1;
		if (d2)
			d2[ax] = (A[2][ax] - 2.0 * w1 * x1 - w2 * x) / w;
	}
}

static double speed_at(struct pl_nurbs *nb, double u)
{
	double c[SH2000_AXES], d[SH2000_AXES], s = 0.0;
	unsigned int ax;

	pl_nurbs_eval(nb, u, c, d, NULL);
	for (ax = 0; ax < SH2000_AXES; ax++)
		s += d[ax] * d[ax];
	return sqrt(s);
}

double pl_nurbs_length(struct pl_nurbs *nb, double u0, double u1)
{
	/* 8-point Gauss-Legendre; the blocks are short, smooth pieces. */
	static const double x[4] = { 0.1834346424956498, 0.5255324099163290,
				     0.7966664774136267, 0.9602898564975363 };
	static const double w[4] = { 0.3626837833783620, 0.3137066458778873,
				     0.2223810344533745, 0.1012285362903763 };
	double m = 0.5 * (u0 + u1), h = 0.5 * (u1 - u0), s = 0.0;
	unsigned int i;

	if (h <= 0.0)
		return 0.0;
	for (i = 0; i < 4; i++)
		s += w[i] * (speed_at(nb, m - h * x[i]) +
			     speed_at(nb, m + h * x[i]));
	return s * h;
}

double pl_nurbs_frame(struct pl_nurbs *nb, double u, double t[SH2000_AXES],
		      double *kappa)
{
	double c[SH2000_AXES], d1[SH2000_AXES], d2[SH2000_AXES], n1 = 0.0, n2 = 0.0, dot = 0.0, cr;
	unsigned int ax;

	pl_nurbs_eval(nb, u, c, d1, d2);
	for (ax = 0; ax < SH2000_AXES; ax++) {
		n1 += d1[ax] * d1[ax];
		n2 += d2[ax] * d2[ax];
		dot += d1[ax] * d2[ax];
	}
	n1 = sqrt(n1);
	for (ax = 0; ax < SH2000_AXES; ax++)
		t[ax] = n1 > 0.0 ? d1[ax] / n1 : 0.0;
	/* |C' x C''| / |C'|^3, written for any dimension */
	cr = n1 * n1 * n2 - dot * dot;
	*kappa = (n1 > 0.0 && cr > 0.0) ? sqrt(cr) / (n1 * n1 * n1) : 0.0;
	return n1;
}

void pl_nurbs_put(struct sh2000_path *p, struct pl_nurbs *nb)
{
	if (--nb->refs > 0 || !nb->expanded)
		return;
	pl_free(p, nb->U, (nb->n + nb->p + 1) * sizeof(double));
	pl_free(p, nb->Pw, nb->n * 5 * sizeof(double));
	pl_free(p, nb->scratch, nb->bytes);
	pl_free(p, nb, sizeof(*nb));
}

int pl_nurbs_expand(struct sh2000_path *p)
{
	struct pl_nurbs *nb = p->pending;

	while (nb && p->count < p->cap) {
		struct pl_block b;
		double u0, u1, du, ks, vl = INFINITY, tt[SH2000_AXES];
		unsigned int i, ax;

		if (nb->span >= nb->n) {
			nb->expanded = 1;
			p->pending = NULL;
			if (nb->refs == 0) {
				nb->refs = 1;
				pl_nurbs_put(p, nb);
			}
			return 1;
		}
		if (nb->U[nb->span] >= nb->U[nb->span + 1]) {
			nb->span++;
			continue;
		}
		du = (nb->U[nb->span + 1] - nb->U[nb->span]) / PL_NURBS_SUBDIV;
		u0 = nb->U[nb->span] + du * nb->sub;
		u1 = nb->sub + 1 == PL_NURBS_SUBDIV ? nb->U[nb->span + 1]
						    : u0 + du;
		if (++nb->sub == PL_NURBS_SUBDIV) {
			nb->sub = 0;
			nb->span++;
		}
		memset(&b, 0, sizeof(b));
		b.type = BLK_NURBS;
		b.feed = p->pending_feed;
		b.g.nurbs.nb = nb;
		b.g.nurbs.u0 = u0;
		b.g.nurbs.u1 = u1;
		b.L = pl_nurbs_length(nb, u0, u1);
		/* the speed limit over the block: five samples */
		for (i = 0; i <= 4; i++) {
			/* the end from the left: at a C0 knot the next
			 * span's tangent is another one (a corner) */
			double u = i < 4 ? u0 + (u1 - u0) * i / 4.0
					 : u1 - (u1 - u0) * 1e-9;

			pl_nurbs_frame(nb, u, tt, &ks);
			vl = fmin(vl, pl_curve_vlim(p, tt, ks));
			if (i == 0)
				memcpy(b.t0, tt, sizeof(tt));
			if (i == 4)
				memcpy(b.t1, tt, sizeof(tt));
		}
		b.vlim = vl;
		pl_nurbs_eval(nb, u0, b.p0, NULL, NULL);
		pl_nurbs_eval(nb, u1, b.p1, NULL, NULL);
		for (ax = 0; ax < SH2000_AXES; ax++)
			if (!isfinite(b.p1[ax]))
				b.p1[ax] = b.p0[ax];
		nb->refs++;
		pl_push_block(p, &b);
	}
	if (nb && nb->span >= nb->n) {
		nb->expanded = 1;
		p->pending = NULL;
		nb->refs++;
		pl_nurbs_put(p, nb);
		return 1;
	}
	return nb ? 0 : 1;
}
