// SPDX-License-Identifier: MIT
/*
 * sh2000-upload: run an NC program on an SH-2000TH card.
 *
 * The order of things (sh2000-upload(1) is the manual): check that the
 * card is ready, read, check and plan the whole program once (the first
 * pass, sh2000_program_check: every error is found before anything moves),
 * then enable the axes, rewind and stream it (the second pass,
 * sh2000_run_program). Both passes read the program block by block, so a
 * program of any length runs in the same memory. An error before
 * streaming leaves the card as it was, and no trace: the --trace file is
 * opened before the card is touched (an unwritable path refuses the run)
 * but written only once the run starts.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <sh2000/run.h>
#include <sh2000/sh2000.h>

#include "upload.h"

/* The card is idle without a latched fault. */
static int card_ready(struct sh2000 *h)
{
	struct sh2000_status st;
	int e = sh2000_poll(h, &st);

	if (e < 0)
		return sh2000_tool_fail(h, e, "status");
	e = sh2000_status_error(h, &st);
	if (e < 0) {
		int x = sh2000_tool_fail(h, e, NULL);

		sh2000_tool_msg("%s: clear it first (sh2000ctl -d %s reset); nothing moved",
				sh2000_device(h), sh2000_device(h));
		return x;
	}
	if (st.card_state != SH2000_STATE_IDLE || st.queue_fill) {
		sh2000_tool_msg("%s: the card is busy (state %u, %u records queued); nothing moved",
				sh2000_device(h), st.card_state, st.queue_fill);
		return SH2000_EXIT_CARD;
	}
	return SH2000_EXIT_OK;
}

/* The planner's configuration for this card and these options. */
static int path_config(struct sh2000 *h, const struct upl_opts *o,
		       struct sh2000_path_config *pc)
{
	int e = sh2000_run_path_config(h, pc);

	if (e < 0)
		return sh2000_tool_fail(h, e, "reading the card's parameters");
	pc->output = o->raw ? SH2000_OUTPUT_RAW : SH2000_OUTPUT_COMPENSATED;
	if (o->trapezoid)
		pc->profile = SH2000_PROFILE_TRAPEZOID;
	if (o->tolerance > 0) {
		pc->corner_tol = o->tolerance;
		pc->chord_tol = o->tolerance;
	}
	return SH2000_EXIT_OK;
}

/* The first pass: everything read, checked and planned; the axes the
 * program never moves held still (their limits do not bound the plan), and
 * a smaller margin where the plan would pass an axis' amax (both passes
 * plan with *pc). */
static int first_pass(struct sh2000 *h, const struct upl_opts *o,
		      struct sh2000_path_config *pc,
		      struct upl_source *src, struct sh2000_program_plan *plan)
{
	struct sh2000_program_opts po;
	struct sh2000_limits lim;
	double margin0 = pc->margin;
	int e = sh2000_limits_get(h, &lim);

	if (e)
		return sh2000_tool_fail(h, e, "soft limits");
	sh2000_program_opts_default(&po);
	po.override = o->override;
	po.optional_stop = o->optional_stop;
	po.limits = &lim;
	e = sh2000_program_check(src->reader, pc, &po, plan);
	if (e == -SH2000_EPROGRAM)
		return upl_source_errors(src, o);
	sh2000_prog_diags_print(&src->diags, stderr);	/* the warnings */
	if (e == -ENOMEM || e == -EIO) {
		sh2000_tool_msg("%s: %s", o->file, sh2000_strerror(e));
		return SH2000_EXIT_CARD;
	}
	if (e) {
		fprintf(stderr, "%s: error: %s\n",
			plan->where[0] ? plan->where : o->file, plan->error);
		sh2000_tool_msg("%s: the plan failed; nothing moved", o->file);
		return SH2000_EXIT_INPUT;
	}
	if (plan->replans && !o->quiet)
		sh2000_tool_msg("%s: planned with the margin %.3f, not %.3f: with that, the set-points passed an axis' amax (the planner's known limits, docs/planner.md)",
				o->file, plan->margin, margin0);
	if (plan->optional_skipped && !o->quiet)
		sh2000_tool_msg("M1 optional stops are skipped (--optional-stop pauses at them)");
	return SH2000_EXIT_OK;
}

