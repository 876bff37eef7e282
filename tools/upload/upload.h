/* SPDX-License-Identifier: MIT */
/*
 * sh2000-upload's parts: the trace and the plot (trace.c), progress and summary
 * (report.c). main.c is the order of things; sh2000-upload(1) the manual.
 */
#ifndef SH2000_UPLOAD_H
#define SH2000_UPLOAD_H

#include <stdint.h>
#include <stdio.h>

#include <sh2000/path.h>
#include <sh2000/run.h>

#include <sh2000/program.h>
#include "toolcommon.h"

/* Exit codes beyond the shared ones of toolcommon.h (0..4). */
enum {
	UPLOAD_EXIT_PROGRAM = 5,	/* the program has errors: nothing moved */
	UPLOAD_EXIT_HELPER = 6,		/* rs274 or gnuplot missing or failed */
	UPLOAD_EXIT_STOPPED = 7,	/* the operator stopped the run */
};

/* ---- trace.c ---------------------------------------------------------- */

struct upl_trace;

/* csv: the --trace file (NULL: none), every: keep every n-th sample;
 * plot: collect plot data too. NULL and a message on failure. */
struct upl_trace *upl_trace_open(const char *csv, unsigned int every,
				 int plot, char *msg, size_t len);
void upl_trace_sample(struct upl_trace *t, const struct sh2000_run_sample *s);
/* Closes the CSV; 0 or -errno (a write failed). */
int upl_trace_close_csv(struct upl_trace *t);
uint64_t upl_trace_rows(const struct upl_trace *t);
/* Draw the plot with gnuplot; 0 or an exit code, message printed. */
int upl_trace_plot(struct upl_trace *t, const char *out, const char *title);
void upl_trace_free(struct upl_trace *t);

/* A program on $PATH: 1 if found. */
int upl_which(const char *prog);

/* ---- report.c --------------------------------------------------------- */

struct upl_report {
	const struct sh2000_program *prog;	/* for the line being run */
	int bar;		/* a progress bar (stderr is a terminal) */
	int quiet;		/* no progress at all */
	uint64_t total_points;	/* planned */
	int last_pct;
	uint64_t last_ns;	/* wall clock of the last bar update */
};

void upl_report_progress(struct upl_report *rp,
			 const struct sh2000_run_progress *p);
void upl_report_end(struct upl_report *rp);

#endif /* SH2000_UPLOAD_H */
