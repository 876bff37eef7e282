/* SPDX-License-Identifier: MIT */
/*
 * Protocol round trips through the library against the card model in
 * virtual time (`sim`): open, status, commands, parameters (with
 * validation that writes nothing), motion, emergency-stop latency,
 * underrun, and the port-cycle costs the model's FPGA counted.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <unistd.h>
#include <linux/capability.h>
#include <sys/syscall.h>
#include <sys/wait.h>

#include "simtest.h"

static void fpga(struct sh2000 *h, uint64_t c[4])
{
	sh2000_cardsim_counters(sh2000_sim_card(h), c);
}

static void test_open_and_status(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	struct sh2000_port_counters pc;
	uint64_t c[4];
	unsigned int a;

	(void)state;
	assert_int_equal(sh2000_backend(h), SH2000_BACKEND_SIM);
	assert_int_equal(sh2000_card_version(h), SH2000_PROTO_VERSION);
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_int_equal(st.card_faults, 0);
	assert_int_equal(st.queue_fill, 0);
	assert_int_equal(st.queue_free, SH2000_RING_RECORDS);
	assert_true(st.heartbeat_age_ns < 1000000);
	for (a = 0; a < SH2000_AXES; a++) {
		/* an incremental scale: the counters power up at 0 */
		assert_int_equal(st.axis[a].pos_counts, 0);
		assert_int_equal(st.axis[a].faults, 0);
	}
	assert_int_equal(sh2000_queue_free(h), SH2000_RING_RECORDS);
	{
		uint16_t w[8];

		CHECK(sh2000_ram_read(h, SH2000_W_MAGIC, 2, w));
		assert_int_equal(w[0], SH2000_PROTO_MAGIC);
		assert_int_equal(sh2000_ram_read(h, 1020, 8, w), -EINVAL);
		assert_non_null(strstr(sh2000_last_error(h), "outside the RAM"));
	}
	/* the library's count of its port cycles is the FPGA's */
	CHECK(sh2000_port_counters(h, &pc));
	fpga(h, c);
	assert_int_equal(pc.clears, c[0]);
	assert_int_equal(pc.increments, c[1]);
	assert_int_equal(pc.data_reads, c[2]);
	assert_int_equal(pc.data_writes, c[3]);
	sh2000_close(h);
}

static void test_costs(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	uint64_t a[4], b[4];
	int32_t p[SH2000_AXES];

	(void)state;
	CHECK(sh2000_poll(h, &st));
	fpga(h, a);
	CHECK(sh2000_poll(h, &st));
	fpga(h, b);
	print_message("poll: %llu port cycles\n",
		      (unsigned long long)(b[0] + b[1] + b[2] + b[3] -
					   a[0] - a[1] - a[2] - a[3]));
	assert_int_equal(b[0] + b[1] + b[2] + b[3] - a[0] - a[1] - a[2] - a[3],
			 96 + 71 * st.retries);
	fpga(h, a);
	CHECK(sh2000_nop(h));
	fpga(h, b);
	/* 31 cycles + 16 per re-read of the answer while the card works */
	assert_true(b[0] + b[1] + b[2] + b[3] - a[0] - a[1] - a[2] - a[3] >= 31);
	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	fpga(h, a);
	CHECK(simtest_line(h, p, 0, 10, 64, 64, SH2000_PUSH_END));
	fpga(h, b);
	print_message("push of 64 records: %llu port cycles\n",
		      (unsigned long long)(b[0] + b[1] + b[2] + b[3] -
					   a[0] - a[1] - a[2] - a[3]));
	CHECK(sh2000_wait_idle(h, 1000));
	sh2000_close(h);
}

