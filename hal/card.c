// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * One card under a servo thread: opening and closing it (at load and
 * exit), the card's state words as the pins show them, and per tick the
 * read half (status, feedback, command answers, emergency stop). The write
 * half is write.c, the clock correction timebase.c, the feedback's delay
 * feedback.c.
 *
 * Only libsh2000's real-time calls run in a tick, so nothing here waits:
 * a command is started in one tick and its answer taken in a later one, a
 * torn status is simply not fresh this tick.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "hsc.h"

#if defined(__x86_64__) || defined(__i386__)
#include <sys/io.h>
#define HSC_HAVE_IOPERM 1
#endif

int hsc_moving(unsigned int state)
{
	return sh2000_state_moving(state);
}

int hsc_faulted(const struct sh2000_status *st)
{
	return sh2000_status_faulted(st);
}

unsigned int hsc_enabled(const struct sh2000_status *st)
{
	unsigned int a, m = 0;

	for (a = 0; a < SH2000_AXES; a++)
		if (st->axis[a].state & SH2000_AXIS_ENABLED)
			m |= 1u << a;
	return m;
}

int hsc_open(struct hsc_card *c, int index, const char *device, char *msg,
	     size_t len)
{
	struct sh2000_status st;
	int r;

	memset(c, 0, sizeof(*c));
	c->index = index;
	c->master = index == 0;
	snprintf(c->device, sizeof(c->device), "%s", device);
	r = sh2000_open(&c->h, device, msg, len);
	if (r < 0)
		return r;
	/* the motion is the servo thread's from now on: other programs
	 * may look (sh2000ctl status) but not move or enable */
	r = sh2000_claim_motion(c->h);
	if (r == 0)
		r = sh2000_poll(c->h, &st);
	if (r < 0) {
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
		sh2000_close(c->h);
		c->h = NULL;
		return r;
	}
	c->st = st;
	c->st_valid = 1;
	c->last_faults = st.card_faults;
	sh2000_port_counters(c->h, &c->pc_last);
	hsc_tb_reset(&c->tb);
	/* the first card's clock drives the thread; the others' are
	 * followed by a virtual clock each */
	c->tb.follow = !c->master;
	return 0;
}

void hsc_close(struct hsc_card *c)
{
	if (!c->h)
		return;
	hsc_comp_watch_stop(c);
	/* a motion left running would underrun: stop it (not real-time) */
	if (c->streaming)
		sh2000_stop(c->h);
	sh2000_release_motion(c->h);
	sh2000_close(c->h);
	c->h = NULL;
}

double hsc_default_scale(struct hsc_card *c, unsigned int axis)
{
	double v = 0;

	if (!c->h || sh2000_param_get(c->h, (int)axis, SH2000_P_SCALE, &v) < 0 ||
	    !(v > 0))
		return 100000.0;
	return v;
}

int hsc_io_thread(const char *device)
{
#ifdef HSC_HAVE_IOPERM
	if (!strncmp(device, "io:", 3) &&
	    ioperm(strtoul(device + 3, NULL, 0), 4, 1) < 0)
		return -errno;
#else
	(void)device;
#endif
	return 0;
}

/* io: is port I/O from this thread: ioperm() is per thread, so the
 * servo thread asks for the four ports itself. */
static void io_thread_setup(struct hsc_card *c)
{
	int r = hsc_io_thread(c->device);

	c->io_thread_ready = 1;
	if (r < 0)
		snprintf(c->err, sizeof(c->err), "%s: ioperm in the servo thread: %s",
			 c->device, strerror(-r));
}

/* ---- read half ---- */

static void note_status(struct hsc_card *c, const struct sh2000_status *st)
{
	/* a new latched fault: say which (no port cycles: it decodes *st) */
	if (hsc_faulted(st) && !(c->st_valid && hsc_faulted(&c->st)) &&
	    sh2000_status_error(c->h, st) < 0)
		snprintf(c->err, sizeof(c->err), "card: %s",
			 sh2000_last_error(c->h));
	/* count underruns by the fault bit's rising edge */
	if ((st->card_faults & SH2000_FAULT_UNDERRUN) &&
	    !(c->last_faults & SH2000_FAULT_UNDERRUN)) {
		c->underruns++;
		c->start_check = 0;	/* the card held: its start says nothing */
	}
	c->last_faults = st->card_faults;
	c->st = *st;
	c->st_valid = 1;
	c->st_fresh = 1;
}

