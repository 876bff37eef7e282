/* SPDX-License-Identifier: MIT */
/*
 * One poll: words 0..SH2000_STATUS_WORDS-1 in one streamed read, re-read
 * while the versioned snapshot is torn, then the host heartbeat (word 47,
 * one increment further). Decoding: 28-bit counters extended to 64 bits
 * per handle, the card heartbeat's age in host time, latched faults to
 * errors.
 */
#include <errno.h>
#include <string.h>

#include "sh2000_internal.h"

/* Pause between re-reads once the immediate ones are spent. */
#define TORN_WAIT_NS	20000ull
/* Torn reads of ever new publications a poll makes before it gives up:
 * the card is alive, the reader too slow for it (a read of the snapshot
 * takes 24 port cycles, about 50 us on a real bus) */
#define TORN_MOVING_READS 1024u

void sh2000_status_decode(struct sh2000 *h, const uint16_t *w,
			  struct sh2000_status *st)
{
	unsigned int a;

	st->estop_req = w[SH2000_W_ESTOP_REQ];
	st->heartbeat = w[SH2000_W_HEARTBEAT];
	st->estop_ack = w[SH2000_W_ESTOP_ACK];
	st->card_state = w[SH2000_W_STATE];
	st->card_faults = w[SH2000_W_FAULTS];
	st->queue_fill = (uint16_t)(h->head - w[SH2000_W_TAIL]);
	st->queue_free = st->queue_fill <= SH2000_RING_RECORDS ?
			 SH2000_RING_RECORDS - st->queue_fill : 0;
	st->reject_seq = w[SH2000_W_REJECT_SEQ];
	st->reject_reason = w[SH2000_W_REJECT_REASON];
	st->reject_count = w[SH2000_W_REJECT_COUNT];
	h->nb.tail = w[SH2000_W_TAIL];
	h->nb.tail_seen = 1;
	sh2000_mbox_status(h, st->card_state);
	h->nb.estop_ack_seen = w[SH2000_W_ESTOP_ACK];
	{
		uint32_t c = (uint32_t)sh2000_w32(&w[SH2000_W_SNAP_TIME_LO]);

		h->ext.cycle_ext = h->ext.cycle_seen ? h->ext.cycle_ext + (uint32_t)(c - h->ext.cycle_last) : c;
		h->ext.cycle_last = c;
		h->ext.cycle_seen = 1;
		st->card_cycle = h->ext.cycle_ext;
	}
	st->snap_seq = w[SH2000_W_SNAP_SEQ_END];
	for (a = 0; a < SH2000_AXES; a++) {
		const uint16_t *s = &w[SH2000_W_SNAP_AXIS(a)];
		struct sh2000_axis_status *ax = &st->axis[a];
		uint32_t raw = (uint32_t)sh2000_w32(&s[SH2000_SNAP_ACT_LO]) &
			       SH2000_COUNTER_MASK;

		if (!h->ext.act_seen)
			h->ext.act_ext[a] = sh2000_counter_signed(raw);
		else
			h->ext.act_ext[a] += sh2000_counter_delta(raw, h->ext.act_last[a]);
		h->ext.act_last[a] = raw;
		ax->pos_counts = h->ext.act_ext[a];
		ax->cmd_counts = sh2000_w32(&s[SH2000_SNAP_CMD_LO]);
		ax->ferr_counts = sh2000_counter_delta(
			(uint32_t)ax->cmd_counts, raw);
		ax->dac = (int16_t)s[SH2000_SNAP_DAC];
		ax->state = w[SH2000_W_AXIS_STATE(a)];
		ax->faults = w[SH2000_W_AXIS_FAULTS(a)];
		ax->pos_mm = (double)ax->pos_counts / h->scale[a];
		ax->cmd_mm = (double)ax->cmd_counts / h->scale[a];
		ax->ferr_mm = (double)ax->ferr_counts / h->scale[a];
	}
	h->ext.act_seen = 1;
}

/*
 * The heartbeat is 16 bits: after 2^16 servo cycles it shows the same
 * value again. An unchanged value read after a gap that long (less a
 * margin for a card clock a little faster than the host's) proves
 * nothing: the watch restarts from now and hb_unsure asks the caller to
 * look again.
 */