static void test_params_round_trip(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_axis_params ap, back;
	double v;
	unsigned int id;

	(void)state;
	CHECK(sh2000_param_set(h, 1, SH2000_P_KP, 0.75));
	CHECK(sh2000_param_get(h, 1, SH2000_P_KP, &v));
	assert_true(fabs(v - 0.75) < 1e-6);
	/* user units: 250 mm/s is 2.5e7 counts/s on the card */
	CHECK(sh2000_param_set(h, 2, SH2000_P_VMAX, 250.0));
	CHECK(sh2000_param_get(h, 2, SH2000_P_VMAX, &v));
	assert_true(fabs(v - 250.0) < 1e-4);
	CHECK(sh2000_param_set(h, 2, SH2000_P_SOFT_MIN, -1.0));
	CHECK(sh2000_param_set(h, 2, SH2000_P_SOFT_MAX, 600.0));
	CHECK(sh2000_param_get(h, 2, SH2000_P_SOFT_MAX, &v));
	assert_true(fabs(v - 600.0) < 1e-9);
	CHECK(sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_HOST_TIMEOUT_MS, 250));
	CHECK(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_HOST_TIMEOUT_MS, &v));
	assert_true(v == 250);
	/* names */
	assert_int_equal(sh2000_param_id("kp"), SH2000_P_KP);
	assert_int_equal(sh2000_param_id("fine_steps"), SH2000_GP_FINE_STEPS);
	assert_int_equal(sh2000_param_id("nope"), -SH2000_EPARAM);
	assert_string_equal(sh2000_param_unit(SH2000_P_AMAX), "mm/s^2");
	/* whole axis */
	CHECK(sh2000_axis_params_get(h, 3, &ap));
	ap.v[SH2000_P_KP] = 0.6;
	ap.v[SH2000_P_SOFT_MIN] = 700.0;	/* moving the window up */
	ap.v[SH2000_P_SOFT_MAX] = 800.0;
	CHECK(sh2000_axis_params_set(h, 3, &ap));
	CHECK(sh2000_axis_params_get(h, 3, &back));
	for (id = 0; id < SH2000_AXIS_PARAMS; id++)
		assert_true(fabs(back.v[id] - ap.v[id]) <=
			    1e-6 * fabs(ap.v[id]) + 1e-5);
	ap.v[SH2000_P_SOFT_MIN] = -10.0;	/* and down again */
	ap.v[SH2000_P_SOFT_MAX] = 10.0;
	CHECK(sh2000_axis_params_set(h, 3, &ap));
	/* a new scale converts the rest of the set */
	ap.v[SH2000_P_SCALE] = 50000.0;
	CHECK(sh2000_axis_params_set(h, 3, &ap));
	CHECK(sh2000_param_get(h, 3, SH2000_P_SOFT_MAX, &v));
	assert_true(fabs(v - 10.0) < 1e-9);
	sh2000_close(h);
}

static uint64_t writes(struct sh2000 *h)
{
	uint64_t c[4];

	fpga(h, c);
	return c[3];
}

static void bad(struct sh2000 *h, int axis, unsigned int id, double v,
		const char *needle)
{
	uint64_t w0 = writes(h);
	int r = sh2000_param_set(h, axis, id, v);

	assert_int_equal(r, -SH2000_EPARAM);
	if (!strstr(sh2000_last_error(h), needle))
		fail_msg("message \"%s\" lacks \"%s\"", sh2000_last_error(h),
			 needle);
	/* soft limits read the other limit (a command), nothing else moves */
	if (id != SH2000_P_SOFT_MIN && id != SH2000_P_SOFT_MAX)
		assert_int_equal(writes(h), w0);
}

