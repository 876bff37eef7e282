// SPDX-License-Identifier: MIT
/*
 * Homing on the home switch with debounce, optionally finishing on the
 * encoder index ([R4]); docs/protocol.md section 13. Each homing axis
 * runs its own small state machine; the card is HOMING while any runs.
 */
#include <math.h>

#include "cardmodel.h"

void sh2000_home_abort(struct sh2000_fw_axis *ax)
{
	ax->home = HOME_NONE;
	ax->state &= (uint16_t)~SH2000_AXIS_HOMING;
}

uint16_t sh2000_latch_cmd_check(const struct sh2000_dsp *fw,
				unsigned int axis, int bad_value)
{
	if (axis >= SH2000_AXES)
		return SH2000_RES_BAD_AXIS;
	if (bad_value)
		return SH2000_RES_BAD_VALUE;
	if (fw->faults)
		return SH2000_RES_FAULTED;
	if (!sh2000_axis_enabled(&fw->ax[axis]))
		return SH2000_RES_DISABLED;
	return SH2000_RES_OK;
}

uint16_t sh2000_home_start(struct sh2000_dsp *fw, unsigned int axis,
			   uint32_t flags)
{
	struct sh2000_fw_axis *ax;
	uint16_t r = sh2000_latch_cmd_check(fw, axis,
					    (flags & ~SH2000_HOME_F_INDEX) != 0);

	if (r != SH2000_RES_OK)
		return r;
	ax = &fw->ax[axis];
	if (fw->state != SH2000_STATE_IDLE && fw->state != SH2000_STATE_HOMING)
		return SH2000_RES_BUSY;
	/* the host's index arm has the latch (index.c) */
	if (ax->home != HOME_NONE || ax->ix.state == SH2000_INDEX_ARMED)
		return SH2000_RES_BUSY;
	/* on the switch already: a reference taken here would depend on
	 * where the axis happened to be, so leave the switch first */
	ax->home = (ax->state & SH2000_AXIS_HOME_SW) ? HOME_BACKOFF : HOME_SEEK;
	ax->home_flags = flags;
	ax->debounce = 0;
	ax->state &= (uint16_t)~(SH2000_AXIS_HOMED | SH2000_AXIS_INDEX);
	ax->state |= SH2000_AXIS_HOMING;
	fw->state = SH2000_STATE_HOMING;
	fw->host_hb_cycles = 0;
	return SH2000_RES_OK;
}

/* Set-point velocity towards vt within AMAX; position integrated. */
static void ramp(struct sh2000_fw_axis *ax, double vt, double T)
{
	double dv = ax->prm.amax * T, v = ax->cmd_v;

	if (v < vt)
		v = v + dv < vt ? v + dv : vt;
	else
		v = v - dv > vt ? v - dv : vt;
	ax->cmd += 0.5 * (ax->cmd_v + v) * T;
	ax->cmd_a = (v - ax->cmd_v) / T;
	ax->cmd_v = v;
}

/* Towards `target` with |v| <= vcap within AMAX; 1 when there. */
static int move_to(struct sh2000_fw_axis *ax, double target, double vcap,
		   double T)
{
	double d = target - ax->cmd, am = ax->prm.amax, vd;

	if (fabs(d) <= am * T * T + 0.5 && fabs(ax->cmd_v) <= 2.0 * am * T) {
		ax->cmd = target;
		ax->cmd_v = 0.0;
		ax->cmd_a = 0.0;
		return 1;
	}
	vd = sqrt(2.0 * am * fabs(d));
	if (vd > vcap)
		vd = vcap;
	ramp(ax, d > 0 ? vd : -vd, T);
	return 0;
}