static void finish_command(struct hsc_card *c)
{
	int32_t value = 0;
	int r = sh2000_command_complete(c->h, &value);

	if (r == -EINPROGRESS || r == -EAGAIN)
		return;
	c->cmd_busy = 0;
	if (c->cmd_op == SH2000_CMD_INDEX_ARM ||
	    c->cmd_op == SH2000_CMD_INDEX_DISARM) {
		hsc_index_answer(c, r, value);
		return;
	}
	if (r == 0) {
		if (c->cmd_op == SH2000_CMD_SET_PARAM && !c->configured)
			c->cfg_step++;
		return;
	}
	snprintf(c->err, sizeof(c->err), "%s", sh2000_last_error(c->h));
	if (c->cmd_op == SH2000_CMD_SET_PARAM && !c->configured)
		c->sfault = HSC_SF_CONFIG;
	else if (c->cmd_op != SH2000_CMD_ENABLE)
		c->sfault = HSC_SF_COMMAND;
	/* a refused ENABLE (a fault latched meanwhile) is retried after a
	 * reset; it needs no fault of its own */
}

static void axis_outputs(struct hsc_card *c, const struct hsc_in *in,
			 struct hsc_out *out)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_axis_status *ax = &c->st.axis[a];
		struct hsc_axis_out *o = &out->axis[a];
		double k = in->axis[a].position_scale;

		if (!(k != 0) || !isfinite(k))
			k = 1.0;
		o->counts = (int32_t)ax->pos_counts;
		o->encoder_position = (double)ax->pos_counts / k;
		o->f_error = (double)ax->ferr_counts / k;
		/* aligned with the command's delay (feedback.c), from the
		 * index mark once one was latched (index.c) */
		o->position_fb = (hsc_feedback_counts(c, a) -
				  hsc_index_offset(c, a)) / k;
		o->amp_fault = ax->faults != 0 || c->ix[a].fault;
		o->home_sw = !!(ax->state & SH2000_AXIS_HOME_SW);
		o->limit_pos = !!(ax->state & SH2000_AXIS_LIMIT_POS);
		o->limit_neg = !!(ax->state & SH2000_AXIS_LIMIT_NEG);
		/* false only in the read that took the mark (index.c) */
		o->index_enable = in->axis[a].index_enable && !c->ix[a].latched;
	}
}

void hsc_read(struct hsc_card *c, const struct hsc_in *in,
	      struct hsc_out *out, long period_ns, long late_ns)
{
	struct sh2000_status st;
	int r;

	c->tick++;
	c->st_fresh = 0;
	c->late_ns = late_ns > 0 ? late_ns : 0;
	if (!c->io_thread_ready)
		io_thread_setup(c);
	if (period_ns > 0 && period_ns != c->period_ns) {
		c->period_ns = period_ns;
		c->configured = 0;
		c->cfg_step = 0;
		c->servo_ns = period_ns / hsc_fine_steps(period_ns);
	}
	hsc_tb_advance(&c->tb, c->tick);
	r = sh2000_poll_once(c->h, &st);
	if (r == 0) {
		c->lost = 0;
		note_status(c, &st);
		c->snap_t = hsc_snap_time(c);
		hsc_clock_offset(c, late_ns);
		hsc_delay_update(c);
		if (hsc_tb_update(&c->tb, c->tick, st.heartbeat, late_ns,
				  c->period_ns, c->servo_ns))
			c->delay_valid = 0;	/* the card's clock jumped */
	} else if (r != -EAGAIN) {
		/* stopped heartbeat, lost firmware, I/O error */
		if (!c->lost)
			snprintf(c->err, sizeof(c->err), "%s", sh2000_last_error(c->h));
		c->lost = 1;
		c->streaming = 0;
		c->delay_valid = 0;
		if (!c->sfault)
			c->sfault = HSC_SF_LOST;
	}
	if (c->cmd_busy)
		finish_command(c);
	hsc_index_read(c, in);
	hsc_comp_take(c);

	/* the estop input: ask until the card shows ESTOP */
	if (in->estop && c->st.card_state != SH2000_STATE_ESTOP &&
	    (!c->estop_last || c->tick - c->estop_tick >= 3)) {
		if (sh2000_estop_request(c->h) == 0)
			c->estop_tick = c->tick;
	}
	if (in->estop)
		c->streaming = 0;	/* the card discards the ring itself */
	c->estop_last = in->estop;

	axis_outputs(c, in, out);
	out->card_state = (int32_t)c->st.card_state;
	out->queue_fill = (int32_t)c->st.queue_fill;
	out->underruns = c->underruns;
	out->delay_ms = hsc_delay_ms(c);
	out->fault = c->lost || hsc_faulted(&c->st) || c->sfault != HSC_SF_NONE;
	out->ok = !out->fault && c->st_valid;
}
