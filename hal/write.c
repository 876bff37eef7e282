// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * The write half of a tick: the card's timing (once, for the thread's
 * period), the commands the pins ask for (reset, enable, disable), and the
 * stream: one coarse point per tick while the enabled axes are the ones
 * the enable pins want. Never more than one command in flight; every call
 * is one of libsh2000's real-time calls.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "hsc.h"

static void start(struct hsc_card *c, unsigned int op, unsigned int axis,
		  unsigned int param, int32_t arg)
{
	int r = sh2000_command_start(c->h, op, axis, param, arg);

	if (r == 0) {
		c->cmd_busy = 1;
		c->cmd_op = op;
		c->cmd_arg = (unsigned int)arg;
	} else if (r != -EAGAIN) {
		snprintf(c->err, sizeof(c->err), "%s", sh2000_last_error(c->h));
		c->sfault = op == SH2000_CMD_SET_PARAM ? HSC_SF_CONFIG :
			    HSC_SF_COMMAND;
	}
}

/* Fine steps for a coarse period: servo cycles near HSC_SERVO_NS that
 * divide it exactly (the card's rule). */
int hsc_fine_steps(long period_ns)
{
	long n = period_ns / HSC_SERVO_NS;

	if (n < 1)
		n = 1;
	while (n > 1 && period_ns % n)
		n--;
	return (int)n;
}

/* The sets that take the card's timing from fine_steps 1 (its coarse
 * period whatever it is: 0, not known) to (coarse_us, fine): libsh2000's
 * path through legal states. Pure, so it runs in the tick; the steps go
 * out one command per tick. 0, or -1 with the reason in c->err. */
static int plan_timing(struct hsc_card *c, unsigned int coarse_us,
		       unsigned int fine)
{
	int n = sh2000_timing_path(0, 1, coarse_us, fine, 0, c->tsteps,
				   SH2000_TIMING_STEPS_MAX);

	if (n < 0) {
		snprintf(c->err, sizeof(c->err),
			 "%s: no legal way from fine_steps 1 to coarse_period_us %u, fine_steps %u",
			 c->device, coarse_us, fine);
		return -1;
	}
	c->ntsteps = n;
	return 0;
}

/*
 * The card's timing follows the thread: coarse period = the thread's
 * period, fine steps for ~100 us servo cycles, and a status period one
 * cycle longer than the coarse period, so that a poll torn by a
 * publication is never torn again on the next tick. fine_steps is set to
 * 1 first, which every coarse period allows, so the driver needs not know
 * the card's timing; the rest is libsh2000's path from there (plan_timing:
 * the coarse period, then the fine steps). Going through fine_steps 1 also
 * starts the card's coarse periods alike on every card of the thread:
 * without it two cards of one thread started 288 us apart in
 * linuxcnc_hsc's drift test, whose bound is 250 us.
 */
static void configure(struct hsc_card *c)
{
	const struct sh2000_param_info *cp =
		sh2000_param_lookup(SH2000_GP_COARSE_PERIOD_US);
	unsigned int us = (unsigned int)(c->period_ns / 1000);
	int n = hsc_fine_steps(c->period_ns);

	if (c->period_ns % 1000 || sh2000_param_in_range(cp, (double)us)) {
		if (c->sfault == HSC_SF_NONE)
			snprintf(c->err, sizeof(c->err),
				 "%s: servo period %ld ns: the card's %s is a whole number of us in %.0f..%.0f",
				 c->device, c->period_ns, cp->name, cp->min,
				 cp->max);
		c->sfault = HSC_SF_CONFIG;
		return;
	}
	if (c->cfg_step == 0) {
		start(c, SH2000_CMD_SET_PARAM, SH2000_AXIS_GLOBAL,
		      SH2000_GP_FINE_STEPS, 1);
		return;
	}
	if (c->cfg_step == 1 && plan_timing(c, us, (unsigned int)n) < 0) {
		c->sfault = HSC_SF_CONFIG;
		return;
	}
	if (c->cfg_step <= c->ntsteps) {
		const struct sh2000_timing_step *t = &c->tsteps[c->cfg_step - 1];

		start(c, SH2000_CMD_SET_PARAM, SH2000_AXIS_GLOBAL, t->id,
		      (int32_t)t->value);
	} else if (c->cfg_step == c->ntsteps + 1) {
		start(c, SH2000_CMD_SET_PARAM, SH2000_AXIS_GLOBAL,
		      SH2000_GP_STATUS_PERIOD, n + 1);
	} else {
		c->configured = 1;
		/* the heartbeat ran at other rates while the timing changed:
		 * the phase reference is read again on the card's own */
		hsc_tb_reset(&c->tb);
	}
}

