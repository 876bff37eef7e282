// SPDX-License-Identifier: MIT
/*
 * The DSP firmware: protocol v1 on the card side (docs/protocol.md). One
 * call of sh2000_dsp_interrupt() is one servo interrupt (card.c's
 * sh2000_fw_cycle() runs it, then the board and the motors). Its order
 * is fixed:
 *   1. sample the encoders, switches and index latches;
 *   2. emergency stop (before any check, command or motion can act);
 *   3. axis checks, card heartbeat, host heartbeat watchdog;
 *   4. at most one command (its status words published before its ACK);
 *   5. ring and motion: records, B-spline, controlled stop or homing;
 *   6. PID + feed-forward per axis, following-error and DAC checks;
 *   7. DAC out (the board then holds it until the next interrupt);
 *   8. data gathering (gather.c);
 *   9. publish the status words and, every STATUS_PERIOD cycles, the
 *      versioned snapshot.
 * Everything is in struct sh2000_dsp, allocated once; nothing allocates or
 * blocks inside a cycle. The card is reached only through board.h: the
 * FPGA's registers and the dual-port RAM.
 */
#include <math.h>

#include "cardmodel.h"

#define RD(fw, w)	sh2000_board_ram_read((fw)->hw, (w))
#define WR(fw, w, v)	sh2000_board_ram_write((fw)->hw, (w), (uint16_t)(v))
#define REG(fw, a, r)	sh2000_board_read((fw)->hw, (a), (r))
#define SETREG(fw, a, r, v) sh2000_board_write((fw)->hw, (a), (r), (v))

#define is_enabled	sh2000_axis_enabled
#define in_motion	sh2000_fw_in_motion

double sh2000_fw_servo_s(const struct sh2000_dsp *fw)
{
	return (double)sh2000_dsp_servo_period_ns(fw) * 1e-9;
}

uint64_t sh2000_dsp_servo_period_ns(const struct sh2000_dsp *fw)
{
	return (uint64_t)fw->coarse_us * 1000u / (uint64_t)fw->fine_steps;
}

/* ---- holding, stopping ---- */

/* Set-point of axis a becomes x, at rest; the window holds x. */
void sh2000_fw_hold_at(struct sh2000_dsp *fw, unsigned int a, double x)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];

	ax->cmd = x;
	ax->cmd_v = 0.0;
	ax->cmd_a = 0.0;
	ax->cmd_j = 0.0;
	sh2000_interp_hold(&fw->ip, a, x);
}

/*
 * Axis a holds where its carriage is: the set-point the loop closes on
 * (the nominal set-point plus the tables' correction) is the counter.
 * Holding the nominal set-point at the counter would move the motor by
 * the correction as soon as the loop adds it; holding the corrected value
 * and not correcting it would need a second kind of set-point the snapshot,
 * the soft limits and the next motion would all have to know about. The
 * held nominal set-point is the one whose correction brings it to the
 * counter, so every later cycle corrects it as any other.
 */
void sh2000_fw_hold_here(struct sh2000_dsp *fw, unsigned int a)
{
	sh2000_fw_hold_at(fw, a,
			  sh2000_comp_nominal_at(fw, a, (double)fw->ax[a].act));
}

static void discard_ring(struct sh2000_dsp *fw)
{
	sh2000_queue_discard(fw);
}

/* The motion is over: every axis holds where its set-point is. */
static void settle(struct sh2000_dsp *fw)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		sh2000_home_abort(&fw->ax[a]);
		sh2000_fw_hold_at(fw, a, fw->ax[a].cmd);
	}
	fw->ending = 0;
	fw->pad_left = 0;
	fw->fine_t = 0.0;
	fw->need_point = 1;
	fw->stop_left = 0;
	fw->state = fw->faults ? SH2000_STATE_FAULT : SH2000_STATE_IDLE;
}

/*
 * Controlled stop: every enabled axis decelerates from its set-point
 * velocity so that all reach zero in the same number of servo cycles (the
 * path keeps its direction) and no axis exceeds its AMAX. The ring is
 * discarded.
 */
static void begin_stop(struct sh2000_dsp *fw)
{
	double T = sh2000_fw_servo_s(fw), tstop = 0.0;
	uint64_t n;
	unsigned int a;

	if (fw->state == SH2000_STATE_ESTOP)
		return;
	discard_ring(fw);
	if (fw->state == SH2000_STATE_STOPPING)
		return;		/* already decelerating within AMAX */
	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];

		sh2000_home_abort(ax);
		if (is_enabled(ax) && fabs(ax->cmd_v) / ax->prm.amax > tstop)
			tstop = fabs(ax->cmd_v) / ax->prm.amax;
	}
	n = (uint64_t)ceil(tstop / T - 1e-9);
	if (n == 0) {
		settle(fw);
		return;
	}
	for (a = 0; a < SH2000_AXES; a++)
		fw->ax[a].stop_a = fw->ax[a].cmd_v / ((double)n * T);
	fw->stop_left = n;
	fw->ending = 0;
	fw->pad_left = 0;
	fw->state = SH2000_STATE_STOPPING;
}

