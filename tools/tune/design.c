/* SPDX-License-Identifier: MIT */
/*
 * Gain design for sh2000-tune --auto, pure functions. The loop is the
 * card's own discrete form, the PID's C(z) and the sampled plant's P(z)
 * with its dead time as loopmodel.c writes them.
 * For a crossover wc and Ti = ratio / wc, C is linear in Kp and
 * Kp Td/tau: two unknowns for the two equations of
 * C(wc) = e^{j(-pi + PM - arg P)} / |P|, the phase margin asked at wc.
 * Of those designs (wc given or searched, ratio searched) the design takes
 * the one with the highest integral gain Kp/Ti whose margins hold:
 * measured on the whole frequency axis (so a second crossover cannot pass
 * unseen), the gain margin at least the floor asked (TUNE_MIN_GM_DB by
 * default), and the closed loop's characteristic polynomial stable. The
 * feed-forward is the plant's exact inverse.
 */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "autotune.h"

#define SCAN_POINTS 6000
#define DEG (180.0 / M_PI)

/* All roots of c[0] z^n + ... + c[n] inside |z| = 1 (Schur-Cohn step-down:
 * every reflection coefficient below 1 in magnitude). */
static int schur_stable(const double *c, int n)
{
	double x[16], y[16];

	if (n > 15)
		return 0;
	memcpy(x, c, sizeof(double) * (size_t)(n + 1));
	for (int m = n; m > 0; m--) {
		double k = x[m] / x[0];

		if (!isfinite(k) || fabs(k) >= 1)
			return 0;
		for (int i = 0; i < m; i++)
			y[i] = (x[i] - k * x[m - i]) / (1 - k * k);
		memcpy(x, y, sizeof(double) * (size_t)m);
	}
	return 1;
}

/* The closed loop's characteristic polynomial
 *   z^(d+1) (z-1)^2 (z-a) + Kp (n0 z^2 + n1 z + n2)(b0 z + b1). */
static int closed_loop_stable(const struct tune_plant *pl,
			      const struct tune_gains *gn)
{
	double a, b0, b1, c[16] = { 0 }, n[3], q[4] = { 1, -(2 + 0), 0, 0 };
	int deg = (int)pl->d + 4;

	if (pl->d > 11)
		return 0;
	tune_plant_z(pl, &a, &b0, &b1);
	tune_pid_numerator(gn, pl->T, n);
	/* (z-1)^2 (z-a) = z^3 - (2+a) z^2 + (1+2a) z - a */
	q[1] = -(2 + a);
	q[2] = 1 + 2 * a;
	q[3] = -a;
	for (int i = 0; i < 4; i++)
		c[i] = q[i];		/* times z^(d+1): the low terms are 0 */
	/* (n0 z^2 + n1 z + n2)(b0 z + b1), degree 3, at the lowest powers */
	c[deg - 3] += gn->kp * n[0] * b0;
	c[deg - 2] += gn->kp * (n[0] * b1 + n[1] * b0);
	c[deg - 1] += gn->kp * (n[1] * b1 + n[2] * b0);
	c[deg] += gn->kp * n[2] * b1;
	return schur_stable(c, deg);
}

void tune_margins_of(const struct tune_plant *pl, const struct tune_gains *gn,
		     struct tune_design_margins *m)
{
	double lo = log(1e-5), hi = log(M_PI * 0.99999);
	double prev_mag = 0, acc = 0, prev_acc = 0;

