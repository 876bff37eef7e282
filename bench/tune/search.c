/* SPDX-License-Identifier: MIT */
/*
 * The benchmark's search for the best gains (the same on x and y).
 * First grids, each point by one run of the circle (a lower bound of the
 * measure: its variant 0), unstable runs left out. The coarse grid is set
 * from the true plant (which the search, unlike the tuner, is told): kp
 * spans crossovers of about 50 Hz to 1.6 kHz, td 0.1 to 4 ms, ti none or
 * 1 to 30 ms, the feed-forward 90, 100 and 110 % of the plant's exact
 * inverse. The fine grids take five values of kp, td and ti around the
 * coarse best of all and around the coarse best admissible, half a coarse
 * step apart, and three of each feed-forward gain, 5 % apart. Then the
 * best SEARCH_TOP of each by the measure, the tuner's gains by the
 * measure, and the local searches of refine.c from the best of them and
 * from the tuner's gains.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench_tune.h"

#define NK 6
#define ND 6
#define NI 5
#define NF 3
#define KP_MAX 1000.0	/* the card's range of kp */
/* grid points per kind (all, admissible) measured after the grids */
#define SEARCH_TOP 4
/* measures per local search: 4 of them, each measure CIRCLE_VARIANTS
 * circles (about 8 x 6 ms): the search's CPU within a minute a plant */
#define REFINE_BUDGET 120

struct grid {
	double kp[7], td[7], ti[7], kvff[7], kaff[7];
	unsigned int nkp, ntd, nti, nvf, naf;
};

/* The grids' best few by one run, of all and of the admissible. */
struct tops {
	struct search_point any[SEARCH_TOP], pm[SEARCH_TOP];
	unsigned int nany, npm;
};

void search_true_plant(const struct bench_machine *m, struct tune_plant *pl)
{
	const struct sh2000_plant_config *pc = &m->cfg.axis[0];

	memset(pl, 0, sizeof(*pl));
	/* counts/s^2 per DAC code: N/V * V/code / kg, m -> counts */
	pl->g = pc->force_n_per_v * (10.0 / 32768) / pc->mass_kg *
		pc->counts_per_mm * 1e3;
	pl->p = pc->friction_ns_per_m / pc->mass_kg;
	pl->T = 1e-4;
}

int search_on_card(const struct tune_gains *g)
{
	return g->kp > 0 && g->kp <= KP_MAX && g->ti >= 0 && g->ti <= 100 &&
	       g->td >= 0 && g->td <= 10 && g->kvff >= 0 && g->kvff <= 1 &&
	       g->kaff >= 0 && g->kaff <= 1;
}

int search_admissible(const struct tune_design_margins *mg)
{
	return mg->stable && mg->pm_deg >= SEARCH_MIN_PM;
}

int search_better(const struct circle_result *a, const struct circle_result *b)
{
	if (a->unstable != b->unstable)
		return !a->unstable;
	return a->max_ferr < b->max_ferr ||
	       (a->max_ferr == b->max_ferr && a->rms_ferr < b->rms_ferr);
}

int search_consider(const struct bench_machine *m, const struct tune_plant *pl,
		    const struct tune_gains *g, const char *from,
		    struct search_best *sb, struct search_point *pt)
{
	pt->g = *g;
	pt->from = from;
	tune_margins_of(pl, g, &pt->mg);
	if (circle_measure(m, g, CIRCLE_VARIANTS, &pt->res) < 0)
		return -1;
	sb->measures++;
	if (pt->res.unstable) {
		sb->measures_unstable++;
		return 0;
	}
	if (search_better(&pt->res, &sb->any.res))
		sb->any = *pt;
	if (search_admissible(&pt->mg) && search_better(&pt->res, &sb->pm.res))
		sb->pm = *pt;
	return 0;
}

/* Insert p into the sorted list l of n (at most SEARCH_TOP) unless the
 * same gains are there (the fine grids repeat the coarse centre). */
static void top_insert(struct search_point *l, unsigned int *n,
		       const struct search_point *p)
{
	unsigned int i = *n;

	for (unsigned int k = 0; k < *n; k++)
		if (!memcmp(&l[k].g, &p->g, sizeof(p->g)))
			return;
	if (i == SEARCH_TOP && !search_better(&p->res, &l[i - 1].res))
		return;
	if (i == SEARCH_TOP)
		i--;
	else
		(*n)++;
	for (; i > 0 && search_better(&p->res, &l[i - 1].res); i--)
		l[i] = l[i - 1];
	l[i] = *p;
}

static int search_grid(const struct bench_machine *m, const struct grid *G,
		       const struct tune_plant *pl, struct search_best *sb,
		       struct tops *t)
{
	for (unsigned int a = 0; a < G->nkp; a++)
	for (unsigned int b = 0; b < G->ntd; b++)
	for (unsigned int c = 0; c < G->nti; c++)
	for (unsigned int d = 0; d < G->nvf; d++)
	for (unsigned int e = 0; e < G->naf; e++) {
		struct search_point p = {
			.g = { G->kp[a], G->ti[c], G->td[b], G->kvff[d], G->kaff[e] },
			.from = "grid",
		};

		if (!search_on_card(&p.g))	/* beyond what the card takes */
			continue;
		if (circle_with(m, &p.g, &p.res) < 0)
			return -1;
		sb->runs++;
		if (p.res.unstable) {
			sb->unstable++;
			continue;
		}
		tune_margins_of(pl, &p.g, &p.mg);
		top_insert(t->any, &t->nany, &p);
		if (search_admissible(&p.mg))
			top_insert(t->pm, &t->npm, &p);
	}
	return 0;
}

