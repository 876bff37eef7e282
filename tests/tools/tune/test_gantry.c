/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune --gantry's measurement (tune_gantry) on the in-process card
 * made a gantry (sh2000_fw_set_gantry: sides y and z, the carriage on x
 * near side y) with the pair of configs/sh2000-gantry: the skew the
 * uncoupled ramp gathers is the beam's yaw the card model had, the
 * coupling cuts it at least tenfold, and the card is left as it was (the
 * coupling's gains, both sides' limits, set-points and enables). A card
 * without a pair, or an axis that is not a side, moves nothing.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include <sh2000/sim.h>

#include "autotune.h"
#include "gantry_run.h"
#include "tune.h"

#define G	SH2000_GLOBAL
#define SIDE_A	1u
#define SIDE_B	2u

/* configs/sh2000-gantry/gantry.params */
static const double pair_params[][2] = {
	{ SH2000_GP_GANTRY_PAIR, 6 },
	{ SH2000_GP_GANTRY_KP, 5 },
	{ SH2000_GP_GANTRY_TI, 0.005 },
	{ SH2000_GP_GANTRY_TD, 0.002 },
	{ SH2000_GP_GANTRY_SKEW_LIMIT, 20000 },
};

/* The largest |yaw| of the machine, counts, over every servo cycle. */
struct yaw_log {
	struct sh2000_fw *fw;
	double peak;
};

static void log_yaw(void *ctx, const struct sh2000_probe *p)
{
	struct yaw_log *l = ctx;
	double y = fabs(sh2000_fw_gantry_yaw_mm(l->fw)) * 1e5;

	(void)p;
	if (y > l->peak)
		l->peak = y;
}

/* The in-process card as a gantry, the carriage carriage_mm from side a,
 * the beam's joints stiffness_n_per_m (0: the model's default). */
static struct sh2000 *open_machine(int pair, struct sh2000_fw **fw,
				   double carriage_mm, double stiffness_n_per_m)
{
	struct sh2000_sim_config cfg;
	struct sh2000_gantry_config g;
	struct sh2000 *h = NULL;
	char msg[256];

	sh2000_tool_init("test_gantry");
	sh2000_sim_config_default(&cfg);
	cfg.axis[0].start_mm = carriage_mm;
	assert_int_equal(sh2000_sim_open(&h, &cfg, msg, sizeof(msg)), 0);
	*fw = sh2000_cardsim_fw(sh2000_sim_card(h));
	sh2000_gantry_config_default(&g);
	if (stiffness_n_per_m > 0)
		g.stiffness_n_per_m = stiffness_n_per_m;
	assert_int_equal(sh2000_fw_set_gantry(*fw, &g), 0);
	/* the sides tuned for what they carry, as the card model's gantry
	 * test tunes them: the acceleration feed-forward for 9 kg (the
	 * default is for 2), 2000 mm/s^2 (configs/sh2000-gantry's) */
	for (unsigned int s = SIDE_A; s <= SIDE_B; s++) {
		assert_int_equal(sh2000_param_set(h, s, SH2000_P_KAFF,
			sh2000_param_lookup(SH2000_P_KAFF)->def * 9 / 2), 0);
		assert_int_equal(sh2000_param_set(h, s, SH2000_P_AMAX, 2000), 0);
	}
	for (size_t i = 0; pair && i < sizeof(pair_params) / sizeof(pair_params[0]); i++)
		assert_int_equal(sh2000_param_set(h, G, (unsigned int)pair_params[i][0],
						  pair_params[i][1]), 0);
	return h;
}

/* The carriage 20 mm from side a, where it loads side a most. */
static struct sh2000 *open_gantry(int pair, struct sh2000_fw **fw)
{
	return open_machine(pair, fw, 20, 0);
}

/* What the test must leave as it was: the sides' limits and set-points,
 * their enables, the coupling's gains. */
