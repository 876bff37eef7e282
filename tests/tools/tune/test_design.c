/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune's gain design (design.c) on plants whose behaviour the test
 * computes on its own: the closed loop is simulated here in the time
 * domain, the card's incremental PID as docs/cardmodel.md writes it and
 * the plant m a = kF u - b v integrated exactly over each servo cycle with
 * the DAC held, d cycles late. The predicted gain margin must be where
 * the simulated loop turns unstable (stable at 0.9 times the margin's
 * gain, growing at 1.1 times); the loop's response at the predicted
 * crossover, from the same difference equations, must have magnitude 1
 * and the phase margin asked; the feed-forward must be the plant's
 * inverse; a margin the plant cannot give, or a bandwidth beyond a quarter
 * of the servo rate, is refused with a message.
 */
#include <complex.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "autotune.h"

#define TS 1e-4

static const struct tune_plant plant_default = {
	.g = 305175.78125, .p = 10, .d = 0, .T = TS,
};

/* the default bandwidth at a phase margin of 50 deg */
static const struct tune_design_req req50 = { 0, 50, 0 };

/* The loop simulated with the PID's gain scaled by k, from an error of
 * 1000 counts: the largest |e| in the last and in the first quarter of n
 * cycles. */
static void simulate(const struct tune_plant *pl, const struct tune_gains *g,
		     double k, int n, double *first, double *last)
{
	double x = -1000, v = 0, u = 0, e1 = 0, e2 = 0, hist[16] = { 0 };
	double a = exp(-pl->p * TS), c = pl->p > 0 ? (1 - a) / pl->p : TS;
	double e0 = pl->p > 0 ? (TS - c) / pl->p : TS * TS / 2;

	*first = *last = 0;
	for (int i = 0; i < n; i++) {
		double e = -x, du, uo;

		du = (e - e1) + (g->td / TS) * (e - 2 * e1 + e2) + (TS / g->ti) * e;
		u += k * g->kp * du;
		e2 = e1;
		e1 = e;
		/* d cycles late */
		memmove(hist + 1, hist, sizeof(double) * 15);
		hist[0] = u;
		uo = hist[pl->d];
		/* exact over the cycle with uo held: m dv/dt = kF u - b v */
		x += c * v + e0 * pl->g * uo;
		v = a * v + c * pl->g * uo;
		if (fabs(e) > 1e12) {	/* grown past any doubt */
			*last = INFINITY;
			return;
		}
		if (i < n / 4)
			*first = fmax(*first, fabs(e));
		if (i >= n - n / 4)
			*last = fmax(*last, fabs(e));
	}
}

static void design_ok(const struct tune_plant *pl, double hz, double pm,
		      struct tune_gains *g, struct tune_design_margins *m)
{
	struct tune_design_req req = { hz, pm, 0 };
	char why[256] = "";

	if (tune_design(pl, &req, g, m, why, sizeof(why)) != 0)
		fail_msg("design refused: %s", why);
}

static void check_gain_margin(const struct tune_plant *pl,
			      const struct tune_gains *g,
			      const struct tune_design_margins *m)
{
	double k = pow(10, m->gm_db / 20), f, l;

	assert_true(isfinite(k));
	simulate(pl, g, 0.9 * k, 40000, &f, &l);
	print_message("gain x %.3f: %g -> %g counts\n", 0.9 * k, f, l);
	assert_true(l < f);
	simulate(pl, g, 1.1 * k, 40000, &f, &l);
	print_message("gain x %.3f: %g -> %g counts\n", 1.1 * k, f, l);
	assert_true(l > f);
}

/* The loop's response at the crossover from the difference equations:
 * PID u(z)(1 - 1/z) = Kp[(1 + TS/Ti + Td/TS) - (1 + 2Td/TS)/z + (Td/TS)/z^2] e,
 * plant x(z)(z - 1)(z - a) = g z^-d (e0 z + (c^2 - a e0)) u with
 * c = (1-a)/p, e0 = (TS - c)/p. */
static double complex loop_at(const struct tune_plant *pl,
			      const struct tune_gains *g, double hz)
{
	double complex z = cexp(I * 2 * M_PI * hz * TS), C, P;
	double a = exp(-pl->p * TS), c = (1 - a) / pl->p, e0 = (TS - c) / pl->p;
	double kd = g->td / TS;

	C = g->kp * ((1 + TS / g->ti + kd) - (1 + 2 * kd) / z + kd / (z * z)) /
	    (1 - 1 / z);
	P = pl->g * cpow(z, -(double)pl->d) * (e0 * z + (c * c - a * e0)) /
	    ((z - 1) * (z - a));
	return C * P;
}

