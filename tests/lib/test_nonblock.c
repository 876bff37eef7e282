/* SPDX-License-Identifier: MIT */
/*
 * The real-time calls (nonblock.c): a poll that gives up on a torn
 * snapshot instead of re-reading, commands started in one tick and
 * completed in a later one, one point pushed against the room the last
 * poll saw, an estop request that does not wait. Against the card model
 * in virtual time (`sim`), the scripted card (torn snapshots, port
 * cycles) and a served card (another program holding the command slot).
 */
#include <errno.h>
#include <unistd.h>

#include "fakecard.h"
#include "rt.h"
#include "simtest.h"

/* One servo cycle of the default timing (100 us). */
#define SERVO_NS	100000ull

/* Ticks a caller tries before a run of torn snapshots fails the test. */
#define TORN_TICKS	10

/*
 * A real-time caller's tick: a torn snapshot (the card publishes one
 * every millisecond, a poll takes 94 us, so about one poll in ten) is
 * read again on the next tick, 1 ms later; TORN_TICKS torn ones in a row
 * are a card that never publishes a whole one.
 */
static void tick_poll(struct sh2000 *h, struct sh2000_status *st)
{
	int r, i;

	for (i = 0; (r = sh2000_poll_once(h, st)) == -EAGAIN; i++) {
		if (i == TORN_TICKS)
			fail_msg("sh2000_poll_once: %d ticks 1 ms apart, every snapshot torn",
				 TORN_TICKS + 1);
		sh2000_sleep_ns(h, 1000000);
	}
	CHECK(r);
}

static void test_poll_once_matches_poll(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status a, b;

	(void)state;
	CHECK(sh2000_poll(h, &a));
	tick_poll(h, &b);
	assert_int_equal(a.card_state, b.card_state);
	assert_int_equal(a.queue_fill, b.queue_fill);
	assert_int_equal(a.axis[1].pos_counts, b.axis[1].pos_counts);
	assert_int_equal(b.retries, 0);
	sh2000_close(h);
}

static void test_poll_once_torn_is_eagain(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	unsigned int c[4];

	(void)state;
	fakecard_boot(f);
	st.card_state = 1234;
	f->tear_polls = 1;
	fakecard_clear_log(f);
	assert_int_equal(sh2000_poll_once(&f->h, &st), -EAGAIN);
	/* left as it was, after one stream and the host heartbeat: no
	 * re-read */
	assert_int_equal(st.card_state, 1234);
	fakecard_counts(f, c);
	assert_int_equal(c[2], SH2000_STATUS_WORDS);
	assert_int_equal(c[3], 1);
	assert_int_equal(f->ram[SH2000_W_HOST_HEARTBEAT], f->h.host_hb);
	/* next tick it reads fine */
	assert_int_equal(sh2000_poll_once(&f->h, &st), 0);
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	fakecard_free(f);
}

/* A card stopped in the middle of a publication leaves its snapshot torn
 * for good: the ticks go on watching its heartbeat and call it stopped at
 * the limit, as for a card stopped between publications, instead of
 * answering -EAGAIN forever. */
static void test_poll_once_torn_stopped(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	uint64_t t0;
	int r;

	(void)state;
	fakecard_boot(f);
	assert_int_equal(sh2000_poll_once(&f->h, &st), 0);
	f->hb_running = 0;
	f->tear_polls = 100000;
	t0 = f->now_ns;
	while ((r = sh2000_poll_once(&f->h, &st)) == -EAGAIN &&
	       f->now_ns - t0 < 2 * f->h.hb.limit_ns)
		f->now_ns += 1000000;	/* the next 1 ms tick */
	assert_int_equal(r, -SH2000_EHEARTBEAT);
	assert_non_null(strstr(sh2000_last_error(&f->h), "left torn"));
	assert_true(st.heartbeat_age_ns >= f->h.hb.limit_ns);
	/* within a tick of the limit, from the first tick that saw the
	 * heartbeat's last move (it may move once after the good poll read it) */
	if (f->now_ns - t0 > f->h.hb.limit_ns + 2000000)
		fail_msg("%.3f ms (limit %.3f, age %.3f)", (f->now_ns - t0) / 1e6,
			 f->h.hb.limit_ns / 1e6, st.heartbeat_age_ns / 1e6);
	fakecard_free(f);
}

