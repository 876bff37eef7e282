/* SPDX-License-Identifier: MIT */
/*
 * Frequency responses from a gathered record (the card's controller
 * computed from its law is loopmodel.c's), and the gains the card has.
 *
 * Estimator: the chirp test's record runs from rest to rest (the axis
 * still before the sweep and settled after it), so each signal, less its
 * value at rest, is a finite sequence whose DTFT is exact: for a linear
 * system Y(f) = H(f) X(f) at every f with no window and no leakage (a
 * window would multiply the input and break that identity; segment
 * averaging would cut the transients). The ratio at one frequency is
 * exact but carries the encoder's quantisation noise divided by whatever
 * excitation is there; so the cross-spectrum Y X* and the auto-spectrum
 * |X|^2 are summed over a few neighbouring DTFT bins (within 5 % of f)
 * before dividing (the H1 estimate), and every response is taken against
 * the set-point, which the loop's noise does not reach: the plant is then
 * (enc vs sp) / (DAC vs sp) = sum E S* / sum D S*, the instrumental-variable
 * estimate that stays unbiased in closed loop, where DAC vs encoder
 * directly would give -1/C wherever quantisation noise drives the DAC.
 */
#include <math.h>

#include "tune.h"

/* neighbouring bins summed on each side, at most */
#define SIDE_BINS 2

void tune_fr_grid(double f0, double f1, size_t n, double *hz)
{
	for (size_t i = 0; i < n; i++)
		hz[i] = n > 1 ? f0 * pow(f1 / f0, (double)i / (double)(n - 1)) : f0;
}

/* The DTFT of x at f: sum x[k] e^(-j 2 pi f k ts), the phasor turned by
 * multiplication (renormalised now and then so its length stays 1). */
static double complex dtft(const double *x, size_t n, double ts, double f)
{
	double complex w = cexp(-I * 2 * M_PI * f * ts), z = 1, s = 0;

	for (size_t k = 0; k < n; k++) {
		s += x[k] * z;
		z *= w;
		if ((k & 1023) == 1023)
			z /= cabs(z);
	}
	return s;
}

void tune_fr_ratio(const double *x, const double *y, size_t n, double ts,
		   const double *hz, size_t nf, double complex *out)
{
	double df = 1.0 / ((double)n * ts);

	for (size_t i = 0; i < nf; i++) {
		int side = (int)floor(0.05 * hz[i] / df);
		double complex xy = 0;
		double xx = 0;

		if (side > SIDE_BINS)
			side = SIDE_BINS;
		for (int b = -side; b <= side; b++) {
			double f = hz[i] + b * df;
			double complex X = dtft(x, n, ts, f), Y = dtft(y, n, ts, f);

			xy += Y * conj(X);
			xx += creal(X * conj(X));
		}
		out[i] = xx > 0 ? xy / xx : NAN;
	}
}

int tune_read_gains(struct sh2000 *h, unsigned int a, struct tune_gains *g)
{
	int r;

	if ((r = sh2000_param_get(h, a, SH2000_P_KP, &g->kp)) < 0 ||
	    (r = sh2000_param_get(h, a, SH2000_P_TI, &g->ti)) < 0 ||
	    (r = sh2000_param_get(h, a, SH2000_P_TD, &g->td)) < 0 ||
	    (r = sh2000_param_get(h, a, SH2000_P_KVFF, &g->kvff)) < 0 ||
	    (r = sh2000_param_get(h, a, SH2000_P_KAFF, &g->kaff)) < 0)
		return r;
	return 0;
}
