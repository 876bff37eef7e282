// SPDX-License-Identifier: MIT
/*
 * HOME with the index flag on a gantry pair, in virtual time: each side
 * homes on its own switch, then on its own scale's index mark, and the
 * squaring moves side b by gantry_square, the offset of the two sides'
 * marks on a square beam. Wherever the pair starts (two places, and
 * skewed within what the beam takes), with steep compensation tables
 * or without, it ends at the same physical place: both sides reading 0,
 * in the mark's count; a side whose mark never comes is a fault the host
 * sees, and neither side reads HOMED.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>

#include <cmocka.h>

#include "gantry_run.h"

/* The scales: marks every mm, side a's at -0.5 mm past its switch (at 0),
 * side b's switch 0.3 mm further on and its marks too, at -0.2 mm: on a
 * square beam side b's mark is 0.3 mm (30000 counts) above side a's. */
#define SQUARE_COUNTS	30000
#define COUNTS_PER_MM	100000.0

struct homed {
	double xa_mm, xb_mm;	/* the sides' physical places (the plant) */
	int32_t act_a, act_b;	/* what they read */
	double cmd_a, cmd_b;	/* their nominal set-points (counts) */
	double peak_ferr;	/* the larger side's following error while
				 * homing and settling (counts) */
	uint16_t state_a, state_b, faults_b, card_state;
};

static void peak_ferr(struct harness *h, unsigned int cycles, struct homed *out)
{
	unsigned int i;

	for (i = 0; i < cycles; i++) {
		h_cycles(h, 1);
		out->peak_ferr = fmax(out->peak_ferr,
				      fmax(fabs(sh2000_fw_ferr(&h->fw->dsp, GR_A)),
					   fabs(sh2000_fw_ferr(&h->fw->dsp, GR_B))));
	}
}

/* HOME with the index on a pair that starts at start_a / start_b mm,
 * side b's marks every index_b mm (0: none), with the compensation tables
 * `tables` loaded first (NULL: none). */
static void home_pair(double start_a, double start_b, double index_b,
		      const char *tables, struct homed *out)
{
	static struct harness h;
	struct sh2000_sim_config cfg;
	unsigned int i;
	char msg[256];

	sh2000_sim_config_default(&cfg);
	cfg.axis[GR_A].start_mm = start_a;
	cfg.axis[GR_B].start_mm = start_b;
	cfg.axis[GR_A].index_pos_mm = 0.5;
	cfg.axis[GR_B].home_mm = 0.3;
	cfg.axis[GR_B].index_pos_mm = 0.8;
	cfg.axis[GR_B].index_period_mm = index_b;
	assert_int_equal(gantry_home_card(&h, &cfg, SQUARE_COUNTS), 0);
	assert_int_equal(h_set_f(&h, SH2000_AXIS_GLOBAL, SH2000_GP_GANTRY_TI,
				 GR_GANTRY_TI), 0);
	assert_int_equal(h_set_f(&h, SH2000_AXIS_GLOBAL, SH2000_GP_GANTRY_TD,
				 GR_GANTRY_TD), 0);
	if (tables) {
		if (h_comp_load(&h, tables, msg, sizeof(msg)))
			fail_msg("%s", msg);
		h_cycles(&h, 20000);	/* the blend in, settled */
		assert_int_equal(h_word(&h, SH2000_W_COMP_STATUS + SH2000_CS_STATE),
				 SH2000_COMP_ACTIVE);
	}
	assert_int_equal(h_cmd(&h, SH2000_CMD_HOME, GR_A, 0,
			       SH2000_HOME_F_INDEX, NULL), 0);
	out->peak_ferr = 0.0;
	for (i = 0; i < 2000000 &&
		    h_word(&h, SH2000_W_STATE) == SH2000_STATE_HOMING; i++)
		peak_ferr(&h, 1, out);
	peak_ferr(&h, 20000, out);	/* 2 s: settled */
	out->xa_mm = sh2000_board_plant(h.fw->hw, GR_A)->x_mm;
	out->xb_mm = sh2000_board_plant(h.fw->hw, GR_B)->x_mm;
	out->act_a = (int32_t)h.fw->dsp.ax[GR_A].act;
	out->act_b = (int32_t)h.fw->dsp.ax[GR_B].act;
	out->cmd_a = h.fw->dsp.ax[GR_A].cmd;
	out->cmd_b = h.fw->dsp.ax[GR_B].cmd;
	out->state_a = h_word(&h, SH2000_W_AXIS_STATE(GR_A));
	out->state_b = h_word(&h, SH2000_W_AXIS_STATE(GR_B));
	out->faults_b = h_word(&h, SH2000_W_AXIS_FAULTS(GR_B));
	out->card_state = h_word(&h, SH2000_W_STATE);
	h_fini(&h);
}

