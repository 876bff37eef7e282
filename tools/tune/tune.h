/* SPDX-License-Identifier: MIT */
/* sh2000-tune's internal interface: the options, the step test on the card
 * (step.c), its figures (metrics.c) and its picture (plot.c). */
#ifndef SH2000_TUNE_H
#define SH2000_TUNE_H

#include <stddef.h>

#include <sh2000/sh2000.h>

#include "toolcommon.h"

/* The test was aborted (following-error limit), the axis is back at its
 * start and the parameters are as they were. */
#define TUNE_EXIT_ABORTED 5
/* gnuplot missing or failed (the figures were printed) */
#define TUNE_EXIT_HELPER 6

/* The settling band of the report, counts. */
#define TUNE_SETTLE_COUNTS 10.0

struct tune_opts {
	const char *device_arg;
	unsigned int axis;
	double step_mm;		/* signed */
	double vmax;		/* mm/s the step's set-point may reach; 0: card's */
	int dac_max;		/* |DAC code| during the test; 0: card's limit */
	double ferr_max_mm;	/* following-error limit during the test */
	double hold_s;		/* time at the step before going back */
	int enable;		/* enable the axis for the test, disable after */
	const char *csv;	/* the record as CSV, or NULL */
	const char *plot;	/* PNG or SVG, or NULL */
	/* --auto (autotune.h): identify, design, then write or not */
	int autotune;
	double travel_mm;	/* the excitation stays within start +- this */
	double bandwidth_hz;	/* 0: the design's default */
	double margin_deg;
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

/* Run the step test on h: exit code (0, TUNE_EXIT_ABORTED, or another
 * with the message printed); *tr filled on 0, tr->start (the axis' start
 * set-point) also on TUNE_EXIT_ABORTED. */
int tune_step(struct sh2000 *h, const struct tune_opts *o,
	      struct tune_trace *tr);
void tune_trace_free(struct tune_trace *tr);

/* The step response as PNG or SVG (by the name's ending) through gnuplot:
 * exit code. */
int tune_plot(const struct tune_trace *tr, const struct tune_metrics *m,
	      const char *out, const char *title);

/* The step's report, the check that the axis is back at its start (an
 * exit code) and the CSV of a trace (an exit code): main.c. */
void tune_report(const struct tune_opts *o, const struct tune_trace *tr,
		 const struct tune_metrics *m);
int tune_check_back(struct sh2000 *h, const struct tune_opts *o,
		    const struct tune_trace *tr);
int tune_write_csv(const struct tune_trace *tr, const char *path);

#endif /* SH2000_TUNE_H */
