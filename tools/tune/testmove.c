/* SPDX-License-Identifier: MIT */
/*
 * What every test move of sh2000-tune shares (step.c, ramp.c, chirp.c):
 * the card idle and unfaulted with the axis enabled before anything moves;
 * the user's following-error and DAC bounds lowered onto the card for the
 * test and put back afterwards whatever happened; raw coarse points pushed
 * in batches the ring has room for; a gather record armed on the motion's
 * start and read out whole; and after a following-error fault, a reset and
 * the planner (libsh2000-motion's runner) taking the axis back to where it
 * started.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sh2000/path.h>
#include <sh2000/run.h>

#include "tune.h"

#define PRETRIGGER	10
/* Records pushed at a time: a quarter of the ring, so that with a short
 * coarse period (a fast sweep, 100 us) the ring still holds the time a
 * batch takes to write while the host waits for room for the next. */
#define PUSH_BATCH	16	/* of the ring's 64 */
/* The way back after a fault: this share of the velocity bound and of the
 * axis' acceleration (the gains that just faulted may be far off: an
 * auto-tuning's excitation runs on the old ones, its check on the new). */
#define RECOVER_SLOWER	0.1

/* What tune_move_push() returns when a signal asked to stop (not a
 * library code). */
#define STOP_ASKED	(-4)

int tune_move_fail(struct tune_move *s, int r, const char *what)
{
	return sh2000_tool_fail(s->h, r, what);
}

/* The axes that move: the axis and those that follow it. */
static unsigned int moving(const struct tune_move *s)
{
	return 1u << s->a | s->o->follow;
}

/* The followers take the axis' moves from their own set-points. */
static void follow(const struct tune_move *s, int32_t *pt, int32_t v)
{
	for (unsigned int b = 0; b < SH2000_AXES; b++)
		if (s->o->follow & (1u << b))
			pt[b] = s->p[b] + (v - s->start);
}

int tune_move_push(struct tune_move *s, const int32_t *v, unsigned int n,
		   unsigned int flags)
{
	int32_t pts[PUSH_BATCH][SH2000_AXES];
	int r = 0;

	while (n) {
		unsigned int k = n < PUSH_BATCH ? n : PUSH_BATCH;

		if (sh2000_tool_stop_asked())
			return STOP_ASKED;
		for (unsigned int i = 0; i < k; i++) {
			memcpy(pts[i], s->p, sizeof(pts[i]));
			pts[i][s->a] = v[i];
			follow(s, pts[i], v[i]);
		}
		r = sh2000_wait_space(s->h, k, 5000);
		if (r >= 0)
			r = sh2000_push_counts(s->h, (const int32_t (*)[SH2000_AXES])pts,
					       k, k == n ? flags : 0);
		if (r < 0)
			return r;
		v += k;
		n -= k;
	}
	return 0;
}

int tune_move_hold(struct tune_move *s, int32_t v, unsigned int n,
		   unsigned int flags)
{
	int32_t pts[32];
	int r = 0;

	for (unsigned int i = 0; i < 32; i++)
		pts[i] = v;
	while (n && r >= 0) {
		unsigned int k = n < 32 ? n : 32;

		n -= k;
		r = tune_move_push(s, pts, k, n ? 0 : flags);
	}
	return r;
}

