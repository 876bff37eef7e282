// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * hal_sh2000's logic (hal/hsc.h) without LinuxCNC: a loop that plays
 * LinuxCNC's servo thread (read, compute the joint's following error as
 * motion does, new command, write) against the card model in virtual time
 * (`sim`), one 1 ms tick after the other. Checks the enable/stream/disable
 * sequence, that LinuxCNC's following error equals the card's own within
 * 1 um on a 200 mm/s move, the fill of the ring, the emergency stop both
 * ways, a jam as an amplifier fault, an underrun, a STOP from another
 * program and the reset that clears them; a stall of the whole machine
 * that the card catches up, and a slip it does not; and two cards whose
 * clocks are off by +-100 ppm in one thread (each ring's fill, the skew
 * between their set-points), alone and with the whole machine stalled
 * every second.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "hsc.h"
#include "sh2000/sim.h"

#define PERIOD_NS	1000000L

struct rig {
	struct hsc_card c;
	struct hsc_in in;
	struct hsc_out out;
	uint64_t t_next;
	double prev_cmd[SH2000_AXES];
	double lc_ferror[SH2000_AXES];	/* LinuxCNC's: cmd - fb */
};

static struct rig *rig_open(void)
{
	struct rig *r = calloc(1, sizeof(*r));
	char msg[256];
	unsigned int a;

	assert_non_null(r);
	if (hsc_open(&r->c, 0, "sim", msg, sizeof(msg)) < 0)
		fail_msg("hsc_open: %s", msg);
	for (a = 0; a < SH2000_AXES; a++)
		r->in.axis[a].position_scale = hsc_default_scale(&r->c, a);
	r->t_next = sh2000_now_ns(r->c.h);
	return r;
}

static void rig_close(struct rig *r)
{
	hsc_close(&r->c);
	free(r);
}

/* One servo period: read, LinuxCNC's motion (its following error against
 * the command of the last tick, then the new command), write. */
static void tick(struct rig *r, const double *cmd)
{
	uint64_t now = sh2000_now_ns(r->c.h);
	unsigned int a;

	if (now < r->t_next)
		sh2000_sleep_ns(r->c.h, r->t_next - now);
	now = sh2000_now_ns(r->c.h);
	hsc_read(&r->c, &r->in, &r->out, PERIOD_NS, (long)(now - r->t_next));
	r->t_next += PERIOD_NS;
	for (a = 0; a < SH2000_AXES; a++) {
		r->lc_ferror[a] = r->prev_cmd[a] - r->out.axis[a].position_fb;
		if (cmd)
			r->in.axis[a].position_cmd = cmd[a];
		r->prev_cmd[a] = r->in.axis[a].position_cmd;
	}
	hsc_write(&r->c, &r->in, &r->out);
}

static void ticks(struct rig *r, int n)
{
	while (n-- > 0)
		tick(r, NULL);
}

/* Enable axes `mask` as LinuxCNC does (command = feedback first) and
 * wait until the driver streams. */
static void machine_on(struct rig *r, unsigned int mask)
{
	unsigned int a;
	int n;

	for (a = 0; a < SH2000_AXES; a++) {
		r->in.axis[a].position_cmd = r->out.axis[a].position_fb;
		r->in.axis[a].enable = !!(mask & (1u << a));
	}
	for (n = 0; n < 50 && !r->c.streaming; n++)
		ticks(r, 1);
	if (!r->c.streaming)
		fail_msg("not streaming after 50 ticks: %s", r->c.err);
	assert_true(r->out.ok);
}

/* A LinuxCNC G0 on one axis: trapezoid at vmax, amax, sampled per tick. */
static double move(struct rig *r, unsigned int axis, double to, double vmax,
		   double amax, double *worst_diff)
{
	double cmd[SH2000_AXES], x0, dist, dir, t, T = PERIOD_NS * 1e-9;
	double ta, tc, total, worst = 0;
	unsigned int a;
	int k, n;

	for (a = 0; a < SH2000_AXES; a++)
		cmd[a] = r->in.axis[a].position_cmd;
	x0 = cmd[axis];
	dist = fabs(to - x0);
	dir = to > x0 ? 1 : -1;
	ta = vmax / amax;
	if (amax * ta * ta > dist)
		ta = sqrt(dist / amax);
	tc = dist / (amax * ta) - ta;
	total = 2 * ta + tc;
	n = (int)ceil(total / T);
	for (k = 1; k <= n + 40; k++) {
		double s;

		t = k * T;
		if (t >= total)
			s = dist;
		else if (t < ta)
			s = 0.5 * amax * t * t;
		else if (t < ta + tc)
			s = 0.5 * amax * ta * ta + amax * ta * (t - ta);
		else
			s = dist - 0.5 * amax * (total - t) * (total - t);
		cmd[axis] = x0 + dir * s;
		tick(r, cmd);
		assert_true(r->out.ok);
		/* LinuxCNC's following error is the card's own */
		if (r->c.delay_valid && r->c.st_fresh) {
			double d = fabs(r->lc_ferror[axis] -
					r->out.axis[axis].f_error);

			if (d > worst)
				worst = d;
		}
	}
	if (worst_diff)
		*worst_diff = worst;
	return total;
}

