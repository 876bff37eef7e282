// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * hal_sh2000's logic (hal/hsc.h) without LinuxCNC: a loop that plays
 * LinuxCNC's servo thread (read, compute the joint's following error as
 * motion does, new command, write) against the card model in virtual time
 * (`sim`), one 1 ms tick after the other. Checks the enable/stream/disable
 * sequence, that LinuxCNC's following error equals the card's own within
 * 1 um on a 200 mm/s move, the fill of the ring, the emergency stop both
 * ways, a jam as an amplifier fault, an underrun, a STOP from another
 * program and the reset that clears them.
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
	/* issue 12: one tick on the simulated card (poll + one point
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

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stream_and_feedback),
		cmocka_unit_test(test_estop_both_ways),
		cmocka_unit_test(test_jam_is_amp_fault),
		cmocka_unit_test(test_underrun),
		cmocka_unit_test(test_stopped_by_another_program),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
