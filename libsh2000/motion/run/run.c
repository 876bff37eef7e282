// SPDX-License-Identifier: MIT
/*
 * Streaming a planned path to a card (sh2000/run.h): the planner's sink
 * gathers points into batches, waits for room and pushes them.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "moved.h"
#include "setpoints.h"
#include "sh2000/run.h"
#include "sh2000/sh2000_protocol.h"

#define RUN_WAIT_MIN_NS 100000ull
/* tags of the last points, more than the batch buffer and the ring hold */
#define RUN_SEQS 256u
#define RUN_WAIT_MAX_NS 5000000ull

struct sh2000_run {
	struct sh2000 *h;
	struct sh2000_path *path;
	struct sh2000_run_config cfg;
	int sim;			/* samples come from the observer */
	double scale[SH2000_AXES];	/* counts per mm */
	struct sh2000_limits limits;	/* the card's soft limits */
	struct sh2000_setpoints sp;	/* ... kept by the set-points */
	struct sh2000_moved moved;	/* what the records moved */
	uint64_t servo_ns, coarse_ns;
	uint64_t cycle0;		/* servo cycle at creation */
	int32_t buf[SH2000_RING_RECORDS][SH2000_AXES];
	unsigned int n;			/* points in buf */
	int in_motion;			/* pushed a batch without END */
	int stopped;			/* sh2000_run_stop() was called */
	int end_held;			/* buf ends with the motion's END */
	/* the card's time base (protocol 1.1): hold and override there */
	int tb;				/* the card has one */
	int held;			/* a feed hold is asked for */
	int tb_dirty;			/* ... or changed, not sent yet */
	double tb_factor;		/* the override the card carries */
	int32_t hold_cmd[SH2000_AXES];	/* set-points at the last poll */
	unsigned int hold_still;	/* polls they stayed the same */
	int failed;			/* the sink failed: r->err says why */
	int halted;			/* ... and halt_card() ran for it */
	double last_mm[SH2000_AXES];
	int have_last;
	struct sh2000_status st;	/* last poll */
	int have_st;
	uint32_t seqs[RUN_SEQS];	/* tag of point k at k % RUN_SEQS */
	uint64_t emitted;		/* points the sink was given */
	int sampled;			/* a poll gave a sample ... */
	uint64_t sample_cycle;		/* ... of this snapshot */
	struct sh2000_run_stats stats;
	char err[512];			/* the run's last failure */
	/* the planner's words when that was recorded: words other than
	 * these are a planner failure since (sh2000_run_error()) */
	char path_err[256];
};

void sh2000_run_config_default(struct sh2000_run_config *cfg)
{
	memset(cfg, 0, sizeof(*cfg));
	cfg->batch = 16;
	cfg->prime = 48;
	cfg->stall_ms = 2000;
}

/* The planner's words now belong to the run's failure (they are older,
 * or the planner's report of the sink failing with it). */
static void seen_path_err(struct sh2000_run *r)
{
	snprintf(r->path_err, sizeof(r->path_err), "%s",
		 r->path ? sh2000_path_error(r->path) : "");
}

static int fail(struct sh2000_run *r, int code, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(r->err, sizeof(r->err), fmt, ap);
	va_end(ap);
	seen_path_err(r);
	return code;
}

/* A library call failed: keep its words (they name the device). A
 * rejected record gets the disabled axis it moved, when it did. */
static int lib_fail(struct sh2000_run *r, int code, const char *what)
{
	struct sh2000_status st;
	char detail[384];

	sh2000_last_error_copy(r->h, detail, sizeof(detail));
	if (detail[0])
		fail(r, code, "%s", detail);
	else
		fail(r, code, "%s: %s: %s", sh2000_device(r->h), what,
		     sh2000_strerror(code));
	if (code == -SH2000_EREJECTED && sh2000_poll(r->h, &st) >= 0)
		sh2000_moved_note(&r->moved, &st, r->scale, r->err,
				  sizeof(r->err));
	return code;
}

/*
 * The card's gantry pair (protocol 1.7) into pc->gantry_pair when both
 * sides are enabled: then the loops couple them and a motion must move
 * them together (pair.c). With a side disabled the other may move alone
 * and drag it, as the beam does.
 */
static int gantry_pair(struct sh2000 *h, const struct sh2000_status *st,
		       struct sh2000_path_config *pc)
{
	unsigned int a, n = 0, mask;
	double v;
	int r;

