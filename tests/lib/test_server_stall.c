/* SPDX-License-Identifier: MIT */
/*
 * A served card whose server the system stops for longer than the host
 * timeout, with the host stopped as well (a whole machine descheduled):
 * the card's oscillator does not stop, so the server replays every cycle
 * it missed (no servo cycle lost against the host's clock), and the
 * replayed cycles do not age the host's heartbeat, which the host could
 * not write while it was stopped either (no host timeout latched). The
 * motion queued before the stall runs to its end.
 */
#include <signal.h>
#include <time.h>

#include "served.h"

#define STALL_MS	110.0	/* over the host timeout (100 ms) */
#define STEP_COUNTS	100	/* per coarse period along X */
/* Caught up: the server's wake-up latency and the poll's own time (a
 * SCHED_FIFO card wakes within 0.65 ms on a busy machine) */
#define CAUGHT_UP_MS	2.0

static uint64_t card_cycle(struct sh2000 *h, double *at_ms)
{
	struct sh2000_status st;

	CHECK(sh2000_poll(h, &st));
	*at_ms = served_now_ms();
	return st.card_cycle;
}

static void test_stall_replayed(void **state)
{
	const struct timespec stall = { 0, (long)(STALL_MS * 1e6) },
			      settle = { 0, 5000000 };
	struct served_card c;
	struct sh2000_status st;
	struct sh2000 *h;
	int32_t p[SH2000_AXES], start;
	uint64_t c0, c1;
	double t0, t1, lost_ms, coarse_us, fine, servo_ms;
	char dev[80];

	(void)state;
	served_name(dev, sizeof(dev), "stall");
	served_spawn(&c, dev);
	h = served_open(dev);
	/* the host was stopped too: its own look at the heartbeat must not
	 * call the card dead */
	sh2000_set_heartbeat_limit(h, 1000000000ull);
	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	start = p[0];
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US, &coarse_us));
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, &fine));
	servo_ms = coarse_us / 1000.0 / fine;
	/* a whole ring of motion, queued at once: it outlasts the stall */
	CHECK(simtest_line(h, p, 0, STEP_COUNTS, SH2000_RING_RECORDS,
			   SH2000_RING_RECORDS, SH2000_PUSH_END));
	nanosleep(&settle, NULL);
	c0 = card_cycle(h, &t0);
	if (kill(c.pid, SIGSTOP))
		fail_msg("SIGSTOP the server");
	nanosleep(&stall, NULL);
	if (kill(c.pid, SIGCONT))
		fail_msg("SIGCONT the server");
	CHECK(sh2000_wait_idle(h, 5000));
	/* the motion ends in card time before the replay has caught up
	 * with the host's clock: watch it catch up (a stall of D takes D) */
	do {
		nanosleep(&settle, NULL);
		c1 = card_cycle(h, &t1);
		lost_ms = (t1 - t0) - (double)(c1 - c0) * servo_ms;
	} while (lost_ms > CAUGHT_UP_MS && t1 - t0 < 20 * STALL_MS);
	printf("# %.0f ms stall: %.1f ms of the host's clock, %llu servo cycles (%.2f ms lost); %.0f ms of motion\n",
	       STALL_MS, t1 - t0, (unsigned long long)(c1 - c0), lost_ms,
	       SH2000_RING_RECORDS * coarse_us / 1000.0);
	CHECK(sh2000_poll(h, &st));
	if (st.card_faults)
		fail_msg("the card latched faults 0x%x after the stall (0x%x: host timeout)",
			 st.card_faults, SH2000_FAULT_HOST_TIMEOUT);
	assert_int_equal(st.axis[0].cmd_counts,
			 start + SH2000_RING_RECORDS * STEP_COUNTS);
	if (lost_ms > CAUGHT_UP_MS)
		fail_msg("the card lost %.2f ms of servo cycles over a %.0f ms stall of its server",
			 lost_ms, STALL_MS);
	sh2000_close(h);
	served_end(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stall_replayed),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
