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

static void report(const struct cal_config *c, double travel,
		   const struct cal_path p[2])
{
	printf("bench_comp: default machine, program within +-%.0f mm, calibration %u pass(es), step %.1f mm, grid %.1f mm\n",
	       0.45 * travel, c->passes, c->step_mm, c->grid_mm);
	printf("%-44s %14s %14s\n", "", "without tables", "with tables");
	printf("%-44s %11.1f nm %11.1f nm\n", "geometric error, largest (every cycle)",
	       1e6 * p[0].geo_max, 1e6 * p[1].geo_max);
	printf("%-44s %11.1f nm %11.1f nm\n", "geometric error, rms",
	       1e6 * p[0].geo_rms, 1e6 * p[1].geo_rms);
	printf("%-44s %11.1f nm %11.1f nm\n", "at rest at the program's points, largest",
	       1e6 * p[0].rest_max, 1e6 * p[1].rest_max);
	printf("%-44s %8.1f counts %8.1f counts\n", "following error, largest (the servo's lag)",
	       p[0].lag_max, p[1].lag_max);
	printf("%-44s %13.3f %14.3f\n", "set-point velocity / vmax, largest",
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