static void test_stream_and_feedback(void **state)
{
	struct rig *r = rig_open();
	double worst, total;
	int32_t fill_min = 1000, fill_max = -1;
	uint64_t cycles = 0;
	int k;

	(void)state;
	ticks(r, 5);
	assert_true(r->out.ok);
	assert_int_equal(r->out.card_state, SH2000_STATE_IDLE);
	machine_on(r, 0x7);
	ticks(r, 20);
	assert_int_equal(r->out.card_state, SH2000_STATE_RUNNING);
	/* a G0 at 200 mm/s, 2 m/s^2: LinuxCNC sees the card's error */
	total = move(r, 0, 100.0, 200.0, 2000.0, &worst);
	print_message("G0 0 -> 100 mm at 200 mm/s (%.3f s): |LinuxCNC f-error - card f-error| <= %.3f um, command to set-point %.2f ms\n",
		      total, worst * 1000.0, r->out.delay_ms);
	assert_true(r->c.delay_valid);
	/* the queue (4 records), the B-spline window (2) and the phase */
	assert_true(r->out.delay_ms > 4.0 && r->out.delay_ms < 8.0);
	assert_true(worst < 0.001);
	/* standing still, streaming: the fill stays at the target */
	for (k = 0; k < 500; k++) {
		tick(r, NULL);
		cycles += r->out.port_cycles;
		if (!r->c.st_fresh)
			continue;
		if (r->out.queue_fill < fill_min)
			fill_min = r->out.queue_fill;
		if (r->out.queue_fill > fill_max)
			fill_max = r->out.queue_fill;
	}
	print_message("fill %d..%d (target %d), port cycles per tick (read + one point) %.1f on average\n",
		      fill_min, fill_max, HSC_QUEUE_TARGET, cycles / 500.0);
	/* the budget: one tick on the simulated card (poll + one point
	 * posted in the mailbox) within 150 port cycles */
	assert_true(cycles <= 150 * 500);
	assert_true(fill_min >= HSC_QUEUE_TARGET - 2);
	assert_true(fill_max <= HSC_QUEUE_TARGET + 2);
	assert_true(fabs(r->out.axis[0].encoder_position - 100.0) < 0.001);
	assert_int_equal(r->out.underruns, 0);
	/* machine off: the motion ends where the command is, axes disable */
	r->in.axis[0].enable = r->in.axis[1].enable = r->in.axis[2].enable = 0;
	ticks(r, 30);
	assert_false(r->c.streaming);
	assert_int_equal(r->out.card_state, SH2000_STATE_IDLE);
	assert_int_equal(hsc_enabled(&r->c.st), 0);
	assert_true(r->out.ok);
	rig_close(r);
}

static void test_estop_both_ways(void **state)
{
	struct rig *r = rig_open();

	(void)state;
	machine_on(r, 0x1);
	/* from LinuxCNC: the estop pin */
	r->in.estop = 1;
	ticks(r, 3);
	assert_int_equal(r->out.card_state, SH2000_STATE_ESTOP);
	assert_false(r->out.ok);
	assert_true(r->out.fault);
	r->in.axis[0].enable = 0;
	/* no reset while the estop input holds */
	r->in.fault_reset = 1;
	ticks(r, 5);
	assert_int_equal(r->out.card_state, SH2000_STATE_ESTOP);
	r->in.fault_reset = 0;
	r->in.estop = 0;
	ticks(r, 2);
	r->in.fault_reset = 1;
	ticks(r, 10);
	r->in.fault_reset = 0;
	assert_int_equal(r->out.card_state, SH2000_STATE_IDLE);
	assert_true(r->out.ok);
	/* from the card (another program's emergency stop) */
	machine_on(r, 0x1);
	assert_int_equal(sh2000_estop(r->c.h, 10), 0);
	ticks(r, 2);
	assert_false(r->out.ok);
	assert_false(r->c.streaming);
	rig_close(r);
}

static void test_jam_is_amp_fault(void **state)
{
	struct rig *r = rig_open();
	double cmd[SH2000_AXES] = { 0 };
	int k;

	(void)state;
	machine_on(r, 0x3);
	assert_int_equal(sh2000_sim_inject(r->c.h, SH2000_INJECT_JAM, 1, 0), 0);
	memcpy(cmd, r->prev_cmd, sizeof(cmd));
	for (k = 0; k < 300 && r->out.ok; k++) {
		cmd[1] += 0.05;	/* 50 mm/s */
		tick(r, cmd);
	}
	assert_false(r->out.ok);
	assert_true(r->out.axis[1].amp_fault);
	assert_false(r->out.axis[0].amp_fault);
	rig_close(r);
}

static void test_underrun(void **state)
{
	struct rig *r = rig_open();

	(void)state;
	machine_on(r, 0x1);
	ticks(r, 10);
	/* the servo thread stalls for 20 ms */
	sh2000_sleep_ns(r->c.h, 20 * PERIOD_NS);
	r->t_next = sh2000_now_ns(r->c.h);
	ticks(r, 3);
	assert_int_equal(r->out.underruns, 1);
	assert_false(r->out.ok);
	assert_false(r->c.streaming);
	r->in.axis[0].enable = 0;
	r->in.fault_reset = 1;
	ticks(r, 10);
	assert_true(r->out.ok);
	assert_int_equal(r->out.underruns, 1);
	rig_close(r);
}

static void test_stopped_by_another_program(void **state)
{
	struct rig *r = rig_open();

	(void)state;
	machine_on(r, 0x1);
	ticks(r, 5);
	assert_int_equal(sh2000_stop(r->c.h), 0);
	ticks(r, 5);
	assert_false(r->out.ok);
	assert_int_equal(r->c.sfault, HSC_SF_STOPPED);
	assert_non_null(strstr(r->c.err, "another program"));
	r->in.axis[0].enable = 0;
	r->in.fault_reset = 1;
	ticks(r, 5);
	assert_true(r->out.ok);
	rig_close(r);
}

/* ---- a stall of the whole machine ---- */

