/* SPDX-License-Identifier: MIT */
/*
 * The identification's fit (identfit.c) on records made here: a plant
 * m a = kF u - b v integrated exactly over each servo cycle with the DAC
 * held, d cycles late, the encoder quantised to whole counts, driven by a
 * deterministic pseudo-random DAC under a weak position loop (as the
 * card's would be). The fit must give back g, b/m and d; a record without
 * motion, or too short, is refused with a message.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "autotune.h"

#define TS 1e-4
#define N 12000

static double enc[N], dac[N];

/* The record of plant (g, p, d). */
static void record(double g, double p, unsigned int d)
{
	double a = exp(-p * TS), c = (1 - a) / p, e0 = (TS - c) / p;
	double x = 0.3, v = 0, hist[8] = { 0 }, level = 0;
	uint32_t lcg = 12345;

	for (int k = 0; k < N; k++) {
		enc[k] = floor(x);
		if (k % 40 == 0) {	/* a new random level every 4 ms */
			lcg = lcg * 1664525u + 1013904223u;
			level = ((double)(lcg >> 8) / (1 << 24) - 0.5) * 400;
		}
		/* a weak loop keeps the axis near 0, as the card's would */
		dac[k] = nearbyint(level - 0.002 * enc[k]);
		memmove(hist + 1, hist, sizeof(double) * 7);
		hist[0] = dac[k];
		x += c * v + e0 * g * hist[d];
		v = a * v + c * g * hist[d];
	}
}

static void fit_ok(double g, double p, unsigned int d)
{
	struct tune_plant pl;
	char why[256] = "";

	record(g, p, d);
	if (tune_ident_fit(enc, dac, N, TS, TUNE_IDENT_DMAX, &pl, why, sizeof(why)))
		fail_msg("refused: %s", why);
	print_message("g %g (%g), b/m %g (%g), d %u (%u), residual %.3f counts\n",
		      pl.g, g, pl.p, p, pl.d, d, pl.resid);
	assert_int_equal(pl.d, d);
	assert_true(fabs(pl.g / g - 1) < 1e-3);
	assert_true(fabs(pl.p / p - 1) < 1e-2);
	/* what is left is the encoder's quantisation: 1/sqrt(12) counts */
	assert_true(pl.resid < 0.35);
	assert_true(pl.T == TS);
}

static void test_plants(void **state)
{
	(void)state;
	fit_ok(305175.78, 10, 0);
	fit_ok(30517.578, 1, 0);
	fit_ok(1e5, 50, 2);
	fit_ok(2e5, 200, 4);
}

static void test_refusals(void **state)
{
	struct tune_plant pl;
	char why[256] = "";

	(void)state;
	memset(enc, 0, sizeof(enc));
	memset(dac, 0, sizeof(dac));
	assert_int_equal(tune_ident_fit(enc, dac, N, TS, 4, &pl, why, sizeof(why)), -1);
	assert_non_null(strstr(why, "does not excite"));
	assert_int_equal(tune_ident_fit(enc, dac, 20, TS, 4, &pl, why, sizeof(why)), -1);
	assert_non_null(strstr(why, "too few"));
	/* the DAC pushing the other way than the encoder counts */
	record(1e5, 10, 0);
	for (int k = 0; k < N; k++)
		dac[k] = -dac[k];
	assert_int_equal(tune_ident_fit(enc, dac, N, TS, 4, &pl, why, sizeof(why)), -1);
	assert_non_null(strstr(why, "sign or wiring"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_plants),
		cmocka_unit_test(test_refusals),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
