// SPDX-License-Identifier: MIT
/*
 * A gantry pair on the card model, in virtual time: the beam's
 * jerk-limited move with the carriage at one end yaws with two
 * independent loops, and the card's cross-coupling loop cuts the peak yaw
 * at least tenfold with the same tuning; a jammed side latches the skew
 * fault in the cycle the encoders cross the limit and both sides stop
 * there; a fault that disables one side disables the other with it, so
 * the beam is not dragged askew; the parameters' rules.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>

#include <cmocka.h>

#include "gantry_run.h"

static const struct gantry_move beam = {
	.carriage_mm = 0.0,	/* all of the carriage on side a */
	.dist_mm = 200.0,
	.v_mm_s = 300.0,
	.a_mm_s2 = 3000.0,
	.couple = 0,
	.skew_limit = 100000,	/* 1 mm: no fault in the comparison */
	.jam_at_s = -1.0,
};

static void test_coupling_cuts_yaw(void **state)
{
	struct gantry_move m = beam;
	struct gantry_result off, on;

	(void)state;
	assert_int_equal(gantry_run(&m, &off), 0);
	m.couple = 1;
	assert_int_equal(gantry_run(&m, &on), 0);
	print_message("peak yaw: %.3f um uncoupled, %.3f um coupled (%.1fx); "
		      "peak ferr %.3f / %.3f um; jerk %.0f mm/s^3\n",
		      off.peak_yaw_um, on.peak_yaw_um,
		      off.peak_yaw_um / on.peak_yaw_um, off.peak_ferr_um,
		      on.peak_ferr_um, off.jerk_mm_s3);
	/* the uncoupled pair does yaw: the asymmetric load is felt */
	assert_true(off.peak_yaw_um > 5.0);
	assert_true(off.peak_yaw_um >= 10.0 * on.peak_yaw_um);
	/* the card saw it as skew: the encoders agree with the machine */
	assert_true(fabs(off.peak_skew_counts / 100.0 - off.peak_yaw_um) <
		    0.1 * off.peak_yaw_um + 0.02);
	assert_int_equal(off.fault_cycle, 0);
	assert_int_equal(on.fault_cycle, 0);
}

/* With the carriage in the middle, the load is symmetric: little yaw
 * either way (what is left is the beam's own joints). */
static void test_centred_carriage(void **state)
{
	struct gantry_move m = beam;
	struct gantry_result mid, end;

	(void)state;
	m.carriage_mm = 300.0;
	assert_int_equal(gantry_run(&m, &mid), 0);
	assert_int_equal(gantry_run(&beam, &end), 0);
	print_message("uncoupled peak yaw: %.3f um centred, %.3f um at the end\n",
		      mid.peak_yaw_um, end.peak_yaw_um);
	assert_true(mid.peak_yaw_um * 5.0 < end.peak_yaw_um);
}

static void test_jam_skew_fault(void **state)
{
	struct gantry_move m = beam;
	struct gantry_result r;
	char t[256];

	(void)state;
	m.couple = 1;
	m.skew_limit = 5000;	/* 50 um */
	m.jam_at_s = 0.15;	/* side b stops dead while accelerating */
	assert_int_equal(gantry_run(&m, &r), 0);
	print_message("%s\n", gantry_jam_text(&r, t, sizeof(t)));
	assert_true(r.cross_cycle > 0);
	/* the cycle that sees the crossing latches and holds both */
	assert_int_equal(r.fault_cycle, r.cross_cycle);
	assert_int_equal(r.held_cycle, r.cross_cycle);
	/* the free side was moving and is braked at once, with all its
	 * DAC has: some 13 kg from 250 mm/s at 200 N is 16 ms, 2 mm */
	assert_true(r.fault_v_mm_s > 100.0);
	assert_true(r.free_side_stop_ms > 0.0 && r.free_side_stop_ms < 25.0);
	assert_true(r.free_side_travel_mm < 3.0);
}

/* HOME on one side homes both, each on its own switch; side b's switch
 * sits 0.3 mm further on: gantry_square says so, and the beam ends
 * square with both sides reading the same. Without it, 0.3 mm of yaw. */