static void test_poll_once_heartbeat_loss(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	uint64_t t0;

	(void)state;
	fakecard_boot(f);
	assert_int_equal(sh2000_poll_once(&f->h, &st), 0);
	f->hb_running = 0;
	t0 = f->now_ns;
	while (sh2000_poll_once(&f->h, &st) == 0)
		f->now_ns += 500000;
	/* within the limit plus one poll interval (and the poll's own port
	 * cycles, 1 us each) */
	assert_true(f->now_ns - t0 >= SH2000_HEARTBEAT_LIMIT_NS);
	assert_true(f->now_ns - t0 <= SH2000_HEARTBEAT_LIMIT_NS + 600000);
	assert_int_equal(sh2000_poll_once(&f->h, &st), -SH2000_EHEARTBEAT);
	fakecard_free(f);
}

static void test_command_start_complete(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	int32_t v = -1;
	int r, ticks = 0;

	(void)state;
	tick_poll(h, &st);
	CHECK(sh2000_command_start(h, SH2000_CMD_NOP, 0, 0, 0));
	assert_int_equal(sh2000_command_start(h, SH2000_CMD_NOP, 0, 0, 0),
			 -EBUSY);
	/* the card answers within a servo cycle; until then: in progress */
	while ((r = sh2000_command_complete(h, &v)) == -EINPROGRESS) {
		sh2000_sleep_ns(h, SERVO_NS / 4);
		ticks++;
	}
	assert_int_equal(r, 0);
	assert_true(ticks >= 1 && ticks <= 5);
	assert_true(v > 0);	/* NOP answers the servo cycle counter */
	assert_int_equal(sh2000_command_complete(h, NULL), -EINVAL);

	/* the answer a poll read after the start is used without port
	 * cycles */
	CHECK(sh2000_command_start(h, SH2000_CMD_ENABLE, 0, 0, 0x3));
	sh2000_sleep_ns(h, 2 * SERVO_NS);
	tick_poll(h, &st);
	{
		struct sh2000_port_counters c0, c1;

		CHECK(sh2000_port_counters(h, &c0));
		CHECK(sh2000_command_complete(h, NULL));
		CHECK(sh2000_port_counters(h, &c1));
		assert_int_equal(c1.data_reads, c0.data_reads);
	}
	tick_poll(h, &st);
	assert_true(st.axis[0].state & SH2000_AXIS_ENABLED);
	assert_true(st.axis[1].state & SH2000_AXIS_ENABLED);

	/* a result code is the command's error */
	CHECK(sh2000_command_start(h, SH2000_CMD_ENABLE, 0, 0, 0x40));
	sh2000_sleep_ns(h, 2 * SERVO_NS);
	assert_int_equal(sh2000_command_complete(h, NULL), -SH2000_ECMD_VALUE);
	/* and the blocking calls still work after it */
	CHECK(sh2000_nop(h));
	sh2000_close(h);
}

static void test_command_timeout(void **state)
{
	struct sh2000 *h = simtest_open();
	uint64_t t0;
	int r;

	(void)state;
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_DSP_STALL, 0, 0));
	CHECK(sh2000_command_start(h, SH2000_CMD_NOP, 0, 0, 0));
	t0 = sh2000_now_ns(h);
	while ((r = sh2000_command_complete(h, NULL)) == -EINPROGRESS)
		sh2000_sleep_ns(h, 1000000);
	assert_true(sh2000_now_ns(h) - t0 >= SH2000_CMD_TIMEOUT_MS * 1000000ull);
	assert_true(r == -SH2000_EHEARTBEAT || r == -SH2000_ETIMEOUT);
	/* the slot is free again */
	assert_int_equal(sh2000_command_complete(h, NULL), -EINVAL);
	sh2000_close(h);
}

