/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune AXIS --gantry --auto: the gantry pair's coupling gains
 * (gantry_kp, _ti, _td) chosen on the pair itself. The coupling's plant
 * is the beam's yaw between two closed loops, the carriage's place
 * shifting it: rather than a model of it, the search measures what it
 * is asked to cut, the peak skew of the pair's ramp (gantry.c: the sides'
 * following errors' difference, the card's skew), for each candidate.
 * From the card's gains (or a seed when its gantry_kp is 0) it steps
 * each gain up and down by a factor (4, then 2, then sqrt 2) and keeps a
 * candidate that cuts the best peak by 2 % or more and holds with margin:
 *  - its own ramp ends without the following-error bound (kept under a
 *    quarter of the skew limit: the skew, the difference of the two
 *    sides' errors, stays under half of it, so a loop that does not hold
 *    trips the bound before the skew fault, with room for what a ringing
 *    pair does when the search takes its gains back; the card disables
 *    both sides at the trip, the pair comes to rest and goes back to its
 *    start with the card's gains, ramp.c's undo);
 *  - the ramp at a tenth of the speed with gantry_kp raised by the gain
 *    margin asked (--gain-margin, default 8 dB) ends without it too, and its skew at
 *    rest after the ramp is within a quarter of its peak (or the settling
 *    band), twice: the loop is stable with that much more gain, a gain
 *    margin measured on the machine.
 * The integral time stays at one servo period or more. Nothing
 * acceptable (every candidate tripped or lacked the margin, or
 * none cut the uncoupled peak): refused, with which. An uncoupled peak
 * under TUNE_SETTLE_COUNTS (the carriage where it loads both sides
 * alike) leaves nothing to cut: refused before any candidate, as a zero
 * peak would otherwise be "cut" to zero by every one of them. --apply writes the
 * three gains, all or none.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tune.h"

/* The search's start when the card's gantry_kp is 0: DAC codes per count
 * of skew, s, s (the card model's gantry takes kp 5, ti 5 ms, td 2 ms). */
static const double seed[3] = { 1.0, 0.01, 0.001 };
/* The raised-gain ramps a kept candidate must hold on, each alike. A
 * loop near the edge of its margin settles or rings by how the ramp
 * happened to excite it (a count's timing on a served card): once, a
 * candidate that rang 272 counts in one run held in another, and the
 * search, stuck beside it, chose 37 counts where other runs chose 4. */
#define GA_MARGIN_RUNS	2
/* The ramps the search may take (each candidate one to three). */
#define GA_MAX_RAMPS	100
/* A candidate must cut the best peak to this share. */
#define GA_BETTER	0.98
/* The raised-gain ramp's speed: the search's divided by this. Whether a
 * loop holds does not depend on the speed, and one that does not trips
 * the bound while the pair is slow: disabled by the fault, it coasts
 * little, and the way back to the start can take it. */
#define GA_MARGIN_SLOWER	10.0
/* The raised-gain ramp's skew at rest, at most this share of its peak. */
#define GA_SETTLED	0.25
/* The following-error bound of the search's ramps, this share of half
 * the skew limit at most: a quarter of it. At 0.9 (both errors within
 * the bound kept the skew just under the limit) a candidate whose pair
 * still rang at the ramp's end latched SKEW when the gains went back
 * (gantry_kp 0 drops the coupling's output at once): a skew limit of
 * 8000 counts did. */
#define GA_FERR_SHARE	0.45

struct ga_search {
	struct sh2000 *h;
	struct tune_opts g;	/* the pair's ramps (tune_gantry_measure) */
	struct tune_gantry *p;
	double raise;		/* gantry_kp's factor for the margin */
	double servo_s;		/* the card's servo period */
	unsigned int ramps;
	double best[3], best_peak;
	/* where the steps go from until a candidate is kept: the card's
	 * gains, or the seed when its gantry_kp is 0 */
	double start[3];
	unsigned int tripped, no_margin, worse;
};

/* The margin check of gains k whose ramp peaked at peak: *ok 1 when the
 * raised loop held and settled; an exit code. */
