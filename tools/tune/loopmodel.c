/* SPDX-License-Identifier: MIT */
/*
 * The tuner's models of the card's loop, each written once: the plant
 * sampled over a servo cycle with the DAC held, and the card's PID as a
 * transfer function C(z). The identification (identfit.c), the design
 * (design.c) and the measured responses (chirp.c) all compute with these.
 *
 * Plant (docs/cardmodel.md "Plant"): m a = kF u - b v, g = kF/m, p = b/m,
 * sampled exactly with u held over T:
 *   v(k+1) = a v(k) + c g u(k),  x(k+1) = x(k) + c v(k) + e g u(k),
 *   a = exp(-p T), c = (1 - a)/p, e = (T - c)/p;
 * with d cycles of dead time, from u to x,
 *   P(z) = z^-d (b0 z + b1) / ((z - 1)(z - a)),  b0 = g e, b1 = g c^2 - a b0.
 *
 * PID (the card's pid.c, docs/cardmodel.md "Controller"): the incremental
 *   u(k) = u(k-1) + Kp{e(k)-e(k-1) + (tau/Ti) e(k) + (Td/tau)[e(k)-2e(k-1)+e(k-2)]}
 * summed is, with d = 1 - z^-1 (no integral term when Ti = 0),
 *   C(z) = Kp [1 + (tau/Ti)/d + (Td/tau) d]
 *        = Kp (n0 + n1 z^-1 + n2 z^-2) / (1 - z^-1),
 *   n0 = 1 + tau/Ti + Td/tau, n1 = -(1 + 2 Td/tau), n2 = Td/tau.
 * The DAC's clamp and rounding are outside the linear response.
 */
#include <math.h>

#include "autotune.h"

void tune_plant_sample(double p, double T, double *a, double *c, double *e)
{
	double pt = p * T;

	*a = exp(-pt);
	*c = pt > 0 ? -expm1(-pt) / p : T;
	/* (T - c) / p by its series for small p T: no cancellation */
	*e = pt < 1e-4 ? T * T / 2 - p * T * T * T / 6 + p * p * T * T * T * T / 24 :
			 (T - *c) / p;
}

void tune_plant_z(const struct tune_plant *pl, double *a, double *b0,
		  double *b1)
{
	double c, e;

	tune_plant_sample(pl->p, pl->T, a, &c, &e);
	*b0 = pl->g * e;
	*b1 = pl->g * c * c - *a * *b0;
}

double complex tune_plant_at(const struct tune_plant *pl, double th)
{
	double a, b0, b1;
	double complex z = cexp(I * th);

	tune_plant_z(pl, &a, &b0, &b1);
	return cpow(z, -(double)pl->d) * (b0 * z + b1) / ((z - 1) * (z - a));
}

void tune_pid_parts(double tau, double ti, double th, double complex *A,
		    double complex *D)
{
	double complex d = 1 - cexp(-I * th);

	*A = 1 + (ti > 0 ? (tau / ti) / d : 0);
	*D = d;
}

void tune_pid_numerator(const struct tune_gains *g, double tau, double n[3])
{
	double k = g->td / tau;

	n[0] = 1 + (g->ti > 0 ? tau / g->ti : 0) + k;
	n[1] = -(1 + 2 * k);
	n[2] = k;
}

double complex tune_pid_response(const struct tune_gains *g, double tau,
				 double hz)
{
	double complex A, D;

	tune_pid_parts(tau, g->ti, 2 * M_PI * hz * tau, &A, &D);
	return g->kp * (A + (g->td / tau) * D);
}
