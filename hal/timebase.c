// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * The card's clock against the servo thread's. The card consumes one
 * record per coarse period of its own clock; the thread pushes records at
 * the ticks of the PC's. The clocks differ by tens of ppm, so without
 * care the ring slowly fills or drains. The card heartbeat (+1 per servo
 * cycle) read at every tick is the phase detector; a PI filter turns the
 * phase error into a correction of a clock's period:
 *
 * - the first card (the master) corrects the servo thread itself:
 *   hal_sh2000.c hands the correction to rtapi_task_pll_set_correction()
 *   (as lcec does for EtherCAT distributed clocks and hostmot2 with its
 *   DPLL), and the clock compared with the card is the thread's ticks;
 * - a further card (a follower) cannot move the thread: the filter
 *   corrects a virtual clock instead, advanced here by 1 - correction
 *   records per tick, which then counts that card's coarse periods in the
 *   thread's time. write.c resamples the command stream on it.
 *
 * The loop is the same in both cases: the phase error integrates the
 * clock's rate error minus the correction.
 *
 * Units: records (= coarse periods = ticks when locked). The heartbeat is
 * quantised to a servo cycle, a tenth of a record at the default timing;
 * the filter's bandwidth (time constant about 300 ticks) averages that.
 */
#include <math.h>

#include "hsc.h"

/* PI gains on the phase error, in records per tick per record: a time
 * constant of some 300 ticks. Clocks drift by tens of ppm (1e-4 records
 * per tick at most), so a slow loop follows them easily and averages the
 * heartbeat's quantisation and the read's jitter. */
#define TB_KP		0.006
#define TB_KI		0.00002
/*
 * A phase reading this far from the centre of the last ones is not the
 * clock. The card's oscillator never jumps; what does is the reading:
 *
 * - behind: the card has run fewer cycles than its clock has. A real
 *   card never does, but a served card's server whose cycles wait for
 *   the CPU lags for some periods, often by the same amount for a while,
 *   and catches up (sh2000-sim beside the servo thread of linuxcnc_drift
 *   on a 2-core machine: by a millisecond or more twice a second).
 *   Such readings are skipped however well they agree with one another
 *   (taken, the card's delay would move by the lag for good: a period or
 *   more of skew against the other cards), until TB_LAG_PERSIST of them
 *   in a row say the card really lost that time (a served card stopped
 *   for over a second resumes from there);
 * - ahead: the reference was read while the card lagged, or the thread's
 *   lateness was misread. TB_SETTLE readings in a row that agree are a
 *   new phase; readings that keep moving are skipped up to TB_PERSIST.
 *
 * A tick that runs a period or more late is not read at all (below).
 */
#define TB_OUTLIER	0.3
#define TB_SETTLE	5
#define TB_PERSIST	100
#define TB_LAG_PERSIST	2500
/*
 * The reference is moved up to the first readings while they agree that
 * it is behind: a reading taken while a served card's server lagged is
 * late by the lag, and every reading after it is ahead by as much. Left
 * to the filter, which slews the clock to it over some hundreds of ticks,
 * such an error moves the card's delay by what is left of it when the
 * stream starts; moving the reference moves nothing the card plays. So
 * within the first TB_REF_READINGS, TB_SETTLE readings in a row ahead of
 * the centre by more than TB_REF_MARGIN (a cycle and a half at the
 * default timing: the heartbeat's quantum and the read's jitter) and by
 * less than TB_RELOCK move the reference by the least of them. A single
 * reading ahead (the heartbeat read late after the lateness was taken:
 * an SMI, a bus stall) moves nothing.
 */
#define TB_REF_READINGS	200
#define TB_REF_MARGIN	0.15
/* Readings the centre averages: a lag that grows by less than
 * TB_OUTLIER a reading (a server that runs slow for a while) leaves it
 * behind within a few readings. */
#define TB_CENTRE_N	16
/* rtapi_app limits a correction to 1 % of the period. */
#define TB_LIMIT	0.01
/* A phase error this large is not drift: the card restarted, or the
 * thread stalled. Start again from here. */
#define TB_RELOCK	2.0

void hsc_tb_reset(struct hsc_timebase *tb)
{
	tb->locked = 0;
	tb->integ = 0;
	tb->phase = 0;
	tb->centre = 0;
	tb->rate = 0;
	tb->correction = 0;
	tb->clock = 0;
	tb->step = 1.0;
	tb->tick_last = 0;
}

static double clamp(double v, double lim)
{
	return v > lim ? lim : v < -lim ? -lim : v;
}

void hsc_tb_advance(struct hsc_timebase *tb, uint64_t tick)
{
	uint64_t n = tick - tb->tick_last;

	tb->tick_last = tick;
	if (!tb->locked) {
		tb->step = 1.0;
		return;
	}
	/* the master's clock is the (corrected) thread: whole ticks */
	tb->step = tb->follow ? (double)n * (1.0 - tb->correction) : (double)n;
	tb->clock += tb->step;
}

