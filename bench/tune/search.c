/* SPDX-License-Identifier: MIT */
/*
 * The benchmark's exhaustive search: the circle's max following error for
 * every point of a grid over kp, ti, td, kvff and kaff (the same on x and
 * y), unstable runs left out. The coarse grid is set from the true plant
 * (which the search, unlike the tuner, is told): kp spans crossovers of
 * about 50 Hz to 1.6 kHz, td 0.1 to 4 ms, ti none or 1 to 30 ms, the
 * feed-forward 90, 100 and 110 % of the plant's exact inverse. The fine
 * grid takes five values of kp, td and ti around the coarse best, half a
 * coarse step apart, and three of each feed-forward gain, 5 % apart.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <sh2000/sh2000_cardsim.h>

#include "bench_tune.h"

#define NK 6
#define ND 6
#define NI 5
#define NF 3
#define KP_MAX 1000.0	/* the card's range of kp */

struct grid {
	double kp[7], td[7], ti[7], kvff[7], kaff[7];
	unsigned int nkp, ntd, nti, nvf, naf;
};

static int search_grid(const struct bench_machine *m, const struct grid *G,
		       const struct tune_plant *pl, struct search_best *sb)
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
		struct tune_design_margins mg;

		if (circle_with(m, &g, &res) < 0)
			return -1;
		sb->runs++;
		if (res.unstable) {
			sb->unstable++;
			continue;
		}
		tune_margins_of(pl, &g, &mg);
		if (res.max_ferr < sb->any.max_ferr) {
			sb->any = res;
			sb->any_gains = g;
			sb->any_margins = mg;
		}
		if (mg.stable && mg.pm_deg >= SEARCH_MIN_PM &&
		    res.max_ferr < sb->pm.max_ferr) {
			sb->pm = res;
			sb->pm_gains = g;
			sb->pm_margins = mg;
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

/* One stage: the grid, then the fine grid around best (the best of the
 * whole search, or of the admissible part). */
static int stage(const struct bench_machine *m, struct grid *G,
		 const struct tune_plant *pl, struct search_best *sb,
		 const struct tune_gains *c)
{
	around(c->kp, 2, G->kp);
	around(c->td, 2, G->td);
	if (c->ti > 0)
		around(c->ti, 3, G->ti);
	else
		memcpy(G->ti, (const double[5]){ 0, 3e-2, 6e-2, 1e-1, 3e-1 }, sizeof(double) * 5);
	for (int i = 0; i < 3; i++) {
		G->kvff[i] = c->kvff * (0.95 + 0.05 * i);
		G->kaff[i] = c->kaff * (0.95 + 0.05 * i);
	}
	G->nkp = G->ntd = G->nti = 5;
	G->nvf = G->naf = 3;
	return search_grid(m, G, pl, sb);
}

int search_best(const struct bench_machine *m, struct search_best *sb)
{
	const struct sh2000_plant_config *pc = &m->cfg.axis[0];
	/* counts/s^2 per DAC code: N/V * V/code / kg, m -> counts */
	double g = pc->force_n_per_v * (10.0 / 32768) / pc->mass_kg *
		   pc->counts_per_mm * 1e3;
	double p = pc->friction_ns_per_m / pc->mass_kg;
	struct tune_plant pl = { .g = g, .p = p, .d = 0, .T = 1e-4 };
	static const double kpw[NK] = { 50, 100, 200, 400, 800, 1600 };
	static const double tds[ND] = { 1e-4, 2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3 };
	static const double tis[NI] = { 0, 1e-3, 3e-3, 1e-2, 3e-2 };
	static const double ffs[NF] = { 0.9, 1.0, 1.1 };
	struct grid G = { .nkp = NK, .ntd = ND, .nti = NI, .nvf = NF, .naf = NF };

	for (int i = 0; i < NK; i++)
		G.kp[i] = pow(2 * M_PI * kpw[i], 2) / g / 4;
	memcpy(G.td, tds, sizeof(tds));
	memcpy(G.ti, tis, sizeof(tis));
	for (int i = 0; i < NF; i++) {
		G.kvff[i] = ffs[i] * p / g;
		G.kaff[i] = ffs[i] / g;
	}
	memset(sb, 0, sizeof(*sb));
	sb->any.max_ferr = sb->pm.max_ferr = INFINITY;
	if (search_grid(m, &G, &pl, sb) < 0 || !isfinite(sb->any.max_ferr))
		return -1;
	/* fine, around the best of all and around the best admissible */
	{
		struct tune_gains any = sb->any_gains, adm = sb->pm_gains;
		int have_adm = isfinite(sb->pm.max_ferr);

		if (stage(m, &G, &pl, sb, &any) < 0)
			return -1;
		if (have_adm && stage(m, &G, &pl, sb, &adm) < 0)
			return -1;
	}
	return 0;
}