/* One tick of x moving at v mm/s, the thread `late_periods` late,
 * `advance` card periods passing before it (on the rig's schedule: the
 * card's virtual time runs in whole status periods). */
static void stall_tick(struct rig *r, double *cmd, double v, int late_periods,
		       int advance)
{
	unsigned int a;
	uint64_t now;

	r->t_next += (uint64_t)advance * PERIOD_NS;
	now = sh2000_now_ns(r->c.h);
	if (now < r->t_next)
		sh2000_sleep_ns(r->c.h, r->t_next - now);
	cmd[0] += v * PERIOD_NS * 1e-9;
	hsc_read(&r->c, &r->in, &r->out, PERIOD_NS,
		 (long)late_periods * PERIOD_NS);
	for (a = 0; a < SH2000_AXES; a++)
		r->in.axis[a].position_cmd = cmd[a];
	hsc_write(&r->c, &r->in, &r->out);
	if (!r->out.ok)
		fail_msg("%s (fill %u)", r->c.err, r->c.st.queue_fill);
}

/*
 * The machine stalls for n ticks with the card on it (a served card, or a
 * virtual machine descheduled). Afterwards the thread runs the n ticks it
 * missed back to back, late by n..1 periods, before the card has moved on
 * (no card time passes); then the card catches up its n periods at a
 * served card's pace, two periods a tick, while the thread is on time.
 * x moves at v mm/s throughout. Returns the largest |card f-error| in mm
 * from the stall to 500 ticks after it.
 */
static double stall_in_motion(struct rig *r, int n, double v)
{
	double cmd[SH2000_AXES] = { 0 }, worst = 0;
	unsigned int a;
	int k, behind = n;

	for (a = 0; a < SH2000_AXES; a++)
		cmd[a] = r->in.axis[a].position_cmd;
	for (k = 0; k < n; k++)
		stall_tick(r, cmd, v, n - k, 0);
	while (behind > 0) {
		int step = behind < 1 ? behind : 1;

		stall_tick(r, cmd, v, 0, step + 1);
		behind -= step;
		worst = fmax(worst, fabs(r->out.axis[0].f_error));
	}
	r->t_next += PERIOD_NS;
	for (k = 0; k < 500; k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
		assert_true(r->out.ok);
		worst = fmax(worst, fabs(r->out.axis[0].f_error));
	}
	return worst;
}

/* A rig streaming x at v mm/s for 400 ticks (the delay measured), queue
 * target 20 as the sample machine's; cmd holds the last command. */
static struct rig *moving_rig(double v, double cmd[SH2000_AXES])
{
	struct rig *r = rig_open();
	unsigned int a;
	int k;

	r->in.queue_target = 20;
	machine_on(r, 0x1);
	for (a = 0; a < SH2000_AXES; a++)
		cmd[a] = r->in.axis[a].position_cmd;
	for (k = 0; k < 400; k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
	}
	return r;
}

/* A stall the card catches up moves neither the card's timeline (the
 * delay from a command to its set-point, the fill) nor its set-point (no
 * record dropped: no jump of a period's motion), with the ring deep
 * enough to take the thread's catch-up (40 ticks) or not (70: records
 * wait for room and still hold the command of their own tick). */
static void test_stall_caught_up(void **state)
{
	static const int stalls[] = { 40, 70 };
	double v = 100.0, cmd[SH2000_AXES] = { 0 }, before, worst;
	unsigned int fill;
	size_t i;

	(void)state;
	for (i = 0; i < sizeof(stalls) / sizeof(stalls[0]); i++) {
		struct rig *r = moving_rig(v, cmd);

		assert_true(r->c.delay_valid);
		before = r->c.delay;
		fill = r->c.st.queue_fill;
		worst = stall_in_motion(r, stalls[i], v);
		print_message("stall of %d ticks at %.0f mm/s: delay %.3f -> %.3f periods, fill %u -> %u, card f-error up to %.3f um\n",
			      stalls[i], v, before, r->c.delay, fill,
			      r->c.st.queue_fill, worst * 1e3);
		assert_true(r->c.delay_valid);
		assert_true(fabs(r->c.delay - before) < 0.2);
		assert_true(abs((int)r->c.st.queue_fill - (int)fill) <= 1);
		/* a dropped record is a step of 100 um in the set-point */
		assert_true(worst < 0.005);
		assert_int_equal(r->out.underruns, 0);
		rig_close(r);
	}
}

/*
 * A homing's turn at the index mark: the search at -1 mm/s stops within
 * a tick (at ten phases of it, so the record across the stop is 5 to 95
 * counts) and LinuxCNC moves 5 mm back to HOME at once. The card plays
 * the stop and the turn while the driver measures its delay: the delay
 * must not move (the card plays without a gap), so LinuxCNC's following
 * error in the move stays the card's own. A match across the stop, whose
 * set-point the B-spline smooths some 30 counts off the records, once
 * moved the delay by 0.14 periods, and LinuxCNC tripped at 15 um.
 */
static void test_delay_through_turn(void **state)
{
	double cmd[SH2000_AXES] = { 0 }, T = PERIOD_NS * 1e-9, before, worst;
	double most = 0, worst_all = 0;
	int k;

	(void)state;
	for (k = 0; k < 10; k++) {
		struct rig *r = moving_rig(-1.0, cmd);

		assert_true(r->c.delay_valid);
		before = r->c.delay;
		cmd[0] -= 1.0 * T * (k + 0.5) / 10.0;
		tick(r, cmd);
		ticks(r, 2);
		move(r, 0, cmd[0] + 5.0, 100.0, 1000.0, &worst);
		assert_true(r->c.delay_valid);
		most = fmax(most, fabs(r->c.delay - before));
		worst_all = fmax(worst_all, worst);
		rig_close(r);
	}
	print_message("a homing's turn at ten phases of a tick: the delay moved by at most %.4f periods, LinuxCNC's following error at most %.3f um off the card's\n",
		      most, worst_all * 1e3);
	assert_true(most < 0.005);
	assert_true(worst_all < 0.001);
}

