// SPDX-License-Identifier: MIT
/*
 * bench_gantry: the yaw table of a gantry pair on the card model
 * (tests/cardmodel/gantry_run.h): the beam moves 200 mm (300 mm/s, 3000
 * mm/s^2, jerk-limited) with the carriage at five places along it, with
 * two independent loops and with the card's cross-coupling loop, the same
 * tuning; then side b jams during the move with the skew limit at 50 um.
 */
#include <stdio.h>

#include "gantry_run.h"

static int yaw_table(void)
{
	static const double at[] = { 0.0, 150.0, 300.0, 450.0, 600.0 };
	struct gantry_move m = {
		.dist_mm = 200.0, .v_mm_s = 300.0, .a_mm_s2 = 3000.0,
		.skew_limit = 100000, .jam_at_s = -1.0,
	};
	unsigned int i;

	printf("gantry: beam 200 mm at 300 mm/s, 3000 mm/s^2, sin^2 jerk-limited; "
	       "coupling kp %g ti %g td %g\n", GR_GANTRY_KP, GR_GANTRY_TI,
	       GR_GANTRY_TD);
	printf("%-12s %16s %16s %8s %18s\n", "carriage mm", "yaw um uncoupled",
	       "yaw um coupled", "ratio", "peak ferr um (c)");
	for (i = 0; i < sizeof(at) / sizeof(at[0]); i++) {
		struct gantry_result off, on;

		m.carriage_mm = at[i];
		m.couple = 0;
		if (gantry_run(&m, &off))
			return 1;
		m.couple = 1;
		if (gantry_run(&m, &on))
			return 1;
		printf("%-12.0f %16.3f %16.3f %8.1f %18.3f\n", at[i],
		       off.peak_yaw_um, on.peak_yaw_um,
		       on.peak_yaw_um > 0 ? off.peak_yaw_um / on.peak_yaw_um : 0.0,
		       on.peak_ferr_um);
	}
	return 0;
}

static int jam_row(void)
{
	struct gantry_move m = {
		.carriage_mm = 0.0, .dist_mm = 200.0, .v_mm_s = 300.0,
		.a_mm_s2 = 3000.0, .couple = 1, .skew_limit = 5000,
		.jam_at_s = 0.15,
	};
	struct gantry_result r;
	char t[256];

	if (gantry_run(&m, &r))
		return 1;
	printf("jam of side b at 0.15 s, skew limit 50 um: %s\n",
	       gantry_jam_text(&r, t, sizeof(t)));
	return r.fault_cycle == r.cross_cycle ? 0 : 1;
}

int main(void)
{
	return yaw_table() || jam_row();
}
