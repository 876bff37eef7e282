// SPDX-License-Identifier: MIT
/*
 * A whole program in two passes (run.h): plan and check everything, then
 * stream it. Both passes read the program block by block, so a program of
 * any length runs in the memory of the planner's window and one line.
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "setpoints.h"
#include "sh2000/run.h"

_Static_assert(offsetof(struct sh2000_program_plan, replans) +
	       sizeof(unsigned int) <=
	       offsetof(struct sh2000_program_plan, reserved) +
	       sizeof(((struct sh2000_program_plan *)0)->reserved) &&
	       sizeof(((struct sh2000_program_plan *)0)->reserved) ==
	       8 * sizeof(uint64_t),
	       "the fields added to struct sh2000_program_plan stay in its room to grow");

void sh2000_program_opts_default(struct sh2000_program_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->override = 1.0;
}

/* Blocks that stop the motion first: G4, and M0 (M1 when it pauses). */
static int halts(const struct sh2000_prog_block *b,
		 const struct sh2000_program_opts *o)
{
	return b->kind == SH2000_PROG_DWELL ||
	       (b->kind == SH2000_PROG_PAUSE &&
		(!b->u.optional || o->optional_stop));
}

int sh2000_program_axes(struct sh2000_prog_reader *r,
			struct sh2000_path_config *pc)
{
	unsigned int moves;
	int e = sh2000_prog_reader_axes(r, pc->start, &moves);

	if (!e)
		pc->still_axes = ~moves & ((1u << SH2000_AXES) - 1u);
	return e;
}

/* ---- the first pass -------------------------------------------------------- */

struct plan_ctx {
	struct sh2000_program_plan *plan;
	const struct sh2000_limits *limits;
	struct sh2000_setpoints sp;	/* the runner's rule, ahead of it,
					 * and the acceleration guard */
	const struct sh2000_path_config *pc;
	double start[SH2000_AXES];
	const char *file;
	int bad;
};

static int plan_sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct plan_ctx *c = ctx;
	double mm[SH2000_AXES];
	unsigned int a;
	int e;

	c->plan->points++;
	/* moved: half a count or more from the start. The planner's
	 * arithmetic leaves an axis it holds an ulp or so off a start that
	 * is no binary fraction (123.4567 mm), which moves nothing; calling
	 * that a move had sh2000-upload enable an axis the program never
	 * names (and catch its carriage, coasting after a fault) */
	for (a = 0; a < SH2000_AXES; a++)
		if (fabs(pt->mm[a] - c->start[a]) * c->pc->counts_per_mm[a] >=
		    0.5)
			c->plan->moved |= 1u << a;
	/* the runner applies the same rules to the same points later */
	memcpy(mm, pt->mm, sizeof(mm));
	e = sh2000_setpoints_point(&c->sp, mm, pt->flags & SH2000_PATH_F_END,
				   c->plan->error, sizeof(c->plan->error));
	if (e < 0) {
		/* the point belongs to the block tagged with this line */
		snprintf(c->plan->where, sizeof(c->plan->where), "%s:%u",
			 c->file, pt->seq);
		c->plan->accel_over = e == -ERANGE;
		c->bad = 1;
		return e;
	}
	return 0;
}

/* Plan one block (or finish the motion before a halt). */
static int plan_block(struct sh2000_path *p, const struct sh2000_prog_block *b,
		      const struct sh2000_program_opts *o,
		      struct sh2000_program_plan *plan)
{
	if (halts(b, o)) {
		if (b->kind == SH2000_PROG_DWELL)
			plan->seconds += b->u.dwell_s;
		return sh2000_path_finish(p);
	}
	if (b->kind == SH2000_PROG_PAUSE)
		plan->optional_skipped++;
	sh2000_path_set_seq(p, b->pos.line);
	return sh2000_path_add_block(p, b);
}

static int plan_all(struct sh2000_prog_reader *r, struct sh2000_path *p,
		    const struct sh2000_program_opts *o, struct plan_ctx *c)
{
	const struct sh2000_prog_block *b = NULL;
	int got = 0, e = 0;

	while (!e && (got = sh2000_prog_reader_next(r, &b)) > 0) {
		c->plan->blocks++;
		c->file = b->pos.file;
		if (b->kind == SH2000_PROG_END)
			break;
		if (sh2000_prog_reader_errors(r))
			continue;	/* read on for the errors; plan nothing */
		e = plan_block(p, b, o, c->plan);
		if (e && !c->bad) {
			sh2000_prog_block_where(b, c->plan->where,
						sizeof(c->plan->where));
			snprintf(c->plan->error, sizeof(c->plan->error), "%s",
				 sh2000_path_error(p));
		}
	}
	if (got < 0)
		return got;
	/* the rest, for its errors: a program with errors is reported as
	 * such, not by its plan */
	while (got > 0 && (got = sh2000_prog_reader_next(r, &b)) > 0)
		;
	if (sh2000_prog_reader_errors(r))
		return -SH2000_EPROGRAM;
	if (!e)
		e = sh2000_path_finish(p);
	if (e && !c->bad && !c->plan->error[0])
		snprintf(c->plan->error, sizeof(c->plan->error), "%s",
			 sh2000_path_error(p));
	return got < 0 ? got : e;
}

int sh2000_program_plan(struct sh2000_prog_reader *r,
			const struct sh2000_path_config *pc,
			const struct sh2000_program_opts *o,
			struct sh2000_program_plan *plan)
{
	struct sh2000_program_opts def;
	struct plan_ctx c;
	struct sh2000_path *p;
	int e;

