/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune's auto-tuning against an exhaustive search, on the card
 * model in virtual time (libsh2000's in-process `sim` card, opened with
 * sh2000_sim_open() and a plant configuration), for three plants: the
 * documented default (2 kg, 20 N/(m/s), 20 N/V), ten times the mass and
 * five times the friction. For each, on x and y:
 *  - the start: bad gains, the card's default PID without feed-forward
 *    (kp 0.5, ti 20 ms, td 4 ms, kvff = kaff = 0);
 *  - the auto-tuner as sh2000-tune --auto runs it (identification on the
 *    card, design at the default bandwidth and margins);
 *  - the reference move, R 5 mm circle at 300 mm/s (circle.c), with the
 *    start gains, the tuned ones and the search's (search.c, refine.c),
 *    by the measure: the worst of 8 runs that start at other angles and
 *    sub-count positions (measure.c), since one run's max following
 *    error at 2-3 counts is a draw (the search's grids screen by one).
 * The card's amax is what the planner may use on the circle: 40 m/s^2,
 * or 60 % of what the motor can give at 10 V when that is less (10x the
 * mass: 6 m/s^2, so the planner slows that circle down). The following
 * error limit is 2 mm so that a slow loop is not taken for an unstable
 * one; the tuner's own test moves lower it to its 0.1 mm.
 * Usage: bench_tune          the table (about two minutes of CPU)
 *        bench_tune bandwidth  the circle against the design's bandwidth
 *                            (the default margins), on the true plants
 *        bench_tune variants the spread of one run of the circle over
 *                            start angles, start positions, servo phase
 *        bench_tune margins  the circle against the design's phase and
 *                            gain margins asked, on the true plants
 *        bench_tune feedforward  the default design with kvff and kaff
 *                            5 % and 2 % off the plant's inverse
 *        bench_tune smoke    the default plant: tuned and both circles, no
 *                            search; exit 1 unless the tuned circle is
 *                            stable and better than the start (a ctest)
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <sh2000/sim.h>

#include "bench_tune.h"
#include "ident.h"

#define FORCE_N_PER_V	20.0
#define AMAX_MM_S2	40000.0
#define AMAX_SHARE	0.6
#define FERR_LIMIT_MM	2.0

static const struct plant_case cases[] = {
	{ "default", 2.0, 20.0 },
	{ "10x mass", 20.0, 20.0 },
	{ "5x friction", 2.0, 100.0 },
};

static double cpu_now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The start: the card's default PID without feed-forward. */
static const struct tune_gains bad = { 0.5, 0.02, 0.004, 0, 0 };

static void machine(const struct plant_case *pc, struct bench_machine *m)
{
	sh2000_sim_config_default(&m->cfg);
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		m->cfg.axis[a].mass_kg = pc->mass;
		m->cfg.axis[a].friction_ns_per_m = pc->friction;
		m->cfg.axis[a].force_n_per_v = FORCE_N_PER_V;
	}
	m->amax = fmin(AMAX_MM_S2, AMAX_SHARE * FORCE_N_PER_V * 10 / pc->mass * 1e3);
	m->ferr_limit = FERR_LIMIT_MM;
}

/* The tuner on x and y, as sh2000-tune --auto --apply runs it. */
static int autotune(struct sh2000 *h, struct row *w)
{
	struct tune_design_req req = { 0, TUNE_DEFAULT_MARGIN, 0 };
	char why[512];

	for (unsigned int a = 0; a < 2; a++) {
		struct tune_opts o = { .axis = a, .ferr_max_mm = 0.1,
				       .travel_mm = 0.1, .margin_deg = TUNE_DEFAULT_MARGIN };
		struct tune_ident_result id;
		struct tune_gains g, old;
		struct tune_design_margins m;

		if (tune_ident(h, &o, &id) != 0)
			return -1;
		if (tune_design(&id.plant, &req, &g, &m, why, sizeof(why)) < 0) {
			fprintf(stderr, "bench_tune: design: %s\n", why);
			return -1;
		}
		if (tune_read_gains(h, a, &old) < 0 ||
		    tune_gains_set(h, a, &g, &old, why, sizeof(why)) < 0)
			return -1;
		if (a == 0) {
			w->id = id.plant;
			w->m = m;
			w->tuned = g;
		}
	}
	return 0;
}

/* tuned, best, best45 and the best within the design's limits on the
 * runs the search did not choose by, and over all of them. */