static void test_params_rejected(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_axis_params ap;
	double kp0, v;
	uint64_t w0;

	(void)state;
	CHECK(sh2000_param_get(h, 2, SH2000_P_KP, &kp0));
	bad(h, 2, SH2000_P_KP, -1.5, "axis z parameter kp: -1.5 DAC/count is outside 0..1000 DAC/count");
	bad(h, 0, SH2000_P_TI, NAN, "axis x parameter ti: nan is not a finite");
	bad(h, 0, SH2000_P_KVFF, INFINITY, "not a finite");
	bad(h, 1, SH2000_P_SCALE, 0.0, "axis y parameter scale");
	bad(h, 1, SH2000_P_VMAX, 1e40, "axis y parameter vmax");
	/* too small for a float is refused too, not rounded to 0 */
	bad(h, 1, SH2000_P_KAFF, 1e-50, "does not fit a 32-bit float");
	bad(h, 1, SH2000_P_SOFT_MIN, 1e9, "does not fit the card's 32-bit value");
	CHECK(sh2000_param_set(h, 1, SH2000_P_SOFT_MAX, 100.0));
	bad(h, 1, SH2000_P_SOFT_MIN, 200.0, "200 mm is not below soft_max (100 mm)");
	bad(h, 1, SH2000_P_DAC_RANGE, 2.5, "not an integer");
	bad(h, 1, SH2000_P_DAC_LIMIT, 40000, "outside");
	bad(h, 1, SH2000_P_HOME_VEL, 0.0, "home_vel");
	bad(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, 0, "global parameter fine_steps");
	bad(h, 1, SH2000_GP_FINE_STEPS, 10, "a global parameter");
	bad(h, SH2000_GLOBAL, SH2000_P_KP, 1, "needs an axis");
	bad(h, 0, 99, 1, "unknown");
	CHECK(sh2000_param_get(h, 2, SH2000_P_KP, &v));
	assert_true(v == kp0);
	/* a whole axis with one bad value: nothing at all is sent */
	CHECK(sh2000_axis_params_get(h, 0, &ap));
	ap.v[SH2000_P_KP] = 2.0;
	ap.v[SH2000_P_AMAX] = -5.0;
	w0 = writes(h);
	assert_int_equal(sh2000_axis_params_set(h, 0, &ap), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "axis x parameter amax"));
	assert_int_equal(writes(h), w0);
	ap.v[SH2000_P_AMAX] = 5000.0;
	ap.v[SH2000_P_SOFT_MIN] = 10.0;
	ap.v[SH2000_P_SOFT_MAX] = -10.0;
	assert_int_equal(sh2000_axis_params_set(h, 0, &ap), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "out of order"));
	assert_int_equal(writes(h), w0);
	CHECK(sh2000_param_get(h, 0, SH2000_P_KP, &v));
	assert_true(v != 2.0);
	/* the card's own check still stands behind the library's: a coarse
	 * period the fine steps do not divide */
	assert_int_equal(sh2000_param_set(h, SH2000_GLOBAL,
					  SH2000_GP_FINE_STEPS, 7),
			 -SH2000_ECMD_VALUE);
	assert_non_null(strstr(sh2000_last_error(h), "value out of range"));
	sh2000_close(h);
}

/*
 * Every parameter: just outside its protocol range and NaN are refused by
 * the library with no port write; the range's own edges are accepted by
 * the library and by the card (one table for both sides).
 */
static void test_param_table_edges(void **state)
{
	struct sh2000 *h = simtest_open();
	unsigned int id;

	(void)state;
	for (id = 0; id < SH2000_GP_END; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);
		int axis = id >= SH2000_GP_FIRST ? SH2000_GLOBAL : 1;
		double k = 1.0, lo, hi;
		int scaled;
		uint64_t w0;

		if (!p)
			continue;
		scaled = strstr(sh2000_param_unit(id), "mm") &&
			 id != SH2000_P_SCALE;
		if (scaled)
			CHECK(sh2000_param_get(h, 1, SH2000_P_SCALE, &k));
		lo = p->min_exclusive ? p->min : p->min - 1.0 - fabs(p->min) * 0.01;
		hi = p->max + 1.0 + fabs(p->max) * 0.01;
		w0 = writes(h);
		assert_int_equal(sh2000_param_set(h, axis, id, NAN), -SH2000_EPARAM);
		if (id != SH2000_P_HOME_VEL) {
			assert_int_equal(sh2000_param_set(h, axis, id, lo / k),
					 -SH2000_EPARAM);
			assert_non_null(strstr(sh2000_last_error(h), p->name));
		}
		assert_int_equal(sh2000_param_set(h, axis, id, hi / k), -SH2000_EPARAM);
		assert_int_equal(writes(h), w0);
		/* edges, where no other parameter's rule interferes */
		if (id == SH2000_P_SCALE || id == SH2000_P_SOFT_MIN ||
		    id == SH2000_P_SOFT_MAX || id == SH2000_GP_COARSE_PERIOD_US ||
		    id == SH2000_GP_FINE_STEPS)
			continue;
		if (!p->min_exclusive && id != SH2000_P_HOME_VEL)
			CHECK(sh2000_param_set(h, axis, id, p->min / k));
		CHECK(sh2000_param_set(h, axis, id, p->max / k));
		CHECK(sh2000_param_set(h, axis, id, p->def / k));
	}
	sh2000_close(h);
}

