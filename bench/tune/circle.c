/* SPDX-License-Identifier: MIT */
/*
 * The benchmark's reference move: an R 5 mm circle at 300 mm/s (or what
 * the card's acceleration limit allows: the planner decides), run by
 * libsh2000-motion's runner, with the card gathering x's and y's following
 * error every servo cycle from the motion's start until TAIL_S after it.
 * Unstable: a fault (following-error limit, DAC saturation) or, in the
 * TAIL_S after the motion, an oscillation whose last TAIL_WIN is larger
 * than its first.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sh2000/path.h>
#include <sh2000/run.h>
#include <sh2000/sim.h>
#include <sh2000/sh2000_cardsim.h>

#include "bench_tune.h"

#define TAIL_S		0.2
#define TAIL_WIN	0.05
#define GROWTH_FLOOR	5.0	/* counts: below it nothing grows */

int bench_card_open(struct sh2000 **h, const struct bench_machine *m,
		    const struct tune_gains *g)
{
	char msg[256], why[256];
	struct tune_gains old;
	int r = 0;

	*h = NULL;
	if (sh2000_sim_open(h, &m->cfg, msg, sizeof(msg)) < 0) {
		fprintf(stderr, "bench_tune: sim: %s\n", msg);
		return -1;
	}
	/* the planner takes the least amax of the four axes on a curve */
	for (unsigned int a = 0; a < SH2000_AXES && r >= 0; a++)
		r = sh2000_param_set(*h, (int)a, SH2000_P_AMAX, m->amax);
	for (unsigned int a = 0; a < 2 && r >= 0; a++) {
		r = sh2000_param_set(*h, (int)a, SH2000_P_FERR_LIMIT, m->ferr_limit);
		if (r >= 0 && g && (r = tune_read_gains(*h, a, &old)) >= 0)
			r = tune_gains_set(*h, a, g, &old, why, sizeof(why));
	}
	if (r >= 0)
		r = sh2000_enable(*h, 3);
	if (r < 0) {
		fprintf(stderr, "bench_tune: card: %s\n", sh2000_last_error(*h));
		sh2000_close(*h);
		*h = NULL;
		return -1;
	}
	return 0;
}

int circle_variant_with(const struct bench_machine *m,
			const struct tune_gains *g,
			const struct circle_variant *v,
			struct circle_result *res)
{
	struct bench_machine mv = *m;
	struct sh2000 *h;
	int r;

	/* the carriage's start within a count of the scale: x and y */
	for (unsigned int a = 0; a < 2; a++)
		mv.cfg.axis[a].start_mm += v->start_counts / mv.cfg.axis[a].counts_per_mm;
	r = bench_card_open(&h, &mv, g);
	if (r == 0 && v->phase > 0)
		sh2000_cardsim_advance(sh2000_sim_card(h), (uint64_t)(v->phase * 1e5));
	if (r == 0)
		r = circle_run(h, v->angle_deg, res);
	sh2000_close(h);
	return r;
}

int circle_with(const struct bench_machine *m, const struct tune_gains *g,
		struct circle_result *res)
{
	static const struct circle_variant v0 = { 0, 0, 0 };

	return circle_variant_with(m, g, &v0, res);
}

static int arm(struct sh2000 *h, double seconds)
{
	struct sh2000_gather_config gc;

	sh2000_gather_config_default(&gc);
	gc.signals[0] = gc.signals[1] = 1u << SH2000_GS_FERR |
					1u << SH2000_GS_SETPOINT_VEL;
	gc.period = 1;
	gc.samples = (uint32_t)fmin(seconds / 1e-4, SH2000_GATHER_BUFFER_VALUES / 4);
	gc.trigger = SH2000_GATHER_ON_MOTION;
	return sh2000_gather_start(h, &gc);
}

