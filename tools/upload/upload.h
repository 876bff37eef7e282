/* SPDX-License-Identifier: MIT */
/*
 * sh2000-upload's parts: the command line (options.c), the program and
 * its diagnostics and tool table (source.c), LinuxCNC's rs274 run on it
 * (rs274.c), the run's callbacks, pauses and failures
 * (execute.c), the trace and the plot (trace.c), progress (report.c).
 * main.c is the order of things; sh2000-upload(1) the manual. The work
 * itself -- reading, checking, planning and streaming the program -- is
 * libsh2000-motion's (sh2000/run.h).
 */
#ifndef SH2000_UPLOAD_H
#define SH2000_UPLOAD_H

#include <signal.h>
#include <stdint.h>
#include <stdio.h>

#include <sh2000/path.h>
#include <sh2000/program.h>
#include <sh2000/run.h>

#include "toolcommon.h"

/* ---- options.c -------------------------------------------------------- */

struct upl_opts {
	const char *device;
	const char *file;
	enum sh2000_prog_format format;
	int rs274;
	const char *tool_table;		/* --tool-table (NULL: none) */
	const char *parameter_file;	/* --parameter-file, for rs274 */
	int pause_tool_change;
	const char *trace;
	unsigned int trace_every;
	const char *plot;
	int dry_run, raw, optional_stop, no_enable, quiet, trapezoid;
	double override;	/* factor */
	double feed_mm_min;	/* for CSV and JSON without their own */
	double tolerance;	/* mm; 0: the planner's default */
};

/* 0, or an exit code (the message printed); --help and --version exit. */
int upl_parse(int argc, char **argv, struct upl_opts *o);

/* ---- source.c --------------------------------------------------------- */

struct upl_source {
	struct sh2000_prog_reader *reader;
	struct sh2000_prog_diags diags;
	struct sh2000_tool_table tools;	/* --tool-table's (empty: none) */
	char dir[64];		/* --rs274's temporary directory */
	char canon[128];	/* and its output in it */
};

/* Open the program (reading the tool table, and running rs274 first with
 * --rs274): 0 or an exit code, the reason printed. upl_source_close() in
 * any case. */
int upl_source_open(struct upl_source *s, const struct upl_opts *o,
		    const double start[SH2000_AXES]);
/* rs274.c: rs274 -g -t DIR/tool.tbl -v DIR/params.var FILE >
 * DIR/rs274.canon in a new temporary DIR (s->dir, s->canon); 0 or an exit
 * code, the reason printed. */
int upl_rs274_run(const struct upl_opts *o, struct upl_source *s);
/* Remove that directory (unless s->dir was emptied to keep it). */
void upl_rs274_clean(struct upl_source *s);
/* Print the program's errors: SH2000_EXIT_INPUT. */
int upl_source_errors(struct upl_source *s, const struct upl_opts *o);
void upl_source_close(struct upl_source *s);

/* ---- execute.c -------------------------------------------------------- */

extern volatile sig_atomic_t upl_resume_flag, upl_hold_flag;

struct upl_trace;

/* upl_report: progress while the card runs (report.c) */
struct upl_report {
	int bar;		/* a progress bar (stderr is a terminal) */
	int quiet;		/* no progress at all */
	uint64_t total_points;	/* planned */
	int last_pct;
	uint64_t last_ns;	/* wall clock of the last bar update */
};

struct upl_runctx {
	struct sh2000 *h;
	struct sh2000_run *run;
	struct upl_trace *trace;
	struct upl_report rep;
	int stop_sent, estop_sent;
	int holding;		/* a feed hold is on */
	int stdin_eof;
	int pause_error;	/* the card failed while paused */
	const struct sh2000_tool_table *tools;	/* for tool change prompts */
	int64_t seq;		/* the line the card was at, last poll */
};

/* SIGINT/SIGTERM stop on the path (a second: estop), SIGUSR2 holds the
 * feed, SIGUSR1 resumes (a hold or an M0). */
void upl_signals(void);
void upl_on_sample(void *ctx, const struct sh2000_run_sample *s);
void upl_on_progress(void *ctx, const struct sh2000_run_progress *p);
/* sh2000_program_pause_fn: wait at rest for the operator. */
int upl_pause(void *ctx, const struct sh2000_prog_block *b);
/* What a failed run says; the exit code. */
int upl_run_fail(const struct upl_runctx *rc, const char *file, int e);
/* Enable the axes in need that are not (unless --no-enable). */
int upl_enable_axes(struct sh2000 *h, const struct upl_opts *o,
		    unsigned int need);
/* "x y a" for a mask of axes; buf holds 8. */
void upl_axes_text(unsigned int mask, char *buf);

/* ---- trace.c ---------------------------------------------------------- */

/* csv: the --trace file (NULL: none), every: keep every n-th sample;
 * plot: collect plot data too. NULL and a message on failure. The file is
 * opened, not yet written: a user's file keeps its contents until
 * upl_trace_start(). */
struct upl_trace *upl_trace_open(const char *csv, unsigned int every,
				 int plot, char *msg, size_t len);
/* The run begins: the file is emptied and gets its header. 0 or -errno. */
int upl_trace_start(struct upl_trace *t);
void upl_trace_sample(struct upl_trace *t, const struct sh2000_run_sample *s);
/* Closes the CSV; 0 or -errno (a write failed). */
int upl_trace_close_csv(struct upl_trace *t);
uint64_t upl_trace_rows(const struct upl_trace *t);
/* Draw the plot with gnuplot; 0 or an exit code, message printed. */
int upl_trace_plot(struct upl_trace *t, const char *out, const char *title);
/* Closes what is open; a file the run created and never started (the run
 * was refused) is removed. */
void upl_trace_free(struct upl_trace *t);

/* A program on $PATH: 1 if found. */
int upl_which(const char *prog);

/* ---- report.c --------------------------------------------------------- */

void upl_report_progress(struct upl_report *rp,
			 const struct sh2000_run_progress *p);
void upl_report_end(struct upl_report *rp);

#endif /* SH2000_UPLOAD_H */
