// SPDX-License-Identifier: MIT
/*
 * How far the simulated machine's tool is from where it was programmed
 * (calib.h, struct cal_path). Every servo cycle: the tool (the
 * interferometer) against the program's segment being run, and what that
 * is made of, from the machine's model (pathmodel.c): the nominal
 * set-point off the segment, the tables' own error, the servo's deviation
 * square to the path while it moves and its hunting across a count at
 * rest. At rest at each of the program's points the tool against the
 * point. Apart: the tool against the position the card reports, the
 * servo's following error and the corrected set-points against every
 * axis' vmax, amax and soft limits. The benchmark prints it, the tests
 * bound it.
 */
#include <math.h>
#include <string.h>

#include "calib.h"

struct watch {
	struct cal_sim *s;
	struct cal_path *out;
	double prev_sp[SH2000_AXES], prev_tool[SH2000_AXES];
	double prev_nom[SH2000_AXES];
	double vmax[SH2000_AXES];	/* counts/s */
	double amax[SH2000_AXES];	/* counts/s^2 */
	double soft_lo[SH2000_AXES], soft_hi[SH2000_AXES];	/* counts */
	double prev_v[SH2000_AXES];	/* the set-point's velocity, counts/s */
	unsigned long cycles_seen;
	double ref_ideal[SH2000_AXES];	/* the model's tool at the reference */
	double seg_a[3], seg_b[3];	/* the segment being run, mm from the
					 * reference */
	double sq, contour_sq, geo_sq;
	double still_s;			/* how long the set-point has stood */
	double count_mm;		/* the largest count of X, Y, Z */
	int have_prev, have_ref;
};

/* The set-point stood this long: the servo has settled (calrun.c waits
 * as long before it measures). */
#define SETTLED_S	0.03

static double norm3(const double v[3])
{
	return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* The tool (pt, mm from the reference) against the segment being run:
 * its distance from the segment, and from the segment's line (the
 * contour error: the along-path lead or lag left out). */
static void against_path(struct watch *w, const double pt[3])
{
	struct cal_path *o = w->out;
	double rel[3], v[3], line, dist;
	unsigned int a;

	for (a = 0; a < 3; a++)
		rel[a] = pt[a] - w->seg_a[a];
	dist = cal_model_segment(w->seg_a, w->seg_b, pt, rel, v);
	line = norm3(v);
	for (a = 0; a < 3; a++)
		o->contour_axis_max = fmax(o->contour_axis_max, fabs(v[a]));
	o->path_max = fmax(o->path_max, dist);
	w->sq += dist * dist;
	o->contour_max = fmax(o->contour_max, line);
	if (line > w->count_mm)
		o->contour_over++;
	w->contour_sq += line * line;
}

/* What the user sees and what it is made of (calib.h): tool against the
 * segment; the nominal set-point against it; the model's tool for the
 * corrected set-point against the nominal one; the tool against the
 * model's, square to the path (moving) or whole (at rest). */
static void breakdown(struct watch *w, const struct sh2000_probe *p,
		      const double off[SH2000_AXES], const double k[SH2000_AXES])
{
	struct cal_sim *s = w->s;
	struct cal_path *o = w->out;
	double sp[SH2000_AXES], ideal[SH2000_AXES], tool[SH2000_AXES];
	double pt[3], nom[3], d[3], et[3], perp[3];
	double T = 1e-9 * (double)sh2000_fw_servo_period_ns(s->fw);
	unsigned int a;
	int moving = 0;

	sh2000_fw_tool_position(s->fw, tool);
	for (a = 0; a < SH2000_AXES; a++)
		sp[a] = p->axis[a].fine_cmd + off[a];
	cal_model_tool(s, k, sp, ideal);
	for (a = 0; a < 3; a++) {
		nom[a] = p->axis[a].fine_cmd / s->scale[a] - s->ref_nom[a];
		pt[a] = tool[a] - s->ref_tool[a];
		d[a] = pt[a] - (ideal[a] - w->ref_ideal[a]);
		et[a] = ideal[a] - w->ref_ideal[a] - nom[a];
		moving |= p->axis[a].fine_cmd != w->prev_nom[a];
	}
	w->still_s = moving ? 0.0 : w->still_s + T;
	against_path(w, pt);
	o->table_max = fmax(o->table_max, norm3(et));
	cal_model_segment(w->seg_a, w->seg_b, pt, d, perp);
	if (w->still_s < SETTLED_S)
		o->servo_perp_max = fmax(o->servo_perp_max, norm3(perp));
	else
		o->quant_max = fmax(o->quant_max, norm3(d));
	o->plan_max = fmax(o->plan_max,
			   cal_model_segment(w->seg_a, w->seg_b, nom, d, perp));
	for (a = 0; a < 3; a++)
		et[a] += nom[a];	/* the model's tool, from the reference */
	o->setpoint_max = fmax(o->setpoint_max,
			       cal_model_segment(w->seg_a, w->seg_b, et, d, perp));
}

/* The corrected set-points against the axes' limits (vmax, amax, the soft
 * limits); the tool against the card's reported (nominal) counter; the
 * servo's lag. */
