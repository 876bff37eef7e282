// SPDX-License-Identifier: MIT
/* The incremental PID alone (the paper's formula, clamping, rounding) and
 * its step response on the default plant. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "card_internal.h"

static void formula(void **state)
{
	struct sh2000_pid p;
	struct sh2000_pid_gains g = { 2.0, 0.01, 0.001, 0.0, 0.0, 32767 };
	double tau = 1e-4, u = 0.0, e[4] = { 10, 20, 5, -3 }, e1 = 0, e2 = 0;
	unsigned int k;

	(void)state;
	sh2000_pid_reset(&p);
	for (k = 0; k < 4; k++) {
		int16_t dac = sh2000_pid_step(&p, &g, e[k], 0, 0, tau);

		u += g.kp * ((e[k] - e1) + tau / g.ti * e[k] +
			     g.td / tau * (e[k] - 2 * e1 + e2));
		e2 = e1;
		e1 = e[k];
		assert_int_equal(dac, (int16_t)lrint(u));
	}
}

static void clamp_and_ff(void **state)
{
	struct sh2000_pid p;
	struct sh2000_pid_gains g = { 1.0, 0.0, 0.0, 0.5, 0.25, 1000 };

	(void)state;
	sh2000_pid_reset(&p);
	assert_int_equal(sh2000_pid_step(&p, &g, 5000, 0, 0, 1e-4), 1000);
	/* the accumulator was clamped too: no wind-up */
	assert_true(p.u == 1000.0);
	sh2000_pid_reset(&p);
	assert_int_equal(sh2000_pid_step(&p, &g, 0, 100, 40, 1e-4), 60);
	assert_int_equal(sh2000_pid_step(&p, &g, 0, -10000, 0, 1e-4), -1000);
	/* nothing in the accumulator from feed-forward */
	assert_true(p.u == 0.0);
}

/* u after n steps at rest (no set-point velocity or acceleration) on the
 * error e, from a reset. */
static double rest_u(double e, unsigned int n)
{
	struct sh2000_pid p;
	struct sh2000_pid_gains g = { 1.0, 0.01, 0.0, 0.0, 0.0, 32767 };
	unsigned int k;

	sh2000_pid_reset(&p);
	for (k = 0; k < n; k++)
		(void)sh2000_pid_step(&p, &g, e, 0, 0, 1e-4);
	return p.u;
}

/* At rest the loop on the counter holds a set-point between two counts on
 * the edge above it (half a count either side), one on a whole count
 * anywhere in that count. A set-point the tables' correction put on a
 * count to its rounding (a homing's end: 8.9e-13 over it) is on the
 * count: taken for a fraction, the loop pushed the carriage a count up. */
static void rest_whole_count(void **state)
{
	(void)state;
	assert_true(rest_u(0.0, 10) == 0.0);
	assert_true(rest_u(8.9e-13, 10) == 0.0);
	assert_true(rest_u(-8.9e-13, 10) == 0.0);
	/* the counter a count above such a set-point: e = -1 */
	assert_true(rest_u(8.9e-13 - 1.0, 10) == rest_u(-1.0, 10));
	assert_true(rest_u(-1.0, 10) < 0.0);
	/* a fraction a table means still holds on the edge ceil(S) */
	assert_true(rest_u(0.3, 10) == rest_u(0.5, 10));
	assert_true(rest_u(1e-5, 10) == rest_u(0.5, 10));
	assert_true(rest_u(0.3 - 1.0, 10) == rest_u(-0.5, 10));
}

static void step_response(void **state)
{
	static uint16_t ram[SH2000_RAM_WORDS];
	struct sh2000_sim_config cfg;
	struct sh2000_board *b;
	struct sh2000_pid p;
	struct sh2000_pid_gains g;
	const struct sh2000_param_info *kp = sh2000_param_lookup(SH2000_P_KP);
	double T = 1e-4, target = 1000.0, peak = 0.0, x = 0.0;
	int settle = -1;
	unsigned int k;

	(void)state;
	g.kp = kp->def;
	g.ti = sh2000_param_lookup(SH2000_P_TI)->def;
	g.td = sh2000_param_lookup(SH2000_P_TD)->def;
	g.kvff = g.kaff = 0.0;
	g.dac_limit = 32767;
	sh2000_sim_config_default(&cfg);
	assert_int_equal(sh2000_board_create(&b, ram, &cfg), 0);
	sh2000_pid_reset(&p);
	/* the loop closed through the board's registers, as the firmware
	 * closes it: counter in, DAC out, the plant runs a period */
	for (k = 0; k < 2000; k++) {	/* 200 ms */
		int16_t dac;

		x = (double)sh2000_counter_delta(
			sh2000_board_read(b, 0, SH2000_HWREG_COUNTER), 0);
		dac = sh2000_pid_step(&p, &g, target - x, 0, 0, T);
		sh2000_board_write(b, 0, SH2000_HWREG_DAC, (uint16_t)dac);
		sh2000_board_run(b, (uint64_t)(T * 1e9));
		if (x > peak)
			peak = x;
		if (fabs(target - x) > 20.0)
			settle = -1;
		else if (settle < 0)
			settle = (int)k;
	}
	printf("# step 1000 counts: overshoot %.1f%%, within 2%% after %.1f ms, final %.0f\n",
	       (peak - target) / target * 100.0, settle * T * 1e3, x);
	assert_true(peak < 1.3 * target);	/* damped */
	assert_true(settle >= 0 && settle * T < 0.05);	/* settles */
	assert_true(fabs(target - x) <= 2.0);	/* integral removes the rest */
	sh2000_board_destroy(b);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(formula),
		cmocka_unit_test(clamp_and_ff),
		cmocka_unit_test(rest_whole_count),
		cmocka_unit_test(step_response),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
