/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune --auto's card side on the in-process `sim` card: the
 * identification (ident.c: the excitation within the bounds, the record,
 * the fit) gives back the card model's plant, the documented default
 * (kF 20 N/V, m 2 kg, b 20 N/(m/s): g = 20 * 10/32768 / 2 * 1e8 counts/s^2
 * per code, b/m 10 1/s, no dead time) and ten times the mass, within 0.5 %
 * (g) and 2 % (b/m), and leaves the axis where it started; the gains are
 * written all or none (a bad one last: the others are put back).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <sh2000/sim.h>

#include "autotune.h"
#include "ident.h"

static struct sh2000 *open_card(double mass, double friction)
{
	struct sh2000_sim_config cfg;
	struct sh2000 *h = NULL;
	char msg[256];

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].mass_kg = mass;
	cfg.axis[0].friction_ns_per_m = friction;
	if (sh2000_sim_open(&h, &cfg, msg, sizeof(msg)) < 0)
		fail_msg("sim: %s", msg);
	return h;
}

/* The plant identified within 0.5 % (g) and 2 % (b/m), the axis' set-point
 * back at its start. by_tool: the tool enables the axis (--enable) and
 * disables it after; else it is enabled before and stays so (a disabled
 * axis of the heavy, nearly frictionless plant coasts on from what is left
 * of its motion, and its set-point follows the encoder). */
static void identify(double mass, double friction, int by_tool)
{
	struct sh2000 *h = open_card(mass, friction);
	struct tune_opts o = { .axis = 0, .ferr_max_mm = 0.1, .travel_mm = 0.1,
			       .enable = by_tool };
	double g = 20.0 * (10.0 / 32768) / mass * 1e8, p = friction / mass;
	struct tune_ident_result id;
	struct sh2000_status st;

	if (!by_tool)
		assert_int_equal(sh2000_enable(h, 1u), 0);
	assert_int_equal(tune_ident(h, &o, &id), 0);
	print_message("%g kg: g %g (%g), b/m %g (%g), d %u, residual %.3f counts, %.3f mm\n",
		      mass, id.plant.g, g, id.plant.p, p, id.plant.d,
		      id.plant.resid, id.amplitude_mm);
	assert_true(fabs(id.plant.g / g - 1) < 0.005);
	assert_true(fabs(id.plant.p / p - 1) < 0.02);
	assert_int_equal(id.plant.d, 0);
	assert_true(id.amplitude_mm <= 0.1 + 1e-9 && id.amplitude_mm > 0.01);
	assert_int_equal(sh2000_poll(h, &st), 0);
	assert_int_equal(st.axis[0].cmd_counts, (int64_t)id.start);
	/* enabled for the test only, or as it was */
	assert_int_equal(!!(st.axis[0].state & SH2000_AXIS_ENABLED), !by_tool);
	sh2000_close(h);
}

static void test_default_plant(void **state)
{
	(void)state;
	identify(2.0, 20.0, 1);
}

static void test_heavy_plant(void **state)
{
	(void)state;
	identify(20.0, 20.0, 0);
}

static void same(const struct tune_gains *a, const struct tune_gains *b)
{
	/* the card keeps binary32 */
	assert_true((float)a->kp == (float)b->kp && (float)a->ti == (float)b->ti &&
		    (float)a->td == (float)b->td && (float)a->kvff == (float)b->kvff &&
		    (float)a->kaff == (float)b->kaff);
}

static void test_all_or_none(void **state)
{
	struct sh2000 *h = open_card(2.0, 20.0);
	struct tune_gains old, now, good = { 3.5, 2e-3, 7e-4, 3e-5, 3e-6 };
	struct tune_gains bad = good;
	char why[256] = "";

	(void)state;
	assert_int_equal(tune_read_gains(h, 1, &old), 0);
	bad.kaff = -1;	/* the last one written: four are on the card first */
	assert_true(tune_gains_set(h, 1, &bad, &old, why, sizeof(why)) < 0);
	print_message("refused: %s\n", why);
	assert_non_null(strstr(why, "kaff"));
	assert_int_equal(tune_read_gains(h, 1, &now), 0);
	same(&now, &old);
	assert_int_equal(tune_gains_set(h, 1, &good, &old, why, sizeof(why)), 0);
	assert_int_equal(tune_read_gains(h, 1, &now), 0);
	same(&now, &good);
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_default_plant),
		cmocka_unit_test(test_heavy_plant),
		cmocka_unit_test(test_all_or_none),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
