// SPDX-License-Identifier: MIT
/*
 * A gantry pair on the card (protocol 1.7, docs/protocol.md "Gantry
 * pairs"): two axes that drive one beam. Each keeps its own set-point and
 * PID; the DSP sees both encoders every servo cycle, so it also closes a
 * cross-coupling loop on the pair's skew, the difference of the two
 * following errors,
 *   s = (cmd_a - act_a) - (cmd_b - act_b),
 * cmd the set-point with the compensation tables' correction (1.5),
 * which is the beam's yaw (act_b - act_a) when both take one set-point,
 * as LinuxCNC's two joints of one axis do, and which does not fight two
 * set-points that differ on purpose (each side homing on its own switch).
 * The loop is the axes' incremental PID (pid.c) with its own gains; its
 * output u pushes side a by u/2 and side b by -u/2, within the DAC limit.
 * A skew beyond gantry_skew_limit latches AXIS_FAULT_SKEW on both sides
 * in the cycle that sees it: both set-points stop at once where the
 * sides are, as an emergency stop holds them, and the card stops.
 * A fault that disables one side (following error, DAC saturation,
 * counter, hard limit) disables the other in the same cycle
 * (firmware.c's axis_fault asks sh2000_gantry_partner): both coast as
 * one beam, its stiffness keeping them together, rather than one side
 * braking under its loop and dragging the coasting one askew behind it
 * (then a way back of the two sides by different distances latched
 * SKEW). The partner latches no bit of its own: the faulted side's bit
 * and the first-fault record say why. After a skew fault, which holds
 * both sides where they stopped, the other side stays held, its
 * following-error check off only while it brakes (a side the beam then
 * drags away faults too); in ESTOP, which has no such check, it goes.
 * HOME on either side homes both, each on its own switch, and with
 * HOME_F_INDEX then on its own scale's index mark; then side b's count is
 * shifted by gantry_square (where its reference, switch or mark, is
 * relative to side a's on a square beam) and side b moves to side a's
 * position: the beam ends square, both sides reading the same. While the
 * sides creep to their marks, what they travel may differ by at most
 * gantry_skew_limit (a side whose mark does not come would otherwise
 * drag the beam askew behind the other): beyond it the sides still
 * creeping latch AXIS_FAULT_HOME, both stop, and neither reads HOMED.
 * The pair is homed only as a pair: an abandoned squaring clears HOMED
 * on both sides.
 */
#include <math.h>
#include <stdlib.h>

#include "cardmodel.h"

int sh2000_gantry_axes(const struct sh2000_dsp *fw, unsigned int *a,
		       unsigned int *b)
{
	unsigned int m = (unsigned int)fw->gantry.pair, i, n = 0;
	unsigned int ax[2] = { 0, 0 };

	for (i = 0; i < SH2000_AXES && n < 2; i++)
		if (m & (1u << i))
			ax[n++] = i;
	if (n != 2)
		return 0;
	*a = ax[0];
	*b = ax[1];
	return 1;
}

int sh2000_gantry_partner(const struct sh2000_dsp *fw, unsigned int axis,
			  unsigned int *other)
{
	unsigned int a, b;

	if (!sh2000_gantry_axes(fw, &a, &b) || (axis != a && axis != b))
		return 0;
	*other = axis == a ? b : a;
	/* the skew fault already stopped both and holds the other where it
	 * stopped (a jammed side saturating its DAC afterwards): it stays,
	 * under its following-error check once it is back where it was
	 * held (firmware.c's servo); in ESTOP that check is off, so it
	 * goes with the faulted side */
	return !(fw->ax[*other].faults & SH2000_AXIS_FAULT_SKEW) ||
	       fw->state == SH2000_STATE_ESTOP;
}

void sh2000_gantry_paired(struct sh2000_dsp *fw)
{
	sh2000_pid_reset(&fw->gantry.pid);
	fw->gantry.skew = 0.0;
	fw->gantry.squaring = 0;
}

/* Both sides stop where they are, now: set-points held at the encoders,
 * no feed-forward, the PID keeps its output and forgets its errors (no
 * derivative kick), as the emergency stop does; the axis fault bits[i]
 * latched on side i (0: none), the card faulted. */
