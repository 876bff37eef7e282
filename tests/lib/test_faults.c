/* SPDX-License-Identifier: MIT */
/*
 * Every fault the card model can inject surfaces through the library as
 * its documented error (docs/library.md, "Errors"), and the heartbeat
 * watch reports a stopped DSP within SH2000_HEARTBEAT_LIMIT_NS.
 */
#include <errno.h>
#include <math.h>

#include "simtest.h"

static struct sh2000 *moving_card(int32_t p[SH2000_AXES])
{
	struct sh2000 *h = simtest_open();

	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	return h;
}

/* Poll every 200 us until the poll fails; returns ns it took. */
static uint64_t until_poll_fails(struct sh2000 *h, int *code)
{
	struct sh2000_status st;
	uint64_t t0 = sh2000_now_ns(h);
	int r;

	while ((r = sh2000_poll(h, &st)) == 0 &&
	       sh2000_now_ns(h) - t0 < 1000000000ull)
		sh2000_sleep_ns(h, 200000);
	*code = r;
	return sh2000_now_ns(h) - t0;
}

static void heartbeat_case(enum sh2000_inject what)
{
	struct sh2000 *h = simtest_open();
	int32_t p[SH2000_AXES];
	uint64_t dt;
	int r;

	CHECK(sh2000_poll(h, NULL));
	CHECK(sh2000_sim_inject(h, what, 0, 0));
	dt = until_poll_fails(h, &r);
	print_message("%s: detected after %.2f ms\n",
		      what == SH2000_INJECT_DSP_STALL ? "DSP stall" :
		      "heartbeat stop", dt / 1e6);
	assert_int_equal(r, -SH2000_EHEARTBEAT);
	assert_non_null(strstr(sh2000_last_error(h), "heartbeat stuck"));
	/* within the bound: the limit plus one poll interval */
	assert_true(dt >= SH2000_HEARTBEAT_LIMIT_NS - 200000);
	assert_true(dt <= SH2000_HEARTBEAT_LIMIT_NS + 500000);
	/* pushes and waits say so too */
	memset(p, 0, sizeof(p));
	assert_int_equal(sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])&p,
					    1, 0), -SH2000_EHEARTBEAT);
	assert_int_equal(sh2000_wait_idle(h, 50), -SH2000_EHEARTBEAT);
	if (what == SH2000_INJECT_DSP_STALL)	/* nobody answers commands */
		assert_int_equal(sh2000_nop(h), -SH2000_EHEARTBEAT);
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_CLEAR, 0, 0));
	CHECK(sh2000_sleep_ns(h, 200000));
	CHECK(sh2000_poll(h, NULL));
	sh2000_close(h);
}

static void test_heartbeat_stop(void **state)
{
	(void)state;
	heartbeat_case(SH2000_INJECT_HEARTBEAT_STOP);
}

static void test_dsp_stall(void **state)
{
	(void)state;
	heartbeat_case(SH2000_INJECT_DSP_STALL);
}

/*
 * The 16-bit heartbeat wraps every 2^16 servo cycles (6.5536 s at 100 us):
 * a host that polls that rarely can find the very value it saw last time
 * on a card that ran all along. That is not a stopped DSP; a stopped one
 * found after such a gap is still reported, within the limit.
 */
