/* SPDX-License-Identifier: MIT */
/*
 * Commands (one in flight per card, sequence-numbered, acknowledged with a
 * result code), the emergency stop, and axis parameters in user units with
 * validation before anything is written. Other programs may use the same
 * card: the command lock (arbiter.c) makes each exchange theirs alone.
 */
#include <errno.h>
#include <fcntl.h>
#include <float.h>
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
	uint16_t w[7], seq = (uint16_t)(h->cmd_seq + 1u);
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
		h->cmd_seq = seq;
	return r;
}

/*
 * The command slot for this handle: other threads of the handle wait on
 * cmd_busy, other programs on the command lock. Returns 0 with both held,
 * or an error with neither.
 */
int sh2000_cmd_slot_take(struct sh2000 *h, const char *what)
{
	int r;

	while (h->cmd_busy)
		pthread_cond_wait(&h->cmd_cond, &h->lock);
	h->cmd_busy = 1;
	r = sh2000_arb_cmd_take(h);
	if (r == -EAGAIN)
		r = sh2000_fail(h, -SH2000_ETIMEOUT,
				"%s: another program has held the card's command slot for over %d ms",
				what, SH2000_ARB_WAIT_MS);
	/* The slot is ours. If another program used it since, the last
	 * sequence number is the one in the RAM (a program that died
	 * mid-command left it there too). */
	if (r > 0) {
		r = sh2000_rd(h, SH2000_W_CMD_SEQ, 1, &h->cmd_seq);
		if (r < 0)
			sh2000_arb_drop(h, SH2000_ARB_CMD);
	}
	if (r < 0) {
		h->cmd_busy = 0;
		pthread_cond_broadcast(&h->cmd_cond);
	}
	return r < 0 ? r : 0;
}