static void test_move(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	int32_t p[SH2000_AXES], start;
	double pts[3][SH2000_AXES];
	unsigned int i, a;

	(void)state;
	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	start = p[0];
	/* 10 mm at 5 mm/s on axis 0 (10 um per 2 ms coarse period) */
	CHECK(simtest_line(h, p, 0, 1000, 1000, 16, SH2000_PUSH_END));
	CHECK(sh2000_wait_idle(h, 5000));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.axis[0].cmd_counts, start + 1000 * 1000);
	assert_true(fabs(st.axis[0].pos_mm - 10.0) < 0.01);
	assert_int_equal(st.card_faults, 0);
	/* points in mm */
	for (i = 0; i < 3; i++)
		for (a = 0; a < SH2000_AXES; a++)
			pts[i][a] = st.axis[a].cmd_mm + (a == 1 ? 0.001 * (i + 1) : 0);
	assert_int_equal(sh2000_push_mm(h, (const double (*)[SH2000_AXES])pts, 3,
					SH2000_PUSH_END), 3);
	CHECK(sh2000_wait_idle(h, 1000));
	CHECK(sh2000_poll(h, &st));
	assert_true(fabs(st.axis[1].cmd_mm - 0.003) < 1e-9);
	pts[1][2] = NAN;
	assert_int_equal(sh2000_push_mm(h, (const double (*)[SH2000_AXES])pts, 3, 0),
			 -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "point 1 axis 2"));
	sh2000_close(h);
}

struct watch {
	uint64_t first_estop;
	uint64_t last_cycle;
};

static void watch_fn(void *ctx, const struct sh2000_probe *p)
{
	struct watch *w = ctx;

	w->last_cycle = p->servo_cycle;
	if (p->state == SH2000_STATE_ESTOP && !w->first_estop)
		w->first_estop = p->servo_cycle;
}

static void test_estop_latency(void **state)
{
	struct sh2000 *h = simtest_open();
	struct watch w = { 0, 0 };
	struct sh2000_probe pr;
	struct sh2000_status st;
	int32_t p[SH2000_AXES];
	uint64_t at;
	int32_t one[1][SH2000_AXES];

	(void)state;
	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	/* moving, with a full ring behind */
	CHECK(simtest_line(h, p, 0, 2000, 200, 32, 0));
	CHECK(sh2000_wait_space(h, 0, 10));
	CHECK(sh2000_sim_set_observer(h, watch_fn, &w));
	CHECK(sh2000_sim_probe(h, &pr));
	at = pr.servo_cycle;
	CHECK(sh2000_estop(h, 10));
	CHECK(sh2000_sim_probe(h, &pr));
	print_message("estop: requested after cycle %llu, acted in cycle %llu, acknowledged by cycle %llu\n",
		      (unsigned long long)at, (unsigned long long)w.first_estop,
		      (unsigned long long)pr.servo_cycle);
	assert_true(w.first_estop == at + 1);
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_ESTOP);
	assert_int_equal(st.queue_fill, 0);	/* ring discarded */
	/* latched: every push and wait says so until a reset */
	memcpy(one[0], p, sizeof(p));
	assert_int_equal(sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])one,
					    1, 0), -SH2000_EESTOP);
	assert_int_equal(sh2000_wait_idle(h, 10), -SH2000_EESTOP);
	/* words for every front end: no C function named */
	assert_non_null(strstr(sh2000_last_error(h), "; a reset clears it"));
	assert_null(strstr(sh2000_last_error(h), "sh2000_"));
	assert_int_equal(sh2000_enable(h, 1), -SH2000_ECMD_FAULTED);
	CHECK(sh2000_reset(h));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	CHECK(sh2000_sim_set_observer(h, NULL, NULL));
	sh2000_close(h);
}