static int check_all(const struct bench_machine *m, struct row *w)
{
	const struct search_point *p[4] = { NULL, &w->sb.any, &w->sb.pm, &w->sb.own };

	for (unsigned int i = 0; i < 4; i++) {
		const struct tune_gains *g = p[i] ? &p[i]->g : &w->tuned;

		if (circle_measure_from(m, g, CIRCLE_VARIANTS, CIRCLE_HELD_OUT,
					&w->held[i]) < 0)
			return -1;
		circle_worst(p[i] ? &p[i]->res : &w->autot, &w->held[i], &w->all[i]);
	}
	return 0;
}

static int one_plant(const struct plant_case *pc, struct row *w, int search)
{
	struct bench_machine m;
	struct sh2000 *h = NULL;
	double t0 = cpu_now();
	int r = -1;

	memset(w, 0, sizeof(*w));
	machine(pc, &m);
	w->amax = m.amax;
	search_true_plant(&m, &w->truth);
	/* the tuner on a card with the bad gains, as a user would run it;
	 * each circle on a fresh card, so no run inherits another's state */
	if (bench_card_open(&h, &m, &bad) == 0 && autotune(h, w) == 0 &&
	    circle_measure(&m, &bad, CIRCLE_VARIANTS, &w->init) == 0 &&
	    circle_measure(&m, &w->tuned, CIRCLE_VARIANTS, &w->autot) == 0 &&
	    (!search || (search_best(&m, &w->tuned, &w->sb) == 0 &&
			 check_all(&m, w) == 0)))
		r = 0;
	if (r)
		fprintf(stderr, "bench_tune: %s: failed\n", pc->name);
	sh2000_close(h);
	w->cpu_s = cpu_now() - t0;
	if (!r && search)	/* progress: a long run says where it is */
		fprintf(stderr, "bench_tune: %s: initial %.1f, tuned %.1f, search %.1f (PM >= %g: %.1f) counts (%u + %u x %u runs, %.1f s CPU)\n",
			pc->name, w->init.max_ferr, w->autot.max_ferr,
			w->sb.any.res.max_ferr, SEARCH_MIN_PM, w->sb.pm.res.max_ferr,
			w->sb.runs, w->sb.measures, CIRCLE_VARIANTS, w->cpu_s);
	return r;
}

static int smoke(void)
{
	struct row w;

	if (one_plant(&cases[0], &w, 0))
		return 1;
	printf("smoke (%s plant): circle max following error %.1f counts at the start, %.1f tuned%s; PM %.1f deg\n",
	       cases[0].name, w.init.max_ferr, w.autot.max_ferr,
	       w.autot.unstable ? " (UNSTABLE)" : "", w.m.pm_deg);
	return !w.autot.unstable && w.autot.max_ferr < w.init.max_ferr ? 0 : 1;
}

/* The circle's max following error for designs at a range of
 * bandwidths on each true plant: where the default lies on that curve. */
static int bandwidths(void)
{
	static const double hz[] = { 0, 200, 400, 600, 800, 1000, 1200 };
	const unsigned int n = sizeof(hz) / sizeof(hz[0]);

	printf("%-12s %8s %8s %8s %10s %8s\n", "plant", "Hz", "PM deg", "GM dB",
	       "max ferr", "rms");
	for (unsigned int i = 0; i < 3; i++) {
		struct bench_machine m;
		struct tune_plant pl;

		machine(&cases[i], &m);
		search_true_plant(&m, &pl);
		for (unsigned int k = 0; k < n; k++) {
			struct tune_design_req req = { hz[k], TUNE_DEFAULT_MARGIN, 0 };
			struct tune_gains g;
			struct tune_design_margins mg;
			struct circle_result res;
			char why[256];

			if (tune_design(&pl, &req, &g, &mg, why, sizeof(why)) < 0) {
				printf("%-12s %8.0f refused: %s\n", cases[i].name, hz[k], why);
				continue;
			}
			if (circle_measure(&m, &g, CIRCLE_VARIANTS, &res) < 0)
				return 1;
			printf("%-12s %8.0f %8.1f %8.1f %10.2f %8.2f  Ti wc %.2f%s%s\n", cases[i].name,
			       mg.wc_hz, mg.pm_deg, mg.gm_db, res.max_ferr, res.rms_ferr,
			       g.ti * 2 * M_PI * mg.wc_hz,
			       hz[k] != 0 ? "" : " (default)",
			       res.unstable ? " unstable" : "");
		}
	}
	printf("(the design on the true plant at phase margin %g deg, gain margin >= %g dB and the crossover\n"
	       " asked; max ferr, rms: the circle, counts, the worst of %u runs)\n",
	       TUNE_DEFAULT_MARGIN, TUNE_MIN_GM_DB, CIRCLE_VARIANTS);
	return 0;
}