/* Five values around v: v * f^(-1, -1/2, 0, 1/2, 1). */
static void around(double v, double f, double *out)
{
	for (int i = 0; i < 5; i++)
		out[i] = v * pow(f, (i - 2) / 2.0);
}

/* The fine grid around c. */
static int stage(const struct bench_machine *m, struct grid *G,
		 const struct tune_plant *pl, struct search_best *sb,
		 struct tops *t, const struct tune_gains *c)
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
	return search_grid(m, G, pl, sb, t);
}

/* The coarse grid, then the fine ones around its best of all and its
 * best admissible. */
static int grids(const struct bench_machine *m, const struct tune_plant *pl,
		 struct search_best *sb, struct tops *t)
{
	static const double kpw[NK] = { 50, 100, 200, 400, 800, 1600 };
	static const double tds[ND] = { 1e-4, 2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3 };
	static const double tis[NI] = { 0, 1e-3, 3e-3, 1e-2, 3e-2 };
	static const double ffs[NF] = { 0.9, 1.0, 1.1 };
	struct grid G = { .nkp = NK, .ntd = ND, .nti = NI, .nvf = NF, .naf = NF };
	struct tune_gains any, adm;
	int have_adm;

	for (int i = 0; i < NK; i++)
		G.kp[i] = pow(2 * M_PI * kpw[i], 2) / pl->g / 4;
	memcpy(G.td, tds, sizeof(tds));
	memcpy(G.ti, tis, sizeof(tis));
	for (int i = 0; i < NF; i++) {
		G.kvff[i] = ffs[i] * pl->p / pl->g;
		G.kaff[i] = ffs[i] / pl->g;
	}
	if (search_grid(m, &G, pl, sb, t) < 0 || !t->nany)
		return -1;
	any = t->any[0].g;
	have_adm = t->npm > 0;
	adm = have_adm ? t->pm[0].g : any;
	if (stage(m, &G, pl, sb, t, &any) < 0 ||
	    (have_adm && stage(m, &G, pl, sb, t, &adm) < 0))
		return -1;
	sb->grid_any = t->any[0].res.max_ferr;
	sb->grid_pm = t->npm ? t->pm[0].res.max_ferr : INFINITY;
	return 0;
}

/* The grids' best few by the measure, and the tuner's gains. */
static int measure_starts(const struct bench_machine *m,
			  const struct tune_plant *pl, const struct tops *t,
			  const struct tune_gains *tuned, struct search_best *sb,
			  struct search_point *grid_pm, struct search_point *tp)
{
	struct search_point p;

	grid_pm->res.max_ferr = INFINITY;
	for (unsigned int i = 0; i < t->nany; i++)
		if (search_consider(m, pl, &t->any[i].g, "grid", sb, &p) < 0)
			return -1;
	for (unsigned int i = 0; i < t->npm; i++) {
		if (search_consider(m, pl, &t->pm[i].g, "grid", sb, &p) < 0)
			return -1;
		if (!p.res.unstable && search_better(&p.res, &grid_pm->res))
			*grid_pm = p;
	}
	if (search_consider(m, pl, tuned, "tuned", sb, tp) < 0)
		return -1;
	sb->own = *tp;
	return 0;
}

int search_best(const struct bench_machine *m, const struct tune_gains *tuned,
		struct search_best *sb)
{
	struct tune_plant pl;
	struct tops t = { .nany = 0 };
	static const struct search_limits adm = { SEARCH_MIN_PM, -INFINITY };
	/* the design's limits, less what the identified plant's margins may
	 * differ from the true one's */
	static const struct search_limits own = {
		TUNE_DEFAULT_MARGIN - 0.5, TUNE_MIN_GM_DB - 0.5
	};
	struct search_point grid_pm, tp, any;

	search_true_plant(m, &pl);
	memset(sb, 0, sizeof(*sb));
	sb->any.res.max_ferr = sb->pm.res.max_ferr = INFINITY;
	sb->any.res.unstable = sb->pm.res.unstable = 1;	/* none yet */
	if (grids(m, &pl, sb, &t) < 0 ||
	    measure_starts(m, &pl, &t, tuned, sb, &grid_pm, &tp) < 0)
		return -1;
	any = sb->any;
	if (search_refine(m, &pl, NULL, REFINE_BUDGET, "refined from the best of all",
			  sb, &any) < 0)
		return -1;
	if (isfinite(grid_pm.res.max_ferr) &&
	    search_refine(m, &pl, &adm, REFINE_BUDGET, "refined from the grid's best45",
			  sb, &grid_pm) < 0)
		return -1;
	if (!tp.res.unstable && search_admissible(&tp.mg) &&
	    search_refine(m, &pl, &adm, REFINE_BUDGET, "refined from the tuned gains",
			  sb, &tp) < 0)
		return -1;
	if (!sb->own.res.unstable &&
	    search_refine(m, &pl, &own, REFINE_BUDGET,
			  "refined from the tuned gains within the design's limits",
			  sb, &sb->own) < 0)
		return -1;
	return 0;
}