static void stop_step(struct sh2000_dsp *fw, double T)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];
		double v;

		if (!is_enabled(ax))
			continue;
		v = fw->stop_left == 1 ? 0.0 : ax->cmd_v - ax->stop_a * T;
		ax->cmd += 0.5 * (ax->cmd_v + v) * T;
		ax->cmd_a = (v - ax->cmd_v) / T;
		ax->cmd_j = 0.0;
		ax->cmd_v = v;
	}
	if (--fw->stop_left == 0)
		settle(fw);
}

static void card_fault(struct sh2000_dsp *fw, uint16_t bit)
{
	sh2000_fw_latch(fw, SH2000_AXIS_GLOBAL, bit);
	begin_stop(fw);
	if (fw->state == SH2000_STATE_IDLE)
		fw->state = SH2000_STATE_FAULT;
}

void sh2000_fw_card_fault(struct sh2000_dsp *fw, uint16_t bit)
{
	card_fault(fw, bit);
}

static void disable_axis(struct sh2000_dsp *fw, unsigned int a)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];

	ax->state &= (uint16_t)~(SH2000_AXIS_ENABLED | SH2000_AXIS_MOVING);
	sh2000_home_abort(ax);
	ax->dac = 0;
	ax->have_rec_hold = 0;
	sh2000_pid_reset(&ax->pid);
	sh2000_fw_hold_here(fw, a);
}

static void axis_fault(struct sh2000_dsp *fw, unsigned int a, uint16_t bit,
		       int disable)
{
	unsigned int b;

	sh2000_fw_latch(fw, a, bit);
	if (disable)
		disable_axis(fw, a);
	/* a gantry pair stops as one beam (gantry_loop.c) */
	if (disable && sh2000_gantry_partner(fw, a, &b))
		disable_axis(fw, b);
	card_fault(fw, SH2000_FAULT_AXIS);
}

/* ---- emergency stop ---- */

/* The emergency stop suspends the following-error check, which is what
 * would fault a gantry side held alone while the beam swings its
 * disabled partner: no side of the pair is held alone in ESTOP. */
static void estop_pair(struct sh2000_dsp *fw)
{
	unsigned int a, b;

	if (!sh2000_gantry_axes(fw, &a, &b))
		return;
	if (!is_enabled(&fw->ax[a]) && is_enabled(&fw->ax[b]))
		disable_axis(fw, b);
	else if (is_enabled(&fw->ax[a]) && !is_enabled(&fw->ax[b]))
		disable_axis(fw, a);
}

static void estop(struct sh2000_dsp *fw)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];

		sh2000_home_abort(ax);
		sh2000_fw_hold_here(fw, a);
		/* keep the accumulated output, forget the error history:
		 * no derivative kick from the jump of the set-point */
		ax->pid.e1 = 0.0;
		ax->pid.e2 = 0.0;
	}
	estop_pair(fw);
	discard_ring(fw);
	fw->ending = 0;
	fw->pad_left = 0;
	fw->fine_t = 0.0;
	fw->need_point = 1;
	fw->stop_left = 0;
	sh2000_fw_latch(fw, SH2000_AXIS_GLOBAL, SH2000_FAULT_ESTOP);
	fw->state = SH2000_STATE_ESTOP;
}

/* ---- sampling and axis checks ---- */

/* The FPGA's counters, switch inputs and index latches, read at the start
 * of the cycle: the position every decision of this cycle uses. A latched
 * index mark is taken and the latch armed for the next. */
static void read_inputs(struct sh2000_dsp *fw)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];
		uint32_t c = REG(fw, a, SH2000_HWREG_COUNTER);
		uint32_t in = REG(fw, a, SH2000_HWREG_INPUTS);
		uint16_t st = ax->state;

		ax->delta = sh2000_counter_delta(c, ax->counter);
		ax->counter = c;
		ax->act += ax->delta;
		ax->limit = ((in & SH2000_HWIN_LIMIT_NEG) ? 1 : 0) |
			    ((in & SH2000_HWIN_LIMIT_POS) ? 2 : 0);
		ax->index_seen = (in & SH2000_HWIN_INDEX) != 0;
		if (ax->index_seen) {
			ax->index_latch = REG(fw, a, SH2000_HWREG_INDEX_LATCH);
			SETREG(fw, a, SH2000_HWREG_INDEX_ARM, 1);
		}
		st &= (uint16_t)~(SH2000_AXIS_LIMIT_NEG | SH2000_AXIS_LIMIT_POS |
				  SH2000_AXIS_HOME_SW);
		if (ax->limit & 1)
			st |= SH2000_AXIS_LIMIT_NEG;
		if (ax->limit & 2)
			st |= SH2000_AXIS_LIMIT_POS;
		if (in & SH2000_HWIN_HOME)
			st |= SH2000_AXIS_HOME_SW;
		if (ax->index_seen && ax->home != HOME_NONE)
			st |= SH2000_AXIS_INDEX;
		ax->state = st;
		sh2000_fw_index_cycle(fw, a);
	}
}