static void card_state(struct sh2000 *h, double v[10])
{
	struct sh2000_status st;
	unsigned int k = 0;

	for (unsigned int s = SIDE_A; s <= SIDE_B; s++) {
		assert_int_equal(sh2000_param_get(h, s, SH2000_P_FERR_LIMIT, &v[k++]), 0);
		assert_int_equal(sh2000_param_get(h, s, SH2000_P_DAC_LIMIT, &v[k++]), 0);
	}
	for (unsigned int i = 1; i <= 3; i++)
		assert_int_equal(sh2000_param_get(h, G, (unsigned int)pair_params[i][0],
						  &v[k++]), 0);
	assert_int_equal(sh2000_poll(h, &st), 0);
	v[k++] = (double)st.axis[SIDE_A].cmd_counts;
	v[k++] = (double)st.axis[SIDE_B].cmd_counts;
	v[k] = (double)(st.axis[SIDE_A].state & st.axis[SIDE_B].state & SH2000_AXIS_ENABLED);
}

static void coupling_cuts_the_yaw(void **state)
{
	struct tune_opts o = { .axis = SIDE_B, .ferr_max_mm = 0.1, .enable = 1 };
	struct sh2000_fw *fw;
	struct sh2000 *h = open_gantry(1, &fw);
	struct yaw_log l = { .fw = fw };
	struct tune_gantry p;
	double before[10], after[10];

	(void)state;
	card_state(h, before);
	assert_int_equal(sh2000_sim_set_observer(h, log_yaw, &l), 0);
	assert_int_equal(tune_gantry(h, &o, &p), 0);
	sh2000_sim_set_observer(h, NULL, NULL);
	tune_gantry_end(h, &p);
	card_state(h, after);
	printf("# gantry ramp %g mm/s over %g mm at %g mm/s^2: peak skew coupled %.1f counts, uncoupled %.1f counts (the machine's peak yaw %.1f counts): %.1fx\n",
	       p.speed_mms, p.travel_mm, p.accel_mms2, p.coupled, p.uncoupled,
	       l.peak, p.uncoupled / p.coupled);
	assert_int_equal(p.a, SIDE_A);
	assert_int_equal(p.b, SIDE_B);
	assert_true(p.speed_mms == 100);
	/* the uncoupled ramp has the largest yaw of both: the record's skew
	 * is that yaw, to the encoder's quantisation */
	assert_true(p.uncoupled > 100);
	assert_true(fabs(p.uncoupled - l.peak) <= 2);
	assert_true(p.coupled * 10 <= p.uncoupled);
	for (int i = 0; i < 10; i++)
		assert_true(after[i] == before[i]);
	sh2000_close(h);
}

/* gantry_kp 0: the uncoupled ramp only. */
static void uncoupled_only(void **state)
{
	struct tune_opts o = { .axis = SIDE_A, .ferr_max_mm = 0.1, .enable = 1,
			       .ramp_mms = -50 };
	struct sh2000_fw *fw;
	struct sh2000 *h = open_gantry(1, &fw);
	struct tune_gantry p;

	(void)state;
	assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_KP, 0), 0);
	assert_int_equal(tune_gantry(h, &o, &p), 0);
	tune_gantry_end(h, &p);
	assert_true(isnan(p.coupled));
	assert_true(p.uncoupled > 10);
	assert_true(p.speed_mms == -50);
	sh2000_close(h);
}

/* No pair, or not a side: refused before anything moves. */
static void refused(void **state)
{
	struct tune_opts o = { .axis = SIDE_A, .ferr_max_mm = 0.1, .enable = 1 };
	struct sh2000_fw *fw;
	struct sh2000 *h = open_gantry(0, &fw);
	struct sh2000_status st;
	struct tune_gantry p;

	(void)state;
	assert_int_equal(tune_gantry(h, &o, &p), SH2000_EXIT_CARD);
	tune_gantry_end(h, &p);
	assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_PAIR, 6), 0);
	o.axis = 0;
	assert_int_equal(tune_gantry(h, &o, &p), SH2000_EXIT_CARD);
	tune_gantry_end(h, &p);
	assert_int_equal(sh2000_poll(h, &st), 0);
	assert_int_equal(st.axis[SIDE_A].state & SH2000_AXIS_ENABLED, 0);
	assert_int_equal(st.axis[0].state & SH2000_AXIS_ENABLED, 0);
	sh2000_close(h);
}