/* The pins' command in counts; 0, or -1 when one is not representable. */
static int command_counts(struct hsc_card *c, const struct hsc_in *in,
			  int32_t cmd[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		double v = nearbyint(in->axis[a].position_cmd *
				     in->axis[a].position_scale);

		if (!isfinite(v) || v < INT32_MIN || v > INT32_MAX) {
			if (c->sfault == HSC_SF_NONE)
				snprintf(c->err, sizeof(c->err),
					 "%s: axis %u: position-cmd %g is not representable in counts",
					 c->device, a, in->axis[a].position_cmd);
			return -1;
		}
		cmd[a] = (int32_t)v;
	}
	return 0;
}

/* The point for the card: the command for enabled axes, where a disabled
 * axis is for the others (the card rejects a disabled axis moved). */
static void point(struct hsc_card *c, const int32_t cmd[SH2000_AXES],
		  int32_t pt[SH2000_AXES])
{
	unsigned int a, en = hsc_enabled(&c->st);

	for (a = 0; a < SH2000_AXES; a++)
		pt[a] = en & (1u << a) ? cmd[a] :
			(int32_t)c->st.axis[a].pos_counts;
}

/*
 * One record of the stream: the command cmd, which is the pins' command
 * at thread time t (ticks). The library posts it in the card's mailbox
 * (protocol 1.3, a few port cycles above the status just read) where it
 * can, else writes it into the ring. A record the card has is kept in
 * the history feedback.c matches the card's set-points against. Returns
 * the library's answer.
 */
static int push(struct hsc_card *c, const int32_t cmd[SH2000_AXES], double t,
		unsigned int flags)
{
	int32_t pt[SH2000_AXES];
	int r;

	point(c, cmd, pt);
	r = sh2000_push_point(c->h, pt, flags);
	if (r >= 0) {
		unsigned int k = (unsigned int)(c->rec_n % HSC_HISTORY);

		memcpy(c->rec[k], cmd, sizeof(c->rec[k]));
		c->rec_t[k] = t;
		c->rec_n++;
	} else if (r != -EAGAIN && r != -SH2000_EQUEUE_FULL) {
		snprintf(c->err, sizeof(c->err), "%s", sh2000_last_error(c->h));
		c->sfault = HSC_SF_COMMAND;
		c->streaming = 0;
	}
	return r;
}

/* The pins' command at thread time t (ticks): linear between the ticks'
 * commands around t, from the history for a t before the last tick (a
 * record pushed late), through the last two ticks' for a t after it,
 * which extrapolates. */
static void command_at(const struct hsc_card *c, double t,
		       int32_t cmd[SH2000_AXES])
{
	double k = floor(t), f;
	const int32_t *p0 = c->prev_cmd, *p1 = c->last_cmd;
	unsigned int a;

	if (k < (double)c->tick - 1.0) {
		uint64_t oldest = c->tick >= HSC_CMD_HISTORY - 1 ?
				  c->tick - (HSC_CMD_HISTORY - 1) : 0;

		if (oldest < c->cmd_hist_from)
			oldest = c->cmd_hist_from;
		if (k < (double)oldest) {
			k = (double)oldest;
			t = k;
		}
		p0 = c->cmd_hist[(uint64_t)k % HSC_CMD_HISTORY];
		p1 = c->cmd_hist[((uint64_t)k + 1) % HSC_CMD_HISTORY];
		f = t - k;
	} else {
		f = t - ((double)c->tick - 1.0);
	}
	if (f < 0)
		f = 0;
	for (a = 0; a < SH2000_AXES; a++) {
		double v = nearbyint(p0[a] + f * (p1[a] - p0[a]));

		/* only an extrapolation leaves the two commands' range */
		cmd[a] = v < INT32_MIN || v > INT32_MAX ? c->last_cmd[a] :
			 (int32_t)v;
	}
}