static void check_axes(struct sh2000_dsp *fw, double T)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];
		int lim = ax->limit;

		if (is_enabled(ax)) {
			double jump = 4.0 * ax->prm.vmax * T +
				      SH2000_FW_COUNTER_SLACK;

			if (fabs((double)ax->delta) > jump) {
				axis_fault(fw, a, SH2000_AXIS_FAULT_COUNTER, 1);
			} else if (ax->home != HOME_NONE) {
				if (lim)
					axis_fault(fw, a, SH2000_AXIS_FAULT_HOME,
						   0);
			} else if ((lim & ~ax->prev_limit) ||
				   ((lim & 1) && ax->cmd_v < 0.0) ||
				   ((lim & 2) && ax->cmd_v > 0.0)) {
				axis_fault(fw, a, SH2000_AXIS_FAULT_HARD_LIMIT,
					   1);
			}
		}
		ax->prev_limit = lim;
	}
}

/* ---- host heartbeat ---- */

static void host_watchdog(struct sh2000_dsp *fw)
{
	uint16_t h = RD(fw, SH2000_W_HOST_HEARTBEAT);

	if (h != fw->host_hb) {
		fw->host_hb = h;
		fw->host_hb_cycles = 0;
		return;
	}
	fw->host_hb_cycles++;
	if (fw->host_timeout_ms > 0 &&
	    (fw->state == SH2000_STATE_RUNNING ||
	     fw->state == SH2000_STATE_HOMING) &&
	    fw->host_hb_cycles * sh2000_dsp_servo_period_ns(fw) >=
		    (uint64_t)fw->host_timeout_ms * 1000000u)
		card_fault(fw, SH2000_FAULT_HOST_TIMEOUT);
}

/* ---- commands ---- */

static uint16_t cmd_enable(struct sh2000_dsp *fw, uint32_t mask, int on)
{
	unsigned int a;

	if (mask & ~((1u << SH2000_AXES) - 1u))
		return SH2000_RES_BAD_VALUE;
	if (!on) {
		for (a = 0; a < SH2000_AXES; a++)
			if (mask & (1u << a))
				disable_axis(fw, a);
		if (fw->state == SH2000_STATE_HOMING) {
			for (a = 0; a < SH2000_AXES; a++)
				if (fw->ax[a].home != HOME_NONE)
					return SH2000_RES_OK;
			fw->state = SH2000_STATE_IDLE;
		}
		return SH2000_RES_OK;
	}
	if (fw->faults)
		return SH2000_RES_FAULTED;
	if (in_motion(fw))
		return SH2000_RES_BUSY;
	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];

		if (!(mask & (1u << a)) || is_enabled(ax))
			continue;
		sh2000_pid_reset(&ax->pid);
		sh2000_obs_reset(&ax->obs);
		sh2000_fw_hold_here(fw, a);
		ax->sat_cycles = 0;
		ax->skew_brake = 0;
		ax->state |= SH2000_AXIS_ENABLED;
	}
	return SH2000_RES_OK;
}

static void reset(struct sh2000_dsp *fw)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];

		ax->faults = 0;
		ax->sat_cycles = 0;
		ax->skew_brake = 0;
		sh2000_home_abort(ax);
		sh2000_pid_reset(&ax->pid);
		sh2000_fw_hold_here(fw, a);
	}
	fw->faults = 0;
	sh2000_fw_first_fault_clear(fw);
	discard_ring(fw);
	fw->ending = 0;
	fw->pad_left = 0;
	fw->fine_t = 0.0;
	fw->need_point = 1;
	fw->stop_left = 0;
	fw->host_hb_cycles = 0;
	fw->state = SH2000_STATE_IDLE;
}