static uint64_t hb_wrap_ns(const struct sh2000 *h)
{
	/* 15/16 of a wrap; before the timing is known, the limit */
	return h->servo_ns ? (h->servo_ns << 16) - (h->servo_ns << 12) :
	       h->hb.limit_ns;
}

uint64_t sh2000_hb_note(struct sh2000 *h, uint16_t hb, uint64_t now)
{
	if (!h->hb.seen || hb != h->hb.last) {
		h->hb.seen = 1;
		h->hb.last = hb;
		h->hb.change_ns = now;
		h->hb.unsure = 0;
	} else if (now - h->hb.seen_ns >= hb_wrap_ns(h)) {
		h->hb.change_ns = now;
		h->hb.unsure = 1;
	}
	h->hb.seen_ns = now;
	return now - h->hb.change_ns;
}

/*
 * A snapshot left torn inside one publication while the card heartbeat
 * (word 3, outside the snapshot) stands still: the card stopped in the
 * middle of a publication (a DSP halted, a served model killed), which
 * the caller learns as a stopped card, not as a tearing one.
 */
int sh2000_torn_dead(struct sh2000 *h, const struct sh2000_status *st,
		     const uint16_t *w)
{
	h->hb.unsure = 0;
	return sh2000_fail(h, -SH2000_EHEARTBEAT,
			   "the card is not answering: card heartbeat stuck at %u for %.1f ms (limit %.1f ms), its status snapshot left torn inside one publication (seq end %u, begin %u)%s",
			   st->heartbeat, st->heartbeat_age_ns / 1e6,
			   h->hb.limit_ns / 1e6, w[SH2000_W_SNAP_SEQ_END],
			   w[SH2000_W_SNAP_SEQ_BEGIN],
			   !strncmp(h->device, "sim:", 4) ?
			   "; is the sh2000-sim serving it still running?" : "");
}

int sh2000_poll_locked(struct sh2000 *h, struct sh2000_status *st)
{
	uint16_t w[SH2000_STATUS_WORDS], torn_end = 0, torn_begin = 0;
	uint16_t hb, hb_stuck = 0;
	unsigned int tries;
	uint64_t now, t0 = 0, t_first = 0;
	int r, hb_moved = 0;

	memset(st, 0, sizeof(*st));
	for (tries = 0;; tries++) {
		/* a retry re-reads the snapshot alone: shorter, so more
		 * likely to fit between two publications */
		unsigned int from = tries ? SH2000_W_SNAP_SEQ_END : 0;

		r = sh2000_rd(h, from, SH2000_STATUS_WORDS - from, &w[from]);
		if (r < 0)
			return r;
		if (w[SH2000_W_SNAP_SEQ_END] == w[SH2000_W_SNAP_SEQ_BEGIN])
			break;
		if (tries < SH2000_POLL_RETRIES)
			continue;
		/*
		 * Still torn: the card was interrupted inside a publication
		 * (a served model descheduled, a DSP stalled mid-write). One
		 * that stays inside the same one for a tenth of the
		 * heartbeat limit while its heartbeat moves on is alive but
		 * not finishing it; one whose heartbeat stands still for the
		 * limit stopped there (sh2000_torn_dead()). A torn read of
		 * another publication shows a card that goes on publishing,
		 * faster than this reader reads (a reader descheduled between
		 * its words or between two reads, a slow bus): that restarts
		 * the tenth, however long the reader was away, and only
		 * TORN_MOVING_READS such reads give up.
		 */
		r = sh2000_rd(h, SH2000_W_HEARTBEAT, 1, &hb);
		if (r < 0)
			return r;
		now = sh2000_now_locked(h);
		if (tries == SH2000_POLL_RETRIES)
			t_first = now;
		if (tries == SH2000_POLL_RETRIES ||
		    w[SH2000_W_SNAP_SEQ_END] != torn_end ||
		    w[SH2000_W_SNAP_SEQ_BEGIN] != torn_begin) {
			t0 = now;
			torn_end = w[SH2000_W_SNAP_SEQ_END];
			torn_begin = w[SH2000_W_SNAP_SEQ_BEGIN];
			hb_stuck = hb;
			hb_moved = 0;
		} else if (hb != hb_stuck) {
			hb_moved = 1;
		}
		st->heartbeat = hb;
		st->heartbeat_age_ns = sh2000_hb_note(h, hb, now);
		if (st->heartbeat_age_ns >= h->hb.limit_ns)
			return sh2000_torn_dead(h, st, w);
		if ((hb_moved && now - t0 >= h->hb.limit_ns / 10) ||
		    tries >= SH2000_POLL_RETRIES + TORN_MOVING_READS)
			return sh2000_fail(h, -SH2000_ETORN,
					   "status snapshot torn %u times in a row over %.1f ms (seq end %u, begin %u)",
					   tries + 1, (now - t_first) / 1e6,
					   w[SH2000_W_SNAP_SEQ_END],
					   w[SH2000_W_SNAP_SEQ_BEGIN]);
		sh2000_hold_wait(h, TORN_WAIT_NS);
	}
	st->heartbeat = 0;
	st->heartbeat_age_ns = 0;
	r = sh2000_host_beat(h, &now);
	if (r < 0)
		return r;
	st->retries = tries;
	st->host_time_ns = now;
	sh2000_status_decode(h, w, st);
	if (w[SH2000_W_MAGIC] == SH2000_PROTO_MAGIC) {
		r = sh2000_first_fault_update(h, w, st, SH2000_POLL_RETRIES);
		if (r < 0)
			return r;
	}
	st->heartbeat_age_ns = sh2000_hb_note(h, st->heartbeat, now);
	/* the same heartbeat as long ago: wrapped, or stopped? Watch it
	 * until it moves or the limit says stopped */
	while (h->hb.unsure && st->heartbeat_age_ns < h->hb.limit_ns) {
		uint16_t hb;

		sh2000_hold_wait(h, h->servo_ns ? h->servo_ns : TORN_WAIT_NS);
		r = sh2000_rd(h, SH2000_W_HEARTBEAT, 1, &hb);
		if (r < 0)
			return r;
		st->heartbeat_age_ns = sh2000_hb_note(h, hb,
						      sh2000_now_locked(h));
	}
	h->hb.unsure = 0;
	return sh2000_status_alive(h, w, st);
}

