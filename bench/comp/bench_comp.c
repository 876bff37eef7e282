// SPDX-License-Identifier: MIT
/*
 * bench_comp: how far the simulated machine's tool is from where it was
 * programmed, along a program's path, without and with compensation tables
 * calibrated on the machine itself (sh2000-comp's calibration; the path
 * and what is measured: tools/comp/pathcheck.c). Prints:
 *  - the geometric error every servo cycle: the tool (the interferometer)
 *    against the position the card reports (nominal counter), which is
 *    what the tables correct; the servo's lag is not in it;
 *  - the error at rest at each of the program's points;
 *  - the servo's largest following error and the corrected set-point's
 *    largest velocity against each axis' vmax (the tables stay inside it).
 *
 *   bench_comp [TRAVEL_MM [PASSES]]   (default 100: the path and the
 *                                      calibration within +-TRAVEL/2)
 */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "calib.h"

static void row(const char *what, double a, double b)
{
	printf("  %-52s %9.1f nm %9.1f nm\n", what, 1e6 * a, 1e6 * b);
}

static void report(const struct cal_config *c, double travel,
		   const struct cal_path p[2])
{
	printf("bench_comp: default machine, program within +-%.0f mm, calibration %u pass(es), step %.2f mm, grid %.1f mm\n",
	       0.45 * travel, c->passes, c->step_mm, c->grid_mm);
	printf("%-54s %12s %12s\n", "", "no tables", "tables");
	printf("the tool against the programmed path, every servo cycle:\n");
	row("largest", p[0].path_max, p[1].path_max);
	row("rms", p[0].path_rms, p[1].path_rms);
	printf("the same square to the path (contour error; the along-path lag\n"
	       "and a corner's overshoot, the servo's, left out):\n");
	row("largest", p[0].contour_max, p[1].contour_max);
	row("rms", p[0].contour_rms, p[1].contour_rms);
	printf("the tool at rest at the program's points:\n");
	row("largest", p[0].rest_max, p[1].rest_max);
	printf("what the path's error is made of (each largest):\n");
	row("nominal set-point off the path (planner)", p[0].plan_max, p[1].plan_max);
	row("tables: perfect servo, unquantised scale", p[0].table_max, p[1].table_max);
	row("servo, moving: tool off that, square to the path", p[0].servo_perp_max,
	    p[1].servo_perp_max);
	row("at rest: dither within the counter's count", p[0].quant_max, p[1].quant_max);
	printf("apart: the tool against the card's reported position (ACT):\n");
	row("largest (includes the count and its rounding)", p[0].geo_max, p[1].geo_max);
	row("rms", p[0].geo_rms, p[1].geo_rms);
	printf("  %-52s %6.1f counts %6.1f counts\n", "following error along the path, largest",
	       p[0].lag_max, p[1].lag_max);
	printf("  %-52s %12.3f %12.3f\n", "corrected set-point velocity / vmax, largest",
	       p[0].vel_ratio, p[1].vel_ratio);
	printf("one count is 10 nm; servo cycles watched: %lu, %lu\n",
	       p[0].cycles, p[1].cycles);
}

int main(int argc, char **argv)
{
	double travel = argc > 1 ? atof(argv[1]) : 100.0;
	char tmp[] = "/tmp/bench-comp-XXXXXX", msg[256];
	struct cal_tables *t = calloc(1, sizeof(*t));
	struct cal_path p[2];
	struct cal_config c;
	struct cal_sim s;
	int fd = mkstemp(tmp), r;
	unsigned int a;

	if (fd < 0 || !t || !(travel > 0))
		return 1;
	close(fd);
	cal_config_default(&c);
	for (a = 0; a < SH2000_AXES; a++) {
		c.lo[a] = -travel / 2;
		c.hi[a] = travel / 2;
	}
	c.grid_mm = travel / 10;
	if (argc > 2)
		c.passes = (unsigned int)atoi(argv[2]);
	r = cal_sim_open(&s, NULL, NULL, tmp, msg, sizeof(msg));
	if (r < 0) {
		fprintf(stderr, "bench_comp: %s\n", msg);
		return 1;
	}
	r = cal_path_check(&s, travel / 2, &p[0]);
	if (!r)
		r = cal_run(&s, &c, t);
	if (!r)
		r = cal_path_check(&s, travel / 2, &p[1]);
	if (r < 0)
		fprintf(stderr, "bench_comp: %s\n", sh2000_last_error(s.h));
	else
		report(&c, travel, p);
	cal_sim_close(&s);
	unlink(tmp);
	free(t);
	return r < 0;
}