static void test_heartbeat_wrap(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	double coarse_us, fine;
	uint64_t servo_ns, t0;
	uint16_t hb0, hb;
	int r;

	(void)state;
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US,
			       &coarse_us));
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, &fine));
	servo_ns = (uint64_t)(coarse_us * 1000.0 / fine);
	CHECK(sh2000_poll(h, &st));
	hb0 = st.heartbeat;
	/* a little less than one wrap, then to the cycle that shows hb0 again */
	CHECK(sh2000_sleep_ns(h, 65536ull * servo_ns - 20 * servo_ns));
	do {
		CHECK(sh2000_sleep_ns(h, servo_ns / 10));
		CHECK(sh2000_ram_read(h, SH2000_W_HEARTBEAT, 1, &hb));
	} while (hb != hb0);
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.heartbeat, hb0);	/* the case under test */
	assert_true(st.heartbeat_age_ns < SH2000_HEARTBEAT_LIMIT_NS);

	/* a DSP that stalls during such a gap is still reported */
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_DSP_STALL, 0, 0));
	CHECK(sh2000_sleep_ns(h, 65536ull * servo_ns));
	t0 = sh2000_now_ns(h);
	r = sh2000_poll(h, &st);
	if (r == 0)
		r = sh2000_poll(h, &st);
	assert_int_equal(r, -SH2000_EHEARTBEAT);
	assert_true(sh2000_now_ns(h) - t0 <= SH2000_HEARTBEAT_LIMIT_NS + 500000);
	sh2000_close(h);
}

static void test_jam(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);

	(void)state;
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_JAM, 1, 0));
	assert_int_equal(simtest_line(h, p, 1, 2000, 200, 32, SH2000_PUSH_END) < 0 ?
			 -SH2000_EFERR : sh2000_wait_idle(h, 2000),
			 -SH2000_EFERR);
	assert_non_null(strstr(sh2000_last_error(h), "axis y: following error"));
	/* the card disabled y: its following error now is 0 and the fault
	 * record keeps none at the trip; the message says that, no 0 mm */
	assert_non_null(strstr(sh2000_last_error(h),
			       "passed ferr_limit and the card disabled the axis; its value at the trip is not kept"));
	assert_null(strstr(sh2000_last_error(h), "following error now"));
	sh2000_close(h);
}

static void test_limit(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);

	(void)state;
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_LIMIT, 3, 1));
	CHECK(sh2000_sleep_ns(h, 1000000));
	assert_int_equal(sh2000_wait_idle(h, 100), -SH2000_EHARD_LIMIT);
	assert_non_null(strstr(sh2000_last_error(h), "axis a: limit switch"));
	/* reset clears the latch; the switch is still active though */
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_CLEAR, 0, 0));
	CHECK(sh2000_reset(h));
	CHECK(sh2000_wait_idle(h, 100));
	sh2000_close(h);
}

static void test_counter_glitch(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);

	(void)state;
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_COUNTER_GLITCH, 0, 0));
	CHECK(sh2000_sleep_ns(h, 1000000));
	assert_int_equal(sh2000_wait_idle(h, 100), -SH2000_ECOUNTER);
	assert_non_null(strstr(sh2000_last_error(h), "axis x: counter"));
	sh2000_close(h);
}

static void test_drop_segment(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);
	char want[64];
	int r;

	(void)state;
	CHECK(simtest_line(h, p, 0, 100, 10, 10, 0));
	CHECK(sh2000_sleep_ns(h, 5000000));	/* a few consumed */
	/* the write of the next record the library pushes is lost */
	snprintf(want, sizeof(want), "segment %llu ",
		 (unsigned long long)sh2000_next_segment(h));
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_DROP_SEGMENT, 0, 0));
	r = simtest_line(h, p, 0, 100, 100, 10, SH2000_PUSH_END);
	if (r >= 0)
		r = sh2000_wait_idle(h, 1000);
	assert_int_equal(r, -SH2000_EREJECTED);
	assert_non_null(strstr(sh2000_last_error(h), "record dropped"));
	assert_non_null(strstr(sh2000_last_error(h), want));
	sh2000_close(h);
}

static void test_ram_flip_record(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);
	uint64_t last;
	unsigned int slot;
	char want[64];

	(void)state;
	CHECK(simtest_line(h, p, 0, 100, 40, 40, SH2000_PUSH_END));
	last = sh2000_next_segment(h) - 1;
	slot = (unsigned int)(last % SH2000_RING_RECORDS);
	/* corrupt the last queued record (still far from the card) */
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_RAM_FLIP, 0,
				SH2000_W_RING_BASE + slot * SH2000_RECORD_WORDS +
				SH2000_REC_POS_LO(0)));
	assert_int_equal(sh2000_wait_idle(h, 1000), -SH2000_EREJECTED);
	snprintf(want, sizeof(want), "segment %llu ", (unsigned long long)last);
	assert_non_null(strstr(sh2000_last_error(h), want));
	assert_non_null(strstr(sh2000_last_error(h), "checksum"));
	sh2000_close(h);
}