int tune_move_prepare(struct tune_move *s)
{
	char an = sh2000_tool_axis_name(s->a);
	struct sh2000_status st;
	unsigned int off = 0;
	int r;

	if ((r = sh2000_poll(s->h, &st)) < 0)
		return tune_move_fail(s, r, "cannot test");
	if ((r = sh2000_status_error(s->h, &st)) < 0) {
		/* from an earlier program or test: the operator's to clear */
		sh2000_tool_msg("%s: a fault is latched (%s): nothing moved; sh2000ctl reset clears it",
				sh2000_device(s->h), sh2000_strerror(r));
		return sh2000_tool_exit_code(r);
	}
	if (st.card_state != SH2000_STATE_IDLE) {
		sh2000_tool_msg("%s: card is %s, not idle: nothing moved",
				sh2000_device(s->h), sh2000_state_name(st.card_state));
		return SH2000_EXIT_CARD;
	}
	for (unsigned int b = 0; b < SH2000_AXES; b++)
		if ((moving(s) & (1u << b)) && !(st.axis[b].state & SH2000_AXIS_ENABLED))
			off |= 1u << b;
	if (off) {
		if (!s->o->enable) {
			an = sh2000_tool_axis_name(off & (1u << s->a) ? s->a :
						   (unsigned int)__builtin_ctz(off));
			sh2000_tool_msg("%s: axis %c is not enabled (sh2000ctl enable %c, or --enable): nothing moved",
					sh2000_device(s->h), an, an);
			return SH2000_EXIT_CARD;
		}
		if ((r = sh2000_enable(s->h, off)) < 0)
			return tune_move_fail(s, r, "enable");
		s->enabled_by_us = off;
		if ((r = sh2000_poll(s->h, &st)) < 0)
			return tune_move_fail(s, r, "status");
	}
	if ((r = sh2000_run_path_config(s->h, &s->pc)) < 0)
		return tune_move_fail(s, r, "get parameter");
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		s->p[a] = (int32_t)st.axis[a].cmd_counts;
	s->start = s->p[s->a];
	s->vlim = s->pc.vmax[s->a];
	for (unsigned int b = 0; b < SH2000_AXES; b++)
		if ((s->o->follow & (1u << b)) && s->pc.vmax[b] < s->vlim)
			s->vlim = s->pc.vmax[b];
	if (s->o->vmax > 0 && s->o->vmax < s->vlim)
		s->vlim = s->o->vmax;
	return 0;
}

/* The limits of the moving axes below b back as they were (a library
 * code: the first failure). */
static int put_limits(struct tune_move *s, unsigned int below)
{
	int r = 0, e;

	for (unsigned int b = 0; b < below; b++) {
		if (!(moving(s) & (1u << b)))
			continue;
		e = sh2000_param_set(s->h, b, SH2000_P_FERR_LIMIT, s->ferr0s[b]);
		if (e >= 0)
			e = sh2000_param_set(s->h, b, SH2000_P_DAC_LIMIT, s->dac0s[b]);
		if (e < 0 && r >= 0)
			r = e;
	}
	return r;
}

/* Axis b's limits read and lowered to the user's bounds: a library code. */
static int lower_axis(struct tune_move *s, unsigned int b)
{
	double ferr, dac;
	int r;

	if ((r = sh2000_param_get(s->h, b, SH2000_P_FERR_LIMIT, &s->ferr0s[b])) < 0 ||
	    (r = sh2000_param_get(s->h, b, SH2000_P_DAC_LIMIT, &s->dac0s[b])) < 0)
		return r;
	ferr = s->o->ferr_max_mm < s->ferr0s[b] ? s->o->ferr_max_mm : s->ferr0s[b];
	dac = s->o->dac_max > 0 && s->o->dac_max < s->dac0s[b] ? s->o->dac_max : s->dac0s[b];
	if (b == s->a)
		s->dac_bound = dac;
	r = sh2000_param_set(s->h, b, SH2000_P_FERR_LIMIT, ferr);
	if (r >= 0) {
		r = sh2000_param_set(s->h, b, SH2000_P_DAC_LIMIT, dac);
		if (r < 0)
			sh2000_param_set(s->h, b, SH2000_P_FERR_LIMIT, s->ferr0s[b]);
	}
	return r;
}

int tune_move_lower_limits(struct tune_move *s)
{
	int r = 0;

	for (unsigned int b = 0; b < SH2000_AXES && r >= 0; b++) {
		if (!(moving(s) & (1u << b)))
			continue;
		r = lower_axis(s, b);
		if (r < 0)
			put_limits(s, b);
	}
	s->ferr0 = s->ferr0s[s->a];
	s->dac0 = s->dac0s[s->a];
	return r < 0 ? tune_move_fail(s, r, "set parameter") : 0;
}

