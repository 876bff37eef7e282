/* SPDX-License-Identifier: MIT */
/*
 * Commands (one in flight per card, sequence-numbered, acknowledged with a
 * result code) and the emergency stop. Other programs may use the same
 * card: the command lock (arbiter.c) makes each exchange theirs alone.
 * The parameters, sent as commands, are params.c's.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "sh2000_internal.h"

/* How often a waiting host re-reads the acknowledgement. */
#define CMD_POLL_NS	20000ull
#define ESTOP_POLL_NS	5000ull

const char *sh2000_cmd_op_name(unsigned int op)
{
	static const char *const n[] = {
		"nop", "enable", "disable", "set_param", "get_param", "home",
		"stop", "reset", "set_position",
		[SH2000_CMD_GATHER_SET] = "gather_set",
		[SH2000_CMD_GATHER_ARM] = "gather_arm",
		[SH2000_CMD_GATHER_STOP] = "gather_stop",
		[SH2000_CMD_GATHER_INFO] = "gather_info",
		[SH2000_CMD_GATHER_READ] = "gather_read",
		[SH2000_CMD_COMP_BEGIN] = "comp_begin",
		[SH2000_CMD_COMP_PAGE] = "comp_page",
		[SH2000_CMD_COMP_COMMIT] = "comp_commit",
		[SH2000_CMD_COMP_CLEAR] = "comp_clear",
		[SH2000_CMD_INDEX_ARM] = "index_arm",
		[SH2000_CMD_INDEX_DISARM] = "index_disarm",
	};

	return op < sizeof(n) / sizeof(n[0]) && n[op] ? n[op] : "?";
}

int sh2000_cmd_result_error(unsigned int res)
{
	if (res >= SH2000_RES_BAD_OP && res <= SH2000_RES_DISABLED)
		return -(SH2000_ECMD_OP + (int)res - SH2000_RES_BAD_OP);
	return -SH2000_ECMD_UNKNOWN;
}

/*
 * The host's limit has passed without an answer. A card that ran on
 * meanwhile had its chance; a served card whose process was descheduled
 * for the whole wait (a loaded machine) has not, and answers in the first
 * cycle it runs. So the host looks again until the card has run
 * LATE_CYCLES servo cycles past the limit (a stopped card ends the wait in
 * EHEARTBEAT through the poll, once the heartbeat limit has passed: the
 * timeout can be shorter than that limit, 100 ms each for sim:NAME).
 * Returns 1 once the card has had them, 0 to look again, or an error.
 */
#define LATE_CYCLES	3u

static int card_had_its_chance(struct sh2000 *h, int *late, uint16_t *hb_late,
			       struct sh2000_status *st)
{
	int r = sh2000_poll_locked(h, st);

	if (r < 0)
		return r;
	if (!*late) {
		*late = 1;
		*hb_late = st->heartbeat;
	}
	if ((uint16_t)(st->heartbeat - *hb_late) >= LATE_CYCLES)
		return 1;
	sh2000_hold_wait(h, h->servo_ns ? h->servo_ns : CMD_POLL_NS);
	return 0;
}

int sh2000_cmd_write(struct sh2000 *h, unsigned int op, unsigned int axis,
		     unsigned int param, int32_t arg)
{
	uint16_t w[7], seq = (uint16_t)(h->cmd.seq + 1u);
	int r;

	w[0] = (uint16_t)op;
	w[1] = (uint16_t)axis;
	w[2] = (uint16_t)param;
	w[3] = (uint16_t)((uint32_t)arg & 0xffffu);
	w[4] = (uint16_t)((uint32_t)arg >> 16);
	w[5] = sh2000_cmd_check(seq, w[0], w[1], w[2], w[3], w[4]);
	w[6] = seq;
	/* one upward stream: OP..CHECK first, SEQ (which publishes) last */
	r = sh2000_wr(h, SH2000_W_CMD_OP, 7, w);
	if (r == 0)
		h->cmd.seq = seq;
	return r;
}

/*
 * The command slot for this handle: other threads of the handle wait on
 * cmd.busy, other programs on the command lock. Returns 0 with both held,
 * or an error with neither.
 */
int sh2000_cmd_slot_take(struct sh2000 *h, const char *what)
{
	int r;

	while (h->cmd.busy)
		pthread_cond_wait(&h->cmd_cond, &h->lock);
	h->cmd.busy = 1;
	r = sh2000_arb_cmd_take(h);
	if (r == -EAGAIN)
		r = sh2000_fail(h, -SH2000_ETIMEOUT,
				"%s: another program has held the card's command slot for over %d ms",
				what, SH2000_ARB_WAIT_MS);
	/* The slot is ours. If another program used it since, the last
	 * sequence number is the one in the RAM (a program that died
	 * mid-command left it there too). */
	if (r > 0) {
		r = sh2000_rd(h, SH2000_W_CMD_SEQ, 1, &h->cmd.seq);
		if (r < 0)
			sh2000_arb_drop(h, SH2000_ARB_CMD);
	}
	if (r < 0) {
		h->cmd.busy = 0;
		pthread_cond_broadcast(&h->cmd_cond);
	}
	return r < 0 ? r : 0;
}