static void print_homed(const char *what, const struct homed *r)
{
	print_message("# %s: sides at %.6f and %.6f mm (%.2f and %.2f counts past the mark, yaw %.1f counts), reading %d and %d, following error %.0f counts at most\n",
		      what, r->xa_mm, r->xb_mm, (r->xa_mm + 0.5) * COUNTS_PER_MM,
		      (r->xb_mm + 0.5) * COUNTS_PER_MM,
		      (r->xa_mm - r->xb_mm) * COUNTS_PER_MM, r->act_a, r->act_b,
		      r->peak_ferr);
}

static void assert_homed_square(const struct homed *r, double mark_counts)
{
	const uint16_t both = SH2000_AXIS_HOMED | SH2000_AXIS_INDEX;

	assert_int_equal(r->card_state, SH2000_STATE_IDLE);
	assert_int_equal(r->state_a & both, both);
	assert_int_equal(r->state_b & both, both);
	/* square to a count, both sides reading home_offset (0) */
	assert_true(fabs(r->xa_mm - r->xb_mm) * COUNTS_PER_MM <= 1.0);
	assert_true(abs(r->act_a) <= 1 && abs(r->act_b) <= 1);
	/* at side a's mark: the first past its switch */
	assert_true(fabs(r->xa_mm + 0.5) * COUNTS_PER_MM <= mark_counts);
}

/* A homing as good as the sides' loops can make it: they close on the
 * counter, so at rest on a set-point of a whole count (home_offset, 0)
 * each side may be anywhere in that count and nowhere else. Both read
 * exactly 0, and both carriages are in the mark's count: from the mark
 * (x = -0.5 mm, side b's squared onto it) to less than a count above it
 * (1e-6 count for the mm-to-count conversion's rounding). */
static void assert_on_mark(const struct homed *r)
{
	double da = (r->xa_mm + 0.5) * COUNTS_PER_MM;
	double db = (r->xb_mm + 0.5) * COUNTS_PER_MM;

	assert_homed_square(r, 1.0);
	assert_int_equal(r->act_a, 0);
	assert_int_equal(r->act_b, 0);
	assert_true(da >= -1e-6 && da < 1.0);
	assert_true(db >= -1e-6 && db < 1.0);
}

/* Two starts, one of them skewed by 0.2 mm: the same physical home. */
static void test_index_home_repeats(void **state)
{
	struct homed r[3];
	unsigned int i;

	(void)state;
	home_pair(20.0, 20.0, 1.0, NULL, &r[0]);
	home_pair(57.3, 57.3, 1.0, NULL, &r[1]);
	home_pair(33.0, 33.2, 1.0, NULL, &r[2]);
	print_homed("from 20 / 20 mm", &r[0]);
	print_homed("from 57.3 / 57.3 mm", &r[1]);
	print_homed("from 33 / 33.2 mm (skewed)", &r[2]);
	for (i = 0; i < 3; i++) {
		assert_on_mark(&r[i]);
		assert_true(fabs(r[i].xa_mm - r[0].xa_mm) * COUNTS_PER_MM <= 1.0);
		assert_true(fabs(r[i].xb_mm - r[0].xb_mm) * COUNTS_PER_MM <= 1.0);
	}
}

/* Side b's scale has no mark: it creeps on to its limit switch, homing
 * fails with AXIS_FAULT_HOME, and the pair is not homed (side a's mark
 * alone does not square the beam). */
static void test_index_never_seen(void **state)
{
	struct homed r;

	(void)state;
	home_pair(20.0, 20.0, 0.0, NULL, &r);
	print_homed("side b without marks", &r);
	assert_int_equal(r.card_state, SH2000_STATE_FAULT);
	assert_true(r.faults_b & SH2000_AXIS_FAULT_HOME);
	assert_int_equal(r.state_a & SH2000_AXIS_HOMED, 0);
	assert_int_equal(r.state_b & SH2000_AXIS_HOMED, 0);
}

/* Steep tables on both sides (2000 ppm, of opposite signs, so the
 * sides' corrections differ by 4000 ppm of where they are: 8 um over
 * the 20 mm the pair starts from home: 80 um), both zero at the home:
 * homing and squaring with them loaded end where they end without tables
 * (the same physical home and readings), no fault, both nominal
 * set-points at home (0) and the beam square. Before the card kept the
 * corrected set-point through the presets, the motor came back to the
 * nominal latch (41 um off the mark here) and, when side b's homing ended
 * in the cycle of the squaring, its set-point jumped by a stale
 * correction (4088 counts) and the pair latched SKEW. Before the sides'
 * loops took a set-point within rounding of a whole count for one, the
 * preset's corrected set-point (8.9e-13 count over 0 here, 5.8e-12 from
 * the skewed start: the inversion of the tables' correction to its
 * rounding) counted as a fraction and the loops held the sides on the
 * edge of count 1, side a reading 1, 1 and 1.5 counts past the mark. */
