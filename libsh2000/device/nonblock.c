/* SPDX-License-Identifier: MIT */
/*
 * The calls a periodic real-time thread makes (a LinuxCNC servo thread,
 * hal/): one bounded port sequence each, no sleep, no retry, every lock
 * tried once. Whatever would have to wait returns -EAGAIN and is done on
 * a later tick instead: a torn snapshot is read again next tick, a
 * command is started in one tick and its answer picked up in a later
 * one, a point is pushed against the room the last poll saw.
 */
#include <errno.h>
#include <string.h>

#include "sh2000_internal.h"

/* The handle's mutex, tried once; h->nb.active makes the locks below it
 * (the io: bus lock) try once too. */
static int nb_enter(struct sh2000 *h)
{
	if (pthread_mutex_trylock(&h->lock))
		return -EAGAIN;
	h->nb.active = 1;
	return 0;
}

static int nb_leave(struct sh2000 *h, int r)
{
	h->nb.active = 0;
	pthread_mutex_unlock(&h->lock);
	return r;
}

/*
 * A torn snapshot is read again next tick; but a card stopped in the
 * middle of a publication leaves it torn for good, so its heartbeat
 * (word 3, outside the snapshot) is watched on torn ticks too: standing
 * still for the limit, that is a stopped card. *st is left as it was
 * otherwise.
 */
static int torn_once(struct sh2000 *h, const uint16_t *w, uint64_t now,
		     struct sh2000_status *st)
{
	uint64_t age = sh2000_hb_note(h, w[SH2000_W_HEARTBEAT], now);

	h->hb.unsure = 0;
	if (age < h->hb.limit_ns)
		return -EAGAIN;
	memset(st, 0, sizeof(*st));
	st->host_time_ns = now;
	st->heartbeat = w[SH2000_W_HEARTBEAT];
	st->heartbeat_age_ns = age;
	return sh2000_torn_dead(h, st, w);
}

static int poll_once_locked(struct sh2000 *h, struct sh2000_status *st)
{
	uint16_t w[SH2000_STATUS_WORDS];
	uint64_t now;
	int r;

	r = sh2000_rd(h, 0, SH2000_STATUS_WORDS, w);
	if (r < 0)
		return r;
	/* the host is alive whether or not the snapshot tore: one stream,
	 * the heartbeat is the next word */
	r = sh2000_host_beat(h, &now);
	if (r < 0)
		return r;
	if (w[SH2000_W_SNAP_SEQ_END] != w[SH2000_W_SNAP_SEQ_BEGIN])
		return torn_once(h, w, now, st);
	if (h->nb.cmd.busy) {
		memcpy(h->nb.cmd.ack, &w[SH2000_W_CMD_ACK], sizeof(h->nb.cmd.ack));
		h->nb.cmd.fresh = 1;
	}
	memset(st, 0, sizeof(*st));
	st->host_time_ns = now;
	sh2000_status_decode(h, w, st);
	/* one read of the first-fault record at most: torn by a RESET, it
	 * is read again on a later tick */
	if (w[SH2000_W_MAGIC] == SH2000_PROTO_MAGIC) {
		r = sh2000_first_fault_update(h, w, st, 1);
		if (r < 0)
			return r;
	}
	st->heartbeat_age_ns = sh2000_hb_note(h, st->heartbeat, now);
	/* An unchanged heartbeat after a gap it may have wrapped in: the
	 * watch restarted from now, so a stopped card still shows within
	 * the limit on later ticks; nothing to wait for here. */
	h->hb.unsure = 0;
	return sh2000_status_alive(h, w, st);
}

int sh2000_poll_once(struct sh2000 *h, struct sh2000_status *st)
{
	int r = nb_enter(h);

	return r ? r : nb_leave(h, poll_once_locked(h, st));
}

/* Motion-changing commands need the motion lock (shared, for the length
 * of the command) unless this handle holds it. */
static int nb_changes_motion(unsigned int op)
{
	return op == SH2000_CMD_ENABLE || op == SH2000_CMD_DISABLE ||
	       op == SH2000_CMD_HOME || op == SH2000_CMD_SET_POSITION ||
	       op == SH2000_CMD_RESET || op == SH2000_CMD_INDEX_ARM ||
	       op == SH2000_CMD_INDEX_DISARM;
}

static int start_locked(struct sh2000 *h, unsigned int op, unsigned int axis,
			unsigned int param, int32_t arg)
{
	int r;

	if (h->nb.cmd.busy)
		return sh2000_fail(h, -EBUSY,
				   "command %s: the started command %s has not completed",
				   sh2000_cmd_op_name(op),
				   sh2000_cmd_op_name(h->nb.cmd.op));
	if (h->cmd.busy)
		return -EAGAIN;		/* another thread's command */
	if (nb_changes_motion(op)) {
		r = sh2000_arb_motion_begin(h, sh2000_cmd_op_name(op));
		if (r < 0)
			return r;
		h->nb.cmd.motion = 1;
	}
	r = sh2000_arb_cmd_try(h);
	if (r > 0)
		r = sh2000_rd(h, SH2000_W_CMD_SEQ, 1, &h->cmd.seq);
	if (r < 0)
		goto fail;
	r = sh2000_cmd_write(h, op, axis, param, arg);
	if (r < 0) {
		sh2000_arb_drop(h, SH2000_ARB_CMD);
		goto fail;
	}
	h->cmd.busy = 1;		/* blocking commands wait for it */
	h->nb.cmd.busy = 1;
	h->nb.cmd.fresh = 0;
	h->nb.cmd.seq = h->cmd.seq;
	h->nb.cmd.op = op;
	h->nb.cmd.t0 = sh2000_now_locked(h);
	return 0;
fail:
	if (h->nb.cmd.motion)
		sh2000_arb_motion_end(h);
	h->nb.cmd.motion = 0;
	return r;
}