static void home_step(struct sh2000_dsp *fw, unsigned int a, double T)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];
	double speed = fabs(ax->prm.home_vel), dir;
	int64_t delta;

	if (speed > ax->prm.vmax)
		speed = ax->prm.vmax;
	dir = ax->prm.home_vel < 0 ? -1.0 : 1.0;
	switch (ax->home) {
	case HOME_BACKOFF:
		ramp(ax, -dir * speed, T);
		ax->debounce = (ax->state & SH2000_AXIS_HOME_SW) ?
				       0 : ax->debounce + 1;
		if (ax->debounce >= (unsigned int)ax->prm.home_debounce)
			ax->home = HOME_BACKSTOP;
		break;
	case HOME_BACKSTOP:
		ramp(ax, 0.0, T);
		if (ax->cmd_v == 0.0) {
			ax->debounce = 0;
			ax->home = HOME_SEEK;
		}
		break;
	case HOME_SEEK:
		ramp(ax, dir * speed, T);
		if (!(ax->state & SH2000_AXIS_HOME_SW)) {
			ax->debounce = 0;
			break;
		}
		/* the reference is the edge that starts the run of active
		 * samples, not where the run is confirmed: it does not
		 * depend on speed or debounce */
		if (ax->debounce++ == 0)
			ax->home_latch = (double)ax->act;
		if (ax->debounce >= (unsigned int)ax->prm.home_debounce)
			ax->home = HOME_STOP1;
		break;
	case HOME_STOP1:
		ramp(ax, 0.0, T);
		if (ax->cmd_v == 0.0)
			ax->home = (ax->home_flags & SH2000_HOME_F_INDEX) ?
					   HOME_CREEP : HOME_RETURN;
		break;
	case HOME_CREEP:
		ramp(ax, dir * speed / SH2000_FW_HOME_CREEP_DIV, T);
		if (ax->index_seen) {
			ax->home_latch = (double)(ax->act +
				sh2000_counter_delta(ax->index_latch,
						     ax->counter));
			ax->home = HOME_STOP2;
		}
		break;
	case HOME_STOP2:
		ramp(ax, 0.0, T);
		if (ax->cmd_v == 0.0)
			ax->home = HOME_RETURN;
		break;
	case HOME_RETURN:
		/* back to the reference: the latch is a counter reading, so
		 * the nominal set-point goes where its correction puts the
		 * motor on the latch (the latch itself without tables) */
		if (!move_to(ax, sh2000_comp_nominal_at(fw, a, ax->home_latch),
			     speed, T))
			break;
		delta = (int64_t)ax->prm.home_offset - (int64_t)ax->home_latch;
		sh2000_home_preset(fw, a, delta);
		ax->home = HOME_NONE;
		ax->state &= (uint16_t)~SH2000_AXIS_HOMING;
		ax->state |= SH2000_AXIS_HOMED;
		break;
	default:
		break;
	}
}

void sh2000_home_cycle(struct sh2000_dsp *fw, double T)
{
	unsigned int a, busy = 0;

	for (a = 0; a < SH2000_AXES; a++)
		if (fw->ax[a].home != HOME_NONE) {
			home_step(fw, a, T);
			busy |= fw->ax[a].home != HOME_NONE;
		}
	if (!busy && fw->state == SH2000_STATE_HOMING)
		fw->state = SH2000_STATE_IDLE;
}

void sh2000_home_preset(struct sh2000_dsp *fw, unsigned int a, int64_t delta)
{
	struct sh2000_fw_axis *ax = &fw->ax[a];
	double was;
	/* the corrected set-point as it is in this cycle: the last cycle's
	 * correction is stale when the set-point moved since (a gantry side's
	 * own homing preset it in this cycle) */
	double sp = sh2000_comp_corrected(fw, a) + (double)delta;

	sh2000_fw_set_position(fw, a, ax->act + delta);	/* re-bases its hold */
	was = ax->cmd;
	sh2000_fw_hold_at(fw, a, sh2000_comp_nominal_at(fw, a, sp));
	sh2000_comp_rebase(fw, a, was);
}

int sh2000_home_move_to(struct sh2000_fw_axis *ax, double target,
			double vcap, double T)
{
	return move_to(ax, target, vcap, T);
}