static const char steep[] =
	"id 0x57ee9\n"
	"pitch Y\n-30 -0.06\n-20 -0.04\n-10 -0.02\n0 0\n10 0.02\n20 0.04\n30 0.06\n"
	"pitch Z\n-30 0.06\n-20 0.04\n-10 0.02\n0 -0\n10 -0.02\n20 -0.04\n30 -0.06\n";

static void test_home_with_tables(void **state)
{
	struct homed plain, r[2];
	unsigned int i;

	(void)state;
	home_pair(20.0, 20.0, 1.0, NULL, &plain);
	home_pair(20.0, 20.0, 1.0, steep, &r[0]);
	home_pair(20.0, 20.2, 1.0, steep, &r[1]);
	assert_on_mark(&plain);
	print_homed("no tables, from 20 / 20 mm", &plain);
	print_homed("steep tables, from 20 / 20 mm", &r[0]);
	print_homed("steep tables, from 20 / 20.2 mm (skewed)", &r[1]);
	for (i = 0; i < 2; i++) {
		print_message("#   nominal set-points %.3g and %.3g counts\n",
			      r[i].cmd_a, r[i].cmd_b);
		assert_int_equal(r[i].faults_b, 0);
		/* on the mark as without tables: both read 0, both in the
		 * mark's count (so within a count of where the pair homes
		 * without tables, which is in it too), the nominal set-points
		 * on 0 to the inversion's rounding (the tables are 0 there) */
		assert_on_mark(&r[i]);
		assert_true(fabs(r[i].cmd_a) <= 1e-6 && fabs(r[i].cmd_b) <= 1e-6);
		assert_true(fabs(r[i].xa_mm - plain.xa_mm) * COUNTS_PER_MM < 1.0);
		assert_true(fabs(r[i].xb_mm - plain.xb_mm) * COUNTS_PER_MM < 1.0);
		/* no set-point step at a preset: the loops follow as well as
		 * without tables (the homing's own speeds make the peak) */
		assert_true(r[i].peak_ferr <= 1.05 * plain.peak_ferr);
	}
}

/* Axis y alone (no gantry: its loop on the observer's reading, finer than
 * a count), on side a's scale, homed with the index from 20 mm with and
 * without the steep tables: the reference the pair's figures are set
 * against. */
static void home_single(const char *tables, struct homed *out)
{
	static struct harness h;
	struct sh2000_sim_config cfg;
	unsigned int i;
	char msg[256];

	sh2000_sim_config_default(&cfg);
	cfg.axis[GR_A].start_mm = 20.0;
	cfg.axis[GR_A].index_pos_mm = 0.5;
	h_init(&h, &cfg);
	assert_int_equal(h_cmd(&h, SH2000_CMD_ENABLE, 0, 0, 1u << GR_A, NULL), 0);
	if (tables) {
		if (h_comp_load(&h, tables, msg, sizeof(msg)))
			fail_msg("%s", msg);
		h_cycles(&h, 20000);
	}
	assert_int_equal(h_cmd(&h, SH2000_CMD_HOME, GR_A, 0,
			       SH2000_HOME_F_INDEX, NULL), 0);
	for (i = 0; i < 2000000 &&
		    h_word(&h, SH2000_W_STATE) == SH2000_STATE_HOMING; i++)
		h_cycles(&h, 1);
	h_cycles(&h, 20000);
	out->xa_mm = sh2000_board_plant(h.fw->hw, GR_A)->x_mm;
	out->act_a = (int32_t)h.fw->dsp.ax[GR_A].act;
	out->cmd_a = h.fw->dsp.ax[GR_A].cmd + h.fw->dsp.comp.off[GR_A];
	out->state_a = h_word(&h, SH2000_W_AXIS_STATE(GR_A));
	out->card_state = h_word(&h, SH2000_W_STATE);
	h_fini(&h);
}

static void test_single_axis(void **state)
{
	struct homed r[2];
	unsigned int i;

	(void)state;
	home_single(NULL, &r[0]);
	home_single(steep, &r[1]);
	for (i = 0; i < 2; i++) {
		print_message("# single axis %s: at %.7f mm (%.2f counts past the mark), reading %d, corrected set-point %.3g\n",
			      i ? "steep tables" : "no tables", r[i].xa_mm,
			      (r[i].xa_mm + 0.5) * COUNTS_PER_MM, r[i].act_a,
			      r[i].cmd_a);
		assert_int_equal(r[i].card_state, SH2000_STATE_IDLE);
		assert_true(r[i].state_a & SH2000_AXIS_HOMED);
		assert_int_equal(r[i].act_a, 0);
		/* its loop on the observer's reading holds the middle of the
		 * count, S + 1/2, to 0.02 count (docs/cardmodel.md) */
		assert_true(fabs((r[i].xa_mm + 0.5) * COUNTS_PER_MM - 0.5) <= 0.02);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_index_home_repeats),
		cmocka_unit_test(test_index_never_seen),
		cmocka_unit_test(test_home_with_tables),
		cmocka_unit_test(test_single_axis),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
