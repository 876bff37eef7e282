/* SPDX-License-Identifier: MIT */
/*
 * sh2000/run.h against the card model in virtual time: a planned line
 * streamed and executed exactly, the ring kept filled, one sample per servo
 * cycle, pause and resume, a stop on the path, a card fault mid-run (card
 * stopped, plan reset, the next run fine), a card that is not ready, bad
 * configurations.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "simtest.h"
#include "sh2000/run.h"

struct obs {
	struct sh2000_run *run;
	struct sh2000 *h;
	uint64_t samples, per_cycle;
	double last_t;
	int monotonic;
	struct sh2000_run_sample last;
	/* act on the progress callback once this many points are pushed */
	uint64_t at_points;
	int action;		/* 1 pause, 2 stop, 3 jam axis 0, 4 heartbeat stop */
	int acted;
	int64_t seq;		/* the last progress' tag */
	int seq_bad;		/* a tag that was never set */
};

static void on_sample(void *ctx, const struct sh2000_run_sample *s)
{
	struct obs *o = ctx;

	if (o->samples && s->t <= o->last_t)
		o->monotonic = 0;
	o->samples++;
	o->per_cycle += s->per_cycle;
	o->last_t = s->t;
	o->last = *s;
}

static void on_progress(void *ctx, const struct sh2000_run_progress *p)
{
	struct obs *o = ctx;

	if (p->seq != -1 && p->seq != 7)
		o->seq_bad = 1;
	o->seq = p->seq;
	if (!o->action || o->acted || p->points < o->at_points)
		return;
	o->acted = 1;
	if (o->action == 1)
		sh2000_run_pause(o->run);
	else if (o->action == 2)
		sh2000_run_stop(o->run);
	else if (o->action == 3)
		sh2000_sim_inject(o->h, SH2000_INJECT_JAM, 0, 0);
	else
		sh2000_sim_inject(o->h, SH2000_INJECT_HEARTBEAT_STOP, 0, 0);
}

static struct sh2000_run *start(struct sh2000 *h, struct obs *o)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_run *r;
	char msg[256];

	CHECK(sh2000_enable(h, 0xf));
	CHECK(sh2000_run_path_config(h, &pc));
	sh2000_run_config_default(&rc);
	rc.sample = on_sample;
	rc.progress = on_progress;
	rc.ctx = o;
	o->h = h;
	o->monotonic = 1;
	if (sh2000_run_create(&r, h, &pc, &rc, msg, sizeof(msg)) < 0)
		fail_msg("run_create: %s", msg);
	o->run = r;
	return r;
}

static void card_at(struct sh2000 *h, const double mm[4], double tol)
{
	struct sh2000_status st;
	unsigned int a;

	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_int_equal(st.queue_fill, 0);
	for (a = 0; a < 4; a++)
		if (fabs(st.axis[a].cmd_mm - mm[a]) > tol)
			fail_msg("axis %u at %.6f mm, expected %.6f", a,
				 st.axis[a].cmd_mm, mm[a]);
}

static void test_line(void **state)
{
	struct sh2000 *h = simtest_open();
	struct obs o = { 0 };
	struct sh2000_run *r = start(h, &o);
	struct sh2000_run_stats s;
	struct sh2000_path_stats ps;
	const double end[4] = { 50.0, -20.0, 5.0, 1.0 };

	(void)state;
	sh2000_path_set_seq(sh2000_run_path(r), 7);
	CHECK(sh2000_path_line(sh2000_run_path(r), end, 100.0));
	assert_int_equal(sh2000_run_finish(r), 0);
	/* progress names the primitive the card is running */
	assert_int_equal(o.seq, 7);
	assert_false(o.seq_bad);
	sh2000_run_stats(r, &s);
	sh2000_path_stats(sh2000_run_path(r), &ps);
	/* every planned point went to the card, in batches of 16 after a
	 * priming batch of 48 */
	assert_int_equal(s.points, ps.points);
	assert_true(s.points > 250);
	assert_true(s.batches >= 1 + (s.points - 48) / 16);
	assert_true(s.batches <= 2 + (s.points - 48) / 16 + 1);
	assert_int_equal(s.motions, 1);
	/* the ring stayed filled: never below 32 of 64 while moving */
	assert_true(s.min_fill >= 32 && s.min_fill < SH2000_RING_RECORDS);
	assert_int_equal(s.underruns, 0);
	/* one sample per servo cycle, in order, ending on the end point */
	assert_true(o.monotonic);
	assert_int_equal(o.per_cycle, o.samples);
	assert_true(fabs((double)o.samples - s.time_s / 100e-6) < 200.0);
	assert_true(fabs(o.last.cmd[0] - 50.0) < 1e-6);
	assert_true(fabs(o.last.cmd[1] + 20.0) < 1e-6);
	assert_true(s.max_ferr_mm > 0.0 && s.max_ferr_mm < 0.01);
	assert_true(fabs(s.distance_mm - sqrt(2500.0 + 400.0 + 26.0)) < 0.01);
	card_at(h, end, 1e-5);
	sh2000_run_destroy(r);
	sh2000_close(h);
}