/* The circle through the runner; 0 or the error (a fault: unstable). */
static int run_circle(struct sh2000 *h, double angle_deg, char *msg,
		      size_t len)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_path_arc arc;
	struct sh2000_run *run = NULL;
	int r;

	if ((r = sh2000_run_path_config(h, &pc)) < 0)
		return r;
	sh2000_run_config_default(&rc);
	if ((r = sh2000_run_create(&run, h, &pc, &rc, msg, len)) < 0)
		return r;
	memset(&arc, 0, sizeof(arc));
	arc.plane = SH2000_PLANE_XY;
	memcpy(arc.end, pc.start, sizeof(arc.end));
	arc.centre[0] = pc.start[0] - CIRCLE_R_MM * cos(angle_deg * M_PI / 180);
	arc.centre[1] = pc.start[1] - CIRCLE_R_MM * sin(angle_deg * M_PI / 180);
	arc.ccw = 1;
	r = sh2000_path_arc(sh2000_run_path(run), &arc, CIRCLE_FEED);
	if (r >= 0)
		r = sh2000_run_finish(run);
	if (r >= 0)
		r = sh2000_run_dwell(run, TAIL_S);
	if (r < 0)
		snprintf(msg, len, "%s", sh2000_run_error(run));
	sh2000_run_destroy(run);
	return r;
}

/* The figures of the record v (4 values a sample: x ferr, x v, y ferr,
 * y v) into res. */
static void figures(const double *v, uint32_t n, double T,
		    struct circle_result *res)
{
	uint32_t last = 0, w = (uint32_t)(TAIL_WIN / T);
	double sum = 0, head = 0, tail = 0;

	for (uint32_t i = 0; i < n; i++) {
		double e = hypot(v[4 * i], v[4 * i + 2]);
		double f = hypot(v[4 * i + 1], v[4 * i + 3]);

		res->max_ferr = fmax(res->max_ferr, e);
		res->feed = fmax(res->feed, f);
		sum += e * e;
		if (f != 0)
			last = i;
	}
	res->rms_ferr = n ? sqrt(sum / n) : 0;
	for (uint32_t i = last + 1; i < n && i < last + 1 + w; i++)
		head = fmax(head, hypot(v[4 * i], v[4 * i + 2]));
	for (uint32_t i = n > w ? n - w : 0; i < n && i > last; i++)
		tail = fmax(tail, hypot(v[4 * i], v[4 * i + 2]));
	if (tail > GROWTH_FLOOR && tail > head) {
		res->unstable = 1;
		snprintf(res->why, sizeof(res->why),
			 "oscillation growing after the motion (%.0f -> %.0f counts)",
			 head, tail);
	}
}

int circle_run(struct sh2000 *h, double angle_deg, struct circle_result *res)
{
	struct sh2000_gather_info gi;
	char msg[512] = "";
	double *v;
	int rec, r;

	memset(res, 0, sizeof(*res));
	rec = arm(h, 1.2);
	if (rec < 0) {
		fprintf(stderr, "bench_tune: gather: %s\n", sh2000_last_error(h));
		return -1;
	}
	r = run_circle(h, angle_deg, msg, sizeof(msg));
	if (r < 0) {
		res->unstable = 1;
		snprintf(res->why, sizeof(res->why), "%s", msg);
		res->max_ferr = res->rms_ferr = INFINITY;
		return 0;
	}
	sh2000_gather_stop(h);
	if ((r = sh2000_gather_wait(h, (unsigned int)rec, &gi, 5000)) < 0 ||
	    !(v = malloc(sizeof(double) * 4 * gi.samples))) {
		fprintf(stderr, "bench_tune: gather: %s\n", sh2000_last_error(h));
		return -1;
	}
	r = sh2000_gather_read(h, &gi, 0, gi.samples, v);
	if (r >= 0)
		figures(v, gi.samples, gi.sample_s, res);
	free(v);
	res->feed *= 1e-5;	/* counts/s -> mm/s at 100000 counts/mm */
	return r < 0 ? -1 : 0;
}