/* This tick's command into the history (streaming or not: the first
 * records of a stream are this tick's). */
static void remember_command(struct hsc_card *c)
{
	memcpy(c->cmd_hist[c->tick % HSC_CMD_HISTORY], c->last_cmd,
	       sizeof(c->last_cmd));
	if (!c->streaming)
		c->cmd_hist_from = c->tick;
}

/* Is the stream still the card's motion? */
static void check_stream(struct hsc_card *c)
{
	if (!c->streaming || !c->st_fresh)
		return;
	if (hsc_faulted(&c->st)) {
		c->streaming = 0;	/* the card stopped: its fault says why */
		return;
	}
	if (c->st.card_state == SH2000_STATE_RUNNING)
		c->seen_running = 1;
	/*
	 * A STOP command from another program: the card decelerates
	 * (STOPPING without a fault) and goes idle with the ring discarded.
	 * A card that has simply not started on the first records yet (a
	 * served model that was descheduled) is idle too, but has not been
	 * seen running.
	 */
	if (c->st.card_state == SH2000_STATE_STOPPING ||
	    (c->seen_running && c->st.card_state == SH2000_STATE_IDLE)) {
		snprintf(c->err, sizeof(c->err),
			 "%s: the card left the motion (state %s): stopped by another program",
			 c->device, sh2000_state_name(c->st.card_state));
		c->sfault = HSC_SF_STOPPED;
		c->streaming = 0;
	}
}

/* A new window of the fill's readings (low_fill()). */
static void fill_window_reset(struct hsc_card *c)
{
	memset(c->fill_hist, 0, sizeof(c->fill_hist));
	c->fill_n = 0;
}

/* Where the batch that lands this tick lands on the card's clock: this
 * tick's start plus its lateness (start_check() takes it from there). */
static void start_note(struct hsc_card *c)
{
	c->start_check = c->tb.locked && c->servo_ns > 0;
	c->delay_n = 0;
	c->start_clock = c->tb.clock +
			 (double)c->late_ns / (double)c->period_ns;
	c->start_ref = c->tb.tick0;
}

/*
 * The card starts on the first batch when it sees it: a served card whose
 * server lags when the batch lands starts that much early on its own
 * clock (a real card never lags), and it plays every record of the
 * stream that much early against the other cards. Once the delay from a
 * record to the card's set-point is measured (feedback.c, in the card's
 * servo cycles: it says on which cycle the card started), the timebase's
 * reference says on which cycle the batch landed. The card plays record u
 * from that cycle on at u + 2 periods (the B-spline window) plus the
 * servo cycle in which it takes the first record. A card found early, or
 * late (a served follower was found up to 0.81 periods late in
 * linuxcnc_drift, its start traced this way to within 0.01 periods of
 * the skew measured from outside), is taken into the schedule at
 * HSC_SLIP_RATE, as a target's change is: the records then hold the
 * commands of the instants the card really plays them at. Found off by
 * more than half the queue, the card's timeline has moved since the
 * start, and the start says nothing; where the driver moves it itself (a
 * point added to a nearly dry ring, the queue re-centred or raised, an
 * underrun), the check is called off.
 */
static void start_check(struct hsc_card *c)
{
	const struct hsc_timebase *tb = &c->tb;
	double n = hsc_period_cycles(c), cycle, early;
	int16_t age = (int16_t)(tb->hb_last - (uint16_t)c->st.card_cycle);

	if (!c->delay_valid || c->delay_n < HSC_START_READINGS)
		return;
	c->start_check = 0;
	/* a new reference, or a snapshot the heartbeat does not place */
	if (!tb->locked || tb->tick0 != c->start_ref || age < -1 ||
	    age > n + 2)
		return;
	/* the landing's cycle, in the status' numbering */
	cycle = (double)c->st.card_cycle - ((double)tb->hb_ext - age) +
		(double)tb->hb0 + n * (c->start_clock + tb->off);
	early = (cycle + 1.0) / n + 2.0 - c->delay;
	/* within half a servo cycle: as good as the schedule gets */
	if (fabs(early) > 0.5 / n && fabs(early) < c->queue_target / 2)
		c->target_left += early;
}