int tune_move_restore(struct tune_move *s)
{
	int r = put_limits(s, SH2000_AXES);

	return r < 0 ? tune_move_fail(s, r, "restoring the limits") : 0;
}

/* The pair at rest before the way back: this speed of every moving axis
 * at most, mm/s, over one REST_WINDOW_NS, within REST_WAIT_NS. */
#define REST_MMS	0.5
#define REST_WINDOWS	1
/* After a signal's stop: still enough that the carriage disabled then
 * coasts on by a fraction of a micrometre (a disabled carriage coasts
 * for some tenths of a second: at 10 um/s it went on 6 um), not the
 * micrometres a settling loop's speed carries it. At this speed a window
 * moves a count or two, so several in a row: a ringing carriage can stand
 * at the same place at both ends of one window. */
#define STILL_MMS	0.001
#define STILL_WINDOWS	5
#define REST_WINDOW_NS	20000000ull
#define REST_WAIT_NS	10000000000ull

/* The moving axes' carriages at rest: 0, or an exit code when one still
 * moves after REST_WAIT_NS. A test that moves a gantry pair (followers):
 * the card disabled both sides together with the faulted one, and they
 * coast as one beam. Enabled while still coasting, each side would brake
 * to its own position under its own loop, the two from different speeds
 * (the beam swings between them): the skew that makes can trip the skew
 * limit on the way back. So the way back begins with every moving axis
 * at rest. After a signal's STOP the card is at rest while its loop still
 * settles the carriage: disabled then, the carriage would coast on.
 * Speeds are taken over the card's own cycles between two snapshots (a
 * host or server late by a window must not read as a carriage at rest),
 * one count of the encoder's quantisation allowed. */
static int wait_rest(struct tune_move *s, double mms, unsigned int windows,
		     const char *what)
{
	double servo = s->pc.period_s / s->pc.fine_steps;
	uint64_t waited = 0, cycle = 0;
	struct sh2000_status st;
	int64_t before[SH2000_AXES] = { 0 };
	unsigned int still = 0;
	int r;

	for (int first = 1; still < windows; first = 0) {
		int now_still;
		double dt;

		if ((r = sh2000_poll(s->h, &st)) < 0)
			return tune_move_fail(s, r, what);
		dt = (double)(st.card_cycle - cycle) * servo;
		now_still = !first && st.card_cycle > cycle;
		for (unsigned int b = 0; b < SH2000_AXES && now_still; b++) {
			double moved = (double)llabs((long long)(st.axis[b].pos_counts - before[b]));

			if ((moving(s) & (1u << b)) &&
			    moved > 1 && moved > mms * dt * s->pc.counts_per_mm[b])
				now_still = 0;
		}
		if (st.card_cycle > cycle || first) {
			still = now_still ? still + 1 : 0;
			cycle = st.card_cycle;
			for (unsigned int b = 0; b < SH2000_AXES; b++)
				before[b] = st.axis[b].pos_counts;
		}
		if (still >= windows)
			break;
		if (waited >= REST_WAIT_NS) {
			sh2000_tool_msg("%s: %s test, %s: axis %c still moves %g s after the motion ended",
					sh2000_device(s->h), s->name, what,
					sh2000_tool_axis_name(s->a), REST_WAIT_NS * 1e-9);
			return SH2000_EXIT_CARD;
		}
		if ((r = sh2000_sleep_ns(s->h, REST_WINDOW_NS)) < 0)
			return tune_move_fail(s, r, what);
		waited += REST_WINDOW_NS;
	}
	return 0;
}