static void dry_run_report(const struct upl_opts *o,
			   const struct sh2000_path_config *pc,
			   const struct sh2000_program_plan *plan)
{
	char names[16];

	upl_axes_text(plan->moved, names);
	printf("sh2000-upload: %s: %llu blocks checked and planned; nothing moved (--dry-run)\n",
	       o->file, (unsigned long long)plan->blocks);
	printf("  planned time         %.3f s (%llu points of %.1f ms)\n",
	       plan->seconds, (unsigned long long)plan->points,
	       pc->period_s * 1e3);
	printf("  axes moved           %s\n", plan->moved ? names : "none");
	upl_axes_text(pc->still_axes, names);
	printf("  axes held still      %s\n", pc->still_axes ? names : "none");
	upl_axes_text(1u << plan->accel_axis, names);
	printf("  peak acceleration    %.1f %% of amax (%s)\n",
	       plan->accel_peak * 100.0, names);
	printf("  planner margin       %.3f", plan->margin);
	if (plan->replans)
		printf(" (planned %u times: with a larger one the set-points passed an axis' amax)",
		       plan->replans + 1);
	printf("\n");
}

/* The plan starts where the card holds now (enabling keeps the position);
 * a card that moved since the check is refused: the library's guard. */
static int same_start(struct sh2000 *h, struct sh2000_path_config *pc)
{
	char msg[200];
	int e = sh2000_run_check_start(h, pc, msg, sizeof(msg));

	if (e == -SH2000_EMOVED) {
		sh2000_tool_msg("%s: %s; nothing moved", sh2000_device(h), msg);
		return SH2000_EXIT_CARD;
	}
	return e < 0 ? sh2000_tool_fail(h, e, "status") : SH2000_EXIT_OK;
}

static void summary(const struct upl_opts *o, struct sh2000 *h,
		    const struct sh2000_run_stats *s, double planned,
		    const struct upl_trace *t)
{
	printf("sh2000-upload: %s on %s: done\n", o->file, sh2000_device(h));
	printf("  time                 %.3f s of card time (planned %.3f s)\n",
	       s->time_s, planned);
	printf("  distance             %.3f mm\n", s->distance_mm);
	printf("  points               %llu coarse points in %llu batches\n",
	       (unsigned long long)s->points, (unsigned long long)s->batches);
	printf("  max following error  %.4f mm (axis %c, %s)\n",
	       s->max_ferr_mm, sh2000_tool_axis_name(s->max_ferr_axis),
	       sh2000_backend(h) == SH2000_BACKEND_SIM ? "every servo cycle" :
	       "at status polls");
	if (s->min_fill < sh2000_queue_size(h))
		printf("  underruns            %llu (ring low-water mark %u of %u records)\n",
		       (unsigned long long)s->underruns, s->min_fill,
		       sh2000_queue_size(h));
	else
		printf("  underruns            %llu\n",
		       (unsigned long long)s->underruns);
	printf("  B-spline compensation %s\n", o->raw ? "off (--raw)" : "on");
	if (o->trace)
		printf("  trace                %s (%llu rows)\n", o->trace,
		       (unsigned long long)upl_trace_rows(t));
}

/* Trace and plot after the run; the exit code given x so far. */
static int finish_trace(const struct upl_opts *o, struct sh2000 *h,
			struct upl_runctx *rc, int x)
{
	char title[512];
	int e, px;

	if (rc->trace && (e = upl_trace_close_csv(rc->trace)) < 0) {
		sh2000_tool_msg("--trace %s: %s", o->trace, strerror(-e));
		if (!x)
			x = SH2000_EXIT_CARD;
	}
	if (!o->plot || !rc->trace || x)
		return x;
	snprintf(title, sizeof(title), "%s on %s%s", o->file, sh2000_device(h),
		 o->raw ? " (--raw)" : "");
	px = upl_trace_plot(rc->trace, o->plot, title);
	if (!px)
		printf("  plot                 %s\n", o->plot);
	return px;
}

/* The second pass: stream the program to the card. */
static int second_pass(struct sh2000 *h, const struct upl_opts *o,
		       const struct sh2000_path_config *pc,
		       struct upl_source *src,
		       const struct sh2000_program_plan *plan,
		       struct upl_runctx *rc)
{
	struct sh2000_program_opts po;
	struct sh2000_run_config rcfg;
	struct sh2000_run_stats stats;
	char msg[512];
	int e, x;