void sh2000_cmd_slot_drop(struct sh2000 *h)
{
	sh2000_arb_drop(h, SH2000_ARB_CMD);
	h->cmd_busy = 0;
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
	seq = h->cmd_seq;
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
	if (ack[1] != SH2000_RES_OK)
		return sh2000_fail(h, sh2000_cmd_result_error(ack[1]), "%s: card answered %s",
				   what, sh2000_result_name(ack[1]));
	if (value)
		*value = sh2000_w32(&ack[2]);
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
	       op == SH2000_CMD_RESET;
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
			h->act_seen = 0;	/* re-base the 64-bit extension */
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

	__atomic_add_fetch(&h->urgent, 1, __ATOMIC_ACQ_REL);
	pthread_mutex_lock(&h->lock);
	__atomic_sub_fetch(&h->urgent, 1, __ATOMIC_ACQ_REL);
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

/* ---- parameters ---- */

static const char *const units[SH2000_GP_END] = {
	[SH2000_P_SCALE] = "counts/mm",
	[SH2000_P_KP] = "DAC/count",
	[SH2000_P_TI] = "s",
	[SH2000_P_TD] = "s",
	[SH2000_P_KVFF] = "DAC/(count/s)",
	[SH2000_P_KAFF] = "DAC/(count/s^2)",
	[SH2000_P_DAC_RANGE] = "",
	[SH2000_P_DAC_LIMIT] = "DAC codes",
	[SH2000_P_FERR_LIMIT] = "mm",
	[SH2000_P_SOFT_MIN] = "mm",
	[SH2000_P_SOFT_MAX] = "mm",
	[SH2000_P_VMAX] = "mm/s",
	[SH2000_P_AMAX] = "mm/s^2",
	[SH2000_P_HOME_VEL] = "mm/s",
	[SH2000_P_HOME_DEBOUNCE] = "servo cycles",
	[SH2000_P_HOME_OFFSET] = "mm",
	[SH2000_GP_COARSE_PERIOD_US] = "us",
	[SH2000_GP_FINE_STEPS] = "servo cycles",
	[SH2000_GP_HOST_TIMEOUT_MS] = "ms",
	[SH2000_GP_STATUS_PERIOD] = "servo cycles",
	[SH2000_GP_TIME_SCALE] = "1/10000 of full rate",
	[SH2000_GP_TIME_RAMP_MS] = "ms",
};

/* Parameters the library scales from mm to counts (x counts/mm). */
static int scaled(unsigned int id)
{
	switch (id) {
	case SH2000_P_FERR_LIMIT:
	case SH2000_P_SOFT_MIN:
	case SH2000_P_SOFT_MAX:
	case SH2000_P_VMAX:
	case SH2000_P_AMAX:
	case SH2000_P_HOME_VEL:
	case SH2000_P_HOME_OFFSET:
		return 1;
	default:
		return 0;
	}
}

static int is_global(unsigned int id)
{
	return id >= SH2000_GP_FIRST && id < SH2000_GP_END;
}

const char *sh2000_param_name(unsigned int id)
{
	const struct sh2000_param_info *p = sh2000_param_lookup(id);

	return p ? p->name : NULL;
}

const char *sh2000_param_unit(unsigned int id)
{
	return id < SH2000_GP_END && sh2000_param_lookup(id) ? units[id] : NULL;
}

int sh2000_param_id(const char *name)
{
	unsigned int id;

	for (id = 0; name && id < SH2000_GP_END; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		if (p && p->name && !strcmp(p->name, name))
			return (int)id;
	}
	return -SH2000_EPARAM;
}

static void where(char *buf, size_t len, int axis, const char *name)
{
	if (axis == SH2000_GLOBAL)
		snprintf(buf, len, "global parameter %s", name);
	else
		snprintf(buf, len, "axis %d parameter %s", axis, name);
}

static const struct sh2000_param_info *check_id(struct sh2000 *h, int axis,
						unsigned int id, int *r)
{
	const struct sh2000_param_info *p = sh2000_param_lookup(id);

	*r = 0;
	if (!p) {
		*r = sh2000_fail(h, -SH2000_EPARAM, "parameter %u: unknown", id);
	} else if (is_global(id) ? axis != SH2000_GLOBAL :
		   (axis < 0 || axis >= (int)SH2000_AXES)) {
		*r = sh2000_fail(h, -SH2000_EPARAM,
				 "parameter %s: %s", p->name,
				 is_global(id) ? "is global (use SH2000_GLOBAL)" :
				 "needs an axis 0..3");
	}
	return *r ? NULL : p;
}

/*
 * User value -> the 32-bit word the card gets, or -SH2000_EPARAM with a
 * message naming axis and parameter. Only reads h (for the message).
 */
static int encode(struct sh2000 *h, int axis, const struct sh2000_param_info *p,
		  double v, double scale, int32_t *word)
{
	double c = scaled(p->id) ? v * scale : v;
	const char *u = units[p->id];
	char at[64];

	where(at, sizeof(at), axis, p->name);
	if (!isfinite(v))
		return sh2000_fail(h, -SH2000_EPARAM, "%s: %g is not a finite number",
				   at, v);
	if (p->type == SH2000_PT_F32) {
		/* too small for a normal binary32 is refused like too large:
		 * never rounded to 0 */
		if (!isfinite(c) || fabs(c) > FLT_MAX ||
		    (c != 0.0 && fabs(c) < FLT_MIN))
			return sh2000_fail(h, -SH2000_EPARAM,
					   "%s: %g %s is not representable as a 32-bit float in card units",
					   at, v, u);
		*word = (int32_t)sh2000_f32_bits(c);
		c = sh2000_f32_value((uint32_t)*word);
	} else {
		double rc = nearbyint(c);

		if (!scaled(p->id) && rc != c)
			return sh2000_fail(h, -SH2000_EPARAM,
					   "%s: %g is not an integer", at, v);
		if (!isfinite(rc) || rc < INT32_MIN || rc > INT32_MAX)
			return sh2000_fail(h, -SH2000_EPARAM,
					   "%s: %g %s is %g counts: does not fit the card's 32-bit value",
					   at, v, u, rc);
		c = rc;
		*word = (int32_t)rc;
	}
	if (sh2000_param_in_range(p, c) != 0) {
		double k = scaled(p->id) ? scale : 1.0;

		if (p->min == 0 && c < 0)
			return sh2000_fail(h, -SH2000_EPARAM, "%s: %g is negative",
					   at, v);
		if (c >= p->min && c <= p->max &&
		    !(p->min_exclusive && c == p->min))
			return sh2000_fail(h, -SH2000_EPARAM,
					   "%s: %g %s is not representable on the card (%s)",
					   at, v, u, p->type == SH2000_PT_F32 ?
					   "not a normal 32-bit float" :
					   p->id == SH2000_P_HOME_VEL ? "must not be 0" :
					   "not an integer");
		return sh2000_fail(h, -SH2000_EPARAM,
				   "%s: %g %s is outside %s%g..%g %s", at, v, u,
				   p->min_exclusive ? "(exclusive) " : "",
				   p->min / k, p->max / k, u);
	}
	return 0;
}

static double decode_word(const struct sh2000_param_info *p, int32_t word,
			  double scale)
{
	double c;

	if (p->type == SH2000_PT_F32)
		c = sh2000_f32_value((uint32_t)word);
	else
		c = word;
	return scaled(p->id) ? c / scale : c;
}

static int get_locked(struct sh2000 *h, int axis, unsigned int id,
		      int32_t *word)
{
	return sh2000_command_locked(h, SH2000_CMD_GET_PARAM,
				     axis == SH2000_GLOBAL ? SH2000_AXIS_GLOBAL :
				     (unsigned int)axis, id, 0, word,
				     SH2000_CMD_TIMEOUT_MS);
}

static int set_locked(struct sh2000 *h, int axis, unsigned int id,
		      int32_t word)
{
	return sh2000_command_locked(h, SH2000_CMD_SET_PARAM,
				     axis == SH2000_GLOBAL ? SH2000_AXIS_GLOBAL :
				     (unsigned int)axis, id, word, NULL,
				     SH2000_CMD_TIMEOUT_MS);
}

int sh2000_param_set(struct sh2000 *h, int axis, unsigned int id, double v)
{
	const struct sh2000_param_info *p;
	int32_t word = 0, other = 0;	/* set by encode() and get_locked() */
	double scale;
	int r;

	pthread_mutex_lock(&h->lock);
	p = check_id(h, axis, id, &r);
	if (!p)
		goto out;
	scale = is_global(id) ? 1.0 : h->scale[axis];
	r = encode(h, axis, p, v, scale, &word);
	if (r)
		goto out;
	if (id == SH2000_P_SOFT_MIN || id == SH2000_P_SOFT_MAX) {
		unsigned int oid = id == SH2000_P_SOFT_MIN ? SH2000_P_SOFT_MAX :
				   SH2000_P_SOFT_MIN;

		r = get_locked(h, axis, oid, &other);
		if (r)
			goto out;
		if (id == SH2000_P_SOFT_MIN ? word >= other : word <= other) {
			r = sh2000_fail(h, -SH2000_EPARAM,
					"axis %d parameter %s: %g mm is not %s soft_%s (%g mm)",
					axis, p->name, v,
					id == SH2000_P_SOFT_MIN ? "below" : "above",
					id == SH2000_P_SOFT_MIN ? "max" : "min",
					other / scale);
			goto out;
		}
	}
	r = set_locked(h, axis, id, word);
	if (!r && id == SH2000_P_SCALE)
		h->scale[axis] = v;
	if (!r && (id == SH2000_GP_COARSE_PERIOD_US ||
		   id == SH2000_GP_FINE_STEPS)) {
		if (id == SH2000_GP_COARSE_PERIOD_US)
			h->coarse_us = word;
		else
			h->fine_steps = word;
		sh2000_timing_changed(h);
	}
out:
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_param_get(struct sh2000 *h, int axis, unsigned int id, double *v)
{
	const struct sh2000_param_info *p;
	int32_t word;
	int r;

	pthread_mutex_lock(&h->lock);
	p = check_id(h, axis, id, &r);
	if (p)
		r = get_locked(h, axis, id, &word);
	if (p && !r) {
		*v = decode_word(p, word, is_global(id) ? 1.0 : h->scale[axis]);
		if (id == SH2000_P_SCALE && *v > 0)
			h->scale[axis] = *v;
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}

void sh2000_axis_params_default(struct sh2000_axis_params *ap)
{
	const struct sh2000_param_info *ps = sh2000_param_lookup(SH2000_P_SCALE);
	double scale = ps && ps->def > 0 ? ps->def : 1.0;
	unsigned int id;

	for (id = 0; id < SH2000_AXIS_PARAMS; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		ap->v[id] = p ? (scaled(id) ? p->def / scale : p->def) : 0.0;
	}
}

int sh2000_axis_params_get(struct sh2000 *h, unsigned int axis,
			   struct sh2000_axis_params *ap)
{
	unsigned int id;
	int r = 0;

	if (axis >= SH2000_AXES)
		return sh2000_fail(h, -EINVAL, "no axis %u", axis);
	/* scale first: the rest is converted with it */
	r = sh2000_param_get(h, (int)axis, SH2000_P_SCALE, &ap->v[SH2000_P_SCALE]);
	for (id = 1; !r && id < SH2000_AXIS_PARAMS; id++)
		r = sh2000_param_get(h, (int)axis, id, &ap->v[id]);
	return r;
}

int sh2000_axis_params_set(struct sh2000 *h, unsigned int axis,
			   const struct sh2000_axis_params *ap)
{
	int32_t word[SH2000_AXIS_PARAMS];
	double scale = ap->v[SH2000_P_SCALE];
	unsigned int id;
	int r = 0;

	if (axis >= SH2000_AXES)
		return sh2000_fail(h, -EINVAL, "no axis %u", axis);
	pthread_mutex_lock(&h->lock);
	/* validate everything first, in the new scale; send only then */
	for (id = 0; !r && id < SH2000_AXIS_PARAMS; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		if (!p) {
			r = sh2000_fail(h, -SH2000_EPARAM, "parameter %u: unknown", id);
			break;
		}
		r = encode(h, (int)axis, p, ap->v[id], scale, &word[id]);
	}
	if (!r && word[SH2000_P_SOFT_MIN] >= word[SH2000_P_SOFT_MAX])
		r = sh2000_fail(h, -SH2000_EPARAM,
				"axis %u parameters soft_min %g mm and soft_max %g mm: out of order",
				axis, ap->v[SH2000_P_SOFT_MIN],
				ap->v[SH2000_P_SOFT_MAX]);
	if (!r) {
		/* The card keeps soft_min < soft_max after every single set:
		 * moving the window up sends max first, else min first. */
		int32_t cur_max = 0;
		unsigned int order[SH2000_AXIS_PARAMS], n = 0;

		r = get_locked(h, (int)axis, SH2000_P_SOFT_MAX, &cur_max);
		for (id = 0; id < SH2000_AXIS_PARAMS; id++)
			if (id != SH2000_P_SOFT_MIN && id != SH2000_P_SOFT_MAX)
				order[n++] = id;
		if (word[SH2000_P_SOFT_MIN] < cur_max) {
			order[n++] = SH2000_P_SOFT_MIN;
			order[n++] = SH2000_P_SOFT_MAX;
		} else {
			order[n++] = SH2000_P_SOFT_MAX;
			order[n++] = SH2000_P_SOFT_MIN;
		}
		for (id = 0; !r && id < n; id++) {
			r = set_locked(h, (int)axis, order[id], word[order[id]]);
			if (!r && order[id] == SH2000_P_SCALE)
				h->scale[axis] = scale;
		}
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}