/* No reading of the phase this tick: the clock runs at the rate
 * estimate alone. The last reading's proportional share is one reading's
 * noise (the heartbeat counts whole servo cycles): held over a stall's
 * skipped ticks it would move the phase by hundredths of a period for a
 * while. */
static void hold(struct hsc_timebase *tb)
{
	tb->correction = clamp(-tb->integ, TB_LIMIT);
}

/* Within the first readings: the reference moved up to readings that
 * agree it is behind (above). */
static void reference_ahead(struct hsc_timebase *tb, double *eps)
{
	double d = *eps - tb->centre;

	tb->readings++;
	if (d <= TB_REF_MARGIN || *eps >= TB_RELOCK) {
		tb->ahead_n = 0;
		return;
	}
	tb->ahead_min = tb->ahead_n ? fmin(tb->ahead_min, *eps) : *eps;
	if (++tb->ahead_n < TB_SETTLE)
		return;
	d = tb->ahead_min;
	tb->off += d;
	tb->centre -= d;
	tb->phase -= d;
	tb->skipped -= d;
	*eps -= d;
	tb->ahead_n = 0;
	tb->outliers = 0;
}

int hsc_tb_update(struct hsc_timebase *tb, uint64_t tick, uint16_t hb,
		  long late_ns, long period_ns, long servo_ns)
{
	double per_tick, x, eps, y;

	if (period_ns <= 0 || servo_ns <= 0)
		return 0;
	per_tick = (double)period_ns / (double)servo_ns;	/* cycles */
	if (!tb->locked) {
		if (late_ns >= period_ns)
			return 0;	/* not from a missed tick (below) */
		/* the reference: this tick is phase zero */
		tb->hb_ext = hb;
		tb->hb_last = hb;
		tb->hb0 = hb;
		tb->tick0 = tick;
		tb->tick_last = tick;
		tb->clock = 0;
		tb->off = -(double)late_ns / (double)period_ns;
		tb->phase = 0;
		tb->centre = 0;
		tb->readings = 0;
		tb->ahead_n = 0;
		tb->outliers = 0;
		tb->locked = 1;
		return 0;
	}
	tb->hb_ext += (uint16_t)(hb - tb->hb_last);
	tb->hb_last = hb;
	/*
	 * A tick that runs a period or more late is one the thread missed
	 * and now runs back to back: the whole machine stalled, and a served
	 * card's server with it, so its heartbeat stands where the stall
	 * began while the lateness moves on. Such readings agree with one
	 * another on a phase that is not the card's: taken as a new one (and
	 * once more when the card has caught up), the reference would keep
	 * whatever phase error the stall left, and the card's skew against
	 * the other cards would grow stall after stall. They say nothing of
	 * the clock: the rate estimate holds.
	 */
	if (late_ns >= period_ns) {
		hold(tb);
		return 0;
	}
	/* card coarse periods since the reference, at the tick's start */
	x = (double)(tb->hb_ext - tb->hb0) / per_tick -
	    (double)late_ns / (double)period_ns - tb->off;
	eps = x - tb->clock;
	if (tb->readings < TB_REF_READINGS)
		reference_ahead(tb, &eps);
	/*
	 * A transient is skipped before it is judged: a new reference taken
	 * in the middle of one would move the thread's phase against card 0
	 * once the card caught up, and with it the delay of every point card
	 * 0 plays (its skew against the other cards).
	 */
	if (fabs(eps - tb->centre) > TB_OUTLIER) {
		int behind = eps < tb->centre;

		/* a run of skipped readings is on one side */
		if (tb->outliers && tb->outlier_side != (behind ? -1 : 1))
			tb->outliers = 0;
		tb->outlier_side = behind ? -1 : 1;
		/* readings that move (a card catching up) never settle */
		tb->settled = !behind && tb->outliers &&
			      fabs(eps - tb->skipped) <= TB_OUTLIER ?
			      tb->settled + 1 : !behind;
		tb->skipped = eps;
		if (++tb->outliers <= (behind ? TB_LAG_PERSIST : TB_PERSIST) &&
		    tb->settled < TB_SETTLE) {
			hold(tb);
			return 0;
		}
		tb->centre = eps;	/* a new phase */
	}
	tb->outliers = 0;
	if (fabs(eps) > TB_RELOCK) {
		/* the rate estimate (integ) stays: only the phase jumped */
		tb->locked = 0;
		hsc_tb_update(tb, tick, hb, late_ns, period_ns, servo_ns);
		tb->step = 1.0;
		return 1;
	}
	tb->phase = eps;
	tb->centre += (eps - tb->centre) / TB_CENTRE_N;
	tb->integ = clamp(tb->integ + TB_KI * eps, TB_LIMIT);
	y = TB_KP * eps + tb->integ;
	tb->rate = tb->integ;
	/* a card ahead (eps > 0) needs shorter ticks (a faster clock) */
	tb->correction = clamp(-y, TB_LIMIT);
	return 0;
}