static int margin_holds(struct ga_search *s, const double k[3], int *ok)
{
	double up[3] = { k[0] * s->raise, k[1], k[2] }, peak, tail;
	struct tune_opts slow = s->g;
	int r;

	*ok = 0;
	if (sh2000_param_in_range(sh2000_param_lookup(SH2000_GP_GANTRY_KP), up[0]))
		up[0] = sh2000_param_lookup(SH2000_GP_GANTRY_KP)->max;
	slow.ramp_mms /= GA_MARGIN_SLOWER;
	slow.travel_mm = 0;	/* the slow ramp's own */
	for (unsigned int i = 0; i < GA_MARGIN_RUNS; i++) {
		s->ramps++;
		r = tune_gantry_ramp(s->h, &slow, s->p, up, &peak, &tail);
		if (r == SH2000_EXIT_ABORTED)
			return 0;
		if (r)
			return r;
		if (tail > fmax(TUNE_SETTLE_COUNTS, GA_SETTLED * peak)) {
			printf("tried                   kp %g ti %g td %g: raised kp x%.2f still %.1f counts apart at rest\n",
			       k[0], k[1], k[2], s->raise, tail);
			return 0;
		}
	}
	*ok = 1;
	return 0;
}

/* One candidate: *ok 1 when it is the best so far and holds; an exit
 * code. */
static int try_gains(struct ga_search *s, const double k[3], int *ok)
{
	double peak;
	int r;

	*ok = 0;
	for (unsigned int i = 0; i < 3; i++)
		if (sh2000_param_in_range(sh2000_param_lookup(tune_gantry_gain_ids[i]), k[i]))
			return 0;
	/* an integral faster than a servo period steps more per cycle than
	 * the proportional part: the discrete law is no PID any more */
	if (k[1] > 0 && k[1] < s->servo_s)
		return 0;
	if (s->ramps + 1 + GA_MARGIN_RUNS > GA_MAX_RAMPS)
		return 0;
	s->ramps++;
	r = tune_gantry_ramp(s->h, &s->g, s->p, k, &peak, NULL);
	if (r == SH2000_EXIT_ABORTED) {
		s->tripped++;
		printf("tried                   kp %g ti %g td %g: tripped the bound\n",
		       k[0], k[1], k[2]);
		return 0;
	}
	if (r)
		return r;
	if (peak > GA_BETTER * s->best_peak) {
		s->worse++;
		printf("tried                   kp %g ti %g td %g: peak skew %.1f counts, not below %.1f\n",
		       k[0], k[1], k[2], peak, GA_BETTER * s->best_peak);
		return 0;
	}
	if ((r = margin_holds(s, k, ok)))
		return r;
	if (!*ok) {
		s->no_margin++;
		return 0;
	}
	memcpy(s->best, k, sizeof(s->best));
	s->best_peak = peak;
	printf("candidate               kp %g ti %g td %g: peak skew %.1f counts, holds with kp x%.2f\n",
	       k[0], k[1], k[2], peak, s->raise);
	return 0;
}

/* One round of steps by factor f around the best: *better 1 when one
 * of them was kept; an exit code. */
static int round_of(struct ga_search *s, double f, int *better)
{
	int r = 0, ok;

	*better = 0;
	for (unsigned int i = 0; !r && i < 3; i++)
		for (int d = 0; !r && d < 2; d++) {
			double k[3];

			/* none kept yet: around the start (before, the seed
			 * alone, tried again and again when the card's
			 * gains lacked the margin) */
			memcpy(k, s->best[0] > 0 ? s->best : s->start, sizeof(k));
			if (k[i] == 0)
				k[i] = d ? 0 : seed[i];
			else
				k[i] = d ? k[i] / f : k[i] * f;
			if (k[0] == s->best[0] && k[1] == s->best[1] &&
			    k[2] == s->best[2])
				continue;
			r = try_gains(s, k, &ok);
			*better |= ok;
		}
	return r;
}

static int search(struct ga_search *s)
{
	static const double steps[] = { 4.0, 2.0, M_SQRT2 };
	int r = 0, ok = 0, better;

	memcpy(s->start, s->p->gains[0] > 0 ? s->p->gains : seed,
	       sizeof(s->start));
	r = try_gains(s, s->start, &ok);
	for (size_t f = 0; !r && f < sizeof(steps) / sizeof(steps[0]); f++)
		do
			r = round_of(s, steps[f], &better);
		while (!r && better && s->ramps + 1 + GA_MARGIN_RUNS <= GA_MAX_RAMPS);
	return r;
}