struct speed {
	double vmax_seen;	/* |fine set-point step| per cycle after */
	double prev;
	int armed;
	uint64_t cycles_moving;
};

static void speed_fn(void *ctx, const struct sh2000_probe *p)
{
	struct speed *s = ctx;
	double d = fabs(p->axis[0].fine_cmd - s->prev);

	if (s->armed && d > s->vmax_seen)
		s->vmax_seen = d;
	if (d > 0)
		s->cycles_moving++;
	s->prev = p->axis[0].fine_cmd;
	s->armed = 1;
}

static void test_underrun(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	struct speed sp = { 0, 0, 0, 0 };
	int32_t p[SH2000_AXES];
	int r;

	(void)state;
	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	sp.prev = p[0];
	CHECK(sh2000_sim_set_observer(h, speed_fn, &sp));
	/* 20 mm/s and then nothing: no END flag */
	CHECK(simtest_line(h, p, 0, 4000, 40, 40, 0));
	r = sh2000_wait_idle(h, 2000);
	assert_int_equal(r, -SH2000_EUNDERRUN);
	assert_non_null(strstr(sh2000_last_error(h), "controlled stop"));
	CHECK(sh2000_sleep_ns(h, 100000000));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_FAULT);
	assert_true(st.card_faults & SH2000_FAULT_UNDERRUN);
	/* controlled: the set-point never stepped faster than the motion */
	assert_true(sp.vmax_seen <= 4000.0 / 20 * 1.05 + 1);
	/* and it came to rest without losing the axes */
	assert_true(fabs((double)st.axis[0].ferr_counts) < 2000);
	assert_int_equal(st.axis[0].faults, 0);
	assert_int_equal(sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])&p,
					    1, 0), -SH2000_EUNDERRUN);
	CHECK(sh2000_reset(h));
	CHECK(sh2000_wait_idle(h, 100));
	CHECK(sh2000_sim_set_observer(h, NULL, NULL));
	sh2000_close(h);
}

static void test_stop_and_home(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	int32_t p[SH2000_AXES];

	(void)state;
	CHECK(sh2000_enable(h, 0xf));
	simtest_cmd(h, p);
	CHECK(simtest_line(h, p, 0, 4000, 64, 64, 0));
	CHECK(sh2000_sleep_ns(h, 20000000));
	CHECK(sh2000_poll(h, &st));
	assert_true(sh2000_state_moving(st.card_state));
	CHECK(sh2000_stop(h));
	CHECK(sh2000_wait_rest(h, 1000));
	CHECK(sh2000_poll(h, &st));
	assert_false(sh2000_state_moving(st.card_state));
	assert_int_equal(st.card_faults, 0);
	assert_int_equal(st.queue_fill, 0);
	/* at rest already: at once */
	CHECK(sh2000_wait_rest(h, 0));
	/* homing axis 2 onto its switch at 0 mm, from 300 mm at 20 mm/s */
	CHECK(sh2000_param_set(h, 2, SH2000_P_HOME_VEL, -100.0));
	CHECK(sh2000_home(h, 2, 0));
	/* a homing that lasts: the wait for rest gives up, naming it */
	assert_int_equal(sh2000_wait_rest(h, 50), -SH2000_ETIMEOUT);
	assert_non_null(strstr(sh2000_last_error(h), "still homing after 0.05 s"));
	CHECK(sh2000_wait_idle(h, 10000));
	CHECK(sh2000_poll(h, &st));
	assert_true(st.axis[2].state & SH2000_AXIS_HOMED);
	assert_true(fabs(st.axis[2].pos_mm) < 0.01);
	/* set_position re-bases the 64-bit position */
	CHECK(sh2000_set_position(h, 1, -12.5));
	CHECK(sh2000_poll(h, &st));
	assert_true(fabs(st.axis[1].pos_mm + 12.5) < 1e-3);
	assert_int_equal(sh2000_home(h, 7, 0), -EINVAL);
	sh2000_close(h);
}