/* How much the circle's max following error moves for the same gains:
 * designs at three bandwidths on each true plant, one run (variant 0),
 * the least and the most over all CIRCLE_VARIANTS_ALL variants, the
 * measure (the worst of CIRCLE_VARIANTS), eight phases of the servo cycle
 * before the start, and the same with kp 1 % higher. */
static int variants(void)
{
	static const double hz[] = { 0, 400, 600 };

	printf("%-12s %6s %7s %7s %7s %7s %13s %9s %9s\n", "plant", "Hz", "run 0",
	       "least", "most", "worst8", "8 phases", "kp+1% r0", "worst8");
	for (unsigned int i = 0; i < 3; i++) {
		struct bench_machine m;
		struct tune_plant pl;

		machine(&cases[i], &m);
		search_true_plant(&m, &pl);
		for (unsigned int k = 0; k < sizeof(hz) / sizeof(hz[0]); k++) {
			struct tune_design_req req = { hz[k], TUNE_DEFAULT_MARGIN, 0 };
			struct tune_gains g, g1;
			struct tune_design_margins mg;
			struct circle_result r0, w8, r1, w81, res;
			double lo = INFINITY, hi = 0, plo = INFINITY, phi = 0;
			char why[256];

			if (tune_design(&pl, &req, &g, &mg, why, sizeof(why)) < 0)
				continue;
			for (unsigned int v = 0; v < CIRCLE_VARIANTS_ALL + 8; v++) {
				struct circle_variant cv = { 0, 0, (v - CIRCLE_VARIANTS_ALL) / 8.0 };

				if (v < CIRCLE_VARIANTS_ALL)
					circle_variant_of(v, &cv);
				if (circle_variant_with(&m, &g, &cv, &res) < 0)
					return 1;
				if (v < CIRCLE_VARIANTS_ALL) {
					lo = fmin(lo, res.max_ferr);
					hi = fmax(hi, res.max_ferr);
				} else {
					plo = fmin(plo, res.max_ferr);
					phi = fmax(phi, res.max_ferr);
				}
			}
			g1 = g;
			g1.kp *= 1.01;
			if (circle_with(&m, &g, &r0) < 0 ||
			    circle_measure(&m, &g, CIRCLE_VARIANTS, &w8) < 0 ||
			    circle_with(&m, &g1, &r1) < 0 ||
			    circle_measure(&m, &g1, CIRCLE_VARIANTS, &w81) < 0)
				return 1;
			printf("%-12s %6.0f %7.2f %7.2f %7.2f %7.2f %6.2f..%-5.2f %9.2f %9.2f\n",
			       cases[i].name, mg.wc_hz, r0.max_ferr, lo, hi,
			       w8.max_ferr, plo, phi, r1.max_ferr, w81.max_ferr);
		}
	}
	printf("(max following error, counts; Hz: the design's crossover at phase margin %g deg, the\n"
	       " first the default; run 0: the table's single run; least, most: over %u runs, 8 start\n"
	       " angles x 8 start positions an eighth of a count apart; worst8: the measure; 8 phases: run 0\n"
	       " started an eighth of a servo cycle apart)\n", TUNE_DEFAULT_MARGIN, CIRCLE_VARIANTS_ALL);
	return 0;
}

/* The design's limits against the circle: designs on each true plant
 * for pairs of (phase margin, gain margin floor) at the default
 * bandwidth (and one above it), by the measure and over every variant:
 * where the default margins lie. */
