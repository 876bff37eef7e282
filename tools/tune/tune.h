/* SPDX-License-Identifier: MIT */
/* sh2000-tune's internal interface: the options, the test moves on the card
 * (testmove.c: what they share; step.c, ramp.c, chirp.c), their figures
 * (metrics.c, freqresp.c, margins.c) and pictures (plot.c, plotbode.c). */
#ifndef SH2000_TUNE_H
#define SH2000_TUNE_H

#include <complex.h>
#include <stddef.h>
#include <stdint.h>

#include <sh2000/path.h>
#include <sh2000/sh2000.h>

#include "toolcommon.h"

/* The settling band of the report, counts. */
#define TUNE_SETTLE_COUNTS 10.0

/* Which test the options ask for. */
enum tune_test { TUNE_TEST_STEP, TUNE_TEST_RAMP, TUNE_TEST_CHIRP };

struct tune_opts {
	const char *device_arg;
	unsigned int axis;
	int test;		/* enum tune_test */
	double step_mm;		/* signed */
	double ramp_mms;	/* --ramp: signed set-point speed, mm/s */
	double travel_mm;	/* --travel: the window from the start; 0:
				 * the ramp's default (tune_ramp_travel) */
	double f0_hz, f1_hz;	/* --chirp F0:F1 */
	double amplitude_mm;	/* --amplitude of the chirp */
	double duration_s;	/* --duration of the chirp */
	double accel_mms2;	/* --accel bound of the chirp; 0: chirp.c's */
	double vmax;		/* mm/s the step's set-point may reach; 0: card's */
	int dac_max;		/* |DAC code| during the test; 0: card's limit */
	double ferr_max_mm;	/* following-error limit during the test */
	double hold_s;		/* time at the step before going back */
	int enable;		/* enable the axis for the test, disable after */
	/* axes that take the axis' test moves too, each from its own
	 * set-point, with the same bounds (the gantry test: the pair's other
	 * side); 0 none */
	unsigned int follow;
	int gantry;		/* --gantry: the pair's ramp, coupled or not */
	/* the coupling's gains (kp, ti, td) put on the card after a fault,
	 * before the way back, when a ramp tries gains that may not hold
	 * (--gantry --auto); NULL: none changed */
	const double *gantry_safe;
	const char *csv;	/* the record as CSV, or NULL */
	const char *plot;	/* PNG or SVG, or NULL */
	/* --auto (autotune.h): identify, design, then write or not; its
	 * excitation stays within start +- travel_mm */
	int autotune;
	double bandwidth_hz;	/* 0: the design's default */
	double margin_deg;	/* phase margin asked, degrees */
	double gm_db;		/* the least gain margin, dB */
	int apply, dry_run;
	const char *save;	/* parameter file, or NULL */
};

/* A gathered step: times (s, 0 at the step's first set-point change) and
 * set-point, encoder and DAC per sample, counts and DAC codes. */
struct tune_trace {
	size_t n;
	double *t, *sp, *enc, *dac;
	double start, end;	/* set-point before and after the step */
};

struct tune_metrics {
	double rise_s;		/* encoder 10 % -> 90 % of the step */
	double overshoot;	/* counts beyond the end (>= 0) */
	double overshoot_pct;	/* of the step */
	double settle_s;	/* from the step until the encoder stays
				 * within TUNE_SETTLE_COUNTS of the end */
	int settled;		/* 0: it never stayed in the band */
	double peak_ferr;	/* max |set-point - encoder|, counts */
	double peak_dac;	/* max |DAC code| */
};

/* The figures of a step in tr (n >= 2, end != start). 0, or -1 when the
 * encoder never crossed 90 % of the step (no rise time). */
int tune_metrics(const struct tune_trace *tr, struct tune_metrics *m);

/* Run the step test on h: exit code (0, SH2000_EXIT_ABORTED, or another
 * with the message printed); *tr filled on 0, tr->start (the axis' start
 * set-point) also on SH2000_EXIT_ABORTED. */
int tune_step(struct sh2000 *h, const struct tune_opts *o,
	      struct tune_trace *tr);
void tune_trace_free(struct tune_trace *tr);

/* The step response as PNG or SVG (by the name's ending) through gnuplot:
 * exit code. */
