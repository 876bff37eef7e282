/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune --auto: plant identification (ident.c on the card, identfit.c
 * the least squares), gain design (design.c, pure), writing the gains
 * all-or-nothing and as a parameter file (gains.c), and the whole flow
 * (auto.c). Kept apart from tune.h, the test moves' interface. The
 * design's predicted margins are struct tune_design_margins; the ones a
 * chirp measures, struct tune_margins (margins.c).
 */
#ifndef SH2000_TUNE_AUTOTUNE_H
#define SH2000_TUNE_AUTOTUNE_H

#include <stddef.h>

#include <sh2000/sh2000.h>

#include "tune.h"	/* struct tune_gains, struct tune_opts */

/* The dead times the identification tries, servo cycles 0..IDENT_DMAX. */
#define TUNE_IDENT_DMAX 4

/*
 * The identified plant: m a = kF u - b v with u the DAC code, the DAC held
 * over each servo cycle, and d whole servo cycles of dead time, in the
 * card's units (counts, s, DAC codes).
 */
struct tune_plant {
	double g;	/* plant gain kF/m: counts/s^2 per DAC code */
	double p;	/* friction pole b/m, 1/s (>= 0) */
	unsigned int d;	/* dead time, servo cycles */
	double T;	/* servo period, s */
	/* the fit: RMS residual of the encoder's change per cycle, counts,
	 * and against the RMS of that change (relative) */
	double resid, resid_rel;
	size_t samples;
};

/* The plant sampled over T with the DAC held (loopmodel.c): a = exp(-p T),
 * c = (1 - a)/p, e = (T - c)/p, each well computed as p T -> 0. */
void tune_plant_sample(double p, double T, double *a, double *c, double *e);
/* pl's P(z) = z^-d (b0 z + b1) / ((z - 1)(z - a)): its a, b0, b1. */
void tune_plant_z(const struct tune_plant *pl, double *a, double *b0,
		  double *b1);
/* P(z) at z = e^(j th), counts per DAC code. */
double complex tune_plant_at(const struct tune_plant *pl, double th);

/* Predicted loop figures (controller x plant incl. delay, discrete). */
struct tune_design_margins {
	double pm_deg;		/* phase margin, degrees */
	double gm_db;		/* gain margin above the crossover, dB
				 * (INFINITY: the phase never crosses -180) */
	double wc_hz;		/* gain crossover */
	double wpc_hz;		/* phase crossover of gm_db (0: none) */
	int stable;		/* closed loop stable (poles inside |z| = 1) */
};

struct tune_design_req {
	double bandwidth_hz;	/* crossover asked; 0: the default */
	double margin_deg;	/* phase margin asked */
	double gm_db;		/* the least gain margin, dB; 0: TUNE_MIN_GM_DB */
};

/* The phase margin asked by default, degrees: the commissioning floor
 * of 45 deg and half a degree for what the identified plant may differ
 * from the machine (bench_tune margins: the circle's following error
 * against the margins asked; docs/tools.md). */
#define TUNE_DEFAULT_MARGIN 45.5
/* The least gain margin the design gives by default, dB (--gain-margin):
 * at the default phase margin the best design has 9 dB or so of its own,
 * a floor of 10 would cut its crossover. */
#define TUNE_MIN_GM_DB 8.0
/* The integral time against the crossover, Ti wc, the design chooses
 * within (the integral's zero at most at the crossover: below it the RMS
 * following error grows, bench_tune bandwidth measured RMS 0.78 at 0.7,
 * 0.61 at 1, 0.58 counts at 1.5 on its circle, default plant, and no
 * clear change of the max; docs/tools.md); the crossover (theta = wc T)
 * below a quarter of the servo rate. */
#define TUNE_RATIO_MIN 1.0
#define TUNE_RATIO_MAX 20.0
#define TUNE_TH_MAX (M_PI / 2)

/* ---- identification (identfit.c: pure) ---- */

/*
 * Least squares fit of the discrete model of the plant to n samples taken
 * every servo cycle T: enc (counts) and dac (codes, the output held over
 * the cycle that follows). The dead time is searched over 0..dmax, the
 * smallest residual wins. 0, or -1 with the reason in why (too few
 * samples, no excitation, a model that is not a mass: g <= 0).
 */
int tune_ident_fit(const double *enc, const double *dac, size_t n, double T,
		   unsigned int dmax, struct tune_plant *pl, char *why,
		   size_t whylen);

/* ---- design (design.c: pure) ---- */

/* The crossover the design takes by default for this plant and margin,
 * Hz (0: none keeps the margins). */
double tune_default_bandwidth(const struct tune_plant *pl,
			      const struct tune_design_req *req);

/*
 * PID gains with the phase margin req->margin_deg at the crossover
 * req->bandwidth_hz (0: the crossover is chosen too), a gain margin of at
 * least TUNE_MIN_GM_DB and a stable closed loop, with the highest
 * integral gain Kp/Ti (the least following error on a path, see
 * design.c); the plant's exact inverse as feed-forward (kaff = 1/g,
 * kvff = p/g). *m gets the predicted margins. 0, or -1 with the reason
 * in why (no PID keeps the margins at that bandwidth): the gains are then
 * not to be used.
 */
int tune_design(const struct tune_plant *pl, const struct tune_design_req *req,
		struct tune_gains *gn, struct tune_design_margins *m, char *why,
		size_t whylen);

/* A crossover of hz Hz at servo period T is one the design may give (0),
 * or -1 with the reason in why: the design's own rule, which --auto also
 * checks before anything moves. */
int tune_bandwidth_check(double hz, double T, char *why, size_t whylen);

/* The predicted margins of gains gn on plant pl (the card's discrete PID
 * in its exact form, the plant with its delay). */
void tune_margins_of(const struct tune_plant *pl, const struct tune_gains *gn,
		     struct tune_design_margins *m);

/* ---- the card's gains (gains.c) ---- */

/*
 * Write all five gains of axis a or none: when one set fails, the ones
 * already written are put back to old and the error is returned, the
 * library's message about it in why.
 */
int tune_gains_set(struct sh2000 *h, unsigned int a,
		   const struct tune_gains *gn, const struct tune_gains *old,
		   char *why, size_t whylen);
/* The gains as a parameter file section "[x]" that `sh2000ctl params
 * load` reads; written with the tools' shared parameter-file writer. An
 * exit code. */
int tune_gains_save(const char *path, const char *device, unsigned int a,
		    const struct tune_gains *gn);

/* ---- the whole flow (auto.c) ---- */

/* The step of the check after --apply when --step is not given, mm. */
#define TUNE_AUTO_STEP_MM 0.01
/* The identification's travel window from the start when --travel is
 * not given, mm. */
#define TUNE_AUTO_TRAVEL_MM 0.1
/* The chirp of the check with --plot: from the predicted crossover / this
 * (at least 1 Hz) to the crossover * this (where the gain margin lies), */
#define TUNE_AUTO_CHIRP_SPAN 6.0
/* and below this share of the highest F1 the servo period permits */
#define TUNE_AUTO_CHIRP_TOP 0.9

/* sh2000-tune --auto on h with o: an exit code. */
int tune_auto(struct sh2000 *h, const struct tune_opts *o);

#endif /* SH2000_TUNE_AUTOTUNE_H */