	m->pm_deg = INFINITY;
	m->gm_db = INFINITY;
	m->wc_hz = 0;
	m->wpc_hz = 0;
	for (int i = 0; i <= SCAN_POINTS; i++) {
		double th = exp(lo + (hi - lo) * i / SCAN_POINTS);
		double complex L = tune_pid_response(gn, pl->T, th / (2 * M_PI * pl->T)) * tune_plant_at(pl, th);
		double mag = cabs(L), ph = carg(L) * DEG, hz = th / (2 * M_PI * pl->T);

		/* unwrapped in degrees; the first point is below -180 degrees
		 * (two integrators and the friction pole's lag) */
		acc = i == 0 ? (ph > 0 ? ph - 360 : ph) : tune_phase_unwrap(acc, ph);
		if (i > 0 && (prev_mag - 1) * (mag - 1) <= 0 && prev_mag != mag &&
		    (tune_phase_margin(acc) < m->pm_deg || m->wc_hz == 0)) {
			m->pm_deg = tune_phase_margin(acc);
			m->wc_hz = hz;
		}
		/* a crossing of -180 - k 360 degrees with |L| < 1 */
		if (i > 0 && mag < 1 &&
		    floor((acc + 180) / 360) != floor((prev_acc + 180) / 360) &&
		    -20 * log10(mag) < m->gm_db) {
			m->gm_db = -20 * log10(mag);
			m->wpc_hz = hz;
		}
		prev_mag = mag;
		prev_acc = acc;
	}
	m->stable = closed_loop_stable(pl, gn);
}

/* Kp, Td and Ti for crossover theta = wc T with phase margin pm_deg and
 * Ti = ratio / wc, and the feed-forward: 0, or -1 when no PID does it
 * (Kp <= 0). */
static int solve_at(const struct tune_plant *pl, double th, double ratio,
		    double pm_deg, struct tune_gains *gn)
{
	double tau = pl->T, wc = th / tau, det, kd;
	double complex P = tune_plant_at(pl, th), A, D, Cs;

	tune_pid_parts(tau, ratio / wc, th, &A, &D);
	Cs = cexp(I * (-M_PI + pm_deg / DEG - carg(P))) / cabs(P);
	/* Kp A + Kd D = Cs: two real equations */
	det = creal(A) * cimag(D) - cimag(A) * creal(D);
	gn->kp = (creal(Cs) * cimag(D) - cimag(Cs) * creal(D)) / det;
	kd = (creal(A) * cimag(Cs) - cimag(A) * creal(Cs)) / det;
	if (kd < 0) {
		/* the plant leads enough on its own: no derivative */
		kd = 0;
		gn->kp = 1 / cabs(P * A);
	}
	gn->ti = ratio / wc;
	gn->td = gn->kp > 0 ? kd * tau / gn->kp : 0;
	gn->kaff = 1 / pl->g;
	gn->kvff = pl->p / pl->g;
	return gn->kp > 0 && isfinite(gn->kp) && isfinite(gn->td) ? 0 : -1;
}

/* Gains the design may give: the asked phase margin over the whole
 * frequency axis, the gain margin floor, a stable closed loop. */
static int admissible(const struct tune_plant *pl, const struct tune_gains *gn,
		      const struct tune_design_req *req,
		      struct tune_design_margins *m)
{
	tune_margins_of(pl, gn, m);
	return m->stable && m->pm_deg >= req->margin_deg - 0.05 &&
	       m->gm_db >= req->gm_db;
}

struct candidate {
	double th, ratio, ki;	/* ki = Kp/Ti: the figure of merit */
	struct tune_gains g;
	struct tune_design_margins m;
};

/* Try (th, ratio): keep it in *best when admissible with a higher ki. */
static void try_at(const struct tune_plant *pl, double th, double ratio,
		   const struct tune_design_req *req, struct candidate *best)
{
	struct candidate c = { .th = th, .ratio = ratio };

	if (th <= 0 || th >= TUNE_TH_MAX || ratio < TUNE_RATIO_MIN ||
	    ratio > TUNE_RATIO_MAX || solve_at(pl, th, ratio, req->margin_deg, &c.g) < 0 ||
	    !admissible(pl, &c.g, req, &c.m))
		return;
	c.ki = c.g.kp / c.g.ti;
	if (c.ki > best->ki)
		*best = c;
}

/*
 * The PID with the highest integral gain Kp/Ti that keeps the margins:
 * with the plant's inverse as feed-forward, what is left of the following
 * error on a path is a disturbance at the path's low frequencies, which
 * the loop divides by |L| ~ (Kp/Ti) g / w^3 there (the integral's share
 * dominates). A grid over the ratio Ti wc (and over the crossover when
 * fixed_th is 0), then a pattern search around the best.
 */