static void test_push_point(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	int32_t p[SH2000_AXES];
	unsigned int i;

	(void)state;
	CHECK(sh2000_enable(h, 0x1));
	simtest_cmd(h, p);
	tick_poll(h, &st);
	/* the room the last poll saw, never more: 64 points, then full
	 * until the next poll (the card consumed meanwhile) */
	for (i = 0; i < SH2000_RING_RECORDS; i++) {
		p[0] += 10;
		assert_int_equal(sh2000_push_point(h, p, 0), 1);
	}
	p[0] += 10;
	assert_int_equal(sh2000_push_point(h, p, 0), -SH2000_EQUEUE_FULL);
	sh2000_sleep_ns(h, 5 * 2000000ull);
	tick_poll(h, &st);
	assert_int_equal(st.card_state, SH2000_STATE_RUNNING);
	assert_true(st.queue_fill < SH2000_RING_RECORDS);
	assert_int_equal(sh2000_push_point(h, p, SH2000_PUSH_END), 1);
	CHECK(sh2000_wait_idle(h, 2000));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.axis[0].cmd_counts, p[0]);
	assert_int_equal(st.card_faults, 0);
	sh2000_close(h);
}

static void test_estop_request(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	struct sh2000_port_counters c0, c1;

	(void)state;
	tick_poll(h, &st);
	CHECK(sh2000_port_counters(h, &c0));
	CHECK(sh2000_estop_request(h));
	CHECK(sh2000_port_counters(h, &c1));
	/* at most a clear and the write: nothing waited for */
	assert_int_equal(c1.data_writes - c0.data_writes, 1);
	assert_int_equal(c1.data_reads, c0.data_reads);
	assert_true(c1.clears - c0.clears <= 1);
	sh2000_sleep_ns(h, 2 * SERVO_NS);
	tick_poll(h, &st);
	assert_int_equal(st.card_state, SH2000_STATE_ESTOP);
	CHECK(sh2000_reset(h));
	sh2000_close(h);
}

/* Another program's command slot: command_start does not wait for it. */
static void test_slot_held_elsewhere(void **state)
{
	struct sh2000_sim_server *s = NULL;
	struct sh2000 *a = NULL, *b = NULL, *h;
	struct sh2000_status st;
	char name[64], dev[80], msg[256];
	int r;

	(void)state;
	snprintf(name, sizeof(name), "test-nb-%d", (int)getpid());
	snprintf(dev, sizeof(dev), "sim:%s", name);
	r = sh2000_sim_server_create(&s, name, NULL, 0, msg, sizeof(msg));
	if (r < 0)
		fail_msg("server: %s", msg);
	assert_int_equal(rt_server_start(s), 0);
	assert_int_equal(sh2000_open(&a, dev, msg, sizeof(msg)), 0);
	assert_int_equal(sh2000_open(&b, dev, msg, sizeof(msg)), 0);
	h = a;
	CHECK(sh2000_command_start(a, SH2000_CMD_NOP, 0, 0, 0));
	assert_int_equal(sh2000_command_start(b, SH2000_CMD_NOP, 0, 0, 0),
			 -EAGAIN);
	/* bounded: the library gives up at its command timeout
	 * (test_command_timeout) */
	while ((r = sh2000_command_complete(a, NULL)) == -EINPROGRESS)
		usleep(100);
	assert_int_equal(r, 0);
	h = b;
	CHECK(sh2000_command_start(b, SH2000_CMD_NOP, 0, 0, 0));
	while ((r = sh2000_command_complete(b, NULL)) == -EINPROGRESS)
		usleep(100);
	assert_int_equal(r, 0);
	/* a motion command while the other program holds the motion */
	CHECK(sh2000_claim_motion(a));
	assert_int_equal(sh2000_command_start(b, SH2000_CMD_ENABLE, 0, 0, 1),
			 -SH2000_EOWNED);
	/* and a point from a handle without the motion */
	tick_poll(b, &st);
	{
		int32_t p[SH2000_AXES] = { 0 };

		assert_int_equal(sh2000_push_point(b, p, 0), -SH2000_EOWNED);
	}
	sh2000_close(a);
	sh2000_close(b);
	sh2000_sim_server_destroy(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_poll_once_matches_poll),
		cmocka_unit_test(test_poll_once_torn_is_eagain),
		cmocka_unit_test(test_poll_once_torn_stopped),
		cmocka_unit_test(test_poll_once_heartbeat_loss),
		cmocka_unit_test(test_command_start_complete),
		cmocka_unit_test(test_command_timeout),
		cmocka_unit_test(test_push_point),
		cmocka_unit_test(test_estop_request),
		cmocka_unit_test(test_slot_held_elsewhere),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