/* The FPGA's counter preset: the axis reads `pos` from now on. */
void sh2000_fw_set_position(struct sh2000_dsp *fw, unsigned int a, int64_t pos)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];
	double was = ax->cmd;

	SETREG(fw, a, SH2000_HWREG_PRESET,
	       (uint32_t)((uint64_t)pos & SH2000_COUNTER_MASK));
	ax->counter = REG(fw, a, SH2000_HWREG_COUNTER);
	/* the preset moves the count, not the scale's fraction in it */
	ax->obs.x += (double)(pos - ax->act);
	ax->act = pos;
	ax->pid.e1 = 0.0;
	ax->pid.e2 = 0.0;
	/* the carriage stays: held at the nominal position whose corrected
	 * set-point is the new count, and the step that made in the tables'
	 * corrections is no motion to feed forward */
	sh2000_fw_hold_here(fw, a);
	sh2000_comp_rebase(fw, a, was);
}

static uint16_t execute(struct sh2000_dsp *fw, uint16_t seq, uint16_t op,
			uint16_t axis, uint16_t param, uint32_t arg,
			uint32_t *value)
{
	switch (op) {
	case SH2000_CMD_NOP:
		*value = (uint32_t)fw->cycle;
		return SH2000_RES_OK;
	case SH2000_CMD_ENABLE:
		return cmd_enable(fw, arg, 1);
	case SH2000_CMD_DISABLE:
		return cmd_enable(fw, arg, 0);
	case SH2000_CMD_SET_PARAM:
		return sh2000_fw_set_param(fw, axis, param, arg);
	case SH2000_CMD_GET_PARAM:
		return sh2000_fw_get_param(fw, axis, param, value);
	case SH2000_CMD_HOME:
		return sh2000_gantry_home(fw, axis, arg);
	case SH2000_CMD_STOP:
		if (in_motion(fw))
			begin_stop(fw);
		else
			discard_ring(fw);
		return SH2000_RES_OK;
	case SH2000_CMD_RESET:
		reset(fw);
		return SH2000_RES_OK;
	case SH2000_CMD_SET_POSITION:
		if (axis >= SH2000_AXES)
			return SH2000_RES_BAD_AXIS;
		if (in_motion(fw))
			return SH2000_RES_BUSY;
		sh2000_fw_set_position(fw, axis, (int32_t)arg);
		return SH2000_RES_OK;
	case SH2000_CMD_INDEX_ARM:
		return sh2000_fw_index_arm(fw, axis, param, arg, value);
	case SH2000_CMD_INDEX_DISARM:
		return sh2000_fw_index_disarm(fw, axis);
	case SH2000_CMD_GATHER_SET:
	case SH2000_CMD_GATHER_ARM:
	case SH2000_CMD_GATHER_STOP:
	case SH2000_CMD_GATHER_INFO:
	case SH2000_CMD_GATHER_READ:
		return sh2000_gather_command(fw, seq, op, axis, param, arg,
					     value);
	case SH2000_CMD_COMP_BEGIN:
	case SH2000_CMD_COMP_PAGE:
	case SH2000_CMD_COMP_COMMIT:
	case SH2000_CMD_COMP_CLEAR:
		return sh2000_comp_command(fw, op, param, arg, value);
	default:
		return SH2000_RES_BAD_OP;
	}
}

static void command(struct sh2000_dsp *fw)
{
	uint16_t seq = RD(fw, SH2000_W_CMD_SEQ);
	uint16_t op, axis, param, lo, hi, res;
	uint32_t value = 0;

	if (seq == fw->cmd_ack)
		return;
	op = RD(fw, SH2000_W_CMD_OP);
	axis = RD(fw, SH2000_W_CMD_AXIS);
	param = RD(fw, SH2000_W_CMD_PARAM);
	lo = RD(fw, SH2000_W_CMD_ARG_LO);
	hi = RD(fw, SH2000_W_CMD_ARG_HI);
	if (RD(fw, SH2000_W_CMD_CHECK) !=
	    sh2000_cmd_check(seq, op, axis, param, lo, hi))
		res = SH2000_RES_CHECKSUM;
	else
		res = execute(fw, seq, op, axis, param,
			      (uint32_t)lo | ((uint32_t)hi << 16), &value);
	WR(fw, SH2000_W_CMD_VALUE_LO, value & 0xffffu);
	WR(fw, SH2000_W_CMD_VALUE_HI, value >> 16);
	WR(fw, SH2000_W_CMD_RESULT, res);
	/* the status words the command changed (ENABLED, state, faults)
	 * before the answer: a host that sees the ACK and polls at once must
	 * not read the state from before the command */
	sh2000_fw_publish_words(fw);
	fw->cmd_ack = seq;
	WR(fw, SH2000_W_CMD_ACK, seq);
}

/* ---- segment ring ---- */

static void reject(struct sh2000_dsp *fw, uint16_t seq, uint16_t reason)
{
	WR(fw, SH2000_W_REJECT_SEQ, seq);
	WR(fw, SH2000_W_REJECT_REASON, reason);
	fw->reject_count++;
	WR(fw, SH2000_W_REJECT_COUNT, fw->reject_count);
	card_fault(fw, SH2000_FAULT_REJECTED);
}