int sh2000_command_start(struct sh2000 *h, unsigned int op, unsigned int axis,
			 unsigned int param, int32_t arg)
{
	int r = nb_enter(h);

	return r ? r : nb_leave(h, start_locked(h, op, axis, param, arg));
}

/* The started command is over (answered or given up): the slot and the
 * locks are free again. */
static void finish(struct sh2000 *h)
{
	sh2000_arb_drop(h, SH2000_ARB_CMD);
	if (h->nb.cmd.motion)
		sh2000_arb_motion_end(h);
	h->nb.cmd.motion = 0;
	h->nb.cmd.busy = 0;
	h->cmd.busy = 0;
	pthread_cond_broadcast(&h->cmd_cond);
}

static int complete_locked(struct sh2000 *h, int32_t *value)
{
	uint64_t waited;
	int r;

	if (!h->nb.cmd.busy)
		return sh2000_fail(h, -EINVAL, "no command was started");
	if (!h->nb.cmd.fresh) {
		r = sh2000_rd(h, SH2000_W_CMD_ACK, 4, h->nb.cmd.ack);
		if (r < 0)
			return r;
	}
	h->nb.cmd.fresh = 0;
	if (h->nb.cmd.ack[0] != h->nb.cmd.seq) {
		waited = sh2000_now_locked(h) - h->nb.cmd.t0;
		if (waited <= SH2000_CMD_TIMEOUT_MS * 1000000ull)
			return -EINPROGRESS;
		finish(h);
		/* the last poll's heartbeat age tells a stopped card */
		if (sh2000_now_locked(h) - h->hb.change_ns >= h->hb.limit_ns)
			return sh2000_fail(h, -SH2000_EHEARTBEAT,
					   "command %s (seq %u): no answer, card heartbeat stopped",
					   sh2000_cmd_op_name(h->nb.cmd.op),
					   h->nb.cmd.seq);
		return sh2000_fail(h, -SH2000_ETIMEOUT,
				   "command %s (seq %u): no answer within %d ms",
				   sh2000_cmd_op_name(h->nb.cmd.op), h->nb.cmd.seq,
				   SH2000_CMD_TIMEOUT_MS);
	}
	finish(h);
	if (h->nb.cmd.ack[1] != SH2000_RES_OK)
		return sh2000_fail(h, sh2000_cmd_result_error(h->nb.cmd.ack[1]),
				   "command %s (seq %u): card answered %s",
				   sh2000_cmd_op_name(h->nb.cmd.op), h->nb.cmd.seq,
				   sh2000_result_name(h->nb.cmd.ack[1]));
	if (value)
		*value = sh2000_w32(&h->nb.cmd.ack[2]);
	return 0;
}

int sh2000_command_complete(struct sh2000 *h, int32_t *value)
{
	int r = nb_enter(h);

	return r ? r : nb_leave(h, complete_locked(h, value));
}

static int push_point_locked(struct sh2000 *h, const int32_t pt[SH2000_AXES],
			     unsigned int flags)
{
	unsigned int fill;
	int r;

	if (h->arb.fd >= 0 && !h->arb.motion)
		return sh2000_fail(h, -SH2000_EOWNED,
				   "pushing a point: this handle does not hold the motion (sh2000_claim_motion() first)");
	if (!h->nb.tail_seen)
		return -EAGAIN;
	fill = (uint16_t)(h->head - h->nb.tail);
	if (fill >= SH2000_RING_RECORDS)
		return sh2000_fail(h, -SH2000_EQUEUE_FULL,
				   "one point: the last poll saw %u of %u records queued",
				   fill, SH2000_RING_RECORDS);
	/* the mailbox where it can carry the point, else the ring */
	r = sh2000_mbox_post_locked(h, pt, flags);
	if (r)
		return r;
	return sh2000_ring_write_locked(h, (const int32_t (*)[SH2000_AXES])pt,
					1, flags);
}

int sh2000_push_point(struct sh2000 *h, const int32_t pt[SH2000_AXES],
		      unsigned int flags)
{
	int r = nb_enter(h);

	return r ? r : nb_leave(h, push_point_locked(h, pt, flags));
}

int sh2000_estop_request(struct sh2000 *h)
{
	int r = nb_enter(h);

	if (r)
		return r;
	/* any value but the card's ESTOP_ACK is a request: step over an
	 * acknowledgement another program's stop left at our next value */
	h->estop_req++;
	if (h->nb.tail_seen && h->estop_req == h->nb.estop_ack_seen)
		h->estop_req++;
	return nb_leave(h, sh2000_wr1(h, SH2000_W_ESTOP_REQ, h->estop_req));
}