/* A card that loses 40 periods for good (a served card further behind
 * than it catches up): after HSC_SLIP_TICKS the stream catches the card
 * up (HSC_SLIP_RATE faster), without a step the card would refuse, and
 * the fill is back at the target. */
static void test_slip_recentred(void **state)
{
	double cmd[SH2000_AXES] = { 0 }, v = 100.0;
	struct rig *r = moving_rig(v, cmd);
	unsigned int fill, most = 0;
	int k;

	(void)state;
	fill = r->c.st.queue_fill;
	for (k = 0; k < 40; k++)
		stall_tick(r, cmd, v, 40 - k, 0);
	r->t_next = sh2000_now_ns(r->c.h) + PERIOD_NS;
	for (k = 0; k < HSC_SLIP_TICKS + (int)(60 / HSC_SLIP_RATE); k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
		if (!r->out.ok)
			fail_msg("tick %d: %s (fill %u)", k, r->c.err,
				 r->c.st.queue_fill);
		if (r->c.st.queue_fill > most)
			most = r->c.st.queue_fill;
	}
	print_message("a slip of 40 periods: fill %u, up to %u, then %u\n",
		      fill, most, r->c.st.queue_fill);
	assert_true(most >= fill + 30);
	assert_true(abs((int)r->c.st.queue_fill - (int)fill) <= 1);
	assert_int_equal(r->out.underruns, 0);
	rig_close(r);
}

/* The thread skips four ticks and never runs them (nothing owes the card
 * the records it played meanwhile): the stream is four records short for
 * good, which no stall rule restores. The low side of the re-centring
 * fills them back gradually, and the card's delay is what it was. */
static void test_lost_refilled(void **state)
{
	double cmd[SH2000_AXES] = { 0 }, v = 100.0, delay;
	struct rig *r = moving_rig(v, cmd);
	unsigned int fill, low = 1000, fill_end;
	int k;

	(void)state;
	for (k = 0; k < 50; k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
	}
	fill = r->c.st.queue_fill;
	delay = r->out.delay_ms;
	r->t_next += 4 * PERIOD_NS;	/* LinuxCNC's time skips nothing */
	for (k = 0; k < 3 * HSC_SLIP_TICKS + (int)(4 / HSC_SLIP_RATE); k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
		if (!r->out.ok)
			fail_msg("tick %d: %s (fill %u)", k, r->c.err,
				 r->c.st.queue_fill);
		if (k > 5 && k < HSC_SLIP_TICKS && r->c.st.queue_fill < low)
			low = r->c.st.queue_fill;
	}
	fill_end = r->c.st.queue_fill;
	print_message("four records lost: fill %u, then %u, at the end %u; delay %.3f ms, then %.3f ms\n",
		      fill, low, fill_end, delay, r->out.delay_ms);
	assert_true(low + 3 <= fill);
	assert_true(abs((int)fill_end - (int)fill) <= 1);
	assert_true(fabs(r->out.delay_ms - delay) < 0.5);
	assert_int_equal(r->out.underruns, 0);
	rig_close(r);
}

/* queue-target raised while the stream runs (the stage test's 30 to 40):
 * the stream fills to the new target at once, and the readings taken
 * for the old one are no reason to add more: the fill stays at it. */
static void test_target_raised(void **state)
{
	double cmd[SH2000_AXES] = { 0 }, v = 100.0;
	struct rig *r = moving_rig(v, cmd);
	unsigned int high = 0, fill;
	int k;

	(void)state;
	for (k = 0; k < HSC_SLIP_TICKS / 2; k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
	}
	fill = r->c.st.queue_fill;
	r->in.queue_target += 10;
	for (k = 0; k < 4 * HSC_SLIP_TICKS; k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
		if (!r->out.ok)
			fail_msg("tick %d: %s (fill %u)", k, r->c.err,
				 r->c.st.queue_fill);
		if (r->c.st.queue_fill > high)
			high = r->c.st.queue_fill;
	}
	print_message("queue-target %d to %d: fill %u, at most %u, at the end %u\n",
		      r->in.queue_target - 10, r->in.queue_target, fill, high,
		      r->c.st.queue_fill);
	assert_true(high <= (unsigned int)r->in.queue_target + 2);
	assert_true(abs((int)r->c.st.queue_fill - r->in.queue_target) <= 2);
	/* and back down, still moving: no record skipped ahead either */
	r->in.queue_target -= 10;
	for (k = 0; k < 4 * HSC_SLIP_TICKS; k++) {
		cmd[0] += v * PERIOD_NS * 1e-9;
		tick(r, cmd);
		if (!r->out.ok)
			fail_msg("down, tick %d: %s (fill %u)", k, r->c.err,
				 r->c.st.queue_fill);
	}
	print_message("and back to %d: fill %u\n", r->in.queue_target,
		      r->c.st.queue_fill);
	assert_true(abs((int)r->c.st.queue_fill - r->in.queue_target) <= 2);
	assert_int_equal(r->out.underruns, 0);
	rig_close(r);
}

/* ---- two cards on their own clocks (the drift test) ---- */

#define DRIFT_PPM	100.0
#define DRIFT_TARGET	10
#define OBS_RING	64u