/* The point reached lies on the segment from a to b, short of b. */
static void on_segment_short(struct sh2000 *h, const double a[4],
			     const double b[4])
{
	struct sh2000_status st;
	double t = 0.0, l2 = 0.0, d = 0.0;
	unsigned int i;

	CHECK(sh2000_poll(h, &st));
	for (i = 0; i < 4; i++) {
		t += (st.axis[i].cmd_mm - a[i]) * (b[i] - a[i]);
		l2 += (b[i] - a[i]) * (b[i] - a[i]);
	}
	t /= l2;
	for (i = 0; i < 4; i++) {
		double e = st.axis[i].cmd_mm - (a[i] + t * (b[i] - a[i]));

		d += e * e;
	}
	if (!(t > 0.05 && t < 0.95 && sqrt(d) < 1e-4))
		fail_msg("stopped at t = %.4f of the line, %.6f mm off it", t,
			 sqrt(d));
}

static void test_pause_resume(void **state)
{
	struct sh2000 *h = simtest_open();
	struct obs o = { .at_points = 200, .action = 1 };
	struct sh2000_run *r = start(h, &o);
	const double a[4] = { 0, 0, 0, 0 }, b[4] = { 100.0, 50.0, 0, 0 };

	(void)state;
	CHECK(sh2000_path_line(sh2000_run_path(r), b, 50.0));
	assert_int_equal(sh2000_run_finish(r), -EAGAIN);
	assert_true(o.acted);
	/* the card holds on the path with the rest of the motion queued
	 * (protocol 1.1's time base) */
	assert_true(sh2000_run_held(r));
	on_segment_short(h, a, b);
	{
		struct sh2000_status st;

		CHECK(sh2000_poll(h, &st));
		assert_int_equal(st.card_state, SH2000_STATE_RUNNING);
		assert_true(st.queue_fill > 0);
		/* and stays there while the host keeps beating */
		CHECK(sh2000_run_hold_wait(r, 200));
		on_segment_short(h, a, b);
	}
	sh2000_run_resume(r);
	assert_int_equal(sh2000_run_finish(r), 0);
	card_at(h, b, 1e-5);
	sh2000_run_destroy(r);
	sh2000_close(h);
}

static void test_stop(void **state)
{
	struct sh2000 *h = simtest_open();
	struct obs o = { .at_points = 200, .action = 2 };
	struct sh2000_run *r = start(h, &o);
	const double a[4] = { 0, 0, 0, 0 }, b[4] = { 100.0, 50.0, 0, 0 };
	const double c[4] = { 10.0, 10.0, 0, 0 };

	(void)state;
	CHECK(sh2000_path_line(sh2000_run_path(r), b, 50.0));
	assert_int_equal(sh2000_run_finish(r), -ECANCELED);
	on_segment_short(h, a, b);
	/* the rest was dropped: the next primitive starts where it stopped */
	CHECK(sh2000_path_line(sh2000_run_path(r), c, 50.0));
	assert_int_equal(sh2000_run_finish(r), 0);
	card_at(h, c, 1e-5);
	sh2000_run_destroy(r);
	sh2000_close(h);
}