/* The card's coupling gains: kp, ti, td. */
static void read_gains(struct sh2000 *h, double k[3])
{
	for (unsigned int i = 0; i < 3; i++)
		assert_int_equal(sh2000_param_get(h, G, tune_gantry_gain_ids[i], &k[i]), 0);
}

/* The card model's benchmark move (cardmodel_gantry, bench_gantry: 200 mm
 * of the beam, jerk-limited, the carriage at side a's end): its peak yaw,
 * um, with gains k (NULL: uncoupled). */
static double bench_yaw(const double *k)
{
	struct gantry_move m = {
		.carriage_mm = 0.0, .dist_mm = 200.0, .v_mm_s = 300.0,
		.a_mm_s2 = 3000.0, .couple = k != NULL, .gains = k,
		.skew_limit = 100000, .jam_at_s = -1.0,
	};
	struct gantry_result r;

	assert_int_equal(gantry_run(&m, &r), 0);
	assert_int_equal(r.fault_cycle, 0);
	return r.peak_yaw_um;
}

/* --gantry --auto --apply from the card's gains (configs/sh2000-gantry's)
 * and from none: the three chosen gains written; on the benchmark move
 * they cut the peak yaw tenfold against two independent loops and do
 * no worse than the card's defaults; the pair back where it started. */
static void auto_chooses(void **state)
{
	struct tune_opts o = { .axis = SIDE_A, .ferr_max_mm = 0.1, .enable = 1,
			       .autotune = 1, .apply = 1,
			       .gm_db = TUNE_MIN_GM_DB };
	const double def[3] = { GR_GANTRY_KP, GR_GANTRY_TI, GR_GANTRY_TD };
	double off = bench_yaw(NULL), card = bench_yaw(def);

	(void)state;
	for (int from_none = 0; from_none < 2; from_none++) {
		struct sh2000_fw *fw;
		struct sh2000 *h = open_gantry(1, &fw);
		struct sh2000_status st;
		double k[3], on;

		if (from_none)
			assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_KP, 0), 0);
		assert_int_equal(sh2000_poll(h, &st), 0);
		assert_int_equal(tune_run_gantry_auto(h, &o), 0);
		read_gains(h, k);
		on = bench_yaw(k);
		printf("# --gantry --auto from %s: kp %g ti %g td %g; benchmark peak yaw %.3f um (uncoupled %.3f, card's defaults %.3f): %.1fx\n",
		       from_none ? "kp 0" : "the card's gains", k[0], k[1], k[2],
		       on, off, card, off / on);
		assert_true(k[0] > 0);
		assert_true(off >= 10 * on);
		assert_true(on <= card);
		assert_int_equal(sh2000_poll(h, &st), 0);
		assert_int_equal(st.card_state, SH2000_STATE_IDLE);
		assert_int_equal(st.axis[SIDE_A].state & SH2000_AXIS_ENABLED, 0);
		sh2000_close(h);
	}
}

/* How often the card went into FAULT (a candidate tripped). */
struct fault_log {
	unsigned int state, faults;
};

static void log_faults(void *ctx, const struct sh2000_probe *p)
{
	struct fault_log *l = ctx;

	if (p->state == SH2000_STATE_FAULT && l->state != SH2000_STATE_FAULT)
		l->faults++;
	l->state = p->state;
}