int tune_plot(const struct tune_trace *tr, const struct tune_metrics *m,
	      const char *out, const char *title);

/* The chirp's defaults: amplitude (mm), duration (s), travel window (mm). */
#define TUNE_CHIRP_AMPLITUDE	0.002
#define TUNE_CHIRP_DURATION	0.8
#define TUNE_CHIRP_TRAVEL	1.0

/* ---- sh2000-tune's ramp and chirp runs (testruns.c) ---- */

/* One of the ramp's and chirp's options (getopt's c: 'r' --ramp, 'C'
 * --chirp, 't' --travel, 'A' --amplitude, 'a' --accel, 'u' --duration) into o: 0, or
 * the usage exit code with the message printed. */
int tune_parse_option(int c, const char *v, struct tune_opts *o);
/* The checks of the options together that need no card (the chirp's
 * amplitude within its travel window, its duration): 0 or exit 2. */
int tune_check_options(struct tune_opts *o);
/* What fn prints, written to path whole (through a memory stream, so a
 * failure leaves no half file): an exit code. */
int tune_write_csv(const char *path, void (*fn)(FILE *m, const void *ctx),
		   const void *ctx);
/* Run, report, write and draw the step test (note: the end of the
 * picture's title, "" or ", ..."), the ramp and chirp tests: an exit
 * code. */
int tune_run_step(struct sh2000 *h, const struct tune_opts *o, const char *note);
int tune_run_ramp(struct sh2000 *h, const struct tune_opts *o);
/* The chirp's margins also into *measured, when not NULL (on 0). */
struct tune_margins;
int tune_run_chirp(struct sh2000 *h, const struct tune_opts *o,
		   struct tune_margins *measured);

/* ---- what the test moves share (testmove.c) ---- */

/* One test move of one axis; o, h, a and name set by the test, the rest
 * by tune_move_prepare() and tune_move_lower_limits(). A test embeds it
 * first in its own context. */
struct tune_move {
	struct sh2000 *h;
	const struct tune_opts *o;
	unsigned int a;
	const char *name;	/* "step", "ramp", "chirp": in messages */
	struct sh2000_path_config pc;
	int32_t p[SH2000_AXES];	/* every axis' set-point, counts */
	int32_t start;		/* the axis' set-point before the test */
	double vlim;		/* mm/s: the user's bound and the card's */
	double ferr0, dac0;	/* the card's limits before the test */
	/* and every moving axis' (the axis' and o->follow's) */
	double ferr0s[SH2000_AXES], dac0s[SH2000_AXES];
	double dac_bound;	/* |DAC| on the card during the test */
	unsigned int enabled_by_us;	/* the axes the test enabled */
	/* what the test changed on the card beyond the limits, undone after
	 * it (after a following-error fault before the way back; NULL:
	 * nothing): an exit code */
	int (*undo)(struct tune_move *s);
	/* after a fault, before the reset: what keeps the card's own loops
	 * from going on as the test set them (the gantry search's gains
	 * that may not hold); NULL: nothing. An exit code. */
	int (*calm)(struct tune_move *s);
};

int tune_move_fail(struct tune_move *s, int r, const char *what);
/* The card idle and unfaulted, the axis enabled (by --enable), the path
 * configuration and the start read: an exit code, nothing moved. */
int tune_move_prepare(struct tune_move *s);
/* The user's following-error and DAC bounds on the card, all or none. */
int tune_move_lower_limits(struct tune_move *s);
/* The card's limits back as they were. */
int tune_move_restore(struct tune_move *s);
/* n coarse points: the axis at v[i], the other axes where they are; the
 * last batch with flags. A library code. */
int tune_move_push(struct tune_move *s, const int32_t *v, unsigned int n,
		   unsigned int flags);
/* n coarse points with the axis at v. */
int tune_move_hold(struct tune_move *s, int32_t v, unsigned int n,
		   unsigned int flags);
/* Arm a record of the axis' signals (1u << SH2000_GS_*) on the next
 * motion, a few samples before it and span_s after, every servo cycle if
 * the card's memory holds that many (else every few): an exit code. */
int tune_move_arm(struct tune_move *s, unsigned int signals, double span_s,
		  unsigned int *rec);
