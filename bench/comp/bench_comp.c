// SPDX-License-Identifier: MIT
/*
 * bench_comp: how far the simulated machine's tool is from where it was
 * programmed, along a program's path, without and with compensation tables
 * calibrated on the machine itself (sh2000-comp's calibration). Prints:
 *  - the geometric error every servo cycle: the tool (the interferometer)
 *    against the position the card reports (nominal counter), which is
 *    what the tables correct; the servo's lag is not in it;
 *  - the error at rest at each of the program's points: the tool against
 *    the programmed point;
 *  - the servo's largest following error and the corrected set-point's
 *    largest velocity against each axis' vmax (the tables stay inside it).
 *
 *   bench_comp [TRAVEL_MM [PASSES]]   (default 100: the path and the
 *                                      calibration within +-TRAVEL/2)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "calib.h"

struct watch {
	struct cal_sim *s;
	double geo_max, geo_sq, lag_max, vel_ratio;
	double prev_sp[SH2000_AXES], prev_tool[SH2000_AXES];
	double vmax[SH2000_AXES];	/* counts/s */
	unsigned long n;
	int have_prev;
};

static void observe(void *ctx, const struct sh2000_probe *p)
{
	struct watch *w = ctx;
	struct cal_sim *s = w->s;
	double off[SH2000_AXES];
	unsigned int a;

	double T = 1e-9 * (double)sh2000_fw_servo_period_ns(s->fw);

	sh2000_fw_comp_offset(s->fw, off);
	for (a = 0; a < 3 && w->have_prev; a++) {
		/* the counter was read at the cycle's start: where the last
		 * cycle left the tool */
		double nom_act = (p->axis[a].actual - off[a]) / s->scale[a];
		double e = (w->prev_tool[a] - s->ref_tool[a]) -
			   (nom_act - s->ref_nom[a]);
		double sp = p->axis[a].fine_cmd + off[a];

		w->geo_max = fmax(w->geo_max, fabs(e));
		w->geo_sq += e * e;
		w->lag_max = fmax(w->lag_max, fabs(p->axis[a].fine_cmd + off[a] -
						     p->axis[a].actual));
		w->vel_ratio = fmax(w->vel_ratio, fabs(sp - w->prev_sp[a]) /
				    T / w->vmax[a]);
	}
	for (a = 0; a < SH2000_AXES; a++)
		w->prev_sp[a] = p->axis[a].fine_cmd + off[a];
	sh2000_fw_tool_position(s->fw, w->prev_tool);
	w->have_prev = 1;
	w->n++;
}

/* The program: a star of lines in X-Y with Z going up and down, every
 * point reached at rest, at 40 mm/s. */
static int run_program(struct cal_sim *s, double half, double *rest_max)
{
	static const double star[][3] = {
		{ 0.0, 1.0, 0.2 }, { 0.59, -0.81, -0.3 }, { -0.95, 0.31, 0.5 },
		{ 0.95, 0.31, -0.6 }, { -0.59, -0.81, 0.9 }, { 0.0, 1.0, -0.9 },
		{ 0.7, 0.7, 0.0 }, { -0.7, -0.7, 0.4 }, { 0.0, 0.0, 0.0 },
	};
	double t[SH2000_AXES], e[SH2000_AXES];
	unsigned int i, a;
	int r = 0;

	*rest_max = 0.0;
	memcpy(t, s->ref_nom, sizeof(t));
	for (i = 0; !r && i < sizeof(star) / sizeof(star[0]); i++) {
		for (a = 0; a < 3; a++)
			t[a] = s->ref_nom[a] + 0.9 * half * star[i][a];
		r = cal_move(s, t, 40.0);
		if (!r)
			r = cal_measure(s, e);
		for (a = 0; !r && a < 3; a++)
			*rest_max = fmax(*rest_max, fabs(e[a]));
	}
	return r;
}

static int measure(struct cal_sim *s, double half, struct watch *w,
		   double *rest)
{
	unsigned int a;
	int r;

	memset(w, 0, sizeof(*w));
	w->s = s;
	for (a = 0; a < SH2000_AXES; a++) {
		r = sh2000_param_get(s->h, (int)a, SH2000_P_VMAX, &w->vmax[a]);
		if (r < 0)
			return r;
		w->vmax[a] *= s->scale[a];	/* mm/s to counts/s */
	}
	sh2000_sim_set_observer(s->h, observe, w);
	r = run_program(s, half, rest);
	sh2000_sim_set_observer(s->h, NULL, NULL);
	return r;
}

int main(int argc, char **argv)
{
	double travel = argc > 1 ? atof(argv[1]) : 100.0, rest[2];
	char tmp[] = "/tmp/bench-comp-XXXXXX", msg[256];
	struct cal_tables *t = calloc(1, sizeof(*t));
	struct cal_config c;
	struct watch w[2];
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
	r = cal_sim_open(&s, NULL, tmp, msg, sizeof(msg));
	if (r < 0) {
		fprintf(stderr, "bench_comp: %s\n", msg);
		return 1;
	}
	r = measure(&s, travel / 2, &w[0], &rest[0]);
	if (!r)
		r = cal_run(&s, &c, t);
	if (!r)
		r = measure(&s, travel / 2, &w[1], &rest[1]);
	if (r < 0) {
		fprintf(stderr, "bench_comp: %s\n", sh2000_last_error(s.h));
		return 1;
	}
	printf("bench_comp: default machine, program within +-%.0f mm, calibration %u pass(es), step %.1f mm, grid %.1f mm\n",
	       travel / 2, c.passes, c.step_mm, c.grid_mm);
	printf("%-44s %14s %14s\n", "", "without tables", "with tables");
	printf("%-44s %11.1f nm %11.1f nm\n", "geometric error, largest (every cycle)",
	       1e6 * w[0].geo_max, 1e6 * w[1].geo_max);
	printf("%-44s %11.1f nm %11.1f nm\n", "geometric error, rms",
	       1e6 * sqrt(w[0].geo_sq / (3.0 * w[0].n)), 1e6 * sqrt(w[1].geo_sq / (3.0 * w[1].n)));
	printf("%-44s %11.1f nm %11.1f nm\n", "at rest at the program's points, largest",
	       1e6 * rest[0], 1e6 * rest[1]);
	printf("%-44s %8.1f counts %8.1f counts\n", "following error, largest (the servo's lag)",
	       w[0].lag_max, w[1].lag_max);
	printf("%-44s %13.3f %14.3f\n", "set-point velocity / vmax, largest",
	       w[0].vel_ratio, w[1].vel_ratio);
	printf("one count is 10 nm; servo cycles watched: %lu, %lu\n", w[0].n, w[1].n);
	cal_sim_close(&s);
	unlink(tmp);
	free(t);
	return 0;
}