/* --gantry --auto from kp 0 with a tight skew limit (5000 and 8000
 * counts, 50 and 80 um, the uncoupled ramp's skew being 45 um): the
 * search's following-error bound, a quarter of the limit, is tripped by
 * some candidates. After each trip the card disabled both sides together,
 * the tool waited for the pair to come to rest, and took it back to its
 * start without the skew fault: the search ends with gains, the card
 * idle, unfaulted, both sides back at their starts, the beam square at
 * rest. (Before, one side coasted while the other braked, and the way
 * back latched SKEW: exit 4.) */
static void auto_recovers_square(void **state)
{
	static const int limits[] = { 5000, 8000 };

	(void)state;
	for (size_t i = 0; i < sizeof(limits) / sizeof(limits[0]); i++) {
		struct tune_opts o = { .axis = SIDE_A, .ferr_max_mm = 0.1,
				       .enable = 1, .autotune = 1,
				       .gm_db = TUNE_MIN_GM_DB };
		struct sh2000_fw *fw;
		struct sh2000 *h = open_gantry(1, &fw);
		struct fault_log l = { 0, 0 };
		struct sh2000_status st;
		double before[10], after[10];

		assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_KP, 0), 0);
		assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_SKEW_LIMIT,
						  limits[i]), 0);
		card_state(h, before);
		assert_int_equal(sh2000_sim_set_observer(h, log_faults, &l), 0);
		/* 0: the tool found both sides back at their set-points */
		assert_int_equal(tune_run_gantry_auto(h, &o), 0);
		sh2000_sim_set_observer(h, NULL, NULL);
		card_state(h, after);
		assert_int_equal(sh2000_poll(h, &st), 0);
		assert_true(l.faults >= 1);
		assert_int_equal(st.card_state, SH2000_STATE_IDLE);
		assert_int_equal(st.axis[SIDE_A].faults | st.axis[SIDE_B].faults, 0);
		/* the limits, gains and enables as they were (disabled again,
		 * the set-points follow the encoders) */
		for (int k = 0; k < 7; k++)
			assert_true(after[k] == before[k]);
		assert_true(after[9] == before[9]);
		assert_int_equal(sh2000_sleep_ns(h, 2000000000ull), 0);
		printf("# skew limit %d: %u trips, each taken back; the beam's yaw 2 s after the end %.4f um\n",
		       limits[i], l.faults, sh2000_fw_gantry_yaw_mm(fw) * 1e3);
		assert_true(fabs(sh2000_fw_gantry_yaw_mm(fw)) * 1e3 < 0.5);
		sh2000_close(h);
	}
}

/* stdout and stderr of fn(h, o) into buf (what the tool said: its
 * "tried" lines and its message). */
static int said(int (*fn)(struct sh2000 *, const struct tune_opts *),
		struct sh2000 *h, const struct tune_opts *o, char *buf,
		size_t len)
{
	FILE *f = tmpfile();
	int saved[2], r;
	size_t n;

	assert_non_null(f);
	fflush(stdout);
	fflush(stderr);
	for (int fd = 1; fd <= 2; fd++) {
		saved[fd - 1] = dup(fd);
		assert_true(saved[fd - 1] >= 0);
		assert_true(dup2(fileno(f), fd) >= 0);
	}
	r = fn(h, o);
	fflush(stdout);
	fflush(stderr);
	for (int fd = 1; fd <= 2; fd++) {
		assert_true(dup2(saved[fd - 1], fd) >= 0);
		close(saved[fd - 1]);
	}
	rewind(f);
	n = fread(buf, 1, len - 1, f);
	buf[n] = '\0';
	fclose(f);
	fputs(buf, stderr);
	return r;
}

/* The count the refusal gives right before phrase (0 if absent). */
static unsigned int count_before(const char *msg, const char *phrase)
{
	const char *p = strstr(msg, phrase);

	if (!p)
		return 0;
	while (p > msg && p[-1] >= '0' && p[-1] <= '9')
		p--;
	return (unsigned int)strtoul(p, NULL, 10);
}