static int margins(void)
{
	static const struct { double pm, gm, hz; } d[] = {
		{ 50, 10, 0 }, { 48, 8, 0 }, { 46, 10, 0 }, { 46, 8, 0 },
		{ TUNE_DEFAULT_MARGIN, TUNE_MIN_GM_DB, 0 },
		{ TUNE_DEFAULT_MARGIN, 6, 0 }, { TUNE_DEFAULT_MARGIN, TUNE_MIN_GM_DB, 1050 },
	};

	printf("%-12s %5s %5s %7s %6s %6s %7s %7s %6s %6s %6s\n", "plant", "PM", "GM>=",
	       "Hz", "PM", "GM dB", "worst8", "all", "rms", "Ti wc", "Td wc");
	for (unsigned int i = 0; i < 3; i++) {
		struct bench_machine m;
		struct tune_plant pl;

		machine(&cases[i], &m);
		search_true_plant(&m, &pl);
		for (unsigned int k = 0; k < sizeof(d) / sizeof(d[0]); k++) {
			struct tune_design_req req = { d[k].hz, d[k].pm, d[k].gm };
			struct tune_gains g;
			struct tune_design_margins mg;
			struct circle_result r8, ra;
			char why[256];

			if (tune_design(&pl, &req, &g, &mg, why, sizeof(why)) < 0) {
				printf("%-12s %5.1f %5.1f refused: %s\n", cases[i].name,
				       d[k].pm, d[k].gm, why);
				continue;
			}
			if (circle_measure(&m, &g, CIRCLE_VARIANTS, &r8) < 0 ||
			    circle_measure(&m, &g, CIRCLE_VARIANTS_ALL, &ra) < 0)
				return 1;
			printf("%-12s %5.1f %5.1f %7.0f %6.1f %6.1f %7.2f %7.2f %6.2f %6.2f %6.2f%s%s\n",
			       cases[i].name, d[k].pm, d[k].gm, mg.wc_hz, mg.pm_deg,
			       mg.gm_db, r8.max_ferr, ra.max_ferr, ra.rms_ferr,
			       g.ti * 2 * M_PI * mg.wc_hz, g.td * 2 * M_PI * mg.wc_hz,
			       k == 4 ? " (default)" : "", ra.unstable ? " unstable" : "");
		}
	}
	printf("(the design on the true plant for the phase margin and gain margin floor asked, at the\n"
	       " default bandwidth or the Hz asked; worst8: the measure; all: the worst of all %u runs;\n"
	       " rms of those, counts)\n", CIRCLE_VARIANTS_ALL);
	return 0;
}

/* The feed-forward against the plant's exact inverse: the default
 * design on each true plant with kvff and kaff scaled, over every
 * variant (is a gap to the search's best a better feed-forward?). */
static int feedforward(void)
{
	static const double kv[] = { 0.9, 0.95, 1.0, 1.05 };
	static const double ka[] = { 0.98, 1.0, 1.02 };

	for (unsigned int i = 0; i < 3; i++) {
		struct bench_machine m;
		struct tune_plant pl;
		struct tune_design_req req = { 0, TUNE_DEFAULT_MARGIN, 0 };
		struct tune_gains g0;
		struct tune_design_margins mg;
		char why[256];

		machine(&cases[i], &m);
		search_true_plant(&m, &pl);
		if (tune_design(&pl, &req, &g0, &mg, why, sizeof(why)) < 0)
			return 1;
		for (unsigned int a = 0; a < 4; a++) {
			printf("%-12s kvff x%.2f:", cases[i].name, kv[a]);
			for (unsigned int b = 0; b < 3; b++) {
				struct tune_gains g = g0;
				struct circle_result ra;

				g.kvff *= kv[a];
				g.kaff *= ka[b];
				if (circle_measure(&m, &g, CIRCLE_VARIANTS_ALL, &ra) < 0)
					return 1;
				printf("  kaff x%.2f %5.2f (%.3f)", ka[b], ra.max_ferr, ra.rms_ferr);
			}
			printf("\n");
		}
	}
	printf("(the default design on the true plant, kvff and kaff scaled from the plant's exact\n"
	       " inverse; max following error on the circle, the worst of all %u runs, counts; RMS\n"
	       " in brackets)\n", CIRCLE_VARIANTS_ALL);
	return 0;
}

int main(int argc, char **argv)
{
	struct row rows[3];
	int fail = 0;

	if (argc > 1 && !strcmp(argv[1], "smoke"))
		return smoke();
	if (argc > 1 && !strcmp(argv[1], "bandwidth"))
		return bandwidths();
	if (argc > 1 && !strcmp(argv[1], "variants"))
		return variants();
	if (argc > 1 && !strcmp(argv[1], "margins"))
		return margins();
	if (argc > 1 && !strcmp(argv[1], "feedforward"))
		return feedforward();

	if (argc > 1) {
		fprintf(stderr, "usage: bench_tune [smoke | bandwidth | variants | margins | feedforward]\n");
		return 2;
	}
	for (unsigned int i = 0; i < 3; i++)
		fail |= one_plant(&cases[i], &rows[i], 1);
	if (fail)
		return 1;
	report_table(cases, rows, 3);
	return 0;
}