/* Wait for the record and read it whole into *values (malloc'd, free
 * it): an exit code. */
int tune_move_read(struct tune_move *s, unsigned int rec,
		   struct sh2000_gather_info *gi, double **values);
/* Arm the record (tune_move_arm), move(s) (pushes, waits until idle: a
 * library code), then undo and the limits back, whatever happened; after
 * a following-error fault the axis back at its start (SH2000_EXIT_ABORTED):
 * an exit code. */
int tune_move_run(struct tune_move *s, unsigned int signals, double span_s,
		  unsigned int *rec, int (*move)(struct tune_move *s));
/* The axis' set-point is back at start (printed): an exit code. */
int tune_check_back(struct sh2000 *h, unsigned int axis, double start);
/* The axis disabled again if the test enabled it. */
void tune_move_end(struct tune_move *s);

/* ---- the ramp test (ramp.c) ---- */

/* A gathered ramp: times (s, 0 at the motion's start), set-point,
 * encoder, following error (the card's) and DAC per sample, and which
 * samples are at constant speed. */
struct tune_ramp {
	size_t n;
	double *t, *sp, *enc, *ferr, *dac;
	/* with a follower (o->follow, one axis): the axis' following error
	 * minus the follower's, as the card's gantry loop has it; else NULL */
	double *skew;
	unsigned char *cruise;	/* 1: the set-point at the ramp's speed */
	double start;		/* counts */
	double counts_per_mm;
	double speed_mms, travel_mm, accel_mms2;
	/* the figures (counts): constant speed, and while the set-point
	 * accelerates or decelerates */
	double cruise_peak, cruise_rms, accel_peak;
	size_t cruise_n;
	double peak_dac;
	double skew_peak;	/* max |skew| over the record, counts */
};

/* The default travel of a ramp at v mm/s accelerating at a mm/s^2: room
 * to reach the speed, hold it for at least 50 ms and stop. */
double tune_ramp_travel(double v, double a);
/* Run the ramp test on h: an exit code as tune_step's; *rp filled on 0. */
int tune_ramp(struct sh2000 *h, const struct tune_opts *o,
	      struct tune_ramp *rp);
/* The figures of rp from its samples and cruise marks. */
void tune_ramp_figures(struct tune_ramp *rp);
void tune_ramp_free(struct tune_ramp *rp);
/* Following error and set-point speed of a ramp as PNG or SVG. */
int tune_plot_ramp(const struct tune_ramp *rp, const char *out,
		   const char *title);

/* ---- the gantry test (gantry.c) ---- */

/* The card's gantry pair and what its ramps measured. */
struct tune_gantry {
	unsigned int a, b;	/* the sides, a < b */
	double gains[3];	/* gantry_kp, _ti, _td as the card has them */
	double limit;		/* gantry_skew_limit, counts */
	double start[2];	/* the sides' set-points before, counts */
	/* the peak skew (counts) with the card's gains (NAN when its
	 * gantry_kp is 0) and with none */
	double coupled, uncoupled;
	double speed_mms, travel_mm, accel_mms2, counts_per_mm;
	unsigned int enabled_by_us;	/* sides --enable enabled */
};

/* The pair of which o->axis is a side ramps (o->ramp_mms, default 100
 * mm/s; o->travel_mm) coupled, then uncoupled, the gains put back: an
 * exit code as tune_ramp's; *p filled on 0. The sides --enable enabled
 * stay enabled until tune_gantry_end (always call it). */
int tune_gantry(struct sh2000 *h, const struct tune_opts *o,
		struct tune_gantry *p);
void tune_gantry_end(struct sh2000 *h, struct tune_gantry *p);
/* tune_gantry, and *g the options of the pair's ramps it took (side a
 * ramping, side b following) for more of them. */
int tune_gantry_measure(struct sh2000 *h, const struct tune_opts *o,
			struct tune_gantry *p, struct tune_opts *g);
/* One ramp of the pair (g from tune_gantry_measure) with the coupling gains
 * gains (kp, ti, td): its peak skew into *peak, the largest over the
 * record's last 25 ms (at rest) into *tail when not NULL (counts), the
 * ramp's figures into p; p->gains put back on the card whatever
 * happened: an exit code as tune_ramp's. */