	pc->gantry_pair = 0;
	r = sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_GANTRY_PAIR, &v);
	if (r == -EOPNOTSUPP)
		return 0;	/* a card before gantry pairs (the library's gate) */
	if (r)
		return r;
	mask = (unsigned int)v;
	for (a = 0; a < SH2000_AXES; a++)
		if ((mask & (1u << a)) &&
		    (st->axis[a].state & SH2000_AXIS_ENABLED))
			n++;
	if (n == 2)
		pc->gantry_pair = mask;
	return 0;
}

int sh2000_run_path_config(struct sh2000 *h, struct sh2000_path_config *pc)
{
	struct sh2000_status st;
	double coarse_us, fine, v;
	unsigned int a;
	int r;

	sh2000_path_config_default(pc);
	r = sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US,
			     &coarse_us);
	if (!r)
		r = sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS,
				     &fine);
	if (r)
		return r;
	pc->period_s = coarse_us * 1e-6;
	pc->fine_steps = (unsigned int)fine;
	for (a = 0; a < SH2000_AXES && a < SH2000_AXES; a++) {
		r = sh2000_param_get(h, (int)a, SH2000_P_VMAX, &v);
		if (r)
			return r;
		pc->vmax[a] = v;
		r = sh2000_param_get(h, (int)a, SH2000_P_AMAX, &v);
		if (r)
			return r;
		pc->amax[a] = v;
		r = sh2000_param_get(h, (int)a, SH2000_P_SCALE, &v);
		if (r)
			return r;
		pc->counts_per_mm[a] = v;
	}
	r = sh2000_poll(h, &st);
	if (r)
		return r;
	for (a = 0; a < SH2000_AXES && a < SH2000_AXES; a++)
		pc->start[a] = (st.axis[a].state & SH2000_AXIS_ENABLED) ?
			       st.axis[a].cmd_mm : st.axis[a].pos_mm;
	return gantry_pair(h, &st, pc);
}

static double cycle_time(const struct sh2000_run *r, uint64_t cycle)
{
	return (double)(cycle - r->cycle0) * (double)r->servo_ns * 1e-9;
}

static void take_sample(struct sh2000_run *r, const struct sh2000_run_sample *s)
{
	unsigned int a;

	r->stats.samples++;
	for (a = 0; a < SH2000_AXES; a++) {
		double e = fabs(s->cmd[a] - s->act[a]);

		if (e > r->stats.max_ferr_mm) {
			r->stats.max_ferr_mm = e;
			r->stats.max_ferr_axis = a;
		}
	}
	if (r->cfg.sample)
		r->cfg.sample(r->cfg.ctx, s);
}

/* A simulated card's servo cycles: runs inside the library, under the
 * handle's lock, once per servo cycle. */
static void observe(void *ctx, const struct sh2000_cycle *p)
{
	struct sh2000_run *r = ctx;
	struct sh2000_run_sample s;
	unsigned int a;

	s.t = cycle_time(r, p->servo_cycle);
	for (a = 0; a < SH2000_AXES; a++) {
		s.cmd[a] = p->axis[a].fine_cmd / r->scale[a];
		s.act[a] = p->axis[a].actual / r->scale[a];
	}
	s.per_cycle = 1;
	take_sample(r, &s);
}

static void progress(struct sh2000_run *r)
{
	struct sh2000_run_progress pr = {0};	/* reserved zero */

	if (!r->cfg.progress || !r->have_st)
		return;
	pr.points = r->stats.points;
	pr.t = cycle_time(r, r->st.card_cycle);
	pr.queue_fill = r->st.queue_fill;
	pr.seq = -1;
	if (r->stats.points > r->st.queue_fill)
		pr.seq = r->seqs[(r->stats.points - r->st.queue_fill - 1) %
				 RUN_SEQS];
	pr.status = &r->st;
	r->cfg.progress(r->cfg.ctx, &pr);
}