static void test_open_errors(void **state)
{
	struct sh2000 *h = (struct sh2000 *)1;
	char msg[256];

	(void)state;
	assert_int_equal(sh2000_open(&h, "io:0x301", msg, sizeof(msg)), -EINVAL);
	assert_null(h);
	assert_non_null(strstr(msg, "io:0x301"));
	assert_int_equal(sh2000_open(&h, "io:zz", msg, sizeof(msg)), -EINVAL);
	/* decimal is refused: 300 would be port 0x12c, another board's */
	assert_int_equal(sh2000_open(&h, "io:300", msg, sizeof(msg)), -EINVAL);
	assert_null(h);
	assert_non_null(strstr(msg, "io:300: not a port base"));
	assert_int_equal(sh2000_open(&h, "/nonexistent/sh2000-9", msg, sizeof(msg)),
			 -ENOENT);
	assert_non_null(strstr(msg, "/nonexistent/sh2000-9"));
	assert_int_equal(sh2000_open(&h, "/dev/null", msg, sizeof(msg)), -ENODEV);
	assert_non_null(strstr(msg, "not an sh2000 device"));
	assert_int_equal(sh2000_open(&h, "sim:no-such-card-here", msg, sizeof(msg)),
			 -ENOENT);
	assert_non_null(strstr(msg, "sim:no-such-card-here"));
	assert_int_equal(sh2000_open(&h, "bogus", msg, sizeof(msg)), -EINVAL);
	/* the default device comes from the environment */
	setenv(SH2000_DEVICE_ENV, "sim", 1);
	CHECK(sh2000_open(&h, NULL, msg, sizeof(msg)));
	assert_string_equal(sh2000_device(h), "sim");
	sh2000_close(h);
	unsetenv(SH2000_DEVICE_ENV);
	h = NULL;
	assert_true(sh2000_open(&h, NULL, msg, sizeof(msg)) < 0);
	assert_non_null(strstr(msg, SH2000_DEFAULT_DEVICE));
	/* io: needs CAP_SYS_RAWIO: without it the message says so. A child
	 * drops the capability (even root), so no port is ever touched. */
	{
		pid_t pid = fork();
		int status = 0;

		assert_true(pid >= 0);
		if (pid == 0) {
			struct __user_cap_header_struct hd = {
				_LINUX_CAPABILITY_VERSION_3, 0 };
			struct __user_cap_data_struct d[2];
			int r;

			memset(d, 0, sizeof(d));
			syscall(SYS_capget, &hd, d);
			d[CAP_SYS_RAWIO / 32].effective &= ~(1u << (CAP_SYS_RAWIO % 32));
			if (syscall(SYS_capset, &hd, d) < 0)
				_exit(2);
			r = sh2000_open(&h, "io:0x300", msg, sizeof(msg));
			_exit(r == -EPERM && strstr(msg, "needs CAP_SYS_RAWIO") &&
			      strstr(msg, "io:0x300") ? 0 : 1);
		}
		assert_int_equal(waitpid(pid, &status, 0), pid);
		assert_true(WIFEXITED(status));
		assert_int_equal(WEXITSTATUS(status), 0);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_open_and_status),
		cmocka_unit_test(test_costs),
		cmocka_unit_test(test_params_round_trip),
		cmocka_unit_test(test_params_rejected),
		cmocka_unit_test(test_param_table_edges),
		cmocka_unit_test(test_move),
		cmocka_unit_test(test_estop_latency),
		cmocka_unit_test(test_underrun),
		cmocka_unit_test(test_stop_and_home),
		cmocka_unit_test(test_open_errors),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