int tune_gantry_ramp(struct sh2000 *h, const struct tune_opts *g,
		     struct tune_gantry *p, const double gains[3],
		     double *peak, double *tail);
/* The coupling's gains' parameters: gantry_kp, _ti, _td. */
extern const unsigned int tune_gantry_gain_ids[3];
/* The coupling's gains (kp, ti, td) on the card: a library code. */
int tune_gantry_set_gains(struct sh2000 *h, const double g[3]);
/* --gantry --auto (gantryauto.c): the coupling's gains chosen on the
 * pair by its ramps, reported, written with --apply: an exit code. */
int tune_run_gantry_auto(struct sh2000 *h, const struct tune_opts *o);
/* The undo of a ramp with o->gantry_safe: those gains on the card. */
int tune_gantry_undo(struct tune_move *s);
/* Its calm after a fault: the pair uncoupled (gantry_kp 0 also drops
 * the coupling's held output), the undo after the reset couples it
 * again. */
int tune_gantry_calm(struct tune_move *s);
/* tune_gantry's figures printed. */
void tune_gantry_report(const struct tune_gantry *p);
/* tune_gantry, reported, both sides checked back at their start. */
int tune_run_gantry(struct sh2000 *h, const struct tune_opts *o);

/* ---- the swept sine and the frequency response (chirp.c, freqresp.c,
 * margins.c) ---- */

/* Frequencies a response holds at most. */
#define TUNE_FR_MAX 64
/* Frequencies of the response by default (log-spaced over F0..F1). */
#define TUNE_FR_POINTS 48

/* The card's controller gains (its units: DAC codes per count, s). */
struct tune_gains {
	double kp, ti, td, kvff, kaff;
};

/* A measured frequency response. The complex responses are at hz[i]:
 *   plant  P = encoder / DAC        counts per DAC code
 *   closed T = encoder / set-point  (with the card's feed-forward)
 *   ctrl   C = the card's PID, DAC codes per count of following error,
 *              exact from its discrete law and the gains read from it
 *   loop   L = C P (the loop broken at the following error) */
struct tune_fr {
	size_t n;
	double hz[TUNE_FR_MAX];
	double complex plant[TUNE_FR_MAX], closed[TUNE_FR_MAX];
	double complex ctrl[TUNE_FR_MAX], loop[TUNE_FR_MAX];
	struct tune_gains gains;
	double servo_s;		/* the card's servo period */
	double sample_s;	/* the record's sample period */
	double coarse_s;	/* the card's coarse period */
	double sweep_coarse_s;	/* the one the sweep ran at (chirptiming.c) */
	double counts_per_mm;
	double peak_dac;	/* max |DAC - its rest| in the record */
	int dac_saturated;	/* the DAC reached the test's bound */
	/* frequencies left out of the response (TUNE_FR_MIN_ERR) */
	size_t weak;
	double weak_lo_hz, weak_hi_hz;
};

/*
 * A frequency's plant counts as measured when the DAC's response to the
 * set-point there is at least what the PID gives for this much following
 * error, counts: below it the PID's answer to the encoder's quantisation
 * (a count) drowns it. On the card model's default plant, the tuned gains
 * (feed-forward, a high integral gain) put 5..25 Hz of a 5..3000 Hz chirp
 * at 0.002..0.03 with the plant 2..31 dB off, and everything at 0.05 or
 * more within 0.15 dB; the default gains are at 0.77 or more everywhere.
 */
#define TUNE_FR_MIN_ERR 0.05

struct tune_margins {
	double gm_db;		/* gain margin: how much the loop gain may
				 * rise before the loop is unstable, dB at
				 * w180_hz; NAN: no such crossing measured */
	double pm_deg;		/* phase margin at wc_hz */
	double wc_hz;		/* crossover: |L| = 1 (the highest) */
	double w180_hz;		/* phase -180 with |L| < 1 (the lowest) */
	double bw_hz;		/* the feedback loop L / (1 + L) -3 dB (the
				 * first drop; without the feed-forward) */
	double gm_low_db;	/* a conditionally stable loop (integral
				 * action): -180 with |L| > 1 below wc,
				 * how much the gain may FALL (<= 0 dB);
				 * NAN: none */
	double w180_low_hz;
};