static int32_t rec_pos(const uint16_t *rec, unsigned int a)
{
	return (int32_t)((uint32_t)rec[SH2000_REC_POS_LO(a)] |
			 ((uint32_t)rec[SH2000_REC_POS_HI(a)] << 16));
}

/*
 * REJECT_DISABLED: the records move a disabled axis, which the card does
 * not drive (a host planning motion the card will not make). They may
 * hold it anywhere: the first record taken since the motion started (or
 * the axis was disabled) sets where, and later ones stay within
 * FERR_LIMIT of it. The encoder is no reference for that: a carriage let
 * go of coasts on (the default model axis 10 mm from 100 mm/s,
 * docs/faults.md), so wherever the host read it, the carriage is
 * elsewhere by the time the card takes the record. A record within
 * FERR_LIMIT of the encoder is accepted too: a host that sends the
 * position it reads, which the rule before asked for, still may.
 */
static int disabled_moved(const struct sh2000_fw_axis *ax, double p)
{
	double lim = (double)ax->prm.ferr_limit;

	return ax->have_rec_hold && fabs(p - ax->rec_hold) > lim &&
	       fabs(p - (double)ax->act) > lim;
}

static uint16_t validate(struct sh2000_dsp *fw, const uint16_t *rec)
{
	double step_max = 0.0;
	unsigned int a;

	/* within a motion the host numbers records consecutively: another
	 * SEQ means the record it wrote never reached the RAM */
	if (fw->have_seq && rec[SH2000_REC_SEQ] != (uint16_t)(fw->seg_seq + 1u))
		return SH2000_REJECT_DROPPED;
	if (rec[SH2000_REC_CHECK] != sh2000_record_check(rec))
		return SH2000_REJECT_CHECKSUM;
	if (rec[SH2000_REC_RESERVED] || (rec[SH2000_REC_FLAGS] &
					 (uint16_t)~SH2000_REC_F_ALL))
		return SH2000_REJECT_RESERVED;
	for (a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_fw_axis *ax = &fw->ax[a];
		double p = (double)rec_pos(rec, a);

		if (!is_enabled(ax)) {
			if (disabled_moved(ax, p))
				return SH2000_REJECT_DISABLED;
			continue;
		}
		if (p < (double)ax->prm.soft_min ||
		    p > (double)ax->prm.soft_max)
			return SH2000_REJECT_SOFT_LIMIT;
		step_max = ax->prm.vmax * (double)fw->coarse_us * 1e-6 *
				   (1.0 + SH2000_FW_VMAX_MARGIN) +
			   SH2000_FW_VMAX_SLACK_COUNTS;
		if (fabs(p - sh2000_interp_last(&fw->ip, a)) > step_max)
			return SH2000_REJECT_VELOCITY;
	}
	return SH2000_REJECT_NONE;
}

/* Start of a coarse period while running: the next point of the window.
 * Returns 0 if the card stopped instead. */
static int next_point(struct sh2000_dsp *fw)
{
	uint16_t rec[SH2000_RECORD_WORDS], why, num;
	unsigned int a, via;

	if (fw->ending) {
		for (a = 0; a < SH2000_AXES; a++)
			sh2000_interp_push(&fw->ip, a,
					   sh2000_interp_last(&fw->ip, a));
		fw->pad_left--;
		return 1;
	}
	if (sh2000_queue_fill(fw) == 0) {
		card_fault(fw, SH2000_FAULT_UNDERRUN);
		return 0;
	}
	via = sh2000_queue_take(fw, rec, &num);
	if (via == SH2000_VIA_MBOX_LOST || via == SH2000_VIA_MBOX_BAD) {
		/* a post the card could not take as it was: named by its
		 * number, like a ring record's SEQ */
		reject(fw, num, via == SH2000_VIA_MBOX_LOST ?
				SH2000_REJECT_DROPPED : SH2000_REJECT_CHECKSUM);
		return 0;
	}
	why = validate(fw, rec);
	if (why != SH2000_REJECT_NONE) {
		/* a lost record is reported by the number it should have had */
		reject(fw, why == SH2000_REJECT_DROPPED ?
				   (uint16_t)(fw->seg_seq + 1u) :
				   rec[SH2000_REC_SEQ], why);
		return 0;
	}
	fw->seg_seq = rec[SH2000_REC_SEQ];
	fw->have_seq = 1;
	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];
		double p = (double)rec_pos(rec, a);

		if (!is_enabled(ax) && !ax->have_rec_hold) {
			ax->rec_hold = p;
			ax->have_rec_hold = 1;
		}
		sh2000_interp_push(&fw->ip, a, is_enabled(ax) ? p :
					       (double)ax->act);
	}
	if (rec[SH2000_REC_FLAGS] & SH2000_REC_F_END) {
		/* two more copies: the last window is (p, e, e, e), whose
		 * x(1) is e */
		fw->ending = 1;
		fw->pad_left = 2;
	}
	return 1;
}