static void report(const struct ga_search *s)
{
	const struct tune_gantry *p = s->p;
	double um = 1e3 / p->counts_per_mm;

	printf("chosen                  kp %g ti %g td %g (%u ramps)\n",
	       s->best[0], s->best[1], s->best[2], s->ramps);
	printf("gain margin             holds with gantry_kp x%.2f (%g dB)\n",
	       s->raise, s->g.gm_db);
	printf("peak skew, chosen       %.1f counts  %.4f um\n", s->best_peak,
	       s->best_peak * um);
	printf("peak skew, uncoupled    %.1f counts  %.4f um  (chosen cut %.1fx)\n",
	       p->uncoupled, p->uncoupled * um,
	       p->uncoupled / fmax(s->best_peak, 1));
	if (isnan(p->coupled))
		printf("peak skew, card's       not measured: the card's gantry_kp is 0\n");
	else
		printf("peak skew, card's       %.1f counts  %.4f um  (kp %g ti %g td %g)\n",
		       p->coupled, p->coupled * um, p->gains[0], p->gains[1],
		       p->gains[2]);
}

/* --apply: the three gains written, or none (the card's put back). */
static int apply(struct ga_search *s)
{
	int r = tune_gantry_set_gains(s->h, s->best);

	if (r < 0) {
		tune_gantry_set_gains(s->h, s->p->gains);
		return sh2000_tool_fail(s->h, r, "writing the coupling's gains (none written)");
	}
	memcpy(s->p->gains, s->best, sizeof(s->best));
	printf("written                 gantry_kp %g gantry_ti %g gantry_td %g\n",
	       s->best[0], s->best[1], s->best[2]);
	return 0;
}

static int refuse(const struct ga_search *s)
{
	sh2000_tool_msg("%s: --gantry --auto: no coupling gains acceptable (nothing written): of the candidates tried in %u ramps, %u tripped the following-error bound %g mm (kept under a quarter of the skew limit), %u did not hold with gantry_kp x%.2f (the gain margin %g dB), %u did not cut the peak skew below %.1f counts",
			sh2000_device(s->h), s->ramps, s->tripped, s->g.ferr_max_mm,
			s->no_margin, s->raise, s->g.gm_db, s->worse,
			GA_BETTER * s->p->uncoupled);
	return SH2000_EXIT_CARD;
}

/* The card's servo period into s->servo_s: an exit code. */
static int servo_period(struct ga_search *s)
{
	double us, fine;
	int r = sh2000_param_get(s->h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US, &us);

	if (r >= 0)
		r = sh2000_param_get(s->h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, &fine);
	if (r < 0)
		return sh2000_tool_fail(s->h, r, "servo period");
	s->servo_s = us * 1e-6 / fine;
	return 0;
}

/* Search, report, write: an exit code (the pair enabled, its baseline
 * measured). */
static int choose(struct ga_search *s, const struct tune_opts *o)
{
	double half = 0.5 * s->p->limit / s->p->counts_per_mm * GA_FERR_SHARE;
	int r;

	if ((r = servo_period(s)))
		return r;
	if (s->p->uncoupled < TUNE_SETTLE_COUNTS) {
		sh2000_tool_msg("%s: --gantry --auto: the uncoupled ramp's peak skew is %.1f counts, under %g: nothing for the coupling to cut, no gains chosen (nothing written); run it with the carriage where it loads one side most",
				sh2000_device(s->h), s->p->uncoupled, TUNE_SETTLE_COUNTS);
		return SH2000_EXIT_CARD;
	}
	s->g.gantry_safe = s->p->gains;
	if (half < s->g.ferr_max_mm)
		s->g.ferr_max_mm = half;
	s->raise = pow(10, s->g.gm_db / 20);
	s->best_peak = s->p->uncoupled;
	if ((r = search(s)))
		return r;
	if (s->best[0] == 0)
		return refuse(s);
	report(s);
	if (o->apply)
		return apply(s);
	printf("not written             (%s)\n",
	       o->dry_run ? "--dry-run" : "--apply writes them");
	return 0;
}

int tune_run_gantry_auto(struct sh2000 *h, const struct tune_opts *o)
{
	struct tune_gantry p;
	struct ga_search s = { .h = h, .p = &p };
	int r = tune_gantry_measure(h, o, &p, &s.g);

	if (!r) {
		tune_gantry_report(&p);
		r = choose(&s, o);
	}
	if ((!r || r == SH2000_EXIT_ABORTED || r == SH2000_EXIT_CARD) &&
	    !isnan(p.start[0]) &&
	    (tune_check_back(h, p.a, p.start[0]) ||
	     tune_check_back(h, p.b, p.start[1])))
		r = SH2000_EXIT_CARD;
	tune_gantry_end(h, &p);
	return r;
}