/* One status poll: samples (not sim), ferr, time, faults. */
static int poll_once(struct sh2000_run *r)
{
	unsigned int a;
	int e;

	e = sh2000_poll(r->h, &r->st);
	if (e < 0)
		return lib_fail(r, e, "status poll");
	r->have_st = 1;
	r->stats.polls++;
	r->stats.time_s = cycle_time(r, r->st.card_cycle);
	if (!r->sim && (!r->sampled || r->st.card_cycle != r->sample_cycle)) {
		struct sh2000_run_sample s;

		/* one sample per snapshot: polls between two publications
		 * see the same one */
		r->sampled = 1;
		r->sample_cycle = r->st.card_cycle;

		s.t = r->stats.time_s;
		for (a = 0; a < SH2000_AXES; a++) {
			s.cmd[a] = r->st.axis[a].cmd_mm;
			s.act[a] = r->st.axis[a].pos_mm;
		}
		s.per_cycle = 0;
		take_sample(r, &s);
	}
	e = sh2000_status_error(r->h, &r->st);
	if (e < 0) {
		if (e == -SH2000_EUNDERRUN)
			r->stats.underruns++;
		return lib_fail(r, e, "card");
	}
	return 0;
}

/* Send the time base's target if it changed: 0 for a hold, else the
 * override the card carries. */
static int tb_apply(struct sh2000_run *r)
{
	double v;
	int e;

	if (!r->tb_dirty)
		return 0;
	r->tb_dirty = 0;
	r->hold_still = 0;
	v = r->held ? 0.0 : llround(r->tb_factor * SH2000_TIME_SCALE_FULL);
	e = sh2000_param_set(r->h, SH2000_GLOBAL, SH2000_GP_TIME_SCALE, v);
	return e < 0 ? lib_fail(r, e, "time base") : 0;
}

/* Held and the set-points still over two polls: at rest. */
static int held_at_rest(struct sh2000_run *r)
{
	unsigned int a, same = 1;

	for (a = 0; a < SH2000_AXES; a++) {
		same &= r->st.axis[a].cmd_counts == r->hold_cmd[a];
		r->hold_cmd[a] = r->st.axis[a].cmd_counts;
	}
	r->hold_still = same ? r->hold_still + 1 : 0;
	return r->hold_still >= 2;
}

static uint64_t wait_step(const struct sh2000_run *r, unsigned int records)
{
	uint64_t ns = (uint64_t)records * r->coarse_ns / 2u;

	if (ns < RUN_WAIT_MIN_NS)
		ns = RUN_WAIT_MIN_NS;
	if (ns > RUN_WAIT_MAX_NS)
		ns = RUN_WAIT_MAX_NS;
	if (r->cfg.sample && !r->sim && ns > r->cfg.sample_ns)
		ns = r->cfg.sample_ns;
	return ns;
}

/*
 * Wait until `need` records fit (idle: until the card is idle with an empty
 * ring), polling: that keeps the host heartbeat, gives samples and
 * progress, and turns latched faults into errors. A card that consumes
 * nothing for stall_ms is an error too.
 */
static int wait_card(struct sh2000_run *r, unsigned int need, int idle)
{
	uint64_t last_change = sh2000_now_ns(r->h);
	unsigned int last_fill = ~0u, fill;
	int e;

	for (;;) {
		e = tb_apply(r);
		if (e)
			return e;
		if (r->sim && !idle && !r->cfg.progress && !r->held) {
			/* the observer samples; a cheap look at the ring */
			e = sh2000_wait_space(r->h, need, r->cfg.stall_ms);
			if (e < 0) {
				if (e == -SH2000_EUNDERRUN)
					r->stats.underruns++;
				return lib_fail(r, e, "waiting for room");
			}
			fill = SH2000_RING_RECORDS - (unsigned int)e;
			goto room;
		}
		e = poll_once(r);
		if (e)
			return e;
		fill = r->st.queue_fill;
		progress(r);
		/*
		 * Mid-motion the card stops or goes idle with an empty ring
		 * only when a STOP (from another program: this run sends none
		 * while streaming) discarded the ring. Pushing on would start
		 * a new motion far from where the card stopped and have it
		 * rejected; say what happened instead.
		 */
		if (r->in_motion &&
		    (r->st.card_state == SH2000_STATE_STOPPING ||
		     (r->st.card_state == SH2000_STATE_IDLE && fill == 0)))
			return fail(r, -SH2000_ESTOPPED,
				    "%s: the card stopped the motion (a STOP command from another program?)",
				    sh2000_device(r->h));
		if (idle ? fill == 0 && r->st.card_state == SH2000_STATE_IDLE :
		    SH2000_RING_RECORDS - fill >= need)
			break;
		if (r->held) {
			/* a feed hold: at rest, the caller hears of it */
			if (held_at_rest(r))
				return -EAGAIN;
			last_change = sh2000_now_ns(r->h);
		} else if (fill != last_fill) {
			last_fill = fill;
			last_change = sh2000_now_ns(r->h);
		} else if (r->cfg.stall_ms >= 0 &&
			   sh2000_now_ns(r->h) - last_change >
			   (uint64_t)r->cfg.stall_ms * 1000000ull) {
			return fail(r, -SH2000_ETIMEOUT,
				    "%s: the card consumed nothing for %d ms (state %u, %u records queued)",
				    sh2000_device(r->h), r->cfg.stall_ms,
				    r->st.card_state, fill);
		}
		e = sh2000_sleep_ns(r->h, wait_step(r, idle ? fill :
				need - (SH2000_RING_RECORDS - fill)));
		if (e < 0)
			return lib_fail(r, e, "waiting");
	}
	if (idle)
		return 0;
room:
	/* the ring's low-water mark while a motion is under way */
	if (r->in_motion && fill < r->stats.min_fill)
		r->stats.min_fill = fill;
	return 0;
}