static void test_default_plant(void **state)
{
	struct tune_gains g;
	struct tune_design_margins m;
	double complex L;

	(void)state;
	design_ok(&plant_default, 0, 50, &g, &m);
	print_message("default: %.1f Hz, PM %.2f, GM %.2f dB; kp %g ti %g td %g\n",
		      m.wc_hz, m.pm_deg, m.gm_db, g.kp, g.ti, g.td);
	assert_true(m.stable);
	assert_true(fabs(m.pm_deg - 50) < 0.2);
	assert_true(fabs(m.wc_hz / tune_default_bandwidth(&plant_default, &req50) - 1) < 0.01);
	L = loop_at(&plant_default, &g, m.wc_hz);
	assert_true(fabs(cabs(L) - 1) < 0.01);
	assert_true(fabs(carg(L) * 180 / M_PI + 180 - 50) < 0.3);
	/* the plant's exact inverse */
	assert_true(fabs(g.kaff * plant_default.g - 1) < 1e-12);
	assert_true(fabs(g.kvff * plant_default.g / plant_default.p - 1) < 1e-12);
	check_gain_margin(&plant_default, &g, &m);
}

static void test_bandwidth_and_delay(void **state)
{
	struct tune_plant heavy = plant_default, late = plant_default;
	struct tune_gains g;
	struct tune_design_margins m;

	(void)state;
	heavy.g /= 10;
	heavy.p /= 10;
	design_ok(&heavy, 150, 60, &g, &m);
	assert_true(fabs(m.wc_hz - 150) < 1.5);
	assert_true(fabs(m.pm_deg - 60) < 0.2);
	assert_true(fabs(cabs(loop_at(&heavy, &g, m.wc_hz)) - 1) < 0.01);
	check_gain_margin(&heavy, &g, &m);
	/* two cycles of dead time: a lower default, the margin all the same */
	late.d = 2;
	assert_true(tune_default_bandwidth(&late, &req50) <
		    0.5 * tune_default_bandwidth(&plant_default, &req50));
	design_ok(&late, 0, 50, &g, &m);
	assert_true(fabs(m.pm_deg - 50) < 0.2);
	check_gain_margin(&late, &g, &m);
}

static void test_refusals(void **state)
{
	struct tune_design_req req = { 1500, 60, 0 };
	struct tune_plant none = plant_default;
	struct tune_gains g;
	struct tune_design_margins m;
	char why[256] = "";

	(void)state;
	/* the delay eats the lead a PID has at 1.5 kHz */
	assert_int_equal(tune_design(&plant_default, &req, &g, &m, why, sizeof(why)), -1);
	print_message("refused: %s\n", why);
	assert_non_null(strstr(why, "1500 Hz"));
	assert_non_null(strstr(why, "--bandwidth"));
	req.bandwidth_hz = 3000;
	assert_int_equal(tune_design(&plant_default, &req, &g, &m, why, sizeof(why)), -1);
	assert_non_null(strstr(why, "quarter of the servo rate"));
	none.g = 0;
	req.bandwidth_hz = 100;
	assert_int_equal(tune_design(&none, &req, &g, &m, why, sizeof(why)), -1);
	assert_non_null(strstr(why, "not a mass"));
}

/* The gain margin floor: kept at the default bandwidth (a lower one),
 * and named when it is what refuses a bandwidth asked. */
static void test_gain_margin_floor(void **state)
{
	struct tune_design_req req = { 0, 45.5, 12 };
	struct tune_gains g;
	struct tune_design_margins m, m8;
	char why[256] = "";

	(void)state;
	design_ok(&plant_default, 0, 45.5, &g, &m8);
	assert_int_equal(tune_design(&plant_default, &req, &g, &m, why, sizeof(why)), 0);
	print_message("GM >= 12: %.1f Hz, GM %.2f dB (default floor: %.1f Hz, %.2f dB)\n",
		      m.wc_hz, m.gm_db, m8.wc_hz, m8.gm_db);
	assert_true(m.gm_db >= 12 && m8.gm_db >= TUNE_MIN_GM_DB);
	assert_true(fabs(m.pm_deg - 45.5) < 0.2);
	assert_true(m.wc_hz < m8.wc_hz);
	check_gain_margin(&plant_default, &g, &m);
	req.bandwidth_hz = 1000;
	assert_int_equal(tune_design(&plant_default, &req, &g, &m, why, sizeof(why)), -1);
	print_message("refused: %s\n", why);
	assert_non_null(strstr(why, "below 12 dB"));
	assert_non_null(strstr(why, "--gain-margin"));
}

/* Margins of given gains, e.g. the card's defaults on their plant. */
static void test_margins_of_defaults(void **state)
{
	const struct tune_gains def = { 0.5, 0.02, 0.004, 0, 0 };
	struct tune_design_margins m;

	(void)state;
	tune_margins_of(&plant_default, &def, &m);
	print_message("card defaults: PM %.1f at %.1f Hz, GM %.1f dB\n",
		      m.pm_deg, m.wc_hz, m.gm_db);
	assert_true(m.stable);
	assert_true(fabs(cabs(loop_at(&plant_default, &def, m.wc_hz)) - 1) < 0.01);
	check_gain_margin(&plant_default, &def, &m);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_default_plant),
		cmocka_unit_test(test_bandwidth_and_delay),
		cmocka_unit_test(test_refusals),
		cmocka_unit_test(test_gain_margin_floor),
		cmocka_unit_test(test_margins_of_defaults),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
