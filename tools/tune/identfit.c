/* SPDX-License-Identifier: MIT */
/*
 * The least squares behind sh2000-tune --auto's plant identification,
 * pure. The record is the closed loop's: the DAC output is computed from
 * encoder readings whose quantisation (one count) it carries, amplified by
 * the PID, so an equation-error fit (regressing the encoder's change on
 * the past ones and the DAC) is biased. An output-error fit is not: the
 * plant's position is exactly the model's response to the DAC as the card
 * put it out, and the encoder adds only its own quantisation. For a
 * friction pole p and dead time d the response is linear in the plant
 * gain g, the start position and the start velocity, so those come from a
 * 3x3 normal system; p is found by a scan and a golden-section search of
 * the residual, d by trying 0..dmax. The model, sampled exactly with the
 * DAC held over each servo cycle T (loopmodel.c's tune_plant_sample()):
 *   v(k+1) = a v(k) + c g u(k-d),  x(k+1) = x(k) + c v(k) + e g u(k-d).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "autotune.h"

#define P_MIN	0.01	/* 1/s: the scan's range (0 tried apart) */
#define P_MAX	5000.0
#define P_SCAN	48

struct fit {
	const double *enc, *dac;
	size_t n;
	double T;
	double *s_u, *s_v;	/* responses to u (g = 1) and to v0 = 1 */
};

/* Solve the 3x3 system M x = r (Cramer: it is small and well scaled by
 * the caller). 0, or -1 when singular. */
static int solve3(double M[3][3], const double r[3], double x[3])
{
	double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
		     M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
		     M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);

	if (!(fabs(det) > 0) || !isfinite(det))
		return -1;
	for (int c = 0; c < 3; c++) {
		double A[3][3];

		memcpy(A, M, sizeof(A));
		for (int i = 0; i < 3; i++)
			A[i][c] = r[i];
		x[c] = (A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
			A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
			A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0])) / det;
	}
	return 0;
}

/* The squared residual of the best (g, x0, v0) for p and d; *g gets g. */
static double sse_at(struct fit *f, double p, unsigned int d, double *g)
{
	double a, c, e, v = 0, x = 0, vv = 1, xv = 0, M[3][3] = { { 0 } };
	double r[3] = { 0 }, th[3], sse = 0;

	tune_plant_sample(p, f->T, &a, &c, &e);
	for (size_t k = 0; k < f->n; k++) {
		double u = k >= d + 1 ? f->dac[k - d - 1] : 0, nx, nxv;

		if (k > 0) {	/* the step from k-1 to k */
			nx = x + c * v + e * u;
			v = a * v + c * u;
			x = nx;
			nxv = xv + c * vv;
			vv = a * vv;
			xv = nxv;
		}
		f->s_u[k] = x;
		f->s_v[k] = xv;
	}
	for (size_t k = 0; k < f->n; k++) {
		double row[3] = { f->s_u[k], 1, f->s_v[k] }, y = f->enc[k];

		for (int i = 0; i < 3; i++) {
			for (int j = 0; j < 3; j++)
				M[i][j] += row[i] * row[j];
			r[i] += row[i] * y;
		}
	}
	if (solve3(M, r, th) < 0)
		return INFINITY;
	for (size_t k = 0; k < f->n; k++) {
		double res = f->enc[k] - th[0] * f->s_u[k] - th[1] - th[2] * f->s_v[k];

		sse += res * res;
	}
	*g = th[0];
	return sse;
}

/* The p of the smallest residual for d: a log scan, then golden section
 * between the scan's neighbours of its best. */
static double best_p(struct fit *f, unsigned int d, double *p_out, double *g)
{
	double lp[P_SCAN], best = sse_at(f, 0, d, g), bp = 0, gg;
	int bi = -1;

	for (int i = 0; i < P_SCAN; i++) {
		double s;

		lp[i] = log(P_MIN) + (log(P_MAX) - log(P_MIN)) * i / (P_SCAN - 1);
		s = sse_at(f, exp(lp[i]), d, &gg);
		if (s < best) {
			best = s;
			bi = i;
		}
	}
	if (bi >= 0) {
		double lo = lp[bi > 0 ? bi - 1 : 0], hi = lp[bi < P_SCAN - 1 ? bi + 1 : bi];
		double q = (sqrt(5) - 1) / 2, x1 = hi - q * (hi - lo), x2 = lo + q * (hi - lo);
		double s1 = sse_at(f, exp(x1), d, &gg), s2 = sse_at(f, exp(x2), d, &gg);

		for (int it = 0; it < 60; it++) {
			if (s1 < s2) {
				hi = x2; x2 = x1; s2 = s1;
				x1 = hi - q * (hi - lo);
				s1 = sse_at(f, exp(x1), d, &gg);
			} else {
				lo = x1; x1 = x2; s1 = s2;
				x2 = lo + q * (hi - lo);
				s2 = sse_at(f, exp(x2), d, &gg);
			}
		}
		bp = exp((lo + hi) / 2);
	}
	*p_out = bp;
	return sse_at(f, bp, d, g);
}

int tune_ident_fit(const double *enc, const double *dac, size_t n, double T,
		   unsigned int dmax, struct tune_plant *pl, char *why,
		   size_t whylen)
{
	struct fit f = { enc, dac, n, T, NULL, NULL };
	double best = INFINITY, mean = 0, var = 0;

	memset(pl, 0, sizeof(*pl));
	if (n < 50 + (size_t)dmax) {
		snprintf(why, whylen, "%zu samples are too few to fit the plant (at least %u)",
			 n, 50 + dmax);
		return -1;
	}
	f.s_u = malloc(sizeof(double) * 2 * n);
	if (!f.s_u) {
		snprintf(why, whylen, "out of memory");
		return -1;
	}
	f.s_v = f.s_u + n;
	for (unsigned int d = 0; d <= dmax; d++) {
		double p, g, s = best_p(&f, d, &p, &g);

		if (s < best) {
			best = s;
			pl->p = p;
			pl->g = g;
			pl->d = d;
		}
	}
	free(f.s_u);
	for (size_t k = 0; k < n; k++)
		mean += enc[k] / (double)n;
	for (size_t k = 0; k < n; k++)
		var += (enc[k] - mean) * (enc[k] - mean) / (double)n;
	pl->T = T;
	pl->samples = n;
	pl->resid = sqrt(best / (double)n);
	pl->resid_rel = var > 0 ? pl->resid / sqrt(var) : INFINITY;
	if (!isfinite(best) || !(var > 0)) {
		snprintf(why, whylen, "the record does not excite the plant (the DAC or the encoder did not move)");
		return -1;
	}
	if (!(pl->g > 0)) {
		snprintf(why, whylen, "the fit gives a plant gain of %g counts/s^2 per code: the DAC does not push the axis the way its encoder counts (sign or wiring?)",
			 pl->g);
		return -1;
	}
	return 0;
}