/* Push k records from the front of the buffer (END on them if end);
 * the rest moves to the front. */
static int push_front(struct sh2000_run *r, unsigned int k, int end)
{
	int e = wait_card(r, k, 0);

	if (e)
		return e;
	for (;;) {
		e = sh2000_push_counts(r->h,
				       (const int32_t (*)[SH2000_AXES])r->buf,
				       k, end ? SH2000_PUSH_END : 0);
		/* the room was there a moment ago: only another writer takes
		 * it, which one controlling handle per card rules out */
		if (e != -SH2000_EQUEUE_FULL)
			break;
		e = wait_card(r, k, 0);
		if (e)
			return e;
	}
	if (e < 0) {
		if (e == -SH2000_EUNDERRUN)
			r->stats.underruns++;
		return lib_fail(r, e, "push");
	}
	memmove(r->buf, r->buf + k, (r->n - k) * sizeof(r->buf[0]));
	r->n -= k;
	r->stats.points += k;
	r->stats.batches++;
	return 0;
}

/* Push the buffer: a batch at a time, the priming batch first in a new
 * motion (a buffer that filled up during a feed hold goes in batches, so
 * the ring never has to run dry to take it). */
static int flush(struct sh2000_run *r, int end)
{
	int e = 0;

	if (!r->n)
		return 0;
	while (!e && r->n) {
		unsigned int k = r->in_motion ? r->cfg.batch : r->cfg.prime;

		if (k > r->n)
			k = r->n;
		e = push_front(r, k, end && k == r->n);
		if (!e && r->n)
			r->in_motion = 1;
	}
	if (e)
		return e;
	r->in_motion = !end;
	if (end)
		r->end_held = 0;
	return 0;
}

/* How long halt_card() waits for the card to acknowledge an emergency
 * stop: the card acts on it within one servo cycle; a stalled DSP acts on
 * it when it runs again, and nothing waits for that. */
#define RUN_ESTOP_WAIT_MS 10

/*
 * After a failure the card must not keep running what is queued. A card
 * with a latched fault has stopped by itself; a running one gets a STOP.
 * A card whose state cannot be read (heartbeat stuck, firmware lost, a
 * snapshot torn for good) or that does not take the STOP cannot be trusted
 * to run its ring out or to time out on time: it gets an emergency stop,
 * one write that needs no answer, which it acts on in its next servo cycle
 * (docs/faults.md). The run's error stays the one that brought it here.
 */
static void halt_card(struct sh2000_run *r)
{
	struct sh2000_status st;

	r->halted = 1;
	if (sh2000_poll(r->h, &st) < 0) {
		sh2000_estop(r->h, RUN_ESTOP_WAIT_MS);
		return;
	}
	if (st.card_state == SH2000_STATE_RUNNING ||
	    (st.card_state == SH2000_STATE_IDLE && st.queue_fill)) {
		if (sh2000_stop(r->h) < 0 || sh2000_wait_idle(r->h, 1000) ==
		    -SH2000_EHEARTBEAT)
			sh2000_estop(r->h, RUN_ESTOP_WAIT_MS);
	}
}