static double home_pair(int32_t square, int32_t *act_a, int32_t *act_b)
{
	static struct harness h;
	struct sh2000_sim_config cfg;
	unsigned int i;
	double yaw;

	sh2000_sim_config_default(&cfg);
	cfg.axis[GR_A].start_mm = cfg.axis[GR_B].start_mm = 20.0;
	cfg.axis[GR_B].home_mm = 0.3;
	assert_int_equal(gantry_home_card(&h, &cfg, square), 0);
	/* HOME on side b: both sides home */
	assert_int_equal(h_cmd(&h, SH2000_CMD_HOME, GR_B, 0, 0, NULL), 0);
	assert_true(h_word(&h, SH2000_W_AXIS_STATE(GR_A)) & SH2000_AXIS_HOMING);
	for (i = 0; i < 400000 &&
		    h_word(&h, SH2000_W_STATE) == SH2000_STATE_HOMING; i++)
		h_cycles(&h, 1);
	assert_int_equal(h_word(&h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_true(h_word(&h, SH2000_W_AXIS_STATE(GR_A)) & SH2000_AXIS_HOMED);
	assert_true(h_word(&h, SH2000_W_AXIS_STATE(GR_B)) & SH2000_AXIS_HOMED);
	h_cycles(&h, 20000);	/* 2 s: settled */
	*act_a = (int32_t)h.fw->dsp.ax[GR_A].act;
	*act_b = (int32_t)h.fw->dsp.ax[GR_B].act;
	yaw = sh2000_fw_gantry_yaw_mm(h.fw);
	h_fini(&h);
	return yaw;
}

static void test_home_squares(void **state)
{
	int32_t a, b;
	double yaw;

	(void)state;
	yaw = home_pair(0, &a, &b);
	print_message("square 0: yaw %.4f mm, sides read %d and %d counts\n",
		      yaw, a, b);
	assert_true(fabs(yaw + 0.3) < 0.0025);
	yaw = home_pair(30000, &a, &b);
	print_message("square 30000: yaw %.4f mm, sides read %d and %d counts\n",
		      yaw, a, b);
	/* each side's switch edge is sampled once a servo cycle: at the
	 * default home_vel (20 mm/s) that is 2 um of travel per side */
	assert_true(fabs(yaw) < 0.0025);
	assert_true(abs(a - b) <= 5 && abs(a) <= 200);
}

/* Side a's following-error fault in the middle of a 50 mm move of the
 * beam at 100 mm/s: as a pair, side b is disabled in the same cycle (no
 * fault bit of its own; the first-fault record names side a), both coast
 * as one beam: the beam hardly yaws. As two axes (pair 0, the same
 * machine), side b brakes under its loop while side a coasts on: side a
 * drags the beam askew until its joints stop it. The peak |yaw| from the
 * fault until both are at rest, um, into *yaw_um. */
static void ferr_on_one_side(int pair, double *yaw_um)
{
	static struct harness h;
	static double x[4096];
	const double Tc = sh2000_param_lookup(SH2000_GP_COARSE_PERIOD_US)->def * 1e-6;
	unsigned int n = h_trapezoid(0.0, 50.0 * 1e5, 100.0 * 1e5, 2000.0 * 1e5,
				     Tc, x, 4096), next = 0;
	struct sh2000_sim_config cfg;
	const struct sh2000_dsp *d;
	uint64_t at = 0;

	sh2000_sim_config_default(&cfg);
	cfg.axis[0].start_mm = 0.0;	/* the carriage at side a: asymmetric */
	assert_int_equal(gantry_home_card(&h, &cfg, 0), 0);
	d = &h.fw->dsp;
	if (!pair)
		assert_int_equal(h_set_i(&h, SH2000_AXIS_GLOBAL,
					 SH2000_GP_GANTRY_PAIR, 0), 0);
	while (!at && d->cycle < 200000u) {
		int32_t pos[SH2000_AXES] = { 0, 0, 0, 0 };

		pos[GR_A] = pos[GR_B] = (int32_t)lrint(x[next]);
		if (next < n && !h_push(&h, pos, (uint16_t)next, 0))
			next++;
		if (next == n / 2)	/* cruising */
			assert_int_equal(h_set_i(&h, GR_A, SH2000_P_FERR_LIMIT, 1), 0);
		h_cycles(&h, 1);
		if (d->ax[GR_A].faults & SH2000_AXIS_FAULT_FERR)
			at = d->cycle;
	}
	assert_true(at > 0);
	assert_true(fabs(sh2000_board_plant(h.fw->hw, GR_A)->v_mm_s) > 90.0);
	assert_int_equal(d->ax[GR_A].state & SH2000_AXIS_ENABLED, 0);
	if (pair) {
		assert_int_equal(d->ax[GR_B].state & SH2000_AXIS_ENABLED, 0);
		assert_int_equal(d->ax[GR_B].faults, 0);
		assert_int_equal(h_word(&h, SH2000_W_FIRST_FAULT + SH2000_FF_AXIS),
				 GR_A);
	} else {
		assert_true(d->ax[GR_B].state & SH2000_AXIS_ENABLED);
	}
	*yaw_um = 0.0;
	for (unsigned int i = 0; i < 100000; i++) {	/* 10 s: at rest */
		h_cycles(&h, 1);
		*yaw_um = fmax(*yaw_um, fabs(sh2000_fw_gantry_yaw_mm(h.fw)) * 1e3);
	}
	assert_true(fabs(sh2000_board_plant(h.fw->hw, GR_A)->v_mm_s) < 0.01);
	assert_true(fabs(sh2000_board_plant(h.fw->hw, GR_B)->v_mm_s) < 0.01);
	print_message("%s: FERR on side a in cycle %llu at 100 mm/s, peak yaw after it %.3f um\n",
		      pair ? "pair" : "two axes", (unsigned long long)at,
		      *yaw_um);
	h_fini(&h);
}

static void test_fault_stops_both_sides(void **state)
{
	double pair, apart;
	const double limit_um = sh2000_param_lookup(
		SH2000_GP_GANTRY_SKEW_LIMIT)->def / 1e5 * 1e3;

	(void)state;
	ferr_on_one_side(1, &pair);
	ferr_on_one_side(0, &apart);
	/* the pair coasts with the carriage's mass on one side: some yaw,
	 * well within the skew limit; dragged, 40 times that */
	assert_true(pair < 0.5 * limit_um);
	assert_true(apart > 10.0 * pair);
}

/* The pair is 0 or two axes; older cards do not know the parameters. */
static void test_pair_rule(void **state)
{
	static struct harness h;
	const struct sh2000_param_info *p =
		sh2000_param_lookup(SH2000_GP_GANTRY_PAIR);

	(void)state;
	assert_int_equal(sh2000_param_in_range(p, 0), 0);
	assert_int_equal(sh2000_param_in_range(p, 6), 0);
	assert_int_equal(sh2000_param_in_range(p, 12), 0);
	assert_int_not_equal(sh2000_param_in_range(p, 2), 0);
	assert_int_not_equal(sh2000_param_in_range(p, 7), 0);
	assert_int_equal(sh2000_param_since_minor(SH2000_GP_GANTRY_KP),
			 SH2000_PROTO_MINOR_GANTRY);
	assert_int_equal(sh2000_param_since_minor(SH2000_P_KP), 0);
	h_init(&h, NULL);
	assert_int_equal(h_set_i(&h, SH2000_AXIS_GLOBAL, SH2000_GP_GANTRY_PAIR,
				 7), SH2000_RES_BAD_VALUE);
	assert_int_equal(h_set_i(&h, 1, SH2000_GP_GANTRY_PAIR, 6),
			 SH2000_RES_BAD_AXIS);
	h_fini(&h);
}

/* A DAC at its limit counts towards DAC_SAT whichever loop put it there:
 * side a's own loop holds 60 % of the DAC (its gains 0, its output
 * kept), the coupling's integral the other half of it (a kp too small to
 * move it, no integral or derivative, output kept at the limit: +50 % on
 * side a; gantry_kp 0 would uncouple and drop it); the sum, clipped at the limit,
 * latches DAC_SAT on side a in the 200th cycle, as an axis' own
 * saturation does. Side b gets -50 % and its own loop: not saturated.
 * (Before the count included the coupling, side a's 60 % never counted.) */
static void test_dac_sat_counts_coupling(void **state)
{
	static struct harness h;
	const unsigned int G = SH2000_AXIS_GLOBAL;
	static const unsigned int zero[] = {
		SH2000_P_KP, SH2000_P_TI, SH2000_P_TD, SH2000_P_KVFF,
		SH2000_P_KAFF,
	};
	struct sh2000_sim_config cfg;
	struct sh2000_dsp *d;
	unsigned int s, i;
	double lim;

	(void)state;
	/* a heavy side a: full DAC takes it to 0.5 m/s in the 200 cycles,
	 * well within the counter's plausibility check */
	sh2000_sim_config_default(&cfg);
	cfg.axis[GR_A].mass_kg = 50.0;
	h_init(&h, &cfg);
	d = &h.fw->dsp;
	assert_int_equal(h_cmd(&h, SH2000_CMD_ENABLE, 0, 0,
			       (1 << GR_A) | (1 << GR_B), NULL), 0);
	assert_int_equal(h_set_i(&h, G, SH2000_GP_GANTRY_PAIR,
				 (1 << GR_A) | (1 << GR_B)), 0);
	assert_int_equal(h_set_i(&h, G, SH2000_GP_GANTRY_SKEW_LIMIT, 134217727), 0);
	assert_int_equal(h_set_f(&h, G, SH2000_GP_GANTRY_KP, 1e-9), 0);
	for (s = GR_A; s <= GR_B; s++)
		assert_int_equal(h_set_i(&h, s, SH2000_P_FERR_LIMIT, 134217727), 0);
	for (i = 0; i < sizeof(zero) / sizeof(zero[0]); i++)
		assert_int_equal(h_set_f(&h, GR_A, zero[i], 0.0), 0);
	lim = (double)d->ax[GR_A].prm.dac_limit;
	d->ax[GR_A].pid.u = 0.6 * lim;
	d->gantry.pid.u = lim;
	h_cycles(&h, SH2000_FW_DAC_SAT_CYCLES - 1);
	assert_int_equal(d->ax[GR_A].dac, (int16_t)lim);
	assert_int_equal(d->ax[GR_A].faults & SH2000_AXIS_FAULT_DAC_SAT, 0);
	h_cycles(&h, 1);
	assert_true(d->ax[GR_A].faults & SH2000_AXIS_FAULT_DAC_SAT);
	assert_int_equal(d->ax[GR_B].faults & SH2000_AXIS_FAULT_DAC_SAT, 0);
	h_fini(&h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_coupling_cuts_yaw),
		cmocka_unit_test(test_centred_carriage),
		cmocka_unit_test(test_jam_skew_fault),
		cmocka_unit_test(test_home_squares),
		cmocka_unit_test(test_fault_stops_both_sides),
		cmocka_unit_test(test_pair_rule),
		cmocka_unit_test(test_dac_sat_counts_coupling),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
