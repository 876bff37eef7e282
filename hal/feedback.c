// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * Feedback aligned with the command's delay.
 *
 * LinuxCNC's following error is motor-pos-cmd (what it sent a tick ago)
 * minus motor-pos-fb. The card plays a command only after the ring and
 * its B-spline window, several coarse periods later, so the raw encoder
 * lags the command by velocity x delay (1.66 mm at 200 mm/s for 8 ms) and
 * LinuxCNC would trip on a card tracking to 0.1 um.
 *
 * The driver measures that delay D: the card's set-point in a status
 * snapshot equals the command history at time t_snap - D. With D known,
 *
 *     position-fb = encoder + command(now) - command(t_snap - D)
 *
 * shifts the encoder forward by what the command did during the delay,
 * and LinuxCNC's following error becomes command(t_snap - D) - encoder:
 * the card's own tracking error, as long as the card plays what was sent.
 * If it does not (a lost record, a card that stopped on its own), the
 * difference shows in LinuxCNC's following error too.
 *
 * Time is the card's, in coarse periods: commands by the stream's record
 * (the card plays one per period of its clock; write.c), the snapshot by
 * the card's servo cycle (hsc_snap_time). D is measured by matching the
 * set-point against the records while the command moves steadily (where
 * the match is unambiguous and the B-spline's smoothing of accelerations
 * does not bias it), and filtered: while the card plays the stream
 * without a gap it is constant, whatever the card's clock does against
 * the PC's. So a measurement far from it is an outlier, not a change:
 * what does move the card's timeline (a gap, a jump of its clock) voids
 * the delay instead. One such outlier, taken while the card played a
 * homing's stop at the index mark, moved D by 0.14 periods and LinuxCNC
 * tripped on the following error of the move to HOME (0.14 ms x 100
 * mm/s is 14 um, the sample's limit there 15 um).
 */
#include <math.h>
#include <string.h>

#include "hsc.h"

/* Below this speed (counts per tick, all axes) a match is ambiguous. */
#define FB_MIN_SPEED		20.0
/* Relative change of speed across the match allowed (steady motion). */
#define FB_MAX_ACCEL		0.002
/* Filter of the measured delay. */
#define FB_GAIN			0.1
/* A measurement this far (periods) from a valid delay is an outlier ... */
#define FB_OUTLIER		0.05
/* ... unless this many in a row, of distinct snapshots, agree. */
#define FB_OUTLIER_RUN		10
/* The largest Newton step (periods) from a valid delay's guess. */
#define FB_MAX_STEP		0.25

/* The stream's command at fractional record u (linear between records),
 * its velocity there (counts per record) and, if t is not NULL, the
 * thread time (ticks) of that command; 0, or -1 when u is outside the
 * history. */
static int history_at(const struct hsc_card *c, double u,
		      double pos[SH2000_AXES], double vel[SH2000_AXES],
		      double *t)
{
	uint64_t kept = c->rec_n < HSC_HISTORY ? c->rec_n : HSC_HISTORY;
	double fl = floor(u), f = u - fl;
	unsigned int a, i0, i1;

	if (!c->rec_n || fl < (double)(c->rec_n - kept) ||
	    fl + 2 > (double)c->rec_n)
		return -1;
	i0 = (unsigned int)((uint64_t)fl % HSC_HISTORY);
	i1 = (i0 + 1) % HSC_HISTORY;
	for (a = 0; a < SH2000_AXES; a++) {
		double p0 = c->rec[i0][a];
		double p1 = c->rec[i1][a];

		pos[a] = p0 + f * (p1 - p0);
		vel[a] = p1 - p0;
	}
	if (t)
		*t = c->rec_t[i0] + f * (c->rec_t[i1] - c->rec_t[i0]);
	return 0;
}

/* The card's servo cycles per coarse period as the driver set them (10
 * until it has). */
double hsc_period_cycles(const struct hsc_card *c)
{
	return c->servo_ns > 0 ? (double)c->period_ns / (double)c->servo_ns :
	       10.0;
}

/*
 * Time of the snapshot in the card's own time, in coarse periods: its
 * servo cycle over the cycles per period. The card plays one record per
 * coarse period of its clock, so in this time base the delay from a
 * command to its playing is constant as long as the card runs the stream
 * without a gap, whatever the servo thread's lateness or the PC's clock.
 */
double hsc_snap_time(const struct hsc_card *c)
{
	return (double)c->st.card_cycle / hsc_period_cycles(c);
}

/*
 * For the delay-ms pin only: the PC's time of the snapshot (the read's
 * time less the snapshot's age; HEARTBEAT counts the same servo cycles as
 * SNAP_TIME) minus its card time, filtered: with it the snapshot's card
 * time becomes the thread's time a person measures.
 */
void hsc_clock_offset(struct hsc_card *c, long late_ns)
{
	/* the heartbeat is read before the snapshot, which may be a cycle
	 * newer: no age then */
	int16_t age = (int16_t)(c->st.heartbeat - (uint16_t)c->st.card_cycle);
	double per = c->period_ns > 0 ? (double)c->period_ns : 1e6;
	double host = (double)c->tick + (double)late_ns / per -
		      (double)(age > 0 ? age : 0) * (double)c->servo_ns / per;
	double off = host - c->snap_t;

	if (!c->clock_off_valid || fabs(off - c->clock_off) > 2.0)
		c->clock_off = off;
	else
		c->clock_off += 0.01 * (off - c->clock_off);
	c->clock_off_valid = 1;
}

/*
 * The motion steady over every record the card's set-point at record u
 * depends on: its B-spline window, records floor(u) - 1 .. floor(u) + 2.
 * A match across a record where the command stops or turns is biased by
 * the spline's smoothing there (some 30 counts off the records' corner
 * at a homing's stop), which the Newton step divides by the speed.
 */
static int steady_at(const struct hsc_card *c, double u, double speed)
{
	double p[3][SH2000_AXES], v[3][SH2000_AXES];
	unsigned int a, i;

	for (i = 0; i < 3; i++)
		if (history_at(c, u - 1.0 + i, p[i], v[i], NULL) < 0)
			return 0;
	for (a = 0; a < SH2000_AXES; a++)
		for (i = 1; i < 3; i++)
			if (fabs(v[i][a] - v[0][a]) > FB_MAX_ACCEL * speed + 1.0)
				return 0;
	return 1;
}

/* A measured delay d into the filter: outliers only as a run that agrees
 * (FB_OUTLIER_RUN), the first of a void delay at once. */
static void delay_take(struct hsc_card *c, double d)
{
	c->delay_n++;
	if (!c->delay_valid) {
		c->delay = d;
		c->delay_valid = 1;
		c->delay_out_n = 0;
		return;
	}
	if (fabs(d - c->delay) <= FB_OUTLIER) {
		c->delay += FB_GAIN * (d - c->delay);
		c->delay_out_n = 0;
		return;
	}
	if (c->delay_out_n && fabs(d - c->delay_out) <= FB_OUTLIER) {
		c->delay_out_n++;
	} else {
		c->delay_out = d;
		c->delay_out_n = 1;
	}
	if (c->delay_out_n >= FB_OUTLIER_RUN) {
		c->delay = d;
		c->delay_out_n = 0;
	}
}

/* One fresh snapshot: measure the delay where the motion allows. */
void hsc_delay_update(struct hsc_card *c)
{
	double pos[SH2000_AXES], vel[SH2000_AXES], v2 = 0, dot = 0;
	double t, u;
	unsigned int a, en = hsc_enabled(&c->st);

	if (!c->streaming || !en)
		return;
	/* once per snapshot: the card's status comes a little slower than
	 * the ticks, and a card that lags leaves one in place for several;
	 * each read of it again would count its measurement again */
	if (c->delay_cycle_seen && c->delay_cycle == c->st.card_cycle)
		return;
	c->delay_cycle = c->st.card_cycle;
	c->delay_cycle_seen = 1;
	t = c->snap_t;
	/* first guess: the card plays the record pushed fill + 2 records
	 * before the newest (the ring, then the B-spline window) */
	u = c->delay_valid ? t - c->delay :
	    (double)c->rec_n - 1.0 - (double)c->st.queue_fill - 2.0;
	if (history_at(c, u, pos, vel, NULL) < 0)
		return;
	for (a = 0; a < SH2000_AXES; a++) {
		if (!(en & (1u << a)))
			continue;
		v2 += vel[a] * vel[a];
		dot += vel[a] * ((double)c->st.axis[a].cmd_counts - pos[a]);
	}
	if (v2 < FB_MIN_SPEED * FB_MIN_SPEED || !steady_at(c, u, sqrt(v2)))
		return;
	/* one Newton step along the motion, then steady there too */
	if (c->delay_valid && fabs(dot / v2) > FB_MAX_STEP)
		return;
	u += dot / v2;
	if (!steady_at(c, u, sqrt(v2)))
		return;
	delay_take(c, t - u);
}

/* position-fb of axis a in counts. */
double hsc_feedback_counts(const struct hsc_card *c, unsigned int a)
{
	const struct sh2000_axis_status *ax = &c->st.axis[a];
	double pos[SH2000_AXES], vel[SH2000_AXES];

	if (!c->streaming || !c->have_cmd)
		return (double)ax->pos_counts;
	if (c->delay_valid &&
	    history_at(c, c->snap_t - c->delay, pos, vel, NULL) == 0)
		return (double)ax->pos_counts + (double)c->last_cmd[a] - pos[a];
	/* no delay measured yet: the set-point is the delayed command */
	return (double)ax->pos_counts + (double)c->last_cmd[a] -
	       (double)ax->cmd_counts;
}

/* The delay from a command to the card's set-point in the thread's time,
 * ms (the delay-ms pin); 0 while unknown. */
double hsc_delay_ms(const struct hsc_card *c)
{
	double pos[SH2000_AXES], vel[SH2000_AXES], t;

	if (!c->delay_valid || !c->clock_off_valid ||
	    history_at(c, c->snap_t - c->delay, pos, vel, &t) < 0)
		return 0;
	return (c->snap_t + c->clock_off - t) * (double)c->period_ns * 1e-6;
}