/* ... and the planner starts again where the card is. */
static void reset_plan(struct sh2000_run *r)
{
	struct sh2000_status st;
	double pos[SH2000_AXES];
	unsigned int a;

	if (!r->halted)
		halt_card(r);
	r->halted = 0;
	memcpy(pos, r->last_mm, sizeof(pos));
	if (sh2000_poll(r->h, &st) >= 0)
		for (a = 0; a < SH2000_AXES; a++)
			pos[a] = st.axis[a].cmd_mm;
	sh2000_path_reset(r->path, pos);
	sh2000_setpoints_rest(&r->sp, pos);
	r->n = 0;
	r->emitted = r->stats.points;	/* the unsent points are gone */
	r->in_motion = 0;
	memcpy(r->last_mm, pos, sizeof(r->last_mm));
	r->have_last = 1;
	r->failed = 0;
	memset(&r->moved, 0, sizeof(r->moved));
	/* the planner said "the sink failed" of the run's failure */
	seen_path_err(r);
}

/* A push that failed: -EAGAIN (a feed hold: the planner keeps the point)
 * as it is; anything else stops the card, and _finish() resets the plan. */
static int sink_fail(struct sh2000_run *r, int e)
{
	if (e && e != -EAGAIN) {
		r->failed = e;
		halt_card(r);
	}
	return e;
}

static int sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct sh2000_run *r = ctx;
	unsigned int a, lim;
	double d = 0.0;

	double mm[SH2000_AXES];
	char why[160];
	int e;

	if (r->failed)
		return r->failed;
	/* a batch the card could not take during a feed hold goes first */
	if (r->n == SH2000_RING_RECORDS || r->end_held) {
		e = flush(r, r->end_held);
		if (e)
			return sink_fail(r, e);
	}
	memcpy(mm, pt->mm, sizeof(mm));
	e = sh2000_setpoints_point(&r->sp, mm, pt->flags & SH2000_PATH_F_END,
				   why, sizeof(why));
	if (e < 0) {
		r->failed = fail(r, e, "%s: point %llu (tag %u): %s",
				 sh2000_device(r->h),
				 (unsigned long long)r->emitted,
				 (unsigned int)pt->seq, why);
		halt_card(r);
		return e;
	}
	memcpy(r->buf[r->n], pt->counts, sizeof(r->buf[0]));
	if (e > 0)	/* put on the limit: the counts follow */
		for (a = 0; a < SH2000_AXES; a++)
			r->buf[r->n][a] = (int32_t)llround(mm[a] *
							   r->scale[a]);
	sh2000_moved_add(&r->moved, r->buf[r->n]);
	r->n++;
	r->seqs[r->emitted++ % RUN_SEQS] = pt->seq;
	if (r->have_last) {
		for (a = 0; a < SH2000_AXES; a++)
			d += (pt->mm[a] - r->last_mm[a]) *
			     (pt->mm[a] - r->last_mm[a]);
		r->stats.distance_mm += sqrt(d);
	}
	memcpy(r->last_mm, pt->mm, sizeof(r->last_mm));
	r->have_last = 1;
	lim = r->in_motion ? r->cfg.batch : r->cfg.prime;
	if (pt->flags & SH2000_PATH_F_END) {
		r->stats.motions++;
		r->end_held = 1;
		e = flush(r, 1);
	} else {
		e = r->n >= lim ? flush(r, 0) : 0;
	}
	/* held: the point is in the batch, which waits for the resume */
	return e == -EAGAIN ? 0 : sink_fail(r, e);
}

/* The card's status, which must show it idle with nothing queued. */
static int card_idle(struct sh2000_run *r, struct sh2000 *h)
{
	int e = sh2000_poll(h, &r->st);

	if (e < 0)
		return lib_fail(r, e, "status poll");
	e = sh2000_status_error(h, &r->st);
	if (e < 0)
		return lib_fail(r, e, "card");
	if (r->st.card_state != SH2000_STATE_IDLE || r->st.queue_fill)
		return fail(r, -SH2000_ECMD_BUSY,
			    "%s: the card is not idle (state %u, %u records queued)",
			    sh2000_device(h), r->st.card_state, r->st.queue_fill);
	return 0;
}