static void start_stream(struct hsc_card *c, int target)
{
	int i;

	c->rec_n = 0;
	/*
	 * The card starts on the batch when it lands, this tick's lateness
	 * after the tick's start; the stream's schedule starts there too, so
	 * every card plays the command with the same delay whenever its
	 * stream started (the cards' skew).
	 */
	c->due = c->late_ns < c->period_ns ?
		 -(double)c->late_ns / (double)c->period_ns : -1.0;
	/* enough records ahead for a thread that is late, pushed at once:
	 * the card starts on the first and needs the next a coarse period
	 * later */
	for (i = 0; i < target; i++)
		push(c, c->last_cmd, (double)c->tick, 0);
	c->streaming = c->sfault == HSC_SF_NONE;
	c->seen_running = 0;
	c->over_ticks = 0;
	c->recentring = 0;
	fill_window_reset(c);
	c->raise_left = 0.0;
	c->target_left = 0.0;
	c->delay_valid = 0;
	c->stream_ticks = -1;	/* this tick's point is in the batch */
	start_note(c);
}

/*
 * The low side of the re-centring: a window of HSC_SLIP_TICKS readings of
 * how far the stream is ahead; when its median sits HSC_LOW_SLACK (a
 * further card: one more) below the natural centre, target - 1, the
 * stream owes the queue the difference, measured as the mean of the
 * readings within a record or two of the median (a stall's short dip
 * does not move a median, nor a mean that leaves it out). It is added
 * back HSC_SLIP_RATE a tick: the card plays the motion that much slower a
 * while, and its delay is what it was. Returns how far to move the
 * schedule this tick.
 */
static double low_fill(struct hsc_card *c, int ahead, int target)
{
	int b, seen = 0, med = -1, slack = HSC_LOW_SLACK + c->tb.follow;
	long sum = 0, n = 0;
	double d;

	if (c->recentring || c->target_left != 0.0) {
		/* a slip's readings, or a target's change, judge nothing */
		if (c->fill_n)
			fill_window_reset(c);
	} else if (c->raise_left <= 0.0) {
		b = ahead < 0 ? 0 : ahead >= HSC_FILL_BINS ?
		    HSC_FILL_BINS - 1 : ahead;
		c->fill_hist[b]++;
		c->fill_n++;
	}
	if (c->fill_n >= HSC_SLIP_TICKS) {
		for (b = 0; b < HSC_FILL_BINS && med < 0; b++) {
			seen += c->fill_hist[b];
			if (2 * seen > c->fill_n)
				med = b;
		}
		for (b = med - 2; b <= med + 2; b++)
			if (b >= 0 && b < HSC_FILL_BINS) {
				sum += (long)b * c->fill_hist[b];
				n += c->fill_hist[b];
			}
		if (med <= target - 1 - slack && n) {
			c->raise_left = (double)(target - 1) -
					(double)sum / (double)n;
			c->start_check = 0;
		}
		fill_window_reset(c);
	}
	if (c->raise_left <= 0.0)
		return 0.0;
	d = c->raise_left < HSC_SLIP_RATE ? c->raise_left : HSC_SLIP_RATE;
	c->raise_left -= d;
	return d;
}

/*
 * The stream after the first batch follows the card's clock
 * (timebase.c): the k-th record holds the command at the instant the
 * card's clock reached k - target + 1 coarse periods after the batch
 * landed, so the card plays the command at its own rate with a constant
 * delay. For the first card the thread itself follows its clock: one
 * record per tick. For a further card the virtual clock counts its
 * periods in the thread's time: about one record per tick, and now and
 * then none or two. Either way the command is interpolated between the
 * last two ticks' (or extrapolated up to HSC_LEAD of a tick, which keeps
 * the queue centred).
 *
 * Only when that fails does the stream move the card's timeline: a card
 * that slipped for HSC_SLIP_TICKS is caught up gradually (faster
 * records), a stream that lost records for good is filled back as
 * gradually (slower records), and a thread that fell so far behind that the ring nearly
 * ran dry adds a record (the measured delay is void then). A tick that runs late sees the card ahead by its
 * lateness; a stall of the whole machine, which the card and the thread
 * both catch up, moves nothing.
 */
