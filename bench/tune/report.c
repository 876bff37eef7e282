/* SPDX-License-Identifier: MIT */
/* bench_tune's table: identification, the circle's figures for the start,
 * the tuned gains and the search's best of all and best admissible, the
 * check over every variant, the gains, and the two verdicts. */
#include <math.h>
#include <stdio.h>

#include "bench_tune.h"

/* The tuner's promise: tuned within 10 % of the best the search finds. */
#define WITHIN 1.10

static void print_ident(const struct plant_case *pc, const struct row *w)
{
	double g = w->truth.g, p = w->truth.p;

	printf("%-12s %12.6g %12.6g %+8.4f %%  %9.4g %9.4g %+8.4f %%  %5u %9.3f\n",
	       pc->name, g, w->id.g, (w->id.g / g - 1) * 100, p, w->id.p,
	       (w->id.p / p - 1) * 100, w->id.d, w->id.resid);
}

static void print_gains(const char *what, const struct tune_gains *g,
			const struct tune_design_margins *m, const char *from)
{
	printf("    %-7s kp %-9.5g ti %-9.4g td %-9.4g kvff %-10.5g kaff %-10.5g PM %5.1f GM %5.1f dB at %4.0f Hz%s%s\n",
	       what, g->kp, g->ti, g->td, g->kvff, g->kaff, m->pm_deg, m->gm_db,
	       m->wc_hz, from ? ", " : "", from ? from : "");
}

static void print_moves(const struct plant_case *cases, const struct row *rows,
			unsigned int n)
{
	printf("Reference move: R %g mm circle at %g mm/s, max following error |(ex, ey)| in counts (10 nm),\n"
	       "the worst of %u runs (start angles 45 deg apart, start positions a quarter count apart)\n",
	       CIRCLE_R_MM, CIRCLE_FEED, CIRCLE_VARIANTS);
	printf("%-12s %5s %6s %9s %9s %9s %6s %9s %6s %6s %6s %9s %10s %9s\n", "plant",
	       "amax", "feed", "initial", "tuned", "best", "ratio", "best45",
	       "ratio", "PM", "GM dB", "unstable", "grid", "measures");
	for (unsigned int i = 0; i < n; i++) {
		const struct row *w = &rows[i];
		int unst = w->init.unstable || w->autot.unstable;

		printf("%-12s %5.0f %6.1f %9.1f %9.2f %9.2f %6.2f %9.2f %6.2f %6.1f %6.1f %9s %4u/%-5u %3u/%u\n",
		       cases[i].name, w->amax / 1e3, w->autot.feed, w->init.max_ferr,
		       w->autot.max_ferr, w->sb.any.res.max_ferr,
		       w->autot.max_ferr / w->sb.any.res.max_ferr,
		       w->sb.pm.res.max_ferr,
		       w->autot.max_ferr / w->sb.pm.res.max_ferr, w->m.pm_deg,
		       w->m.gm_db, unst ? "YES" : "none", w->sb.unstable,
		       w->sb.runs, w->sb.measures_unstable, w->sb.measures);
	}
	printf("(amax: m/s^2 given to the planner; feed: the fastest the set-point went, mm/s;\n"
	       " tuned: sh2000-tune --auto's gains; best: the search's best; best45: its best among\n"
	       " gains with a predicted phase margin >= %g deg on the true plant; ratio: tuned / best;\n"
	       " PM (deg), GM: predicted for the tuned gains; unstable: the initial or tuned run faulted\n"
	       " or oscillated; grid: unstable / all circles of the grids (one run each);\n"
	       " measures: unstable / all of the measure (%u runs each) after the grids)\n\n",
	       SEARCH_MIN_PM, CIRCLE_VARIANTS);
}

static void print_check(const struct plant_case *cases, const struct row *rows,
			unsigned int n)
{
	printf("The design against the best PID within its own limits (predicted PM >= %g deg, GM >= %g dB,\n"
	       "less half a unit; a local search from the tuned gains): own\n",
	       TUNE_DEFAULT_MARGIN, TUNE_MIN_GM_DB);
	printf("and the gains again on the %u runs the search did not choose by (the same 8 angles at\n"
	       "7 other start positions an eighth of a count apart), and over all %u:\n",
	       CIRCLE_HELD_OUT, CIRCLE_VARIANTS_ALL);
	printf("%-12s %7s %6s | %-8s %6s %6s %6s %6s %6s %6s %6s | %-6s %6s %6s %6s\n",
	       "plant", "own", "ratio", "held-out", "tuned", "best", "ratio",
	       "best45", "ratio", "own", "ratio", "all 64", "tuned", "best45", "ratio");
	for (unsigned int i = 0; i < n; i++) {
		const struct circle_result *h = rows[i].held, *a = rows[i].all;
		double own = rows[i].sb.own.res.max_ferr;

		printf("%-12s %7.2f %6.2f | %-8s %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f | %-6s %6.2f %6.2f %6.2f%s\n",
		       cases[i].name, own, rows[i].autot.max_ferr / own, "",
		       h[0].max_ferr, h[1].max_ferr, h[0].max_ferr / h[1].max_ferr,
		       h[2].max_ferr, h[0].max_ferr / h[2].max_ferr,
		       h[3].max_ferr, h[0].max_ferr / h[3].max_ferr, "",
		       a[0].max_ferr, a[2].max_ferr, a[0].max_ferr / a[2].max_ferr,
		       h[0].unstable || h[1].unstable || h[2].unstable ||
		       h[3].unstable ? " (a run UNSTABLE)" : "");
	}
	printf("\nRMS following error (counts, the worst of the %u runs): initial / tuned / best / best45\n",
	       CIRCLE_VARIANTS);
	for (unsigned int i = 0; i < n; i++)
		printf("%-12s %11.2f %11.2f %11.2f %11.2f\n", cases[i].name,
		       rows[i].init.rms_ferr, rows[i].autot.rms_ferr,
		       rows[i].sb.any.res.rms_ferr, rows[i].sb.pm.res.rms_ferr);
}