static void reported(struct watch *w, const struct sh2000_probe *p,
		     const double off[SH2000_AXES])
{
	struct cal_sim *s = w->s;
	struct cal_path *o = w->out;
	double T = 1e-9 * (double)sh2000_fw_servo_period_ns(s->fw);
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		double sp = p->axis[a].fine_cmd + off[a];
		double v = (sp - w->prev_sp[a]) / T;

		o->vel_ratio = fmax(o->vel_ratio, fabs(v) / w->vmax[a]);
		if (w->cycles_seen > 1)
			o->acc_ratio = fmax(o->acc_ratio, fabs(v - w->prev_v[a]) /
					    T / w->amax[a]);
		w->prev_v[a] = v;
		if (sp < w->soft_lo[a] || sp > w->soft_hi[a])
			o->outside++;
	}
	w->cycles_seen++;
	for (a = 0; a < 3; a++) {
		/* the counter was read at the cycle's start: where the last
		 * cycle left the tool */
		double nom_act = (p->axis[a].actual - off[a]) / s->scale[a];
		double e = (w->prev_tool[a] - s->ref_tool[a]) -
			   (nom_act - s->ref_nom[a]);
		double sp = p->axis[a].fine_cmd + off[a];

		o->geo_max = fmax(o->geo_max, fabs(e));
		w->geo_sq += e * e;
		o->lag_max = fmax(o->lag_max, fabs(sp - p->axis[a].actual));
	}
}

static void observe(void *ctx, const struct sh2000_probe *p)
{
	struct watch *w = ctx;
	struct cal_sim *s = w->s;
	double off[SH2000_AXES], k[SH2000_AXES], c[SH2000_AXES];
	unsigned int a;

	sh2000_fw_comp_offset(s->fw, off);
	if (w->have_prev) {
		for (a = 0; a < SH2000_AXES; a++)
			c[a] = p->axis[a].actual;
		cal_model_offset(s, c, w->prev_tool, k);
		if (!w->have_ref) {
			cal_model_tool(s, k, s->ref_sp, w->ref_ideal);
			w->have_ref = 1;
		}
		breakdown(w, p, off, k);
		reported(w, p, off);
		w->out->cycles++;
	}
	for (a = 0; a < SH2000_AXES; a++) {
		w->prev_sp[a] = p->axis[a].fine_cmd + off[a];
		w->prev_nom[a] = p->axis[a].fine_cmd;
	}
	sh2000_fw_tool_position(s->fw, w->prev_tool);
	w->have_prev = 1;
}

/* The program: a star of lines in X-Y with Z going up and down, every
 * point reached at rest, at 40 mm/s, within +-0.9 half of the reference. */
static int run_program(struct watch *w, double half, double *rest_max)
{
	struct cal_sim *s = w->s;
	static const double star[][3] = {
		{ 0.0, 1.0, 0.2 }, { 0.59, -0.81, -0.3 }, { -0.95, 0.31, 0.5 },
		{ 0.95, 0.31, -0.6 }, { -0.59, -0.81, 0.9 }, { 0.0, 1.0, -0.9 },
		{ 0.7, 0.7, 0.0 }, { -0.7, -0.7, 0.4 }, { 0.0, 0.0, 0.0 },
	};
	double t[SH2000_AXES], e[SH2000_AXES];
	unsigned int i, a;
	int r = 0;

	memcpy(t, s->ref_nom, sizeof(t));
	for (i = 0; !r && i < sizeof(star) / sizeof(star[0]); i++) {
		for (a = 0; a < 3; a++) {
			t[a] = s->ref_nom[a] + 0.9 * half * star[i][a];
			w->seg_a[a] = w->seg_b[a];
			w->seg_b[a] = t[a] - s->ref_nom[a];
		}
		r = cal_move(s, t, 40.0);
		if (!r)
			r = cal_measure(s, e);
		for (a = 0; !r && a < 3; a++)
			*rest_max = fmax(*rest_max, fabs(e[a]));
	}
	return r;
}

int cal_path_check(struct cal_sim *s, double half, struct cal_path *out)
{
	struct watch w;
	unsigned int a;
	int r = 0;

	memset(out, 0, sizeof(*out));
	memset(&w, 0, sizeof(w));
	w.s = s;
	w.out = out;
	for (a = 0; !r && a < SH2000_AXES; a++) {
		/* user units (mm) to the card's counts */
		r = sh2000_param_get(s->h, (int)a, SH2000_P_VMAX, &w.vmax[a]);
		if (!r)
			r = sh2000_param_get(s->h, (int)a, SH2000_P_AMAX, &w.amax[a]);
		if (!r)
			r = sh2000_param_get(s->h, (int)a, SH2000_P_SOFT_MIN,
					     &w.soft_lo[a]);
		if (!r)
			r = sh2000_param_get(s->h, (int)a, SH2000_P_SOFT_MAX,
					     &w.soft_hi[a]);
		w.vmax[a] *= s->scale[a];
		w.amax[a] *= s->scale[a];
		w.soft_lo[a] *= s->scale[a];
		w.soft_hi[a] *= s->scale[a];
		if (a < 3)
			w.count_mm = fmax(w.count_mm, 1.0 / s->scale[a]);
	}
	if (!r)
		r = sh2000_sim_set_observer(s->h, observe, &w);
	if (!r)
		r = run_program(&w, half, &out->rest_max);
	sh2000_sim_set_observer(s->h, NULL, NULL);
	if (out->cycles) {
		out->path_rms = sqrt(w.sq / (double)out->cycles);
		out->contour_rms = sqrt(w.contour_sq / (double)out->cycles);
		out->geo_rms = sqrt(w.geo_sq / (3.0 * (double)out->cycles));
	}
	return r;
}
