/* SPDX-License-Identifier: MIT */
/*
 * The benchmark's exhaustive search: the circle's max following error for
 * every point of a grid over kp, ti, td, kvff and kaff (the same on x and
 * y), unstable runs left out. The coarse grid is set from the true plant
 * (which the search, unlike the tuner, is told): kp spans crossovers of
 * about 50 Hz to 1.6 kHz, td 0.1 to 4 ms, ti none or 1 to 30 ms, the
 * feed-forward 80 to 120 % of the plant's exact inverse. The fine grid
 * takes five values of each around the coarse best, half a coarse step
 * apart.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <sh2000/sh2000_cardsim.h>

#include "bench_tune.h"

#define NK 6
#define ND 6
#define NI 5
#define NF 5
#define KP_MAX 1000.0	/* the card's range of kp */

struct grid {
	double kp[7], td[7], ti[7], kvff[7], kaff[7];
	unsigned int nkp, ntd, nti, nvf, naf;
};

static int search_grid(const struct bench_machine *m, const struct grid *G,
		       struct tune_gains *best, struct circle_result *bres,
		       unsigned int *runs, unsigned int *unstable)
{
	for (unsigned int a = 0; a < G->nkp; a++)
	for (unsigned int b = 0; b < G->ntd; b++)
	for (unsigned int c = 0; c < G->nti; c++)
	for (unsigned int d = 0; d < G->nvf; d++)
	for (unsigned int e = 0; e < G->naf; e++) {
		struct tune_gains g = { G->kp[a], G->ti[c], G->td[b],
					G->kvff[d], G->kaff[e] };
		struct circle_result res;

		if (g.kp > KP_MAX)	/* beyond what the card takes */
			continue;
		if (circle_with(m, &g, &res) < 0)
			return -1;
		(*runs)++;
		if (res.unstable) {
			(*unstable)++;
			continue;
		}
		if (res.max_ferr < bres->max_ferr) {
			*bres = res;
			*best = g;
		}
	}
	return 0;
}

/* Five values around v: v * f^(-1, -1/2, 0, 1/2, 1). */
static void around(double v, double f, double *out)
{
	for (int i = 0; i < 5; i++)
		out[i] = v * pow(f, (i - 2) / 2.0);
}

int search_best(const struct bench_machine *m, struct tune_gains *best,
		struct circle_result *res, unsigned int *runs,
		unsigned int *unstable)
{
	const struct sh2000_plant_config *pl = &m->cfg.axis[0];
	/* counts/s^2 per DAC code: N/V * V/code / kg, m -> counts */
	double g = pl->force_n_per_v * (10.0 / 32768) / pl->mass_kg *
		   pl->counts_per_mm * 1e3;
	double p = pl->friction_ns_per_m / pl->mass_kg;
	static const double kpw[NK] = { 50, 100, 200, 400, 800, 1600 };
	static const double tds[ND] = { 1e-4, 2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3 };
	static const double tis[NI] = { 0, 1e-3, 3e-3, 1e-2, 3e-2 };
	static const double ffs[NF] = { 0.8, 0.9, 1.0, 1.1, 1.2 };
	struct grid G = { .nkp = NK, .ntd = ND, .nti = NI, .nvf = NF, .naf = NF };
	struct tune_gains c;

	for (int i = 0; i < NK; i++)
		G.kp[i] = pow(2 * M_PI * kpw[i], 2) / g / 4;
	memcpy(G.td, tds, sizeof(tds));
	memcpy(G.ti, tis, sizeof(tis));
	for (int i = 0; i < NF; i++) {
		G.kvff[i] = ffs[i] * p / g;
		G.kaff[i] = ffs[i] / g;
	}
	res->max_ferr = INFINITY;
	if (search_grid(m, &G, best, res, runs, unstable) < 0)
		return -1;
	if (!isfinite(res->max_ferr))
		return -1;
	/* fine: half a coarse step each way */
	c = *best;
	around(c.kp, 2, G.kp);
	around(c.td, 2, G.td);
	if (c.ti > 0)
		around(c.ti, 3, G.ti);
	else
		memcpy(G.ti, (const double[5]){ 0, 3e-2, 6e-2, 1e-1, 3e-1 }, sizeof(double) * 5);
	around(c.kvff, 1.1, G.kvff);
	around(c.kaff, 1.1, G.kaff);
	G.nkp = G.ntd = G.nti = G.nvf = G.naf = 5;
	return search_grid(m, &G, best, res, runs, unstable);
}