/* One verdict: tuned within WITHIN of best (which = 1: of all, 2: the
 * admissible) on every plant, PM >= 45, nothing unstable; by the runs the
 * search chose by, and on the held-out runs. */
static void verdict(const char *what, const struct plant_case *cases,
		    const struct row *rows, unsigned int n, int which)
{
	int ok = 1, ok_held = 1;

	printf("%s\n    by the %u runs the search chose by: ", what, CIRCLE_VARIANTS);
	for (unsigned int i = 0; i < n; i++) {
		const struct row *w = &rows[i];
		const struct search_point *b = which == 2 ? &w->sb.pm : &w->sb.any;
		double r = w->autot.max_ferr / b->res.max_ferr;
		int sound = w->m.pm_deg >= SEARCH_MIN_PM && !w->autot.unstable &&
			    !w->init.unstable;

		ok &= sound && r <= WITHIN;
		printf("%s%s %.3f", i ? ", " : "", cases[i].name, r);
	}
	printf(" -> %s\n    on the %u held-out runs:               ",
	       ok ? "MET" : "NOT MET", CIRCLE_HELD_OUT);
	for (unsigned int i = 0; i < n; i++) {
		const struct row *w = &rows[i];
		double r = w->held[0].max_ferr / w->held[which].max_ferr;
		int sound = w->m.pm_deg >= SEARCH_MIN_PM && !w->autot.unstable &&
			    !w->init.unstable && !w->held[0].unstable;

		ok_held &= sound && r <= WITHIN;
		printf("%s%s %.3f", i ? ", " : "", cases[i].name, r);
	}
	printf(" -> %s\n", ok_held ? "MET" : "NOT MET");
}

void report_table(const struct plant_case *cases, const struct row *rows,
		  unsigned int n)
{
	printf("Auto-tuning benchmark: sh2000-tune --auto (default bandwidth, phase margin %g deg)\n"
	       "against a search over kp, ti, td, kvff, kaff (grids, then local searches); the card model\n"
	       "in virtual time.\n\n", TUNE_DEFAULT_MARGIN);
	printf("Identification (axis x): true vs identified\n");
	printf("%-12s %12s %12s %10s  %9s %9s %10s  %5s %9s\n", "plant", "g true",
	       "g ident", "error", "b/m true", "b/m ident", "error", "delay", "resid");
	for (unsigned int i = 0; i < n; i++)
		print_ident(&cases[i], &rows[i]);
	printf("(g: counts/s^2 per DAC code; b/m: 1/s; delay: servo cycles; resid: counts RMS)\n\n");
	print_moves(cases, rows, n);
	print_check(cases, rows, n);
	printf("\nGains (x) and their predicted margins on the true plant:\n");
	for (unsigned int i = 0; i < n; i++) {
		const struct row *w = &rows[i];

		printf("  %s (CPU %.1f s; the grids' best by one run: %.2f, admissible %.2f)\n",
		       cases[i].name, w->cpu_s, w->sb.grid_any, w->sb.grid_pm);
		print_gains("tuned", &w->tuned, &w->m, NULL);
		print_gains("best", &w->sb.any.g, &w->sb.any.mg, w->sb.any.from);
		print_gains("best45", &w->sb.pm.g, &w->sb.pm.mg, w->sb.pm.from);
		print_gains("own", &w->sb.own.g, &w->sb.own.mg, NULL);
	}
	printf("\nTarget: tuned within 10 %% of the best (ratio tuned / best <= %.2f), PM >= %g deg, nothing\n"
	       "unstable; the ratio of the worst runs:\n", WITHIN, SEARCH_MIN_PM);
	verdict("  within 10 % of the best with PM >= 45 deg (best45)", cases, rows, n, 2);
	verdict("  within 10 % of the best of any PM (best)", cases, rows, n, 1);
}