/* Lines of msg that start with prefix. */
static unsigned int lines_starting(const char *msg, const char *prefix)
{
	unsigned int n = 0;

	for (const char *l = msg; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL)
		n += !strncmp(l, prefix, strlen(prefix));
	return n;
}

/* --gantry --auto --apply on a pair made with carriage_mm and
 * stiffness_n_per_m (open_machine), asking gm_db: refused (exit 1) with
 * a message holding want, and a "tried" line for every candidate the
 * message counts; nothing written: the card's gains, limits and enables
 * as they were, the pair back at its start, idle, unfaulted. */
static void refusal(double carriage_mm, double stiffness_n_per_m,
		    double gm_db, const char *want)
{
	struct tune_opts o = { .axis = SIDE_A, .ferr_max_mm = 0.1, .enable = 1,
			       .autotune = 1, .apply = 1, .gm_db = gm_db };
	struct sh2000_fw *fw;
	struct sh2000 *h = open_machine(1, &fw, carriage_mm, stiffness_n_per_m);
	struct sh2000_status st;
	double before[10], after[10];
	char msg[16384];

	card_state(h, before);
	assert_int_equal(said(tune_run_gantry_auto, h, &o, msg, sizeof(msg)),
			 SH2000_EXIT_CARD);
	card_state(h, after);
	assert_non_null(strstr(msg, "(nothing written)"));
	assert_non_null(strstr(msg, want));
	assert_null(strstr(msg, "written                 "));
	/* a "tried" line for every candidate the refusal counts */
	assert_int_equal(lines_starting(msg, "tried "),
			 count_before(msg, " tripped the following-error") +
			 count_before(msg, " did not hold with") +
			 count_before(msg, " did not cut the peak"));
	for (int k = 0; k < 10; k++)
		assert_true(after[k] == before[k]);
	assert_int_equal(sh2000_poll(h, &st), 0);
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_int_equal(st.axis[SIDE_A].faults | st.axis[SIDE_B].faults, 0);
	sh2000_close(h);
}

/* A beam 400 times stiffer than the model's (2e7 N/m): the sides hardly
 * yaw apart (45 counts uncoupled), and no candidate that cuts it holds
 * with gantry_kp raised 30 dB (x31.6): refused, the message naming the
 * margin. The same pair with the default 8 dB gets gains (kp 40: 3
 * counts): the refusal is the margin's. */
static void auto_refuses_margin(void **state)
{
	struct tune_opts o = { .axis = SIDE_A, .ferr_max_mm = 0.1, .enable = 1,
			       .autotune = 1, .gm_db = TUNE_MIN_GM_DB };
	struct sh2000_fw *fw;
	struct sh2000 *h = open_machine(1, &fw, 20, 2e7);

	(void)state;
	refusal(20, 2e7, 30, "did not hold with gantry_kp x31.62 (the gain margin 30 dB)");
	assert_int_equal(tune_run_gantry_auto(h, &o), 0);
	sh2000_close(h);
}

/* The carriage in the middle of the beam: the sides carry the same mass
 * and the uncoupled ramp shows no skew; there is nothing for the
 * coupling to cut, so nothing to choose gains on: refused before any
 * candidate (before, every candidate "cut" 0 counts to 0 and the search
 * kept the largest gains it tried). */
static void auto_refuses_no_skew(void **state)
{
	(void)state;
	refusal(300, 0, TUNE_MIN_GM_DB, "nothing for the coupling to cut");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(coupling_cuts_the_yaw),
		cmocka_unit_test(uncoupled_only),
		cmocka_unit_test(refused),
		cmocka_unit_test(auto_chooses),
		cmocka_unit_test(auto_recovers_square),
		cmocka_unit_test(auto_refuses_margin),
		cmocka_unit_test(auto_refuses_no_skew),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