int sh2000_run_create(struct sh2000_run **out, struct sh2000 *h,
		      const struct sh2000_path_config *pc,
		      const struct sh2000_run_config *rc, char *msg,
		      size_t msglen)
{
	struct sh2000_run *r;
	double coarse_us, fine;
	unsigned int a;
	int e;

	*out = NULL;
	if (!h || !pc) {
		if (msg && msglen)
			snprintf(msg, msglen, "run: no card or no planner configuration");
		return -EINVAL;
	}
	r = calloc(1, sizeof(*r));
	if (!r) {
		if (msg && msglen)
			snprintf(msg, msglen, "run: out of memory");
		return -ENOMEM;
	}
	r->h = h;
	if (rc)
		r->cfg = *rc;
	else
		sh2000_run_config_default(&r->cfg);
	if (r->cfg.batch < 1 || r->cfg.batch > SH2000_RING_RECORDS ||
	    r->cfg.prime < r->cfg.batch || r->cfg.prime > SH2000_RING_RECORDS) {
		e = fail(r, -EINVAL,
			 "run: batch %u / prime %u: need 1 <= batch <= prime <= %u",
			 r->cfg.batch, r->cfg.prime, SH2000_RING_RECORDS);
		goto err;
	}
	e = sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US,
			     &coarse_us);
	if (!e)
		e = sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS,
				     &fine);
	if (e) {
		lib_fail(r, e, "reading the card's timing");
		goto err;
	}
	r->coarse_ns = (uint64_t)llround(coarse_us * 1000.0);
	r->servo_ns = r->coarse_ns / (uint64_t)(fine >= 1.0 ? fine : 1.0);
	if (!r->cfg.sample_ns)
		r->cfg.sample_ns = r->coarse_ns;
	for (a = 0; a < SH2000_AXES; a++) {
		e = sh2000_param_get(h, (int)a, SH2000_P_SCALE, &r->scale[a]);
		if (e) {
			lib_fail(r, e, "reading the scales");
			goto err;
		}
		if (pc->counts_per_mm[a] != r->scale[a]) {
			e = fail(r, -EINVAL,
				 "run: planner scale of axis %u (%g counts/mm) is not the card's (%g)",
				 a, pc->counts_per_mm[a], r->scale[a]);
			goto err;
		}
	}
	e = sh2000_limits_get(h, &r->limits);
	if (e) {
		lib_fail(r, e, "reading the soft limits");
		goto err;
	}
	sh2000_setpoints_init(&r->sp, &r->limits);
	sh2000_setpoints_rest(&r->sp, pc->start);
	sh2000_setpoints_pair(&r->sp, pc);
	/* the distance counts from where the card stands: the first point
	 * of a motion from rest is a period's travel away from it */
	memcpy(r->last_mm, pc->start, sizeof(r->last_mm));
	r->have_last = 1;
	e = card_idle(r, h);
	if (e < 0)
		goto err;
	r->have_st = 1;
	r->cycle0 = r->st.card_cycle;
	r->stats.min_fill = SH2000_RING_RECORDS;
	e = sh2000_path_create(&r->path, pc, sink, r, r->err, sizeof(r->err));
	if (e)
		goto err;
	e = sh2000_setpoints_bound(&r->limits, r->path);
	if (e) {
		fail(r, e, "run: the card's soft limits: %s",
		     sh2000_path_error(r->path));
		goto err;
	}
	if (sh2000_backend(h) == SH2000_BACKEND_SIM) {
		r->sim = 1;
		e = sh2000_watch_cycles(h, observe, r);
		if (e) {
			lib_fail(r, e, "sim observer");
			goto err;
		}
	}
	/* a card with a time base (protocol 1.1) holds and overrides
	 * itself; it starts at full rate */
	e = sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_TIME_SCALE,
			     SH2000_TIME_SCALE_FULL);
	r->tb = e == 0;
	r->tb_factor = 1.0;
	*out = r;
	return 0;
err:
	if (msg && msglen)
		snprintf(msg, msglen, "%s", r->err);
	if (r->path)
		sh2000_path_destroy(r->path);
	free(r);
	return e;
}

void sh2000_run_destroy(struct sh2000_run *r)
{
	if (!r)
		return;
	if (r->sim)
		sh2000_watch_cycles(r->h, NULL, NULL);
	sh2000_path_destroy(r->path);
	free(r);
}

struct sh2000_path *sh2000_run_path(struct sh2000_run *r)
{
	return r->path;
}