/* A card's fine set-point of axis x at every servo cycle, in host time
 * (the card model's: a period lasts nominal * (1 + ppm * 1e-6)). */
struct obs {
	double scale;		/* host ns per card ns */
	double t[OBS_RING], x[OBS_RING];
	unsigned int n;
};

static void observe(void *ctx, const struct sh2000_probe *p)
{
	struct obs *o = ctx;

	o->t[o->n % OBS_RING] = (double)p->time_ns * o->scale;
	o->x[o->n % OBS_RING] = p->axis[0].fine_cmd;
	o->n++;
}

/* Card 0's set-point at host time t and its velocity (counts per ns);
 * 0, or -1 when t is not inside the cycles kept. */
static int obs_at(const struct obs *o, double t, double *x, double *v)
{
	unsigned int i;

	for (i = 1; i < OBS_RING && i < o->n; i++) {
		unsigned int k1 = (o->n - i) % OBS_RING;
		unsigned int k0 = (o->n - i - 1) % OBS_RING;

		if (o->t[k0] <= t && t <= o->t[k1]) {
			double dt = o->t[k1] - o->t[k0];

			*v = (o->x[k1] - o->x[k0]) / dt;
			*x = o->x[k0] + (t - o->t[k0]) * *v;
			return 0;
		}
	}
	return -1;
}

struct drift {
	struct rig *r[2];
	struct obs o[2];
	uint64_t t_next;
	long correction_ns;
	int ticks;		/* drift_tick()s run */
	/* card 1's server lag_ns behind the thread for its first
	 * lag_ticks (0: none) */
	uint64_t lag_ns;
	int lag_ticks;
	int enable_at;		/* ticks the axes wait to be enabled */
};

/* One period of a thread running both cards, slaved to card 0's clock as
 * rtapi_task_pll_set_correction() slaves it. The cards' times only
 * advance on their own port cycles: both are brought to the tick. */
static void drift_tick(struct drift *d, double cmd_mm)
{
	int i;

	for (i = 0; i < 2; i++) {
		struct hsc_card *c = &d->r[i]->c;
		uint64_t now = sh2000_now_ns(c->h), at = d->t_next;

		if (i == 1 && d->ticks < d->lag_ticks)	/* its server lags */
			at = at > d->lag_ns ? at - d->lag_ns : 0;
		if (now < at)
			sh2000_sleep_ns(c->h, at - now);
		now = sh2000_now_ns(c->h);
		hsc_read(c, &d->r[i]->in, &d->r[i]->out, PERIOD_NS,
			 (long)(now - at));
	}
	for (i = 0; i < 2; i++) {
		d->r[i]->in.axis[0].position_cmd = cmd_mm;
		hsc_write(&d->r[i]->c, &d->r[i]->in, &d->r[i]->out);
	}
	d->correction_ns = d->r[0]->out.pll_correction_ns;
	d->t_next += (uint64_t)(PERIOD_NS + d->correction_ns);
	d->ticks++;
}

/* Two cards at ppm[0] and ppm[1] in one thread, queue target `target`,
 * both enabled where they stand (the same place) and streaming; returns
 * that place (mm). */
static double drift_open(struct drift *d, const double ppm[2], int target)
{
	double x_0;
	int i, k;

	for (i = 0; i < 2; i++) {
		char msg[256];

		d->r[i] = calloc(1, sizeof(*d->r[i]));
		assert_non_null(d->r[i]);
		if (hsc_open(&d->r[i]->c, i, "sim", msg, sizeof(msg)) < 0)
			fail_msg("hsc_open: %s", msg);
		assert_int_equal(sh2000_sim_set_clock_ppm(d->r[i]->c.h, ppm[i]), 0);
		d->o[i].scale = 1.0 + ppm[i] * 1e-6;
		assert_int_equal(sh2000_sim_set_observer(d->r[i]->c.h, observe,
							 &d->o[i]), 0);
		d->r[i]->in.axis[0].position_scale =
			hsc_default_scale(&d->r[i]->c, 0);
		d->r[i]->in.queue_target = target;
	}
	assert_int_equal(d->r[0]->c.master, 1);
	assert_int_equal(d->r[1]->c.master, 0);
	for (i = 0; i < 2; i++) {
		uint64_t now = sh2000_now_ns(d->r[i]->c.h);

		if (now > d->t_next)
			d->t_next = now;
	}
	drift_tick(d, 0.0);
	x_0 = d->r[0]->out.axis[0].position_fb;
	assert_true(fabs(d->r[1]->out.axis[0].position_fb - x_0) < 0.001);
	for (k = 0; k < d->enable_at; k++)
		drift_tick(d, x_0);
	d->r[0]->in.axis[0].enable = d->r[1]->in.axis[0].enable = 1;
	for (k = 0; k < 100; k++)
		drift_tick(d, x_0);
	assert_true(d->r[0]->c.streaming && d->r[1]->c.streaming);
	return x_0;
}

/* How far card 1's latest set-point is behind card 0's (ns of host
 * time), where card 0 moves faster than vmin counts per ns; 0, or -1
 * when there is no such sample. */
static int drift_skew(const struct drift *d, double vmin, double *skew)
{
	double x0, v0;
	unsigned int last = (d->o[1].n - 1) % OBS_RING;

	if (!d->o[1].n || obs_at(&d->o[0], d->o[1].t[last], &x0, &v0) < 0 ||
	    fabs(v0) <= vmin)
		return -1;
	*skew = (x0 - d->o[1].x[last]) / v0;
	return 0;
}

