/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune's figures on responses whose answers are known: a ramp
 * (rise time 80 % of it, settling where it enters the band), a second-order
 * system (overshoot exp(-zeta pi / sqrt(1 - zeta^2))), the same mirrored
 * for a negative step, and responses that never rise or never settle.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "tune.h"

#define N 20000
#define DT 1e-6

static double t[N], sp[N], enc[N], dac[N];

/* t from -1 ms, the set-point a step of `step` at 0; enc from fn. */
static struct tune_trace make(double step, double (*fn)(double, double))
{
	struct tune_trace tr = { .n = N, .t = t, .sp = sp, .enc = enc,
				 .dac = dac, .start = 0, .end = step };

	for (int i = 0; i < N; i++) {
		t[i] = (i - 1000) * DT;
		sp[i] = t[i] >= 0 ? step : 0;
		enc[i] = t[i] >= 0 ? fn(t[i], step) : 0;
		dac[i] = i == 5000 ? -123 : 0;
	}
	return tr;
}

/* 0 to the step in 1 ms, straight */
static double ramp(double x, double step)
{
	return x < 1e-3 ? step * x / 1e-3 : step;
}

#define ZETA 0.3
#define WN (2 * M_PI * 1000)

static double second_order(double x, double step)
{
	double wd = WN * sqrt(1 - ZETA * ZETA);

	return step * (1 - exp(-ZETA * WN * x) *
			       (cos(wd * x) + ZETA / sqrt(1 - ZETA * ZETA) * sin(wd * x)));
}

static void ramp_figures(void **state)
{
	struct tune_trace tr = make(1000, ramp);
	struct tune_metrics m;

	(void)state;
	assert_int_equal(tune_metrics(&tr, &m), 0);
	assert_true(fabs(m.rise_s - 0.8e-3) < 1e-9);
	assert_true(m.overshoot == 0);
	assert_int_equal(m.settled, 1);
	/* 990 counts at 0.99 ms: the first sample inside, one past 990 */
	assert_true(m.settle_s > 0.99e-3 - 1e-9 && m.settle_s <= 0.99e-3 + DT + 1e-9);
	assert_true(fabs(m.peak_ferr - 1000) < 1e-6);
	assert_true(m.peak_dac == 123);
}

static void second_order_figures(void **state)
{
	double want = 100 * exp(-ZETA * M_PI / sqrt(1 - ZETA * ZETA));

	(void)state;
	for (int sign = -1; sign <= 1; sign += 2) {
		struct tune_trace tr = make(sign * 1000.0, second_order);
		struct tune_metrics m;
		int i;

		assert_int_equal(tune_metrics(&tr, &m), 0);
		assert_true(fabs(m.overshoot_pct - want) < 0.01);
		assert_true(fabs(m.overshoot - want * 10) < 0.1);
		assert_true(m.rise_s > 0 && m.rise_s < 1e-3);
		assert_int_equal(m.settled, 1);
		/* inside the band from settle_s on, outside just before */
		for (i = 0; t[i] < m.settle_s - DT / 2; i++)
			;
		assert_true(fabs(enc[i - 1] - tr.end) > TUNE_SETTLE_COUNTS);
		for (; i < N; i++)
			assert_true(fabs(enc[i] - tr.end) <= TUNE_SETTLE_COUNTS);
	}
}

static double stuck(double x, double step)
{
	return step * 0.5 * (1 - exp(-x / 1e-4));
}

static double ringing(double x, double step)
{
	return step + 50 * sin(2 * M_PI * 2000 * x);
}

static void no_rise_no_settling(void **state)
{
	struct tune_trace tr = make(1000, stuck);
	struct tune_metrics m;

	(void)state;
	assert_int_equal(tune_metrics(&tr, &m), -1);
	assert_int_equal(m.settled, 0);
	/* ringing: passes through the band, the trace ends inside it */
	tr = make(1000, ringing);
	assert_true(fabs(tr.enc[N - 1] - tr.end) < TUNE_SETTLE_COUNTS);
	assert_int_equal(tune_metrics(&tr, &m), 0);
	assert_int_equal(m.settled, 0);
	assert_true(fabs(m.overshoot - 50) < 0.01);
	/* a step within the band: settled at once */
	tr = make(5, ramp);
	assert_int_equal(tune_metrics(&tr, &m), 0);
	assert_int_equal(m.settled, 1);
	assert_true(m.settle_s == 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ramp_figures),
		cmocka_unit_test(second_order_figures),
		cmocka_unit_test(no_rise_no_settling),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