int tune_move_recover(struct tune_move *s, int fault)
{
	struct sh2000_run_config rc;
	struct sh2000_run *run = NULL;
	double target[SH2000_AXES];
	char err[512] = "";
	int r;

	sh2000_tool_msg("%s: %s test aborted: %s (limit %g mm during the test); returning to the start",
			sh2000_device(s->h), s->name, sh2000_strerror(fault),
			s->o->ferr_max_mm < s->ferr0 ? s->o->ferr_max_mm : s->ferr0);
	if (s->calm && (r = s->calm(s)))
		return r;
	if (s->o->follow && (r = wait_rest(s, REST_MMS, REST_WINDOWS, "recovering")))
		return r;
	if ((r = sh2000_reset(s->h)) < 0 || (r = put_limits(s, SH2000_AXES)) < 0 ||
	    (r = sh2000_enable(s->h, moving(s))) < 0)
		return tune_move_fail(s, r, "recovering");
	if (s->undo && (r = s->undo(s)))
		return r;
	if ((r = sh2000_run_path_config(s->h, &s->pc)) < 0)
		return tune_move_fail(s, r, "recovering");
	/* the way back squares a gantry pair again: each side to its own
	 * start, by distances as different as the trip left them */
	s->pc.gantry_pair = 0;
	s->pc.amax[s->a] *= RECOVER_SLOWER;
	sh2000_run_config_default(&rc);
	r = sh2000_run_create(&run, s->h, &s->pc, &rc, err, sizeof(err));
	if (r < 0) {
		sh2000_tool_msg("%s", err);
		return sh2000_tool_exit_code(r);
	}
	memcpy(target, s->pc.start, sizeof(target));
	target[s->a] = s->start / s->pc.counts_per_mm[s->a];
	for (unsigned int b = 0; b < SH2000_AXES; b++)
		if (s->o->follow & (1u << b))
			target[b] = s->p[b] / s->pc.counts_per_mm[b];
	r = sh2000_path_move_abs(sh2000_run_path(run), target,
				 s->vlim * RECOVER_SLOWER);
	if (r >= 0)
		r = sh2000_run_finish(run);
	if (r < 0)
		sh2000_tool_msg("%s", sh2000_run_error(run));
	sh2000_run_destroy(run);
	return r < 0 ? sh2000_tool_exit_code(r) : SH2000_EXIT_ABORTED;
}

int tune_move_arm(struct tune_move *s, unsigned int signals, double span_s,
		  unsigned int *rec)
{
	struct sh2000_gather_config gc;
	double servo = s->pc.period_s / s->pc.fine_steps;
	unsigned int nsig = (unsigned int)(__builtin_popcount(signals) *
					   __builtin_popcount(moving(s)));
	unsigned int max = SH2000_GATHER_BUFFER_VALUES / nsig - PRETRIGGER;
	int r;

	sh2000_gather_config_default(&gc);
	for (unsigned int b = 0; b < SH2000_AXES; b++)
		if (moving(s) & (1u << b))
			gc.signals[b] = signals;
	gc.period = (unsigned int)ceil(span_s / servo / max);
	gc.samples = (uint32_t)ceil(span_s / (servo * gc.period)) + PRETRIGGER;
	gc.trigger = SH2000_GATHER_ON_MOTION;
	gc.pretrigger = PRETRIGGER;
	r = sh2000_gather_start(s->h, &gc);
	if (r == -SH2000_ECMD_BUSY) {
		/* the card records one thing at a time */
		sh2000_tool_msg("%s: another gather record is armed or recording on the card (another program's, or one a killed program left; it ends when its samples are taken): nothing moved",
				sh2000_device(s->h));
		return SH2000_EXIT_CARD;
	}
	if (r < 0)
		return tune_move_fail(s, r, "gather");
	*rec = (unsigned int)r;
	return 0;
}

int tune_move_read(struct tune_move *s, unsigned int rec,
		   struct sh2000_gather_info *gi, double **values)
{
	int r;

	*values = NULL;
	if ((r = sh2000_gather_wait(s->h, rec, gi, 10000)) < 0)
		return tune_move_fail(s, r, "gather");
	*values = malloc(sizeof(**values) * gi->values * (gi->samples + 1));
	r = *values ? sh2000_gather_read(s->h, gi, 0, gi->samples, *values) : -12;
	if (r < 0) {
		free(*values);
		*values = NULL;
		return tune_move_fail(s, r, "gather");
	}
	return 0;
}