int sh2000_status_alive(struct sh2000 *h, const uint16_t *w,
			const struct sh2000_status *st)
{
	if (w[SH2000_W_MAGIC] != SH2000_PROTO_MAGIC)
		return sh2000_fail(h, -SH2000_EMAGIC,
				   "magic word (%u) now reads 0x%04x, expected 0x%04x: card lost its firmware",
				   SH2000_W_MAGIC, w[SH2000_W_MAGIC],
				   SH2000_PROTO_MAGIC);
	if (st->heartbeat_age_ns >= h->hb.limit_ns)
		return sh2000_fail(h, -SH2000_EHEARTBEAT,
				   "the card is not answering: card heartbeat stuck at %u for %.1f ms (limit %.1f ms; its last snapshot: state %s, cycle %llu)%s",
				   st->heartbeat, st->heartbeat_age_ns / 1e6,
				   h->hb.limit_ns / 1e6,
				   sh2000_state_name(st->card_state),
				   (unsigned long long)st->card_cycle,
				   !strncmp(h->device, "sim:", 4) ?
				   "; is the sh2000-sim serving it still running?" : "");
	return 0;
}

int sh2000_host_beat(struct sh2000 *h, uint64_t *now)
{
	int r;

	h->host_hb++;
	r = sh2000_wr1(h, SH2000_W_HOST_HEARTBEAT, h->host_hb);
	if (r < 0)
		return r;
	*now = sh2000_now_locked(h);
	h->host_hb_ns = *now;
	return 0;
}

int sh2000_fresh_snapshot(struct sh2000 *h, int timeout_ms)
{
	uint16_t s0, s;
	uint64_t t0 = sh2000_now_locked(h);
	int r = sh2000_rd(h, SH2000_W_SNAP_SEQ_END, 1, &s0);

	while (r == 0) {
		sh2000_hold_wait(h, 100000);
		r = sh2000_rd(h, SH2000_W_SNAP_SEQ_END, 1, &s);
		if (r < 0 || s != s0)
			break;
		if (sh2000_now_locked(h) - t0 > (uint64_t)timeout_ms * 1000000ull) {
			struct sh2000_status st;

			r = sh2000_poll_locked(h, &st);
			if (r == 0)
				r = sh2000_fail(h, -SH2000_ETIMEOUT,
						"no new status snapshot within %d ms",
						timeout_ms);
		}
	}
	return r;
}