static void stream(struct hsc_card *c, int target)
{
	int fill = (int)c->st.queue_fill, n;
	double step = c->tb.step > 0.5 ? c->tb.step : 1.0;

	if (c->stream_ticks++ < 0)
		return;
	if (c->start_check)
		start_check(c);
	c->due += step;
	if (c->target_left != 0.0) {
		double d = fmax(-HSC_SLIP_RATE, fmin(HSC_SLIP_RATE, c->target_left));

		c->target_left -= d;
		c->due += d * step;
	}
	if (c->st_fresh) {
		int ahead = fill + (int)(c->late_ns / c->period_ns);
		int slack = target / 2 > HSC_FILL_SLACK ? target / 2 :
			    HSC_FILL_SLACK;

		/*
		 * The card has taken fewer records than its clock should
		 * have: a stall it will catch up, or a slip. Only when that
		 * lasts is the stream re-centred, and gradually: the records
		 * sample the command HSC_SLIP_RATE faster than the thread's
		 * time until the fill is back at the target, so the card
		 * plays the motion that much faster a while instead of
		 * jumping over what it missed. A full ring alone drops
		 * nothing: the records wait (the loop below stops at a full
		 * ring) and go out when there is room.
		 */
		c->over_ticks = ahead > target + slack &&
				c->target_left == 0.0 ? c->over_ticks + 1 : 0;
		if (c->over_ticks >= HSC_SLIP_TICKS) {
			c->recentring = 1;
			c->start_check = 0;
		}
		if (c->recentring && ahead <= target)
			c->recentring = 0;
		if (c->recentring)
			c->due -= HSC_SLIP_RATE * step;
		c->due += low_fill(c, ahead, target) * step;
		/* the ring nearly dry and nothing owed to it but this
		 * tick's record: the thread fell behind the card, which
		 * holds this point a period (a record owed from earlier
		 * ticks holds an older command: it goes first) */
		if (ahead < target - slack && fill < 2 &&
		    (double)c->rec_n - (double)target + 1.0 >
		    c->due + HSC_LEAD * step - step) {
			c->delay_valid = 0;
			c->start_check = 0;
			c->due += 1.0;
			push(c, c->last_cmd, (double)c->tick, 0);
		}
	}
	for (n = 0; n < HSC_MAX_PUSH; n++) {
		double s = (double)c->rec_n - (double)target + 1.0;
		double t = (double)c->tick - (c->due - s) / step;
		int32_t cmd[SH2000_AXES];

		if (s > c->due + HSC_LEAD * step)
			break;
		command_at(c, t, cmd);
		if (push(c, cmd, t, 0) < 0)
			break;
	}
}

static void commands(struct hsc_card *c, const struct hsc_in *in, int target)
{
	unsigned int en = hsc_enabled(&c->st), want = c->want_mask;
	int idle = c->st.card_state == SH2000_STATE_IDLE;

	if (c->reset_edge && !in->estop && !c->streaming) {
		c->reset_edge = 0;
		c->sfault = HSC_SF_NONE;
		c->err[0] = 0;
		if (hsc_faulted(&c->st) && !hsc_moving(c->st.card_state))
			start(c, SH2000_CMD_RESET, 0, 0, 0);
		return;
	}
	if (!c->configured) {
		if (!hsc_moving(c->st.card_state) && !c->streaming)
			configure(c);
		return;
	}
	if (c->sfault != HSC_SF_NONE || c->lost || hsc_faulted(&c->st) ||
	    in->estop || c->ending) {
		/* axes still enabled after a fault and not wanted */
		if ((en & ~want) && !hsc_moving(c->st.card_state) && !c->streaming)
			start(c, SH2000_CMD_DISABLE, 0, 0, (int32_t)(en & ~want));
		return;
	}
	if (c->streaming) {
		if ((want & en) != en || want != en) {
			/* an axis is being disabled: end the motion where
			 * the command is, then disable once idle */
			if (push(c, c->last_cmd, (double)c->tick,
				 SH2000_PUSH_END) == -EAGAIN)
				return;	/* the handle is busy: next tick */
			c->streaming = 0;
			c->ending = 1;
		}
		return;
	}
	if ((want & ~en) && idle)
		start(c, SH2000_CMD_ENABLE, 0, 0, (int32_t)(want & ~en));
	else if ((en & ~want) && !hsc_moving(c->st.card_state))
		start(c, SH2000_CMD_DISABLE, 0, 0, (int32_t)(en & ~want));
	else if (want && want == en && idle && c->st_fresh)
		start_stream(c, target);
}