static void test_two_cards_drift(void **state)
{
	struct drift d = { 0 };
	double ppm[2] = { DRIFT_PPM, -DRIFT_PPM }, skew_max = 0, skew_0 = 0;
	double A = 10.0, w = 2 * 3.14159265358979 * 1.0, vmax = A * w, x_0;
	int fill_min[2] = { 1000, 1000 }, fill_max[2] = { -1, -1 };
	int i, k, n = 60000, samples = 0;
	uint64_t cycles[2] = { 0, 0 };
	uint32_t cycles_max[2] = { 0, 0 };

	(void)state;
	x_0 = drift_open(&d, ppm, DRIFT_TARGET);
	/* a minute of the same motion on both: 10 mm (1 - cos), 1 Hz */
	for (k = 0; k < n; k++) {
		double t = k * 1e-3, skew;

		drift_tick(&d, x_0 + A * (1 - cos(w * t)));
		for (i = 0; i < 2; i++) {
			assert_true(d.r[i]->out.ok);
			cycles[i] += d.r[i]->out.port_cycles;
			if (d.r[i]->out.port_cycles > cycles_max[i])
				cycles_max[i] = d.r[i]->out.port_cycles;
			if (k < 1000 || !d.r[i]->c.st_fresh)
				continue;
			if (d.r[i]->out.queue_fill < fill_min[i])
				fill_min[i] = d.r[i]->out.queue_fill;
			if (d.r[i]->out.queue_fill > fill_max[i])
				fill_max[i] = d.r[i]->out.queue_fill;
		}
		/* skew: card 0's set-point where card 1's latest is, in
		 * host time, over card 0's velocity, where it is fast */
		if (drift_skew(&d, 0.7 * vmax * 1e-9 *
			       d.r[0]->in.axis[0].position_scale, &skew) == 0) {
			if (!samples++)
				skew_0 = skew;
			if (fabs(skew) > skew_max)
				skew_max = fabs(skew);
		}
	}
	print_message("two cards at %+g and %+g ppm, 1 ms thread on card 0 (correction %ld ns), %d s of motion: fill %d..%d and %d..%d (target %d), skew of card 1 against card 0 at most %.1f us (%d samples, the first %.1f us)\n",
		      ppm[0], ppm[1], d.correction_ns, n / 1000, fill_min[0],
		      fill_max[0], fill_min[1], fill_max[1], DRIFT_TARGET,
		      skew_max * 1e-3, samples, skew_0 * 1e-3);
	print_message("port cycles per tick: card 0 %.1f on average (at most %u), card 1 %.1f (at most %u: a tick with two points)\n",
		      (double)cycles[0] / n, cycles_max[0],
		      (double)cycles[1] / n, cycles_max[1]);
	/* the budget: <= 150 port cycles per tick, a follower's occasional
	 * second point (through the ring) included */
	assert_true(cycles[0] <= 150ull * (uint64_t)n);
	assert_true(cycles[1] <= 150ull * (uint64_t)n);
	/* the thread follows card 0: 100 ppm of a period */
	assert_true(labs(d.correction_ns - (long)(DRIFT_PPM * 1e-6 * PERIOD_NS)) <= 20);
	assert_true(samples > 1000);
	for (i = 0; i < 2; i++) {
		assert_true(fill_min[i] >= DRIFT_TARGET - 2);
		assert_true(fill_max[i] <= DRIFT_TARGET + 2);
		assert_int_equal(d.r[i]->out.underruns, 0);
	}
	assert_true(skew_max < 0.25 * PERIOD_NS);
	for (i = 0; i < 2; i++)
		rig_close(d.r[i]);
}

/* One period of the thread during a stall of the whole machine: the
 * thread's read comes late_ns after the tick's start, and card i's time
 * has got to until[i] (the cards' servers were stopped with it). */
static void stalled_tick(struct drift *d, double cmd_mm, long late_ns,
			 const uint64_t until[2])
{
	int i;

	for (i = 0; i < 2; i++) {
		struct hsc_card *c = &d->r[i]->c;
		uint64_t now = sh2000_now_ns(c->h);

		if (now < until[i])
			sh2000_sleep_ns(c->h, until[i] - now);
		hsc_read(c, &d->r[i]->in, &d->r[i]->out, PERIOD_NS, late_ns);
	}
	for (i = 0; i < 2; i++) {
		d->r[i]->in.axis[0].position_cmd = cmd_mm;
		hsc_write(&d->r[i]->c, &d->r[i]->in, &d->r[i]->out);
		if (!d->r[i]->out.ok)
			fail_msg("card %d: %s (fill %u)", i, d->r[i]->c.err,
				 d->r[i]->c.st.queue_fill);
	}
	d->correction_ns = d->r[0]->out.pll_correction_ns;
	d->t_next += (uint64_t)(PERIOD_NS + d->correction_ns);
}

/*
 * The whole machine, both cards' servers with it, stops for n periods
 * from the start of the next tick (as linuxcnc_drift under a stall loop of
 * real-time busy processes on every core). The thread then runs the n
 * ticks it missed back to back, each read n..1 periods late, before the
 * cards have moved on; then the cards catch up their periods at a served
 * card's pace (two periods a period: sh2000-sim), card i starting lag[i]
 * periods after the thread, while the thread is on time. wave(k) is the
 * command (mm) of tick k; *k counts the thread's ticks.
 */