	if (!o) {
		sh2000_program_opts_default(&def);
		o = &def;
	}
	memset(plan, 0, sizeof(*plan));
	memset(&c, 0, sizeof(c));
	c.plan = plan;
	c.limits = o->limits;
	c.pc = pc;
	c.file = "";
	memcpy(c.start, pc->start, sizeof(c.start));
	sh2000_setpoints_init(&c.sp, o->limits);
	sh2000_setpoints_rest(&c.sp, pc->start);
	sh2000_setpoints_pair(&c.sp, pc);
	sh2000_setpoints_accel(&c.sp, pc);
	e = sh2000_path_create(&p, pc, plan_sink, &c, plan->error,
			       sizeof(plan->error));
	if (e)
		return e;
	e = sh2000_path_set_override(p, o->override);
	if (!e)
		e = sh2000_setpoints_bound(o->limits, p);
	if (e)
		snprintf(plan->error, sizeof(plan->error), "%s",
			 sh2000_path_error(p));
	else
		e = plan_all(r, p, o, &c);
	plan->seconds += (double)plan->points * pc->period_s;
	plan->accel_peak = c.sp.accel_peak;
	plan->accel_axis = c.sp.accel_axis;
	plan->margin = pc->margin;
	sh2000_path_destroy(p);
	return e;
}

/*
 * The margin to plan with again, the k-th time (from 0): a hundredth less
 * at first, then steps that grow by half as much again every other time
 * (1, 1.4, 2, 2.8, 4 ... %), so that ten plans reach about half the margin.
 * Not the excess the guard saw: the planner's excess does not shrink in
 * proportion with the margin (3D_Chips at 10000 mm/s^2 passes amax at
 * 0.95 by 3 %, at 0.94 by 17 % and keeps it at 0.90), and the first record
 * over amax need not be the worst; small steps first keep the margin near
 * where it was.
 */
static double next_margin(double margin, unsigned int k)
{
	return margin * (1.0 - 0.01 * pow(2.0, 0.5 * k));
}

int sh2000_program_check(struct sh2000_prog_reader *r,
			 struct sh2000_path_config *pc,
			 const struct sh2000_program_opts *o,
			 struct sh2000_program_plan *plan)
{
	double margin = pc->margin;
	unsigned int replans = 0;
	int e = sh2000_program_axes(r, pc);

	while (!e) {
		e = sh2000_program_plan(r, pc, o, plan);
		plan->replans = replans;
		if (e != -ERANGE || !plan->accel_over ||
		    replans == SH2000_PROGRAM_REPLANS)
			break;
		e = sh2000_prog_reader_rewind(r);
		pc->margin = next_margin(pc->margin, replans++);
	}
	/* a program that cannot run leaves the margin as it was */
	if (e)
		pc->margin = margin;
	return e;
}

/* ---- the second pass ------------------------------------------------------- */

/* A feed hold on the card (sh2000_run_pause() from a callback): keep the
 * card's heartbeat and the callbacks going until it ends. */
static int wait_hold(struct sh2000_run *run)
{
	int e = 0;

	while (!e && sh2000_run_held(run) && !sh2000_run_stop_requested(run))
		e = sh2000_run_hold_wait(run, 100);
	return e;
}

/* sh2000_run_finish() through any feed holds. */
static int finish(struct sh2000_run *run)
{
	int e;

	while ((e = sh2000_run_finish(run)) == -EAGAIN &&
	       sh2000_run_held(run)) {
		e = wait_hold(run);
		if (e)
			break;
	}
	return e;
}

/* Add a block; a full window during a feed hold waits for its end. */
static int add_block(struct sh2000_run *run, const struct sh2000_prog_block *b)
{
	struct sh2000_path *p = sh2000_run_path(run);
	int e;

	while ((e = sh2000_path_add_block(p, b)) == -EAGAIN &&
	       sh2000_run_held(run)) {
		e = wait_hold(run);
		if (e)
			break;
	}
	return e;
}

/* A block that holds the motion: finish what is planned, then dwell or
 * pause. 1 for a skipped M1. */
static int run_halt(struct sh2000_run *run, const struct sh2000_prog_block *b,
		    sh2000_program_pause_fn pause, void *ctx)
{
	int e = finish(run);

	if (e)
		return e;
	if (b->kind == SH2000_PROG_DWELL)
		return sh2000_run_dwell(run, b->u.dwell_s);
	return pause ? pause(ctx, b) : 0;
}

int sh2000_run_program(struct sh2000_run *run, struct sh2000_prog_reader *r,
		       const struct sh2000_program_opts *o,
		       sh2000_program_pause_fn pause, void *ctx)
{
	struct sh2000_path *p = sh2000_run_path(run);
	const struct sh2000_prog_block *b;
	struct sh2000_program_opts def;
	int got = 0, e = 0;

	if (!o) {
		sh2000_program_opts_default(&def);
		o = &def;
	}
	while (!e && !sh2000_run_stop_requested(run) &&
	       (got = sh2000_prog_reader_next(r, &b)) > 0) {
		if (b->kind == SH2000_PROG_END)
			break;
		if (halts(b, o)) {
			e = run_halt(run, b, pause, ctx);
			continue;
		}
		sh2000_path_set_seq(p, b->pos.line);
		e = add_block(run, b);
		/* planned before: a card failure while the look-ahead
		 * streamed, or a stop; finish says which */
		if (e) {
			e = finish(run);
			return e ? e : -EIO;
		}
	}
	if (!e && got < 0)
		e = got;
	if (!e)
		e = finish(run);
	return e;
}