static void test_fault(void **state)
{
	struct sh2000 *h = simtest_open();
	struct obs o = { .at_points = 100, .action = 3 };
	struct sh2000_run *r = start(h, &o);
	const double b[4] = { 100.0, 0, 0, 0 }, c[4] = { 0, 10.0, 0, 0 };
	struct sh2000_status st;
	int e;

	(void)state;
	e = sh2000_path_line(sh2000_run_path(r), b, 50.0);
	if (!e)
		e = sh2000_run_finish(r);
	assert_int_equal(e, -SH2000_EFERR);
	assert_non_null(strstr(sh2000_run_error(r), "sim"));
	assert_non_null(strstr(sh2000_run_error(r), "axis x: "));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_FAULT);
	/* the card is stopped and the run usable again: after a card reset
	 * (which may hold the encoder's position) it goes on from there */
	sh2000_sim_inject(h, SH2000_INJECT_CLEAR, 0, 0);
	CHECK(sh2000_reset(h));
	CHECK(sh2000_enable(h, 0xf));
	CHECK(sh2000_poll(h, &st));
	{
		double here[4], end[4];
		unsigned int a;

		for (a = 0; a < 4; a++)
			here[a] = st.axis[a].cmd_mm;
		CHECK(sh2000_path_reset(sh2000_run_path(r), here));
		for (a = 0; a < 4; a++)
			end[a] = c[a];
		CHECK(sh2000_path_line(sh2000_run_path(r), end, 50.0));
		assert_int_equal(sh2000_run_finish(r), 0);
		card_at(h, end, 1e-5);
	}
	sh2000_run_destroy(r);
	sh2000_close(h);
}

/*
 * A card whose heartbeat cell sticks mid-run runs on: the run ends with
 * EHEARTBEAT, and must not leave the card running its ring out until its
 * own host timeout. The card is in ESTOP with an empty ring before the
 * host timeout could have fired, a reset brings it back, the next run works.
 */
static void test_heartbeat(void **state)
{
	struct sh2000 *h = simtest_open();
	struct obs o = { .at_points = 100, .action = 4 };
	struct sh2000_run *r = start(h, &o);
	const double b[4] = { 100.0, 0, 0, 0 }, c[4] = { 0, 10.0, 0, 0 };
	struct sh2000_status st;
	double to, here[4];
	uint64_t t_fail;
	unsigned int a;
	int e;

	(void)state;
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_HOST_TIMEOUT_MS, &to));
	e = sh2000_path_line(sh2000_run_path(r), b, 50.0);
	if (!e)
		e = sh2000_run_finish(r);
	t_fail = sh2000_now_ns(h);
	assert_int_equal(e, -SH2000_EHEARTBEAT);
	assert_non_null(strstr(sh2000_run_error(r), "heartbeat"));
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_CLEAR, 0, 0));
	CHECK(sh2000_sleep_ns(h, 200000));
	CHECK(sh2000_poll(h, &st));
	/* stopped by the host, well before the card's own timeout */
	assert_true(sh2000_now_ns(h) - t_fail < (uint64_t)to * 1000000ull / 2);
	assert_int_equal(st.card_state, SH2000_STATE_ESTOP);
	assert_int_equal(st.queue_fill, 0);
	assert_false(st.card_faults & SH2000_FAULT_HOST_TIMEOUT);
	CHECK(sh2000_reset(h));
	CHECK(sh2000_enable(h, 0xf));
	CHECK(sh2000_poll(h, &st));
	for (a = 0; a < 4; a++)
		here[a] = st.axis[a].cmd_mm;
	CHECK(sh2000_path_reset(sh2000_run_path(r), here));
	CHECK(sh2000_path_line(sh2000_run_path(r), c, 50.0));
	assert_int_equal(sh2000_run_finish(r), 0);
	card_at(h, c, 1e-5);
	sh2000_run_destroy(r);
	sh2000_close(h);
}

static void test_not_ready(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_run *r = (struct sh2000_run *)&rc;
	char msg[256];

	(void)state;
	CHECK(sh2000_run_path_config(h, &pc));
	/* a batch larger than the priming batch */
	sh2000_run_config_default(&rc);
	rc.batch = 60;
	assert_int_equal(sh2000_run_create(&r, h, &pc, &rc, msg, sizeof(msg)),
			 -EINVAL);
	assert_null(r);
	assert_non_null(strstr(msg, "batch"));
	/* a planner scale that is not the card's */
	pc.counts_per_mm[2] = 1000.0;
	assert_int_equal(sh2000_run_create(&r, h, &pc, NULL, msg, sizeof(msg)),
			 -EINVAL);
	assert_non_null(strstr(msg, "scale"));
	/* a latched emergency stop */
	CHECK(sh2000_run_path_config(h, &pc));
	CHECK(sh2000_estop(h, 100));
	assert_int_equal(sh2000_run_create(&r, h, &pc, NULL, msg, sizeof(msg)),
			 -SH2000_EESTOP);
	assert_non_null(strstr(msg, "sim"));
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_line),
		cmocka_unit_test(test_pause_resume),
		cmocka_unit_test(test_stop),
		cmocka_unit_test(test_fault),
		cmocka_unit_test(test_heartbeat),
		cmocka_unit_test(test_not_ready),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