void sh2000_cmd_slot_drop(struct sh2000 *h)
{
	sh2000_arb_drop(h, SH2000_ARB_CMD);
	h->cmd.busy = 0;
	pthread_cond_broadcast(&h->cmd_cond);
}

int sh2000_cmd_exchange(struct sh2000 *h, unsigned int op, unsigned int axis,
			unsigned int param, int32_t arg, int32_t *value,
			int timeout_ms)
{
	struct sh2000_status st;
	uint16_t ack[4];
	uint16_t seq, hb_late = 0;
	uint64_t t0, limit;
	char what[96];
	int r, late = 0;

	r = sh2000_cmd_write(h, op, axis, param, arg);
	if (r < 0)
		return r;
	seq = h->cmd.seq;
	snprintf(what, sizeof(what), "command %s (seq %u, axis %u, param %u, arg %d)",
		 sh2000_cmd_op_name(op), seq, axis == SH2000_AXIS_GLOBAL ? 0xffffu : axis,
		 param, arg);
	t0 = sh2000_now_locked(h);
	limit = (uint64_t)(timeout_ms < 0 ? SH2000_CMD_TIMEOUT_MS : timeout_ms) *
		1000000ull;
	for (;;) {
		/* the clock before the look: a program descheduled between a
		 * look and the clock (a loaded machine) looks once more after
		 * the limit instead of timing out an answered command */
		int over = late || sh2000_now_locked(h) - t0 > limit;

		r = sh2000_rd(h, SH2000_W_CMD_ACK, 4, ack);
		if (r < 0)
			return r;
		if (ack[0] == seq)
			break;
		if (!over) {
			sh2000_hold_wait(h, CMD_POLL_NS);
			continue;
		}
		r = card_had_its_chance(h, &late, &hb_late, &st);
		if (r < 0)
			return r;
		if (r)
			return sh2000_fail(h, -SH2000_ETIMEOUT,
					   "%s: no answer within %d ms (card state %s, heartbeat alive)",
					   what, (int)(limit / 1000000ull),
					   sh2000_state_name(st.card_state));
	}
	/* VALUE of a refusal too: it may say why (COMP_COMMIT) */
	if (value)
		*value = sh2000_w32(&ack[2]);
	if (ack[1] != SH2000_RES_OK)
		return sh2000_fail(h, sh2000_cmd_result_error(ack[1]), "%s: card answered %s",
				   what, sh2000_result_name(ack[1]));
	return 0;
}

int sh2000_command_locked(struct sh2000 *h, unsigned int op,
			  unsigned int axis, unsigned int param, int32_t arg,
			  int32_t *value, int timeout_ms)
{
	char what[96];
	int r;

	snprintf(what, sizeof(what), "command %s (axis %u, param %u, arg %d)",
		 sh2000_cmd_op_name(op), axis == SH2000_AXIS_GLOBAL ? 0xffffu : axis,
		 param, arg);
	r = sh2000_cmd_slot_take(h, what);
	if (r < 0)
		return r;
	r = sh2000_cmd_exchange(h, op, axis, param, arg, value, timeout_ms);
	sh2000_cmd_slot_drop(h);
	return r;
}

/* Commands that change what the axes do belong to the program that
 * controls the motion, if one does. STOP does not: anyone may stop. */
static int changes_motion(unsigned int op)
{
	return op == SH2000_CMD_ENABLE || op == SH2000_CMD_DISABLE ||
	       op == SH2000_CMD_HOME || op == SH2000_CMD_SET_POSITION ||
	       op == SH2000_CMD_RESET || op == SH2000_CMD_INDEX_ARM ||
	       op == SH2000_CMD_INDEX_DISARM;
}