/* The set-points at t of the window, at the time base's rate: velocity
 * scaled by sigma, acceleration by sigma^2 plus sigma' v. */
static void eval_window(struct sh2000_dsp *fw, double t)
{
	double Tc = (double)fw->coarse_us * 1e-6, s = fw->tb_sigma, v, acc;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];

		if (!is_enabled(ax))
			continue;
		sh2000_interp_eval(&fw->ip, a, t, Tc, &ax->cmd, &v, &acc);
		fw->tb_v[a] = v;
		fw->tb_a[a] = acc;
		ax->cmd_v = s * v;
		ax->cmd_a = s * s * acc + fw->tb_rate * v;
		ax->cmd_j = s * s * s * sh2000_interp_jerk(&fw->ip, a, Tc);
	}
}

/* A coarse period is complete: past END's padding, the motion is over. */
static void period_done(struct sh2000_dsp *fw)
{
	unsigned int a;

	fw->fine_t = 0.0;
	fw->need_point = 1;
	if (fw->ending && fw->pad_left == 0) {
		/* the end point exactly, not the polynomial's rounding */
		for (a = 0; a < SH2000_AXES; a++)
			if (is_enabled(&fw->ax[a]))
				fw->ax[a].cmd = sh2000_interp_last(&fw->ip, a);
		settle(fw);
	}
}

static void run_step(struct sh2000_dsp *fw, double T)
{
	double t;

	if (fw->need_point) {
		if (!next_point(fw)) {
			/* decelerate from this very cycle: no set-point
			 * hiccup */
			if (fw->state == SH2000_STATE_STOPPING)
				stop_step(fw, T);
			return;
		}
		fw->need_point = 0;
	}
	sh2000_tb_step(fw, T);
	t = fw->fine_t + fw->tb_sigma / (double)fw->fine_steps;
	if (t > 1.0 + 1e-9) {
		/* the period ends inside this cycle: on into the next */
		if (fw->ending && fw->pad_left == 0) {
			eval_window(fw, 1.0);
			period_done(fw);
			return;
		}
		if (!next_point(fw)) {
			if (fw->state == SH2000_STATE_STOPPING)
				stop_step(fw, T);
			return;
		}
		t -= 1.0;
	}
	if (t >= 1.0 - 1e-9) {
		eval_window(fw, 1.0);
		period_done(fw);
		return;
	}
	fw->fine_t = t;
	eval_window(fw, t);
}

/* Rejected while a fault is latched: the host learns the first record it
 * pushed after the fault was not executed. */
static void reject_all(struct sh2000_dsp *fw)
{
	uint16_t seq = sh2000_queue_first_seq(fw);

	discard_ring(fw);
	reject(fw, seq, SH2000_REJECT_STATE);
}

/* ---- motion by state ---- */

static void motion(struct sh2000_dsp *fw, double T)
{
	unsigned int a;
	uint16_t fill;

	sh2000_queue_receive(fw);
	if (fw->queue_bad) {
		/* more than the ring holds: everything published goes */
		fw->queue_bad = 0;
		card_fault(fw, SH2000_FAULT_PROTOCOL);
		discard_ring(fw);
	}
	fill = sh2000_queue_fill(fw);
	switch (fw->state) {
	case SH2000_STATE_IDLE:
		if (fill == 0)
			break;
		fw->state = SH2000_STATE_RUNNING;
		fw->have_seq = 0;
		for (a = 0; a < SH2000_AXES; a++)
			fw->ax[a].have_rec_hold = 0;
		fw->fine_t = 0.0;
		fw->need_point = 1;
		fw->host_hb_cycles = 0;
		run_step(fw, T);
		break;
	case SH2000_STATE_RUNNING:
		run_step(fw, T);
		break;
	case SH2000_STATE_STOPPING:
		stop_step(fw, T);
		break;
	case SH2000_STATE_HOMING:
		sh2000_home_cycle(fw, T);
		sh2000_gantry_home_cycle(fw, T);
		break;
	case SH2000_STATE_FAULT:
	case SH2000_STATE_ESTOP:
		if (fill)
			reject_all(fw);
		break;
	default:
		break;
	}
}

/* ---- the servo loop ---- */

/* The axes whose loops ran this cycle (ran: a bit each): a DAC at its
 * limit counts towards DAC_SAT, whichever loop put it there (a gantry
 * pair's coupling adds its share after the axis' own PID). */