/* What the test changed back: its own (undo), then the limits. */
static int put_back(struct tune_move *s)
{
	int u = s->undo ? s->undo(s) : 0;
	int r = tune_move_restore(s);

	return u ? u : r;
}

/* After a signal: the card stops the motion on its way (STOP: a
 * controlled stop, nothing latched), the card at rest, what the test
 * changed goes back, and then the carriage comes to rest (its loop, with
 * the gains put back, settles it: an axis disabled before would coast
 * on); the axis stays where it stopped, and that is where the message
 * says it is. */
static int stopped(struct tune_move *s)
{
	struct sh2000_status st;
	double k = s->pc.counts_per_mm[s->a];
	int r = sh2000_stop(s->h), p, w = 0;

	if (r >= 0)
		r = sh2000_wait_rest(s->h, 5000);
	sh2000_gather_stop(s->h);
	p = put_back(s);
	/* the gains put back move the loop's settling too: still after */
	if (r >= 0)
		w = wait_rest(s, STILL_MMS, STILL_WINDOWS, "stopping");
	if (r < 0)
		return tune_move_fail(s, r, "stopping");
	if (w || p)
		return w ? w : p;
	if (sh2000_poll(s->h, &st) >= 0)
		sh2000_tool_msg("%s: %s test stopped by a signal: the limits and timing are as they were, axis %c at rest at %.6f mm (%.6f mm from its start; set-point %.6f mm)",
				sh2000_device(s->h), s->name, sh2000_tool_axis_name(s->a),
				st.axis[s->a].pos_counts / k,
				(st.axis[s->a].pos_counts - s->start) / k,
				st.axis[s->a].cmd_counts / k);
	return SH2000_EXIT_STOPPED;
}

int tune_move_run(struct tune_move *s, unsigned int signals, double span_s,
		  unsigned int *rec, int (*move)(struct tune_move *s))
{
	int r = tune_move_arm(s, signals, span_s, rec);

	if (r) {
		put_back(s);
		return r;
	}
	r = move(s);
	if (r == STOP_ASKED || (r >= 0 && sh2000_tool_stop_asked()))
		return stopped(s);
	if (r == -SH2000_EFERR) {
		/* the bound the user set: back to the start */
		sh2000_gather_stop(s->h);
		return tune_move_recover(s, r);
	}
	if (r < 0) {
		/* anything else (an emergency stop, another fault) is the
		 * operator's or the machine's: left as it is */
		char what[32];

		snprintf(what, sizeof(what), "%s test", s->name);
		if (r == -SH2000_EUNDERRUN)
			sh2000_tool_msg("%s: %s test: the card ran out of records: this program was held off the CPU longer than the card's queue lasts (docs/tools.md, chirp timing); the fault stays latched (sh2000ctl reset)",
					sh2000_device(s->h), s->name);
		r = tune_move_fail(s, r, what);
		sh2000_gather_stop(s->h);
		put_back(s);
		return r;
	}
	return put_back(s);
}

int tune_check_back(struct sh2000 *h, unsigned int axis, double start)
{
	struct sh2000_status st;
	int r = sh2000_poll(h, &st);

	if (r < 0)
		return sh2000_tool_fail(h, r, "status");
	if ((double)st.axis[axis].cmd_counts != start) {
		sh2000_tool_msg("%s: axis %c is at %lld counts, not back at %.0f",
				sh2000_device(h), sh2000_tool_axis_name(axis),
				(long long)st.axis[axis].cmd_counts, start);
		return SH2000_EXIT_CARD;
	}
	/* the label and the value are what scripts parse; the value is the
	 * axis' position, which alone reads like an error when the axis did
	 * not start at 0 */
	printf("back at the start       %.6f mm (position, 0 counts from where it started)\n",
	       st.axis[axis].cmd_mm);
	return 0;
}

void tune_move_end(struct tune_move *s)
{
	if (s->enabled_by_us)
		sh2000_disable(s->h, s->enabled_by_us);
}
