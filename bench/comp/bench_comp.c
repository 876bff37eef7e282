// SPDX-License-Identifier: MIT
/*
 * bench_comp: how far the simulated machine's tool is from the path it
 * was programmed on, without and with compensation tables calibrated on
 * the machine itself (sh2000-comp's calibration), beside a machine
 * without geometric errors held half a count off whole counts as the
 * calibrated one is: its figures are the servo's and the counter's own,
 * what no table can take out. The path
 * and what is measured: tools/comp/pathcheck.c. Prints, every servo cycle:
 *  - the tool (interferometer) against the program's segments, and square
 *    to them (the contour error; the along-path lag left out);
 *  - the path the corrected set-points describe (the tool a perfect servo
 *    on an unquantised scale would give): the tables' and the planner's
 *    part, the servo's out;
 *  - what the error is made of;
 * then the tool at rest at each of the program's points, and apart the
 * tool against the position the card reports, the servo's following
 * error and the corrected set-point's velocity against vmax.
 *
 *   bench_comp [TRAVEL_MM [PASSES]]   (default 100: the path and the
 *                                      calibration within +-TRAVEL/2)
 */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "calib.h"

#define RUNS	3	/* without tables, with, a perfect machine */

static void row(const char *what, const struct cal_path p[RUNS], size_t off)
{
	unsigned int i;

	printf("  %-50s", what);
	for (i = 0; i < RUNS; i++)
		printf(" %8.1f nm", 1e6 * *(const double *)((const char *)&p[i] + off));
	printf("\n");
}

#define ROW(what, field)	row(what, p, offsetof(struct cal_path, field))

static void report(const struct cal_config *c, double travel,
		   const struct cal_path p[RUNS])
{
	printf("bench_comp: default machine, program within +-%.0f mm, calibration %u pass(es), step %.2f mm, grid %.1f mm\n",
	       0.45 * travel, c->passes, c->step_mm, c->grid_mm);
	printf("%-52s %11s %11s %11s\n", "", "no tables", "tables", "perfect");
	printf("the tool against the programmed path, every servo cycle:\n");
	ROW("largest", path_max);
	ROW("rms", path_rms);
	printf("the same square to the path (contour error; the along-path lag\n"
	       "and a corner's overshoot, the servo's, left out):\n");
	ROW("largest", contour_max);
	ROW("rms", contour_rms);
	ROW("largest along one axis", contour_axis_max);
	printf("  %-50s %11lu %11lu %11lu\n", "cycles over one count",
	       p[0].contour_over, p[1].contour_over, p[2].contour_over);
	printf("the corrected set-points' path (a perfect servo's tool):\n");
	ROW("largest", setpoint_max);
	printf("the tool at rest at the program's points (averaged):\n");
	ROW("largest", rest_max);
	printf("what the path's error is made of (each largest):\n");
	ROW("nominal set-point off the path (whole counts)", plan_max);
	ROW("tables: perfect servo, unquantised scale", table_max);
	ROW("servo, moving: the tool off that, square to the path", servo_perp_max);
	ROW("servo, at rest: the tool off that", quant_max);
	printf("apart: the tool against the card's reported position (ACT):\n");
	ROW("largest (includes the count and its rounding)", geo_max);
	ROW("rms", geo_rms);
	printf("  %-50s %8.1f ct %8.1f ct %8.1f ct\n", "following error along the path, largest",
	       p[0].lag_max, p[1].lag_max, p[2].lag_max);
	printf("  %-50s %11.3f %11.3f %11.3f\n", "corrected set-point velocity / vmax, largest",
	       p[0].vel_ratio, p[1].vel_ratio, p[2].vel_ratio);
	printf("  %-50s %11.3f %11.3f %11.3f\n", "corrected set-point acceleration / amax, largest",
	       p[0].acc_ratio, p[1].acc_ratio, p[2].acc_ratio);
	printf("  %-50s %11lu %11lu %11lu\n", "cycles with a set-point outside the soft limits",
	       p[0].outside, p[1].outside, p[2].outside);
	printf("one count is 10 nm; servo cycles watched: %lu, %lu, %lu\n",
	       p[0].cycles, p[1].cycles, p[2].cycles);
}

/* The same program on a machine without geometric errors, its set-points
 * half a count from a whole one as the calibration's are (calcentre.c):
 * the best the tables could do. */
static int perfect(double half, const char *tmp, struct cal_path *out)
{
	struct sh2000_geometry none;
	struct cal_tables *t = calloc(1, sizeof(*t));
	struct cal_sim s;
	char msg[256];
	int r;

	if (!t)
		return -1;
	sh2000_geometry_none(&none);
	r = cal_sim_open(&s, NULL, &none, tmp, msg, sizeof(msg));
	if (r < 0) {
		fprintf(stderr, "bench_comp: %s\n", msg);
		free(t);
		return r;
	}
	cal_half_count(t, &s);
	r = cal_load(&s, t);
	if (!r)
		r = cal_path_check(&s, half, out);
	if (r < 0)
		fprintf(stderr, "bench_comp: %s\n", sh2000_last_error(s.h));
	cal_sim_close(&s);
	free(t);
	return r;
}

static int calibrated(const struct cal_config *c, double half, const char *tmp,
		      struct cal_path p[2])
{
	struct cal_tables *t = calloc(1, sizeof(*t));
	struct cal_sim s;
	char msg[256];
	int r = t ? cal_sim_open(&s, NULL, NULL, tmp, msg, sizeof(msg)) : -1;

	if (r < 0) {
		fprintf(stderr, "bench_comp: %s\n", t ? msg : "out of memory");
		free(t);
		return -1;
	}
	r = cal_path_check(&s, half, &p[0]);
	if (!r)
		r = cal_run(&s, c, t);
	if (!r)
		r = cal_path_check(&s, half, &p[1]);
	if (r < 0)
		fprintf(stderr, "bench_comp: %s\n", sh2000_last_error(s.h));
	cal_sim_close(&s);
	free(t);
	return r;
}

int main(int argc, char **argv)
{
	double travel = argc > 1 ? atof(argv[1]) : 100.0;
	char tmp[] = "/tmp/bench-comp-XXXXXX";
	struct cal_path p[RUNS];
	struct cal_config c;
	int fd = mkstemp(tmp), r;
	unsigned int a;

	if (fd < 0 || !(travel > 0))
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
	r = calibrated(&c, travel / 2, tmp, p);
	if (!r)
		r = perfect(travel / 2, tmp, &p[2]);
	if (!r)
		report(&c, travel, p);
	unlink(tmp);
	return r < 0;
}
