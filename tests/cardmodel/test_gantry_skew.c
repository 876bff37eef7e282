// SPDX-License-Identifier: MIT
/*
 * A gantry's skew fault must leave the beam at rest. The scenario is a
 * program that moves one side of the pair alone (G1 Y5 at 20 mm/s on
 * the configs/sh2000-gantry card): side a drags the beam askew until the
 * skew limit latches SKEW and holds both sides where they are, the beam
 * twisted by millimetres. Holding that twist saturates a side's DAC;
 * DAC_SAT disables it, and the beam then swings the side still held.
 * Whatever follows, within a bounded time every side of the pair is
 * either enabled and at rest or disabled with its DAC at 0, and the
 * beam's two ends stand still. The same after an emergency stop that
 * comes while the pair is held.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "gantry_run.h"

#define MM		100000.0	/* counts per mm */
#define SETTLE_S	5.0	/* from the skew fault to the beam at rest */
#define STILL_S		1.0	/* the window it must stand still in */

/* The card of configs/sh2000-gantry: gantry.params on the model's beam. */
static struct sh2000_dsp *gantry_card(struct harness *h)
{
	struct sh2000_sim_config cfg;
	unsigned int s;

	sh2000_sim_config_default(&cfg);
	assert_int_equal(gantry_home_card(h, &cfg, 0), 0);
	assert_int_equal(h_set_f(h, SH2000_AXIS_GLOBAL, SH2000_GP_GANTRY_TI,
				 GR_GANTRY_TI), 0);
	assert_int_equal(h_set_f(h, SH2000_AXIS_GLOBAL, SH2000_GP_GANTRY_TD,
				 GR_GANTRY_TD), 0);
	assert_int_equal(h_set_i(h, SH2000_AXIS_GLOBAL,
				 SH2000_GP_GANTRY_SKEW_LIMIT, 20000), 0);
	for (s = GR_A; s <= GR_B; s++)
		assert_int_equal(h_set_f(h, s, SH2000_P_KAFF, 1.5e-5), 0);
	return &h->fw->dsp;
}

/* Streams side a's 5 mm move alone until the card latches SKEW. */
static void one_side_until_skew(struct harness *h)
{
	static double x[4096];
	const double Tc = sh2000_param_lookup(SH2000_GP_COARSE_PERIOD_US)->def *
			  1e-6;
	unsigned int n = h_trapezoid(0.0, 5.0 * MM, 20.0 * MM, 5000.0 * MM, Tc,
				     x, 4096), next = 0;
	const struct sh2000_dsp *d = &h->fw->dsp;

	assert_true(n > 0 && n < 4096);
	while (!(d->ax[GR_A].faults & SH2000_AXIS_FAULT_SKEW) &&
	       d->cycle < 100000u) {
		int32_t pos[SH2000_AXES] = { 0, 0, 0, 0 };

		pos[GR_A] = (int32_t)lrint(x[next < n ? next : n - 1]);
		if (next < n && !h_push(h, pos, (uint16_t)next,
					next + 1 == n ? SH2000_REC_F_END : 0))
			next++;
		h_cycles(h, 1);
	}
	assert_true(d->ax[GR_A].faults & SH2000_AXIS_FAULT_SKEW);
	assert_true(d->ax[GR_B].faults & SH2000_AXIS_FAULT_SKEW);
	print_message("SKEW in cycle %llu, sides at %.3f and %.3f mm\n",
		      (unsigned long long)d->cycle,
		      sh2000_board_plant(h->fw->hw, GR_A)->x_mm,
		      sh2000_board_plant(h->fw->hw, GR_B)->x_mm);
}

/* Runs SETTLE_S then STILL_S; over the last, both ends of the beam stand
 * still (1 um, 0.01 mm/s) and each side is held or disabled at DAC 0. */
static void beam_comes_to_rest(struct harness *h, const char *what)
{
	const struct sh2000_dsp *d = &h->fw->dsp;
	const double Ts = (double)sh2000_fw_servo_period_ns(h->fw) * 1e-9;
	const unsigned int settle = (unsigned int)lrint(SETTLE_S / Ts),
			   still = (unsigned int)lrint(STILL_S / Ts);
	double x0[2], vmax = 0.0, dx = 0.0;
	unsigned int i, s;

	h_cycles(h, settle);
	for (s = 0; s < 2; s++)
		x0[s] = sh2000_board_plant(h->fw->hw, GR_A + s)->x_mm;
	for (i = 0; i < still; i++) {
		h_cycles(h, 1);
		for (s = 0; s < 2; s++) {
			const struct sh2000_plant *p =
				sh2000_board_plant(h->fw->hw, GR_A + s);

			vmax = fmax(vmax, fabs(p->v_mm_s));
			dx = fmax(dx, fabs(p->x_mm - x0[s]));
		}
	}
	print_message("%s: %.0f s on, sides %s/%s, DACs %d/%d; over %.0f s "
		      "more the beam's ends moved %.4f mm, at most %.4f mm/s\n",
		      what, SETTLE_S,
		      d->ax[GR_A].state & SH2000_AXIS_ENABLED ? "held" : "disabled",
		      d->ax[GR_B].state & SH2000_AXIS_ENABLED ? "held" : "disabled",
		      d->ax[GR_A].dac, d->ax[GR_B].dac, STILL_S, dx, vmax);
	for (s = GR_A; s <= GR_B; s++)
		if (!(d->ax[s].state & SH2000_AXIS_ENABLED))
			assert_int_equal(d->ax[s].dac, 0);
	assert_true(dx < 0.001);
	assert_true(vmax < 0.01);
}

static void test_skew_fault_ends_at_rest(void **state)
{
	static struct harness h;
	const struct sh2000_dsp *d = gantry_card(&h);

	(void)state;
	one_side_until_skew(&h);
	beam_comes_to_rest(&h, "skew fault");
	assert_true(d->state == SH2000_STATE_FAULT);
	h_fini(&h);
}

/* An emergency stop while the pair is held after SKEW (before a side's
 * DAC has been saturated long enough to fault): the estop suspends the
 * following-error check, so a side left held alone could be swung by
 * the beam for ever. */
static void test_estop_after_skew_ends_at_rest(void **state)
{
	static struct harness h;
	const struct sh2000_dsp *d = gantry_card(&h);

	(void)state;
	one_side_until_skew(&h);
	h_cycles(&h, 5);
	sh2000_dpram_write(h.ram, SH2000_W_ESTOP_REQ, 1);
	h_cycles(&h, 1);
	assert_int_equal(h_word(&h, SH2000_W_STATE), SH2000_STATE_ESTOP);
	beam_comes_to_rest(&h, "skew fault, then estop");
	assert_int_equal(d->state, SH2000_STATE_ESTOP);
	h_fini(&h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_skew_fault_ends_at_rest),
		cmocka_unit_test(test_estop_after_skew_ends_at_rest),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