/*
 * queue-target changed. Before the stream starts, the first batch is the
 * new target. While it streams, the schedule (stream(): record k holds
 * the command of clock k - target + 1) would jump by the difference: as
 * many records of past commands at once, or none for as many ticks, a
 * step back or ahead the card rejects as too fast while it moves. So the
 * schedule keeps its place and takes the difference HSC_SLIP_RATE a tick
 * (the card plays the motion that much slower or faster a while, as when
 * it re-centres). The fill read for the old target judges nothing, and
 * what the low side owed is not owed.
 */
static void target_changed(struct hsc_card *c, int target)
{
	if (c->streaming && c->queue_target > 0) {
		double d = (double)(target - c->queue_target);

		c->due -= d;
		c->target_left += d;
	}
	fill_window_reset(c);
	c->raise_left = 0.0;
}

void hsc_write(struct hsc_card *c, const struct hsc_in *in,
	       struct hsc_out *out)
{
	struct sh2000_port_counters pc;
	int32_t cmd[SH2000_AXES];
	int target = in->queue_target > 0 ? in->queue_target : HSC_QUEUE_TARGET;
	unsigned int a;

	if (!c->h)
		return;
	if (target > (int)sh2000_queue_size(c->h) - 4)
		target = (int)sh2000_queue_size(c->h) - 4;
	if (target != c->queue_target)
		target_changed(c, target);
	c->queue_target = target;
	c->want_mask = 0;
	for (a = 0; a < SH2000_AXES; a++)
		if (in->axis[a].enable)
			c->want_mask |= 1u << a;
	if (in->fault_reset && !c->reset_last)
		c->reset_edge = 1;
	c->reset_last = in->fault_reset;

	/* the last two ticks' commands (a bad one repeats the last good) */
	if (command_counts(c, in, cmd) == 0) {
		memcpy(c->prev_cmd, c->have_cmd ? c->last_cmd : cmd, sizeof(cmd));
		memcpy(c->last_cmd, cmd, sizeof(cmd));
		c->have_cmd = 1;
	} else {
		memcpy(c->prev_cmd, c->last_cmd, sizeof(cmd));
		if (c->streaming) {
			c->sfault = HSC_SF_POINT;
			c->streaming = 0;
		}
	}
	remember_command(c);
	if (c->ending && c->st_fresh && !hsc_moving(c->st.card_state))
		c->ending = 0;
	check_stream(c);
	if (!c->cmd_busy && !c->lost)
		commands(c, in, target);
	if (c->streaming && c->sfault == HSC_SF_NONE)
		stream(c, target);

	/* the first card's corrects the thread, a further card's its
	 * virtual clock */
	out->pll_correction_ns = c->tb.locked ?
		(int32_t)lrint(c->tb.correction * (double)c->period_ns) : 0;
	if (sh2000_port_counters(c->h, &pc) == 0) {
		c->port_cycles = (uint32_t)((pc.clears + pc.increments +
					     pc.data_reads + pc.data_writes) -
					    (c->pc_last.clears + c->pc_last.increments +
					     c->pc_last.data_reads + c->pc_last.data_writes));
		c->pc_last = pc;
	}
	out->port_cycles = c->port_cycles;
	out->fault = c->lost || hsc_faulted(&c->st) || c->sfault != HSC_SF_NONE;
	out->ok = !out->fault && c->st_valid;
}