static void count_saturation(struct sh2000_dsp *fw, unsigned int ran)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];

		if (!(ran & (1u << a)))
			continue;
		if (ax->dac >= ax->prm.dac_limit ||
		    ax->dac <= -ax->prm.dac_limit) {
			if (++ax->sat_cycles >= SH2000_FW_DAC_SAT_CYCLES)
				axis_fault(fw, a, SH2000_AXIS_FAULT_DAC_SAT, 1);
		} else {
			ax->sat_cycles = 0;
		}
	}
}

/* The DAC holds over the coming period: the feed-forward takes the
 * set-point's mean velocity and acceleration over it, from the B-spline's
 * acceleration and jerk (cmd_j is 0 off the B-spline, whose ramps' cmd_a
 * is the period's already). */
static double lead_v(const struct sh2000_dsp *fw,
		     const struct sh2000_fw_axis *ax, double T)
{
	if (fw->state != SH2000_STATE_RUNNING)
		return 0.0;
	return ax->cmd_a * T / 2 + ax->cmd_j * T * T / 6;
}

/* Axis a's PID on the corrected set-point, against the observer's
 * reading finer than a count (observer.c; a gantry pair's sides, which
 * the beam couples, against the counter). */
static void loop_step(struct sh2000_dsp *fw, unsigned int a, double T)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];
	struct sh2000_pid_gains g;
	unsigned int ga, gb;
	int model = !sh2000_gantry_axes(fw, &ga, &gb) || (a != ga && a != gb);
	double v = ax->cmd_v + fw->comp.v[a] + lead_v(fw, ax, T);
	double acc = ax->cmd_a + fw->comp.a[a] + ax->cmd_j * T / 2;

	g.kp = ax->prm.kp;
	g.ti = ax->prm.ti;
	g.td = ax->prm.td;
	g.kvff = ax->prm.kvff;
	g.kaff = ax->prm.kaff;
	g.dac_limit = ax->prm.dac_limit;
	ax->loop_e = sh2000_obs_error(ax, ax->cmd + fw->comp.off[a], model, T);
	if (ax->obs.on)
		ax->dac = sh2000_pid_step_fine(&ax->pid, &g, ax->loop_e, v,
					       acc, T);
	else
		ax->dac = sh2000_pid_step(&ax->pid, &g, ax->loop_e, v, acc, T);
}

static void servo(struct sh2000_dsp *fw, double T)
{
	unsigned int a, ran = 0;

	/* the tables' corrections at the nominal set-points: the loop closes
	 * on the corrected one, everything else stays nominal */
	sh2000_comp_cycle(fw, T);
	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];
		double e;
		int braking;

		if (!is_enabled(ax)) {
			ax->dac = 0;
			sh2000_obs_reset(&ax->obs);
			sh2000_fw_hold_here(fw, a);
			continue;
		}
		if (ax->cmd_v != 0.0)
			ax->state |= SH2000_AXIS_MOVING;
		else
			ax->state &= (uint16_t)~SH2000_AXIS_MOVING;
		if (ax->cmd_v != 0.0 && ax->home == HOME_NONE &&
		    (ax->cmd < (double)ax->prm.soft_min ||
		     ax->cmd > (double)ax->prm.soft_max) &&
		    !(ax->faults & SH2000_AXIS_FAULT_SOFT_LIMIT))
			axis_fault(fw, a, SH2000_AXIS_FAULT_SOFT_LIMIT, 0);
		e = sh2000_fw_ferr(fw, a);
		/* an emergency stop or a gantry's skew fault held the
		 * set-point where the carriage was: it brakes to there (a
		 * side the beam drags away from it cannot hold it) */
		braking = sh2000_gantry_brake_exempt(ax, e);
		if (fabs(e) > (double)ax->prm.ferr_limit &&
		    fw->state != SH2000_STATE_ESTOP && !braking) {
			axis_fault(fw, a, SH2000_AXIS_FAULT_FERR, 1);
			continue;
		}
		loop_step(fw, a, T);
		ran |= 1u << a;
	}
	sh2000_gantry_servo(fw, T);
	count_saturation(fw, ran);
	/* the codes the DACs hold now, the gantry's share included */
	for (a = 0; a < SH2000_AXES; a++)
		if (ran & (1u << a))
			sh2000_obs_predict(&fw->ax[a], T);
}

static void put32(struct sh2000_dsp *fw, unsigned int w, uint32_t v)
{
	WR(fw, w, v & 0xffffu);
	WR(fw, w + 1u, v >> 16);
}