static void pair_fault(struct sh2000_dsp *fw, unsigned int a, unsigned int b,
		       const uint16_t bits[2])
{
	unsigned int s[2] = { a, b }, i;

	for (i = 0; i < 2; i++) {
		struct sh2000_fw_axis *ax = &fw->ax[s[i]];

		sh2000_home_abort(ax);
		sh2000_fw_hold_here(fw, s[i]);
		ax->stop_a = 0.0;
		ax->pid.e1 = 0.0;
		ax->pid.e2 = 0.0;
		ax->pid.ff = 0.0;
		ax->dac = (int16_t)lrint(ax->pid.u);
		ax->skew_brake = bits[i] == SH2000_AXIS_FAULT_SKEW ?
					 SKEW_BRAKE_STOPPING : SKEW_BRAKE_NONE;
		ax->brake_dir = (ax->delta > 0) - (ax->delta < 0);
		if (bits[i])
			sh2000_fw_latch(fw, s[i], bits[i]);
	}
	sh2000_pid_reset(&fw->gantry.pid);
	fw->gantry.squaring = 0;
	sh2000_fw_card_fault(fw, SH2000_FAULT_AXIS);
}

/* The brake is over when the side stands or turns back, where it is
 * furthest from the held point; its return may swing (its loop's
 * integral, wound up by the brake), but a side that gets further from
 * the held point than its brake took it, by more than FERR_LIMIT, is
 * dragged away by the beam and cannot hold it. A turn within FERR_LIMIT
 * ends the brake: the side is an axis like any other again. */
int sh2000_gantry_brake_exempt(struct sh2000_fw_axis *ax, double e)
{
	double lim = (double)ax->prm.ferr_limit, d = fabs(e);
	int dir = (ax->delta > 0) - (ax->delta < 0);

	if (ax->skew_brake == SKEW_BRAKE_NONE)
		return 0;
	if (ax->skew_brake == SKEW_BRAKE_RETURNING &&
	    d > ax->brake_peak_e + lim) {
		ax->skew_brake = SKEW_BRAKE_NONE;	/* dragged */
		return 0;
	}
	if (ax->brake_dir == 0 || (dir != 0 && dir != ax->brake_dir)) {
		if (ax->skew_brake == SKEW_BRAKE_STOPPING)
			ax->brake_peak_e = d;
		ax->skew_brake = SKEW_BRAKE_RETURNING;
		ax->brake_dir = dir;
		if (d <= lim) {
			ax->skew_brake = SKEW_BRAKE_NONE;
			return 0;
		}
	}
	return 1;
}

static void skew_fault(struct sh2000_dsp *fw, unsigned int a, unsigned int b)
{
	static const uint16_t skew[2] = {
		SH2000_AXIS_FAULT_SKEW, SH2000_AXIS_FAULT_SKEW,
	};

	pair_fault(fw, a, b, skew);
}

static int16_t add_dac(const struct sh2000_fw_axis *ax, double du)
{
	double lim = (double)ax->prm.dac_limit, v = (double)ax->dac + du;

	if (v > lim)
		v = lim;
	if (v < -lim)
		v = -lim;
	return (int16_t)lrint(v);
}

void sh2000_gantry_servo(struct sh2000_dsp *fw, double T)
{
	struct sh2000_gantry_loop *g = &fw->gantry;
	struct sh2000_fw_axis *xa, *xb;
	struct sh2000_pid_gains k;
	unsigned int a, b;
	double u;

	if (!sh2000_gantry_axes(fw, &a, &b))
		return;
	xa = &fw->ax[a];
	xb = &fw->ax[b];
	if (!sh2000_axis_enabled(xa) || !sh2000_axis_enabled(xb) ||
	    fw->state == SH2000_STATE_ESTOP) {
		sh2000_pid_reset(&g->pid);
		g->skew = 0.0;
		return;
	}
	/* the loops' errors: a compensation table's correction of one side
	 * is what that side is meant to do, not skew */
	g->skew = sh2000_fw_ferr(fw, a) - sh2000_fw_ferr(fw, b);
	if (fabs(g->skew) > (double)g->skew_limit) {
		if (!((xa->faults | xb->faults) & SH2000_AXIS_FAULT_SKEW))
			skew_fault(fw, a, b);
		return;
	}
	if (g->kp == 0.0) {
		/* uncoupled: no output left over from gains before (the
		 * incremental law would hold its last u for ever) */
		sh2000_pid_reset(&g->pid);
		return;
	}
	k.kp = g->kp;
	k.ti = g->ti;
	k.td = g->td;
	k.kvff = 0.0;
	k.kaff = 0.0;
	k.dac_limit = xa->prm.dac_limit < xb->prm.dac_limit ?
			      xa->prm.dac_limit : xb->prm.dac_limit;
	(void)sh2000_pid_step(&g->pid, &k, g->skew, 0.0, 0.0, T);
	u = g->pid.u;
	xa->dac = add_dac(xa, 0.5 * u);
	xb->dac = add_dac(xb, -0.5 * u);
}