	rc->h = h;
	rc->seq = -1;
	rc->tools = o->tool_table ? &src->tools : NULL;
	rc->rep.bar = isatty(STDERR_FILENO);
	rc->rep.quiet = o->quiet;
	rc->rep.total_points = plan->points;
	rc->rep.last_pct = -1;
	sh2000_run_config_default(&rcfg);
	rcfg.sample = (o->trace || o->plot) ? upl_on_sample : NULL;
	rcfg.progress = upl_on_progress;
	rcfg.ctx = rc;
	e = sh2000_run_create(&rc->run, h, pc, &rcfg, msg, sizeof(msg));
	if (e < 0) {
		sh2000_tool_msg("%s", msg);
		return sh2000_tool_exit_code(e);
	}
	sh2000_run_set_override(rc->run, o->override);
	sh2000_program_opts_default(&po);
	po.optional_stop = o->optional_stop;
	e = sh2000_prog_reader_rewind(src->reader);
	if (!e && rc->trace && (x = upl_trace_start(rc->trace)) < 0) {
		sh2000_tool_msg("--trace %s: %s; nothing moved", o->trace,
				strerror(-x));
		return SH2000_EXIT_CARD;
	}
	if (!e)
		e = sh2000_run_program(rc->run, src->reader, &po, upl_pause, rc);
	if (!e && sh2000_tool_stop_asked())
		e = -ECANCELED;
	upl_report_end(&rc->rep);
	x = e ? upl_run_fail(rc, o->file, e) : SH2000_EXIT_OK;
	sh2000_run_stats(rc->run, &stats);
	if (!x)
		summary(o, h, &stats, plan->seconds, rc->trace);
	return finish_trace(o, h, rc, x);
}

static int upload(struct sh2000 *h, const struct upl_opts *o,
		  struct upl_source *src, struct upl_runctx *rc)
{
	struct sh2000_program_plan plan;
	struct sh2000_path_config pc;
	char msg[512];
	int x;

	x = card_ready(h);
	if (!x)
		x = path_config(h, o, &pc);
	if (!x)
		x = upl_source_open(src, o, pc.start);
	if (!x)
		x = first_pass(h, o, &pc, src, &plan);
	if (x)
		return x;
	if (o->dry_run) {
		dry_run_report(o, &pc, &plan);
		return SH2000_EXIT_OK;
	}
	if (o->trace || o->plot) {
		rc->trace = upl_trace_open(o->trace, o->trace_every, !!o->plot,
					   msg, sizeof(msg));
		if (!rc->trace) {
			sh2000_tool_msg("%s; nothing moved", msg);
			return SH2000_EXIT_CARD;
		}
	}
	x = upl_enable_axes(h, o, plan.moved);
	if (!x)
		x = same_start(h, &pc);
	if (x)
		return x;
	upl_signals();
	return second_pass(h, o, &pc, src, &plan, rc);
}

int main(int argc, char **argv)
{
	struct upl_source src;
	struct upl_runctx rc;
	struct sh2000 *h = NULL;
	struct upl_opts o;
	int x;

	sh2000_tool_init("sh2000-upload");
	x = upl_parse(argc, argv, &o);
	if (x)
		return x;
	/* helpers first: a missing one must not cost a run */
	if (o.rs274 && !upl_which("rs274")) {
		sh2000_tool_msg("--rs274: LinuxCNC's rs274 interpreter is not installed (Debian package linuxcnc-uspace); without --rs274 the built-in parser reads the G-code subset");
		return SH2000_EXIT_HELPER;
	}
	if (o.plot && !upl_which("gnuplot")) {
		sh2000_tool_msg("--plot %s: gnuplot not found on PATH (Debian package gnuplot-nox)",
				o.plot);
		return SH2000_EXIT_HELPER;
	}
	/* the outputs' folders before the card is touched: a typo there
	 * must not be found after the run */
	x = sh2000_tool_writable("--trace", o.trace);
	if (!x)
		x = sh2000_tool_writable("--plot", o.plot);
	if (x)
		return x;
	x = sh2000_tool_open(&h, o.device);
	if (x)
		return x;
	memset(&src, 0, sizeof(src));
	memset(&rc, 0, sizeof(rc));
	x = upload(h, &o, &src, &rc);
	fflush(stdout);
	if (rc.run)
		sh2000_run_destroy(rc.run);
	upl_trace_free(rc.trace);
	upl_source_close(&src);
	sh2000_close(h);
	return x;
}