static void publish_snapshot(struct sh2000_dsp *fw)
{
	uint16_t s = (uint16_t)(fw->snap_seq + 1u);
	unsigned int a;

	WR(fw, SH2000_W_SNAP_SEQ_BEGIN, s);
	for (a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_fw_axis *ax = &fw->ax[a];
		unsigned int w = SH2000_W_SNAP_AXIS(a);

		put32(fw, w + SH2000_SNAP_CMD_LO, (uint32_t)sh2000_fw_cmd_counts(ax));
		put32(fw, w + SH2000_SNAP_ACT_LO,
		      sh2000_comp_nominal_counter(fw, a));
		WR(fw, w + SH2000_SNAP_DAC, (uint16_t)ax->dac);
	}
	put32(fw, SH2000_W_SNAP_TIME_LO, (uint32_t)fw->cycle);
	WR(fw, SH2000_W_SNAP_SEQ_END, s);
	fw->snap_seq = s;
}

void sh2000_fw_publish_words(struct sh2000_dsp *fw)
{
	unsigned int a;

	WR(fw, SH2000_W_FAULTS, fw->faults);
	for (a = 0; a < SH2000_AXES; a++) {
		WR(fw, SH2000_W_AXIS_FAULTS(a), fw->ax[a].faults);
		WR(fw, SH2000_W_AXIS_STATE(a), fw->ax[a].state);
	}
	WR(fw, SH2000_W_STATE, fw->state);
}

/* DAC out: each axis' code goes to the DAC7744, which holds it until the
 * next interrupt writes again. */
static void dac_out(struct sh2000_dsp *fw)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		SETREG(fw, a, SH2000_HWREG_DAC, (uint16_t)fw->ax[a].dac);
}

void sh2000_dsp_interrupt(struct sh2000_dsp *fw)
{
	double T = sh2000_fw_servo_s(fw);
	uint16_t req;

	fw->cycle++;
	read_inputs(fw);
	req = RD(fw, SH2000_W_ESTOP_REQ);
	if (req != fw->estop_ack) {
		estop(fw);
		fw->estop_ack = req;
		WR(fw, SH2000_W_ESTOP_ACK, req);
	}
	check_axes(fw, T);
	WR(fw, SH2000_W_HEARTBEAT, ++fw->heartbeat);
	host_watchdog(fw);
	command(fw);
	motion(fw, T);
	servo(fw, T);
	dac_out(fw);
	sh2000_gather_cycle(fw);
	sh2000_fw_publish_words(fw);
	if (++fw->status_div >= (unsigned int)fw->status_period) {
		fw->status_div = 0;
		publish_snapshot(fw);
	}
}

/* ---- boot ---- */

void sh2000_dsp_boot(struct sh2000_dsp *fw, struct sh2000_board *hw)
{
	unsigned int a, w;

	fw->hw = hw;
	WR(fw, SH2000_W_STATE, SH2000_STATE_BOOT);
	sh2000_fw_default_params(fw);
	sh2000_gather_boot(&fw->gather);
	fw->tb_sigma = 1.0;	/* full rate until the host says otherwise */
	fw->tb_rate = 0.0;
	fw->need_point = 1;
	for (a = 0; a < SH2000_AXES; a++) {
		struct sh2000_fw_axis *ax = &fw->ax[a];

		ax->counter = REG(fw, a, SH2000_HWREG_COUNTER);
		ax->act = ax->counter;
		ax->prev_limit = 0;
		SETREG(fw, a, SH2000_HWREG_INDEX_ARM, 1);
		SETREG(fw, a, SH2000_HWREG_DAC, 0);
		sh2000_fw_hold_at(fw, a, (double)ax->act);
	}
	/* Whatever the host left in its words is history, not a request. */
	fw->estop_ack = RD(fw, SH2000_W_ESTOP_REQ);
	fw->cmd_ack = RD(fw, SH2000_W_CMD_SEQ);
	fw->host_hb = RD(fw, SH2000_W_HOST_HEARTBEAT);
	for (w = SH2000_W_HEARTBEAT; w < SH2000_STATUS_WORDS; w++)
		if (w != SH2000_W_STATE)
			WR(fw, w, 0);
	WR(fw, SH2000_W_ESTOP_ACK, fw->estop_ack);
	WR(fw, SH2000_W_CMD_ACK, fw->cmd_ack);
	sh2000_fw_first_fault_clear(fw);
	sh2000_fw_index_boot(fw);
	sh2000_queue_boot(fw);
	sh2000_comp_boot(fw);
	fw->state = SH2000_STATE_IDLE;
	sh2000_fw_publish_words(fw);
	publish_snapshot(fw);
	WR(fw, SH2000_W_VERSION, SH2000_PROTO_VERSION);
	WR(fw, SH2000_W_MAGIC, SH2000_PROTO_MAGIC);
}