static void drift_stall(struct drift *d, int n, const int lag[2],
			double (*wave)(int k), int *k)
{
	uint64_t until[2], t0 = d->t_next, card[2];
	int j, i, behind = 1;

	for (i = 0; i < 2; i++)
		card[i] = until[i] = sh2000_now_ns(d->r[i]->c.h);
	for (j = 0; j < n; j++, (*k)++)
		stalled_tick(d, wave(*k), (long)(t0 + (uint64_t)n * PERIOD_NS -
						 d->t_next), until);
	for (j = 1; behind; j++, (*k)++) {
		behind = 0;
		for (i = 0; i < 2; i++) {
			int run = j - lag[i] > 0 ? j - lag[i] : 0;

			until[i] = card[i] + 2 * (uint64_t)run * PERIOD_NS;
			if (until[i] >= d->t_next)
				until[i] = d->t_next;
			else
				behind = 1;
		}
		stalled_tick(d, wave(*k), 0, until);
	}
}

/* The drift test's motion: 10 mm (1 - cos), 1 Hz, at tick k. */
static double stall_wave(int k)
{
	return 10.0 * (1 - cos(2 * 3.14159265358979 * k * 1e-3));
}

/*
 * The drift test's two cards (DRIFT_PPM apart, queue target 30) streaming
 * its motion for a second: *vmin is the speed above which the skew is
 * judged (counts per ns), tick0 each timebase's reference, *k the ticks
 * run. Returns where both cards stood (mm).
 */
static double drift_start(struct drift *d, double *vmin, uint64_t tick0[2],
			  int *k)
{
	double ppm[2] = { DRIFT_PPM, -DRIFT_PPM };
	double x_0 = drift_open(d, ppm, 30);
	int i;

	*vmin = 0.7 * 10.0 * 2 * 3.14159265358979 * 1e-9 *
		d->r[0]->in.axis[0].position_scale;
	for (*k = 0; *k < 1000; (*k)++)
		drift_tick(d, x_0 + stall_wave(*k));
	for (i = 0; i < 2; i++)
		tick0[i] = d->r[i]->c.tb.tick0;
	return x_0;
}

/* What a run of drift_start()'s cards with `events` disturbances must
 * keep: every second's end at the target less one (fill_off: those that
 * were not), the skew within a quarter of a period over enough samples,
 * the phase references never taken again, no underrun. Closes the cards. */
static void drift_judge(struct drift *d, int events, double worst,
			int samples, int fill_off, const uint64_t tick0[2])
{
	int i;

	assert_int_equal(fill_off, 0);
	assert_true(samples > 10 * events);
	assert_true(worst < 0.25 * PERIOD_NS);
	for (i = 0; i < 2; i++) {
		assert_true(d->r[i]->c.tb.tick0 == tick0[i]);
		assert_int_equal(d->r[i]->out.underruns, 0);
	}
	for (i = 0; i < 2; i++)
		rig_close(d->r[i]);
}

#define STALLS		70
#define STALL_TICKS	30

/*
 * linuxcnc_drift under a loop that stalls the whole machine for 30 ms
 * every second: a stall every 1000 ticks, the cards' servers stopped with
 * the thread and catching up at their pace afterwards, the follower's a
 * few periods after the first card's. A stall moves neither card's
 * timeline: the skew between the cards stays within a quarter of a period
 * (the drift test's bound) at every sample, during the stalls too, the
 * timebases keep their references, and both queues stay at their target.
 * Before, the readings of the ticks run back to back settled on a phase
 * that was not the card's and the reference was taken again twice a
 * stall, each time a little off: the skew grew stall after stall.
 */
static void test_two_cards_stalls(void **state)
{
	struct drift d = { 0 };
	double skew, x_0, vmin, worst = 0, last_min = 0, last_max = 0;
	static const int lag[2] = { 0, 3 };
	uint64_t tick0[2];
	int i, k, s, samples = 0, fill_off = 0;

	(void)state;
	x_0 = drift_start(&d, &vmin, tick0, &k);
	for (s = 0; s < STALLS; s++) {
		last_min = 1e99;
		last_max = -1e99;
		drift_stall(&d, STALL_TICKS, lag, stall_wave, &k);
		for (i = 0; i < 1000; i++, k++) {
			drift_tick(&d, x_0 + stall_wave(k));
			if (drift_skew(&d, vmin, &skew) < 0)
				continue;
			samples++;
			last_min = fmin(last_min, skew);
			last_max = fmax(last_max, skew);
			worst = fmax(worst, fabs(skew));
		}
		/* the fill a second after: the target less one (hsc.h) */
		for (i = 0; i < 2; i++)
			if (abs((int)d.r[i]->c.st.queue_fill - 29) > 2)
				fill_off++;
	}
	print_message("%d stalls of %d ticks, one a second: skew of card 1 against card 0 at most %.1f us (%d samples), after the last %.1f..%.1f us; fill %u and %u (target 30), %d seconds' ends off it\n",
		      STALLS, STALL_TICKS, worst * 1e-3, samples,
		      last_min * 1e-3, last_max * 1e-3,
		      d.r[0]->c.st.queue_fill, d.r[1]->c.st.queue_fill,
		      fill_off);
	drift_judge(&d, STALLS, worst, samples, fill_off, tick0);
}

/*
 * A served card's server falls behind while the thread runs on time (on
 * a busy CPU its cycles wait: sh2000-sim beside the servo thread of
 * linuxcnc_drift lags by a millisecond or more twice a second): the cards
 * marked in `which` stop for `stop` periods, run `hold` periods at their
 * own pace still that far behind, then catch up at a served card's pace
 * (two periods a period). In the card's own time nothing happened: what it
 * plays, and when, must not change.
 */