void sh2000_timing_changed(struct sh2000 *h)
{
	if (h->coarse_us > 0 && h->fine_steps > 0)
		h->servo_ns = (uint64_t)h->coarse_us * 1000u /
			      (uint64_t)h->fine_steps;
	/* 10 ms, or 5 servo periods when those are longer (docs/protocol.md
	 * section 5: a slow servo must not look like a stalled DSP) */
	h->hb.limit_ns = SH2000_HEARTBEAT_LIMIT_NS;
	/* a served model is an ordinary process: allow for scheduling */
	if (h->be && h->be->kind == SH2000_BACKEND_SHM)
		h->hb.limit_ns = SH2000_HEARTBEAT_LIMIT_SHM_NS;
	if (5 * h->servo_ns > h->hb.limit_ns)
		h->hb.limit_ns = 5 * h->servo_ns;
	if (h->hb.limit_user)
		h->hb.limit_ns = h->hb.limit_user;
}

void sh2000_set_heartbeat_limit(struct sh2000 *h, uint64_t ns)
{
	pthread_mutex_lock(&h->lock);
	h->hb.limit_user = ns;
	sh2000_timing_changed(h);
	pthread_mutex_unlock(&h->lock);
}

int sh2000_poll(struct sh2000 *h, struct sh2000_status *st)
{
	struct sh2000_status local;
	int r;

	pthread_mutex_lock(&h->lock);
	r = sh2000_poll_locked(h, st ? st : &local);
	pthread_mutex_unlock(&h->lock);
	return r;
}

static const struct {
	unsigned int bit;
	int code;
	const char *what;
} axis_faults[] = {
	{ SH2000_AXIS_FAULT_FERR, SH2000_EFERR, "following error limit" },
	{ SH2000_AXIS_FAULT_HARD_LIMIT, SH2000_EHARD_LIMIT, "limit switch" },
	{ SH2000_AXIS_FAULT_SOFT_LIMIT, SH2000_ESOFT_LIMIT, "soft limit" },
	{ SH2000_AXIS_FAULT_DAC_SAT, SH2000_EDAC_SAT, "DAC saturation" },
	{ SH2000_AXIS_FAULT_COUNTER, SH2000_ECOUNTER, "counter fault" },
	{ SH2000_AXIS_FAULT_HOME, SH2000_EHOME, "homing failed" },
	{ SH2000_AXIS_FAULT_SKEW, SH2000_ESKEW, "gantry skew limit" },
};

/* Axis a's fault: the first bit of `bits` in the table's order. The
 * following error is worth saying only while the axis is enabled: a fault
 * the card disabled the axis for leaves its set-point following the
 * counter (0 mm), and the fault record (protocol.md 10.1) keeps no value
 * of it at the trip. */
static int axis_error(struct sh2000 *h, const struct sh2000_status *st,
		      unsigned int a, unsigned int bits)
{
	const struct sh2000_axis_status *ax = &st->axis[a];
	char an = sh2000_axis_letter((int)a);
	unsigned int i;

	for (i = 0; i < sizeof(axis_faults) / sizeof(axis_faults[0]); i++) {
		int code = -axis_faults[i].code;

		if (!(bits & axis_faults[i].bit))
			continue;
		if (ax->state & SH2000_AXIS_ENABLED)
			return sh2000_fail(h, code,
					   "axis %c: %s (axis faults 0x%04x, following error now %.6f mm)",
					   an, axis_faults[i].what, ax->faults, ax->ferr_mm);
		if (axis_faults[i].bit == SH2000_AXIS_FAULT_FERR)
			return sh2000_fail(h, code,
					   "axis %c: following error limit (axis faults 0x%04x): the following error passed ferr_limit and the card disabled the axis; its value at the trip is not kept",
					   an, ax->faults);
		return sh2000_fail(h, code,
				   "axis %c: %s (axis faults 0x%04x): the card disabled the axis",
				   an, axis_faults[i].what, ax->faults);
	}
	return sh2000_fail(h, -SH2000_EFAULTED,
			   "axis %c: unknown fault bits 0x%04x",
			   sh2000_axis_letter((int)a), bits);
}

static int rejected_error(struct sh2000 *h, const struct sh2000_status *st)
{
	uint64_t last = h->segments ? h->segments - 1 : 0;
	uint64_t seg = last - (uint16_t)((uint16_t)last - st->reject_seq);

	return sh2000_fail(h, -SH2000_EREJECTED,
			   "segment %llu (record seq %u) rejected: %s (rejection #%u)",
			   (unsigned long long)seg, st->reject_seq,
			   sh2000_reject_name(st->reject_reason),
			   st->reject_count);
}