int sh2000_run_finish(struct sh2000_run *r)
{
	int e, paused;

	e = r->failed ? r->failed : sh2000_path_finish(r->path);
	paused = e == -EAGAIN;
	if (e && !paused) {
		/* a sink failure already has the card's words in r->err */
		if (!r->failed)
			fail(r, e, "planner: %s", sh2000_path_error(r->path));
		reset_plan(r);
		return e;
	}
	/* a motion always ends with END, which flushes: nothing is left
	 * but what a feed hold keeps back */
	e = flush(r, r->end_held);
	if (!e)
		e = wait_card(r, 0, 1);
	if (e == -EAGAIN)
		return e;	/* a feed hold: at rest on the path */
	if (!e) {
		e = sh2000_wait_idle(r->h, r->cfg.stall_ms);
		if (e < 0)
			lib_fail(r, e, "waiting for idle");
	}
	if (!e)
		e = poll_once(r);
	if (e) {
		reset_plan(r);
		return e;
	}
	progress(r);
	if (r->stopped) {
		r->stopped = 0;
		return -ECANCELED;
	}
	return paused ? -EAGAIN : 0;
}

int sh2000_run_dwell(struct sh2000_run *r, double seconds)
{
	uint64_t end, now;
	int e;

	if (r->failed)
		return r->failed;
	if (!(seconds >= 0.0) || seconds > 1e6)
		return fail(r, -EINVAL, "dwell: %g s", seconds);
	now = sh2000_now_ns(r->h);
	end = now + (uint64_t)llround(seconds * 1e9);
	while (now < end) {
		uint64_t step = end - now;

		if (step > RUN_WAIT_MAX_NS)
			step = RUN_WAIT_MAX_NS;
		if (r->cfg.sample && !r->sim && step > r->cfg.sample_ns)
			step = r->cfg.sample_ns;
		e = sh2000_sleep_ns(r->h, step);
		if (e < 0)
			return lib_fail(r, e, "dwell");
		e = poll_once(r);
		if (e)
			return e;
		progress(r);
		if (r->stopped)
			break;
		now = sh2000_now_ns(r->h);
	}
	return 0;
}

void sh2000_run_stop(struct sh2000_run *r)
{
	r->stopped = 1;
	sh2000_path_stop(r->path);
}

int sh2000_run_stop_requested(const struct sh2000_run *r)
{
	return r->stopped;
}

void sh2000_run_pause(struct sh2000_run *r)
{
	if (!r->tb) {
		sh2000_path_pause(r->path);
		return;
	}
	r->held = 1;
	r->tb_dirty = 1;
}

void sh2000_run_resume(struct sh2000_run *r)
{
	if (!r->tb) {
		sh2000_path_resume(r->path);
		return;
	}
	r->held = 0;
	r->tb_dirty = 1;
}

int sh2000_run_held(const struct sh2000_run *r)
{
	return r->tb && r->held;
}

/* Up to full rate on the card's time base, above it in the plan. */
int sh2000_run_set_override(struct sh2000_run *r, double factor)
{
	int card = r->tb && factor <= 1.0;
	int e = sh2000_path_set_override(r->path, card ? 1.0 : factor);

	if (e)
		return fail(r, e, "override: %s", sh2000_path_error(r->path));
	if (r->tb) {
		r->tb_factor = card ? factor : 1.0;
		r->tb_dirty = 1;
	}
	return 0;
}

int sh2000_run_hold_wait(struct sh2000_run *r, unsigned int ms)
{
	uint64_t end = sh2000_now_ns(r->h) + (uint64_t)ms * 1000000ull;
	int e = 0;

	while (!e && sh2000_now_ns(r->h) < end) {
		e = tb_apply(r);
		if (!e)
			e = poll_once(r);
		if (e)
			break;
		progress(r);
		if (!sh2000_run_held(r) || r->stopped)
			break;
		e = sh2000_sleep_ns(r->h, 1000000ull);
		if (e < 0)
			e = lib_fail(r, e, "waiting");
	}
	/* a held card keeps its ring: a failure must not leave it there */
	if (e < 0)
		halt_card(r);
	return e;
}

const char *sh2000_run_error(const struct sh2000_run *r)
{
	const char *pe = sh2000_path_error(r->path);

	if (r->failed || !strcmp(pe, r->path_err))
		return r->err;
	return pe;
}

void sh2000_run_stats(const struct sh2000_run *r, struct sh2000_run_stats *st)
{
	*st = r->stats;
}