static void drift_lag(struct drift *d, int stop, int hold, const int which[2],
		      double (*wave)(int k), int *k)
{
	uint64_t until[2], card[2];
	int j, i, behind = 1;

	for (i = 0; i < 2; i++)
		card[i] = sh2000_now_ns(d->r[i]->c.h);
	for (j = 1; behind; j++, (*k)++) {
		int run = j <= stop ? 0 : j <= stop + hold ? j - stop :
			  hold + 2 * (j - stop - hold);

		behind = 0;
		for (i = 0; i < 2; i++) {
			until[i] = which[i] ?
				   card[i] + (uint64_t)run * PERIOD_NS : d->t_next;
			if (until[i] >= d->t_next)
				until[i] = d->t_next;
			else
				behind = 1;
		}
		stalled_tick(d, wave(*k), 0, until);
	}
}

#define LAGS		60

/*
 * linuxcnc_drift with the cards' servers lagging now and then, the
 * thread on time: both servers at once, or the follower's alone, by 2 to
 * 15 periods held for 10 to 40. The lags move neither card's timeline:
 * the skew between the cards stays within a quarter of a period, the
 * timebases keep their references and both queues their target. Before,
 * a lag held for five readings was taken for the card's phase (the
 * follower's reference taken again), and the card's delay moved by the
 * lag for good: linuxcnc_drift failed with 1 to 4 periods of skew.
 */
static void test_two_cards_lags(void **state)
{
	struct drift d = { 0 };
	double skew, x_0, vmin, worst = 0;
	static const int both[2] = { 1, 1 }, follower[2] = { 0, 1 };
	static const int stop[4] = { 2, 3, 15, 2 }, hold[4] = { 10, 12, 40, 30 };
	uint64_t tick0[2];
	int i, k, s, samples = 0, fill_off = 0;

	(void)state;
	x_0 = drift_start(&d, &vmin, tick0, &k);
	for (s = 0; s < LAGS; s++) {
		drift_lag(&d, stop[s % 4], hold[s % 4],
			  s % 3 ? both : follower, stall_wave, &k);
		for (i = 0; i < 1000; i++, k++) {
			drift_tick(&d, x_0 + stall_wave(k));
			if (drift_skew(&d, vmin, &skew) < 0)
				continue;
			samples++;
			worst = fmax(worst, fabs(skew));
		}
		for (i = 0; i < 2; i++)
			if (abs((int)d.r[i]->c.st.queue_fill - 29) > 2)
				fill_off++;
	}
	print_message("%d lags of the cards' servers: skew of card 1 against card 0 at most %.1f us (%d samples); fill %u and %u (target 30), %d seconds' ends off it; references taken %s\n",
		      LAGS, worst * 1e-3, samples, d.r[0]->c.st.queue_fill,
		      d.r[1]->c.st.queue_fill, fill_off,
		      d.r[0]->c.tb.tick0 == tick0[0] &&
		      d.r[1]->c.tb.tick0 == tick0[1] ? "once" : "again");
	drift_judge(&d, LAGS, worst, samples, fill_off, tick0);
}

/*
 * The drift test's minute of motion after a start in which card 1's server
 * lagged lag_us behind the thread for its first lag_ticks periods, the
 * axes enabled after enable_at: the skew stays within a quarter of a
 * period.
 */
static void late_start(uint64_t lag_us, int lag_ticks, int enable_at)
{
	struct drift d = { .lag_ns = lag_us * 1000, .lag_ticks = lag_ticks,
			   .enable_at = enable_at };
	double skew, x_0, vmin, worst = 0;
	uint64_t tick0[2];
	int k, samples = 0;

	x_0 = drift_start(&d, &vmin, tick0, &k);
	for (; k < 60000; k++) {
		drift_tick(&d, x_0 + stall_wave(k));
		if (drift_skew(&d, vmin, &skew) < 0)
			continue;
		samples++;
		worst = fmax(worst, fabs(skew));
	}
	print_message("card 1's server %llu us late for the first %d periods, the axes enabled after %d: skew of card 1 against card 0 at most %.1f us (%d samples); fill %u and %u (target 30)\n",
		      (unsigned long long)lag_us, lag_ticks, enable_at,
		      worst * 1e-3, samples, d.r[0]->c.st.queue_fill,
		      d.r[1]->c.st.queue_fill);
	assert_true(samples > 1000);
	assert_true(worst < 0.25 * PERIOD_NS);
	rig_close(d.r[0]);
	rig_close(d.r[1]);
}

/*
 * Card 1's server 0.6 periods behind while its timing is set, its phase
 * reference read and its stream started: the card starts the stream
 * early on its own clock. Without the start's check (write.c), some
 * 600 us of skew for good.
 */
static void test_two_cards_early_start(void **state)
{
	(void)state;
	late_start(600, 150, 0);
}

/*
 * Card 1's server 1.5 periods behind while its phase reference is read,
 * caught up before its stream starts: the reference is late by the lag.
 * Slewed out by the filter while the stream runs, it would move the
 * card's delay by what is left of it.
 */
static void test_two_cards_late_reference(void **state)
{
	(void)state;
	late_start(1500, 40, 60);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stream_and_feedback),
		cmocka_unit_test(test_estop_both_ways),
		cmocka_unit_test(test_jam_is_amp_fault),
		cmocka_unit_test(test_underrun),
		cmocka_unit_test(test_stopped_by_another_program),
		cmocka_unit_test(test_stall_caught_up),
		cmocka_unit_test(test_delay_through_turn),
		cmocka_unit_test(test_slip_recentred),
		cmocka_unit_test(test_lost_refilled),
		cmocka_unit_test(test_target_raised),
		cmocka_unit_test(test_two_cards_drift),
		cmocka_unit_test(test_two_cards_stalls),
		cmocka_unit_test(test_two_cards_lags),
		cmocka_unit_test(test_two_cards_early_start),
		cmocka_unit_test(test_two_cards_late_reference),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