static int command(struct sh2000 *h, unsigned int op, unsigned int axis,
		   unsigned int param, int32_t arg, int32_t *value)
{
	int r = 0;

	pthread_mutex_lock(&h->lock);
	if (changes_motion(op))
		r = sh2000_arb_motion_begin(h, sh2000_cmd_op_name(op));
	if (!r) {
		r = sh2000_command_locked(h, op, axis, param, arg, value,
					  SH2000_CMD_TIMEOUT_MS);
		if (changes_motion(op))
			sh2000_arb_motion_end(h);
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_command(struct sh2000 *h, unsigned int op, unsigned int axis,
		   unsigned int param, int32_t arg, int32_t *value)
{
	return command(h, op, axis, param, arg, value);
}

int sh2000_nop(struct sh2000 *h)
{
	return command(h, SH2000_CMD_NOP, 0, 0, 0, NULL);
}

static int check_mask(struct sh2000 *h, unsigned int mask)
{
	if (!mask || mask >= (1u << SH2000_AXES))
		return sh2000_fail(h, -EINVAL, "axis mask 0x%x: must be 1..0x%x",
				   mask, (1u << SH2000_AXES) - 1);
	return 0;
}

int sh2000_enable(struct sh2000 *h, unsigned int mask)
{
	int r = check_mask(h, mask);

	return r ? r : command(h, SH2000_CMD_ENABLE, 0, 0, (int32_t)mask, NULL);
}

int sh2000_disable(struct sh2000 *h, unsigned int mask)
{
	int r = check_mask(h, mask);

	return r ? r : command(h, SH2000_CMD_DISABLE, 0, 0, (int32_t)mask, NULL);
}

int sh2000_stop(struct sh2000 *h)
{
	return command(h, SH2000_CMD_STOP, 0, 0, 0, NULL);
}

int sh2000_reset(struct sh2000 *h)
{
	return command(h, SH2000_CMD_RESET, 0, 0, 0, NULL);
}

int sh2000_home(struct sh2000 *h, unsigned int axis, unsigned int flags)
{
	if (axis >= SH2000_AXES)
		return sh2000_fail(h, -EINVAL, "home: no axis %u", axis);
	return command(h, SH2000_CMD_HOME, axis, 0, (int32_t)flags, NULL);
}

int sh2000_set_position(struct sh2000 *h, unsigned int axis, double pos_mm)
{
	double c;
	int r;

	if (axis >= SH2000_AXES)
		return sh2000_fail(h, -EINVAL, "set_position: no axis %u", axis);
	pthread_mutex_lock(&h->lock);
	c = nearbyint(pos_mm * h->scale[axis]);
	if (!isfinite(c) || c < INT32_MIN || c > INT32_MAX) {
		r = sh2000_fail(h, -SH2000_EPARAM,
				"axis %u position %g mm: not representable in 32-bit counts",
				axis, pos_mm);
	} else if (!(r = sh2000_arb_motion_begin(h, "set_position"))) {
		r = sh2000_command_locked(h, SH2000_CMD_SET_POSITION, axis, 0,
					  (int32_t)c, NULL,
					  SH2000_CMD_TIMEOUT_MS);
		sh2000_arb_motion_end(h);
		if (!r)
			r = sh2000_fresh_snapshot(h, SH2000_CMD_TIMEOUT_MS);
		if (!r)
			h->ext.act_seen = 0;	/* re-base the 64-bit extension */
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_estop(struct sh2000 *h, int timeout_ms)
{
	struct sh2000_status st;
	uint64_t t0, limit;
	uint16_t w[2], hb_late = 0;	/* w: ESTOP_ACK, STATE */
	int r, late = 0;

	__atomic_add_fetch(&h->cmd.urgent, 1, __ATOMIC_ACQ_REL);
	pthread_mutex_lock(&h->lock);
	__atomic_sub_fetch(&h->cmd.urgent, 1, __ATOMIC_ACQ_REL);
	/* never behind the command slot, the ring or another program: word
	 * 0, at once */
	h->estop_req++;
	r = sh2000_wr1(h, SH2000_W_ESTOP_REQ, h->estop_req);
	if (r < 0)
		goto out;
	t0 = sh2000_now_locked(h);
	limit = (uint64_t)(timeout_ms < 0 ? SH2000_CMD_TIMEOUT_MS : timeout_ms) *
		1000000ull;
	for (;;) {
		r = sh2000_rd(h, SH2000_W_ESTOP_ACK, 2, w);
		if (r < 0 || (w[0] == h->estop_req &&
			      w[1] == SH2000_STATE_ESTOP))
			break;
		/*
		 * The card acts on any value other than ESTOP_ACK. Another
		 * program's emergency stop (and a reset since) may have left
		 * ACK at the value this handle just wrote: acknowledged but
		 * not stopped. Then ask again with the next value (a second
		 * request while stopped does nothing more).
		 */
		if (w[0] == h->estop_req) {
			h->estop_req++;
			r = sh2000_wr1(h, SH2000_W_ESTOP_REQ, h->estop_req);
			if (r < 0)
				break;
		}
		if (late || sh2000_now_locked(h) - t0 > limit) {
			r = card_had_its_chance(h, &late, &hb_late, &st);
			if (r == 1)
				r = sh2000_fail(h, -SH2000_ETIMEOUT,
						"emergency stop not acknowledged within %d ms (card state %s, ESTOP_REQ %u, ESTOP_ACK %u)",
						(int)(limit / 1000000ull),
						sh2000_state_name(st.card_state),
						h->estop_req, w[0]);
			if (r)
				break;
			continue;
		}
		sh2000_hold_wait(h, ESTOP_POLL_NS);
	}
out:
	pthread_mutex_unlock(&h->lock);
	return r;
}
