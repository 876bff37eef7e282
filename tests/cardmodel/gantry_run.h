/* SPDX-License-Identifier: MIT */
/*
 * The gantry scenario of test_gantry and bench/gantry: the card model as
 * a gantry (sides y and z, the carriage on x), a jerk-limited move of the
 * beam streamed to both sides alike, every servo cycle of it observed.
 */
#ifndef SH2000_TEST_GANTRY_RUN_H
#define SH2000_TEST_GANTRY_RUN_H

#include <stdint.h>

#include "harness.h"

#define GR_A	1u	/* side a: axis y */
#define GR_B	2u	/* side b: axis z */

struct gantry_move {
	double carriage_mm;	/* the carriage's place on the beam (x) */
	double dist_mm;		/* the beam's move, both sides */
	double v_mm_s, a_mm_s2;	/* its top speed and acceleration */
	int couple;		/* the card's cross-coupling loop on */
	/* with couple: its gains kp, ti, td; NULL: GR_GANTRY_KP, _TI, _TD */
	const double *gains;
	int32_t skew_limit;	/* counts; 0: the table's default */
	double jam_at_s;	/* side b jams this far into the move; < 0 no */
};

struct gantry_result {
	double peak_yaw_um;	/* |side a - side b| of the machine */
	double peak_skew_counts;	/* |e_a - e_b| the card saw */
	double peak_ferr_um;	/* the larger side's following error */
	double jerk_mm_s3;	/* the move's largest jerk */
	unsigned int cycles;	/* servo cycles run */
	/* the skew fault: the first cycle whose encoders differ by more than
	 * the limit, the cycle the card latched SKEW on both sides, and the
	 * first cycle from which both set-points stood still (0: never) */
	uint64_t cross_cycle, fault_cycle, held_cycle;
	/* side a, moving when the fault came: its speed then, how long it
	 * took to come to rest and how far it went */
	double fault_x_mm, fault_v_mm_s;
	double free_side_stop_ms, free_side_travel_mm;
};

/* The sides' tuning every run shares (coupled or not): the axes' PID
 * defaults, the acceleration feed-forward for the sides' mean mass. The
 * coupling loop's gains, used when couple is set. */
#define GR_KAFF_KG	9.0
#define GR_GANTRY_KP	5.0
#define GR_GANTRY_TI	0.005
#define GR_GANTRY_TD	0.002

/* A fresh card in h from cfg made a gantry (the model's default beam),
 * axes x, y, z enabled, y+z the pair with gantry_square square and
 * gantry_kp GR_GANTRY_KP, ready to HOME: 0, or -1 when the card refused
 * a command or parameter. */
int gantry_home_card(struct harness *h, const struct sh2000_sim_config *cfg,
		     int32_t square);
/* Runs the move on a fresh card; 0, or -1 when the card refused a
 * command or parameter on the way. */
int gantry_run(const struct gantry_move *m, struct gantry_result *r);
/* The skew fault's figures in words (test and benchmark print them). */
const char *gantry_jam_text(const struct gantry_result *r, char *buf,
			    unsigned int len);

#endif
