// SPDX-License-Identifier: MIT
/*
 * The card's time base (protocol 1.1): a feed hold set while the ring is
 * full starts decelerating within one servo cycle of the request, comes
 * to rest on the path without consuming a record, stays within the axes'
 * acceleration limit, resumes on request and the motion ends exactly where
 * its records say; an override below full rate slows the motion in the
 * same way.
 */
#include <math.h>
#include <stdlib.h>

#include "simtest.h"

#define SCALE	100000.0	/* counts per mm (the default) */
#define TC	0.002		/* coarse period, s */

struct trace {
	double x[2], v[2];	/* last set-point and velocity of X and Y */
	uint64_t cycle, n;
	double vmax, amax_seen, path_err;
	uint64_t first_slow;	/* first cycle X slowed down */
	double slow_from;	/* after this cycle, counts/s */
	int watch;
};

static void observe(void *ctx, const struct sh2000_probe *p)
{
	struct trace *t = ctx;
	double x = p->axis[0].fine_cmd, y = p->axis[1].fine_cmd;
	double tau = 1e-4, v = (x - t->x[0]) / tau, vy = (y - t->x[1]) / tau;

	if (t->n >= 1) {
		if (t->n >= 2) {
			t->amax_seen = fmax(t->amax_seen, fabs(v - t->v[0]) / tau);
			t->amax_seen = fmax(t->amax_seen, fabs(vy - t->v[1]) / tau);
		}
		if (t->watch && !t->first_slow && v < t->v[0] - 1.0 &&
		    p->servo_cycle > t->cycle)
			t->first_slow = p->servo_cycle;
		t->vmax = fmax(t->vmax, v);
	}
	/* on the path: Y is half of X from where both started */
	t->path_err = fmax(t->path_err, fabs(y - 0.5 * x));
	t->x[0] = x;
	t->x[1] = y;
	t->v[0] = v;
	t->v[1] = vy;
	t->cycle = p->servo_cycle;
	t->n++;
}

#define RECORDS 500	/* the whole motion */
#define RAMP	100	/* records of its ramps up and down */
#define SPEED	200.0	/* mm/s between them */

/* X at record k: a ramp to SPEED, the cruise, a ramp down to rest at
 * record RECORDS (1000 mm/s^2). */
static double profile(size_t k)
{
	double t = (double)k * TC, ta = RAMP * TC, a = SPEED / ta;
	double td = (double)(RECORDS - RAMP) * TC, x;

	if (t <= ta)
		return 0.5 * a * t * t;
	x = 0.5 * a * ta * ta + SPEED * (fmin(t, td) - ta);
	if (t > td)
		x += SPEED * (t - td) - 0.5 * a * (t - td) * (t - td);
	return x;
}

/* Push records k0..k1-1 of the motion (the last one with END if end). */
static void push_range(struct sh2000 *h, size_t k0, size_t k1, int end)
{
	int32_t pts[16][SH2000_AXES];

	while (k0 < k1) {
		size_t n = k1 - k0 < 16 ? k1 - k0 : 16, i;

		CHECK(sh2000_wait_space(h, (unsigned int)n, 10000));
		for (i = 0; i < n; i++) {
			double x = profile(k0 + i);

			memset(pts[i], 0, sizeof(pts[i]));
			pts[i][0] = (int32_t)llround(x * SCALE);
			pts[i][1] = (int32_t)llround(0.5 * x * SCALE);
		}
		CHECK(sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])pts,
					 n, end && k0 + n == k1 ?
					 SH2000_PUSH_END : 0));
		k0 += n;
	}
}

/* Let ms of card time pass, the host beating as a host does. */
static void wait_ms(struct sh2000 *h, unsigned int ms)
{
	struct sh2000_status st;

	for (unsigned int i = 0; i < ms; i++) {
		CHECK(sh2000_sleep_ns(h, 1000000ull));
		CHECK(sh2000_poll(h, &st));
	}
}

static void test_feed_hold(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	struct trace t;
	uint64_t asked;
	unsigned int fill;
	double held;

	(void)state;
	memset(&t, 0, sizeof(t));
	CHECK(sh2000_sim_set_observer(h, observe, &t));
	CHECK(sh2000_enable(h, 0x3));
	/* a ramp to 200 mm/s and well into the cruise, the ring full */
	push_range(h, 1, 300, 0);
	CHECK(sh2000_poll(h, &st));
	fill = st.queue_fill;
	assert_true(fill > 32);
	/* hold: from the last cycle before the request */
	asked = t.cycle;
	t.watch = 1;
	CHECK(sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_TIME_SCALE, 0));
	wait_ms(h, 400);
	CHECK(sh2000_poll(h, &st));
	print_message("hold: %u records queued; deceleration began %llu servo cycles after the request; at rest with %u queued\n",
		      fill, (unsigned long long)(t.first_slow - asked),
		      st.queue_fill);
	/* within one servo cycle of the request landing (it lands in the
	 * cycle after the last one seen) */
	assert_true(t.first_slow > 0 && t.first_slow - asked <= 2);
	assert_true(fabs(t.v[0]) < 1e-6);	/* at rest */
	assert_int_equal(st.card_state, SH2000_STATE_RUNNING);
	assert_true(st.queue_fill > 0);
	assert_int_equal(st.card_faults, 0);
	held = t.x[0];
	wait_ms(h, 100);
	assert_true(t.x[0] == held);		/* held */
	/* resume and finish: the end point exactly */
	CHECK(sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_TIME_SCALE,
			       SH2000_TIME_SCALE_FULL));
	push_range(h, 300, RECORDS + 1, 1);
	CHECK(sh2000_wait_idle(h, 10000));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_faults, 0);
	assert_int_equal(st.axis[0].cmd_counts,
			 (int32_t)llround(profile(RECORDS) * SCALE));
	print_message("hold and resume: largest acceleration %.0f mm/s^2 (amax %.0f), off the path %.3f counts\n",
		      t.amax_seen / SCALE, 5e8 / SCALE, t.path_err);
	assert_true(t.amax_seen <= 5e8 * 1.001);
	assert_true(t.path_err <= 1.0);
	sh2000_close(h);
}

static void test_override(void **state)
{
	struct sh2000 *h = simtest_open();
	struct trace t;
	double v;

	(void)state;
	memset(&t, 0, sizeof(t));
	CHECK(sh2000_sim_set_observer(h, observe, &t));
	CHECK(sh2000_enable(h, 0x3));
	push_range(h, 1, 200, 0);
	CHECK(sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_TIME_SCALE, 2500));
	wait_ms(h, 300);
	v = t.v[0] / SCALE;
	print_message("override 25 %%: %.3f mm/s of 200\n", v);
	assert_true(fabs(v - 50.0) < 0.01);
	/* a bad value is refused and changes nothing */
	assert_int_equal(sh2000_param_set(h, SH2000_GLOBAL,
					  SH2000_GP_TIME_SCALE, 10001),
			 -SH2000_EPARAM);
	CHECK(sh2000_param_set(h, SH2000_GLOBAL, SH2000_GP_TIME_SCALE,
			       SH2000_TIME_SCALE_FULL));
	push_range(h, 200, RECORDS + 1, 1);
	CHECK(sh2000_wait_idle(h, 10000));
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_feed_hold),
		cmocka_unit_test(test_override),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