static void test_ram_flip_magic(void **state)
{
	struct sh2000 *h = simtest_open();

	(void)state;
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_RAM_FLIP, 0, SH2000_W_MAGIC));
	assert_int_equal(sh2000_poll(h, NULL), -SH2000_EMAGIC);
	assert_non_null(strstr(sh2000_last_error(h), "0x5358"));
	sh2000_close(h);
}

static void test_host_timeout(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);
	double to;

	(void)state;
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_HOST_TIMEOUT_MS, &to));
	/* a 128 ms motion, and a host that goes silent (no poll, no push) */
	CHECK(simtest_line(h, p, 0, 100, 64, 64, SH2000_PUSH_END));
	CHECK(sh2000_sleep_ns(h, (uint64_t)(to + 5) * 1000000ull));
	assert_int_equal(sh2000_wait_idle(h, 1000), -SH2000_EHOST_TIMEOUT);
	CHECK(sh2000_reset(h));
	/* a host that keeps waiting keeps beating: no timeout */
	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	CHECK(simtest_line(h, p, 0, 100, 64, 64, SH2000_PUSH_END));
	CHECK(sh2000_wait_idle(h, 1000));
	sh2000_close(h);
}

static void test_dac_saturation(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);

	(void)state;
	CHECK(sh2000_param_set(h, 2, SH2000_P_DAC_LIMIT, 5));
	CHECK(sh2000_param_set(h, 2, SH2000_P_FERR_LIMIT, 1000.0));
	assert_int_equal(simtest_line(h, p, 2, 20000, 60, 30, SH2000_PUSH_END) < 0 ?
			 -SH2000_EDAC_SAT : sh2000_wait_idle(h, 2000),
			 -SH2000_EDAC_SAT);
	assert_non_null(strstr(sh2000_last_error(h), "axis z: DAC saturation"));
	sh2000_close(h);
}

static void test_soft_limit_record(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);

	(void)state;
	CHECK(sh2000_param_set(h, 0, SH2000_P_SOFT_MAX, 0.005));
	assert_int_equal(simtest_line(h, p, 0, 100, 60, 30, SH2000_PUSH_END) < 0 ?
			 -SH2000_EREJECTED : sh2000_wait_idle(h, 2000),
			 -SH2000_EREJECTED);
	assert_non_null(strstr(sh2000_last_error(h), "soft limit"));
	sh2000_close(h);
}

static void test_velocity_record(void **state)
{
	int32_t p[SH2000_AXES];
	struct sh2000 *h = moving_card(p);

	(void)state;
	/* 1 mm per 2 ms = 500 mm/s > vmax 400 mm/s */
	assert_int_equal(simtest_line(h, p, 0, 100000, 3, 3, SH2000_PUSH_END),
			 3);
	assert_int_equal(sh2000_wait_idle(h, 100), -SH2000_EREJECTED);
	assert_non_null(strstr(sh2000_last_error(h), "segment 0 "));
	assert_non_null(strstr(sh2000_last_error(h), "max velocity"));
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_heartbeat_stop),
		cmocka_unit_test(test_dsp_stall),
		cmocka_unit_test(test_heartbeat_wrap),
		cmocka_unit_test(test_jam),
		cmocka_unit_test(test_limit),
		cmocka_unit_test(test_counter_glitch),
		cmocka_unit_test(test_drop_segment),
		cmocka_unit_test(test_ram_flip_record),
		cmocka_unit_test(test_ram_flip_magic),
		cmocka_unit_test(test_host_timeout),
		cmocka_unit_test(test_dac_saturation),
		cmocka_unit_test(test_soft_limit_record),
		cmocka_unit_test(test_velocity_record),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