/* The card fault `bit` (one SH2000_FAULT_* bit). */
static int card_error(struct sh2000 *h, const struct sh2000_status *st,
		      unsigned int bit)
{
	unsigned int f = st->card_faults;

	switch (bit) {
	case SH2000_FAULT_ESTOP:
		return sh2000_fail(h, -SH2000_EESTOP,
				   "emergency stop latched (card state %s, faults 0x%04x); a reset clears it",
				   sh2000_state_name(st->card_state), f);
	case SH2000_FAULT_REJECTED:
		return rejected_error(h, st);
	case SH2000_FAULT_HOST_TIMEOUT:
		return sh2000_fail(h, -SH2000_EHOST_TIMEOUT,
				   "card stopped: no host heartbeat or segments within its host timeout");
	case SH2000_FAULT_UNDERRUN:
		return sh2000_fail(h, -SH2000_EUNDERRUN,
				   "segment queue ran dry mid-motion: card made a controlled stop (state %s)",
				   sh2000_state_name(st->card_state));
	case SH2000_FAULT_PROTOCOL:
		return sh2000_fail(h, -SH2000_EPROTOCOL,
				   "card latched a protocol fault (impossible ring fill %u)",
				   st->queue_fill);
	case SH2000_FAULT_AXIS:
		return sh2000_fail(h, -SH2000_EFAULTED,
				   "card reports an axis fault but no axis has one");
	default:
		return sh2000_fail(h, -SH2000_EFAULTED,
				   "card faulted (state %s, faults 0x%04x)",
				   sh2000_state_name(st->card_state), f);
	}
}

/* A card before 1.4 keeps no order of its faults: a fixed ranking. */
static int ranked_error(struct sh2000 *h, const struct sh2000_status *st)
{
	static const unsigned int after_rejected[] = {
		SH2000_FAULT_HOST_TIMEOUT, SH2000_FAULT_UNDERRUN,
		SH2000_FAULT_PROTOCOL, SH2000_FAULT_AXIS,
	};
	unsigned int f = st->card_faults, a, i;

	if (st->card_state == SH2000_STATE_ESTOP || (f & SH2000_FAULT_ESTOP))
		return card_error(h, st, SH2000_FAULT_ESTOP);
	for (a = 0; a < SH2000_AXES; a++)
		if (st->axis[a].faults)
			return axis_error(h, st, a, st->axis[a].faults);
	/* a record refused because the card had already stopped is a
	 * consequence: report the cause first */
	if ((f & SH2000_FAULT_REJECTED) &&
	    (st->reject_reason != SH2000_REJECT_STATE ||
	     !(f & (SH2000_FAULT_HOST_TIMEOUT | SH2000_FAULT_UNDERRUN |
		    SH2000_FAULT_PROTOCOL))))
		return rejected_error(h, st);
	for (i = 0; i < sizeof(after_rejected) / sizeof(after_rejected[0]); i++)
		if (f & after_rejected[i])
			return card_error(h, st, after_rejected[i]);
	if (f || st->card_state == SH2000_STATE_FAULT)
		return card_error(h, st, 0);
	return 0;
}

int sh2000_status_faulted(const struct sh2000_status *st)
{
	unsigned int a;

	if (st->card_faults || st->card_state == SH2000_STATE_FAULT ||
	    st->card_state == SH2000_STATE_ESTOP)
		return 1;
	for (a = 0; a < SH2000_AXES; a++)
		if (st->axis[a].faults)
			return 1;
	return 0;
}

int sh2000_status_error_locked(struct sh2000 *h,
			       const struct sh2000_status *st)
{
	const struct sh2000_first_fault *ff = &st->first_fault;

	/* the card's own record of which came first (1.4) */
	if (ff->bit && ff->axis < SH2000_AXES)
		return axis_error(h, st, ff->axis, ff->bit);
	if (ff->bit)
		return card_error(h, st, ff->bit);
	return ranked_error(h, st);
}

int sh2000_status_error(struct sh2000 *h, const struct sh2000_status *st)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = sh2000_status_error_locked(h, st);
	pthread_mutex_unlock(&h->lock);
	return r;
}