static struct candidate optimise(const struct tune_plant *pl, double fixed_th,
				 const struct tune_design_req *req)
{
	struct candidate best = { .ki = 0 };
	double lo = log(1e-3), hi = log(TUNE_TH_MAX * 0.999);
	double step_th = fixed_th > 0 ? 0 : 0.2, step_r = 0.2;
	int nth = fixed_th > 0 ? 1 : 36;

	for (int i = 0; i < nth; i++)
		for (int k = 0; k < 16; k++)
			try_at(pl, fixed_th > 0 ? fixed_th : exp(lo + (hi - lo) * i / (nth - 1)),
			       TUNE_RATIO_MIN * pow(TUNE_RATIO_MAX / TUNE_RATIO_MIN, k / 15.0),
			       req, &best);
	for (int it = 0; best.ki > 0 && it < 40; it++) {
		struct candidate before = best;

		for (int a = -1; a <= 1; a++)
			for (int b = -1; b <= 1; b++)
				try_at(pl, before.th * exp(a * step_th),
				       before.ratio * exp(b * step_r), req, &best);
		if (best.ki == before.ki) {
			step_th /= 2;
			step_r /= 2;
		}
	}
	return best;
}

int tune_bandwidth_check(double hz, double T, char *why, size_t whylen)
{
	if (2 * M_PI * hz * T < TUNE_TH_MAX)
		return 0;
	snprintf(why, whylen, "a bandwidth of %g Hz is beyond a quarter of the servo rate (%g Hz)",
		 hz, TUNE_TH_MAX / (2 * M_PI * T));
	return -1;
}

/* req with its defaults filled in */
static struct tune_design_req resolved(const struct tune_design_req *req)
{
	struct tune_design_req r = *req;

	if (!(r.gm_db > 0))
		r.gm_db = TUNE_MIN_GM_DB;
	return r;
}

double tune_default_bandwidth(const struct tune_plant *pl,
			      const struct tune_design_req *req)
{
	struct tune_design_req r = resolved(req);
	struct candidate c = optimise(pl, 0, &r);

	return c.ki > 0 ? c.th / (2 * M_PI * pl->T) : 0;
}

int tune_design(const struct tune_plant *pl, const struct tune_design_req *req,
		struct tune_gains *gn, struct tune_design_margins *m, char *why,
		size_t whylen)
{
	struct tune_design_req r = resolved(req);
	double th = 2 * M_PI * r.bandwidth_hz * pl->T;
	struct candidate c;

	memset(gn, 0, sizeof(*gn));
	memset(m, 0, sizeof(*m));
	if (!(pl->g > 0) || !(pl->p >= 0) || !(pl->T > 0)) {
		snprintf(why, whylen, "the plant (gain %g, friction pole %g 1/s) is not a mass on a servo period",
			 pl->g, pl->p);
		return -1;
	}
	if (tune_bandwidth_check(req->bandwidth_hz, pl->T, why, whylen) < 0)
		return -1;
	c = optimise(pl, th, &r);
	if (!(c.ki > 0)) {
		/* which limit refuses: the same search without the gain
		 * margin floor tells */
		struct tune_design_req loose = r;
		double t = th > 0 ? th : 0.1;
		struct candidate l;

		loose.gm_db = -INFINITY;
		l = optimise(pl, th, &loose);
		if (l.ki > 0)
			snprintf(why, whylen, "the gains for %g Hz with a phase margin of %g deg leave a gain margin of %.1f dB, below %g dB: ask a lower --bandwidth, --margin or --gain-margin",
				 th > 0 ? r.bandwidth_hz : l.m.wc_hz,
				 req->margin_deg, l.m.gm_db, r.gm_db);
		else
			snprintf(why, whylen, "no PID reaches a phase margin of %g deg at %g Hz on this plant (its delay costs %.1f deg there): ask a lower --bandwidth or --margin",
				 req->margin_deg, t / (2 * M_PI * pl->T),
				 (pl->d + 0.5) * t * DEG);
		return -1;
	}
	*gn = c.g;
	*m = c.m;
	return 0;
}