uint16_t sh2000_gantry_home(struct sh2000_dsp *fw, unsigned int axis,
			    uint32_t flags)
{
	unsigned int a, b;
	uint16_t r;

	if (!sh2000_gantry_axes(fw, &a, &b) || (axis != a && axis != b))
		return sh2000_home_start(fw, axis, flags);
	if (!sh2000_axis_enabled(&fw->ax[a]) || !sh2000_axis_enabled(&fw->ax[b]))
		return SH2000_RES_DISABLED;
	if (fw->ax[a].home != HOME_NONE || fw->ax[b].home != HOME_NONE ||
	    (fw->gantry.squaring != GANTRY_SQ_NONE &&
	     fw->state == SH2000_STATE_HOMING))
		return SH2000_RES_BUSY;
	r = sh2000_home_start(fw, a, flags);
	if (r != SH2000_RES_OK)
		return r;
	r = sh2000_home_start(fw, b, flags);
	if (r != SH2000_RES_OK) {
		sh2000_home_abort(&fw->ax[a]);
		return r;
	}
	fw->gantry.squaring = GANTRY_SQ_HOMING;
	fw->gantry.sq_cycle = fw->cycle - 1u;	/* motion() runs this cycle */
	fw->gantry.creeping[0] = fw->gantry.creeping[1] = 0;
	return SH2000_RES_OK;
}

/* The squaring is over without a square pair: neither side is homed. */
static void abandon(struct sh2000_dsp *fw, unsigned int a, unsigned int b)
{
	fw->ax[a].state &= (uint16_t)~SH2000_AXIS_HOMED;
	fw->ax[b].state &= (uint16_t)~SH2000_AXIS_HOMED;
	fw->gantry.squaring = GANTRY_SQ_NONE;
}

/* Homing with the index: the sides' travel since each began creeping to
 * its mark may differ by gantry_skew_limit at most; beyond it the sides
 * still creeping latch AXIS_FAULT_HOME and the pair stops. 1 on a
 * fault. */
static int creep_check(struct sh2000_dsp *fw, unsigned int a, unsigned int b)
{
	struct sh2000_gantry_loop *g = &fw->gantry;
	unsigned int s[2] = { a, b }, i;
	uint16_t bits[2] = { 0, 0 };

	for (i = 0; i < 2; i++) {
		struct sh2000_fw_axis *ax = &fw->ax[s[i]];

		if (ax->home != HOME_CREEP)
			continue;
		if (!g->creeping[i]) {
			g->creeping[i] = 1;
			g->creep_from[i] = ax->act;
		}
		bits[i] = SH2000_AXIS_FAULT_HOME;
		g->creep_travel[i] = ax->act - g->creep_from[i];
	}
	if (!g->creeping[0] || !g->creeping[1] || (!bits[0] && !bits[1]) ||
	    llabs(g->creep_travel[0] - g->creep_travel[1]) <=
		    (long long)g->skew_limit)
		return 0;
	pair_fault(fw, a, b, bits);
	abandon(fw, a, b);
	return 1;
}

void sh2000_gantry_home_cycle(struct sh2000_dsp *fw, double T)
{
	struct sh2000_gantry_loop *g = &fw->gantry;
	struct sh2000_fw_axis *xa, *xb;
	unsigned int a, b;

	if (g->squaring == GANTRY_SQ_NONE || !sh2000_gantry_axes(fw, &a, &b))
		return;
	/* a cycle not HOMING since the last (STOP, RESET, a fault, an
	 * emergency stop): the squaring was abandoned with the homing */
	if (fw->cycle != g->sq_cycle + 1u) {
		abandon(fw, a, b);
		return;
	}
	g->sq_cycle = fw->cycle;
	xa = &fw->ax[a];
	xb = &fw->ax[b];
	if (g->squaring == GANTRY_SQ_HOMING && creep_check(fw, a, b))
		return;
	if (xa->home != HOME_NONE || xb->home != HOME_NONE)
		return;		/* still on the way to the references */
	if (!(xa->state & xb->state & SH2000_AXIS_HOMED)) {
		abandon(fw, a, b);	/* aborted */
		return;
	}
	if (g->squaring == GANTRY_SQ_HOMING) {
		/* as a homing's preset: with tables the corrected set-point
		 * moves by gantry_square, not the nominal one */
		sh2000_home_preset(fw, b, g->square);
		g->squaring = GANTRY_SQ_MOVE;
	}
	fw->state = SH2000_STATE_HOMING;
	if (sh2000_home_move_to(xb, xa->cmd, fabs(xb->prm.home_vel), T)) {
		sh2000_interp_hold(&fw->ip, b, xb->cmd);
		g->squaring = GANTRY_SQ_NONE;
		fw->state = SH2000_STATE_IDLE;
	}
}