/* F1 * coarse period, at most (chirptiming.c) */
#define TUNE_CHIRP_F_PERIOD 0.4

/* The card's timing before the sweep (coarse0_us, fine0), for it
 * (coarse_us, fine) and as it is now (cur_*: 0 before the first change). */
struct tune_chirp_timing {
	long coarse0_us, coarse_us;
	unsigned int fine0, fine;
};

/* The coarse period (a divisor of the card's, the servo period kept) that
 * carries a sweep up to f1_hz: 0, or -1 when none does. */
int tune_chirp_timing_plan(const struct tune_move *m, double f1_hz,
			   struct tune_chirp_timing *t);
/* Set the card's timing for the sweep (sweep = 1) or back (0), updating
 * m->pc: an exit code. */
int tune_chirp_timing_apply(struct tune_move *m, struct tune_chirp_timing *t,
			    int sweep);

/* Run the chirp test on h (o->f0_hz, f1_hz, amplitude_mm, duration_s)
 * and compute *fr: an exit code as tune_step's. */
int tune_chirp(struct sh2000 *h, const struct tune_opts *o,
	       struct tune_fr *fr);
/* The highest F1 a sweep may have at servo period servo_s (the coarse
 * period shortened to one servo cycle). */
double tune_chirp_f1_max(double servo_s);
/* The margins of fr's loop and closed loop: 0, or -1 when fr's loop never
 * crosses 0 dB in the measured band (no crossover, no phase margin; the
 * other figures are still filled, NAN where absent). */
int tune_margins(const struct tune_fr *fr, struct tune_margins *m);
/* One step of unwrapping a phase along the frequencies: ph (degrees) moved
 * by whole turns to within 180 degrees of the previous unwrapped prev. */
double tune_phase_unwrap(double prev, double ph);
/* The phase margin of a loop whose unwrapped phase at its gain crossover
 * is ph degrees: 180 + ph placed by whole turns in (-180, 180]. */
double tune_phase_margin(double ph);

/* The card's PID (pid.c's incremental law with integral and derivative,
 * the feed-forward aside) at hz, servo period tau: DAC codes per count
 * (loopmodel.c, with C(z) in its other forms). */
double complex tune_pid_response(const struct tune_gains *g, double tau,
				 double hz);
/* C(z) = Kp A + (Kp Td/tau) D at theta = w tau, the parts without Kp: A
 * the proportional and integral, D the derivative per Kp Td/tau. */
void tune_pid_parts(double tau, double ti, double th, double complex *A,
		    double complex *D);
/* C(z) = Kp (n[0] + n[1] z^-1 + n[2] z^-2) / (1 - z^-1). */
void tune_pid_numerator(const struct tune_gains *g, double tau, double n[3]);
/* The gains of axis a as the card has them: a library code. */
int tune_read_gains(struct sh2000 *h, unsigned int a, struct tune_gains *g);
/* The response of y to x (n samples each, from rest to rest) at hz[0..nf)
 * with sample period ts: sum over a few neighbouring bins of
 * Y X* / sum of |X|^2 (freqresp.c says why). */
void tune_fr_ratio(const double *x, const double *y, size_t n, double ts,
		   const double *hz, size_t nf, double complex *out);
/* n log-spaced frequencies over f0..f1 into hz. */
void tune_fr_grid(double f0, double f1, size_t n, double *hz);

/* The Bode plot (plant, loop, closed loop; margins marked) as PNG or SVG. */
int tune_plot_bode(const struct tune_fr *fr, const struct tune_margins *m,
		   const char *out, const char *title);

/* A picture of the tool: write_data(ctx) writes NAME.dat into a private
 * temporary directory, sh2000_tool_plot() draws out from it with
 * write_script, the directory is removed after. An exit code with the
 * message printed. */
int tune_gnuplot_run(const char *name, const char *out,
		     int (*write_data)(const void *ctx, const char *path),
		     sh2000_tool_plot_script write_script, const void *ctx);

/* Every picture's size in pixels. */
#define TUNE_PLOT_W	1200
#define TUNE_PLOT_H	900

#endif /* SH2000_TUNE_H */
