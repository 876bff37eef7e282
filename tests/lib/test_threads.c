/* SPDX-License-Identifier: MIT */
/*
 * Threads sharing one handle: a streaming thread and a watching thread
 * that triggers an emergency stop (which must not wait behind the
 * streamer's waits), and several threads sending commands at once (one
 * command slot, each answered to its sender).
 */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>

#include "simtest.h"
#include "sh2000_fpga.h"

struct run {
	struct sh2000 *h;
	const uint16_t *ram;	/* the card side of the RAM */
	uint16_t req0;		/* ESTOP_REQ before the test */
	int stream_result;
	int estop_result;
	uint64_t asked_cycle, acted_cycle;
	uint64_t last_unrequested;	/* last cycle that ended before the request */
	int started;		/* atomic */
};

/*
 * Runs after every servo cycle, in whichever thread holds the handle. The
 * card side of the RAM tells when the host's request landed, so the latency
 * is measured from the request itself and not from when this thread asked
 * (which the scheduler may delay by any number of the streamer's cycles).
 */
static void watch(void *ctx, const struct sh2000_probe *p)
{
	struct run *r = ctx;

	if (sh2000_dpram_read(r->ram, SH2000_W_ESTOP_REQ) == r->req0)
		r->last_unrequested = p->servo_cycle;
	if (p->state == SH2000_STATE_ESTOP && !r->acted_cycle)
		r->acted_cycle = p->servo_cycle;
}

static void *streamer(void *arg)
{
	struct run *r = arg;
	int32_t p[SH2000_AXES];
	struct sh2000 *h = r->h;

	simtest_cmd(h, p);
	__atomic_store_n(&r->started, 1, __ATOMIC_RELEASE);
	r->stream_result = simtest_line(h, p, 0, 200, 5000, 16, SH2000_PUSH_END);
	if (r->stream_result >= 0)
		r->stream_result = sh2000_wait_idle(h, 60000);
	return NULL;
}

static void test_estop_from_another_thread(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_probe pr;
	struct run r;
	pthread_t t;

	(void)state;
	memset(&r, 0, sizeof(r));
	r.h = h;
	r.ram = sh2000_cardsim_ram(sh2000_sim_card(h));
	r.req0 = sh2000_dpram_read(r.ram, SH2000_W_ESTOP_REQ);
	CHECK(sh2000_enable(h, 0xf));
	CHECK(sh2000_sim_set_observer(h, watch, &r));
	assert_int_equal(pthread_create(&t, NULL, streamer, &r), 0);
	while (!__atomic_load_n(&r.started, __ATOMIC_ACQUIRE))
		sched_yield();
	/* let it stream for a while (card time) */
	do {
		CHECK(sh2000_sim_probe(h, &pr));
	} while (pr.servo_cycle < 2000);
	r.asked_cycle = pr.servo_cycle;
	r.estop_result = sh2000_estop(h, 10);
	pthread_join(t, NULL);
	CHECK(sh2000_sim_set_observer(h, NULL, NULL));
	print_message("estop asked at cycle >= %llu, request landed after cycle %llu, acted at %llu; streamer got %d (%s)\n",
		      (unsigned long long)r.asked_cycle,
		      (unsigned long long)r.last_unrequested,
		      (unsigned long long)r.acted_cycle, r.stream_result,
		      sh2000_strerror(r.stream_result));
	assert_int_equal(r.estop_result, 0);
	assert_int_equal(r.stream_result, -SH2000_EESTOP);
	/* the card acts in the first servo cycle after the request landed,
	 * although another thread was streaming on the same handle */
	assert_true(r.acted_cycle >= r.asked_cycle);
	assert_int_equal(r.acted_cycle, r.last_unrequested + 1);
	sh2000_close(h);
}

struct cmdrun {
	struct sh2000 *h;
	unsigned int axis;
	int fails;
};

static void *commander(void *arg)
{
	struct cmdrun *c = arg;
	unsigned int i;

	for (i = 0; i < 200; i++) {
		double kp = 0.1 + 0.001 * i + 0.1 * c->axis, back;

		if (sh2000_param_set(c->h, (int)c->axis, SH2000_P_KP, kp) < 0 ||
		    sh2000_param_get(c->h, (int)c->axis, SH2000_P_KP, &back) < 0 ||
		    fabs(back - kp) > 1e-6)
			c->fails++;
		if (sh2000_poll(c->h, NULL) < 0)
			c->fails++;
	}
	return NULL;
}

static void test_commands_from_many_threads(void **state)
{
	struct sh2000 *h = simtest_open();
	struct cmdrun c[SH2000_AXES];
	pthread_t t[SH2000_AXES];
	unsigned int a;

	(void)state;
	for (a = 0; a < SH2000_AXES; a++) {
		c[a].h = h;
		c[a].axis = a;
		c[a].fails = 0;
		assert_int_equal(pthread_create(&t[a], NULL, commander, &c[a]), 0);
	}
	for (a = 0; a < SH2000_AXES; a++) {
		pthread_join(t[a], NULL);
		assert_int_equal(c[a].fails, 0);
	}
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_estop_from_another_thread),
		cmocka_unit_test(test_commands_from_many_threads),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
