// SPDX-License-Identifier: MIT
/*
 * How far the simulated machine's tool is from where it was programmed
 * (calib.h, struct cal_path): every servo cycle the tool (the
 * interferometer) against the position the card reports (its counter in
 * nominal counts), which is what the tables correct and which leaves the
 * servo's lag out; at rest at each of a program's points the tool against
 * the point; the servo's following error and the corrected set-point's
 * velocity against vmax. The benchmark prints it, the tests bound it.
 */
#include <math.h>
#include <string.h>

#include "calib.h"

struct watch {
	struct cal_sim *s;
	struct cal_path *out;
	double prev_sp[SH2000_AXES], prev_tool[SH2000_AXES];
	double vmax[SH2000_AXES];	/* counts/s */
	double sq;
	int have_prev;
};

static void observe(void *ctx, const struct sh2000_probe *p)
{
	struct watch *w = ctx;
	struct cal_sim *s = w->s;
	struct cal_path *o = w->out;
	double T = 1e-9 * (double)sh2000_fw_servo_period_ns(s->fw);
	double off[SH2000_AXES];
	unsigned int a;

	sh2000_fw_comp_offset(s->fw, off);
	for (a = 0; a < 3 && w->have_prev; a++) {
		/* the counter was read at the cycle's start: where the last
		 * cycle left the tool */
		double nom_act = (p->axis[a].actual - off[a]) / s->scale[a];
		double e = (w->prev_tool[a] - s->ref_tool[a]) -
			   (nom_act - s->ref_nom[a]);
		double sp = p->axis[a].fine_cmd + off[a];

		o->geo_max = fmax(o->geo_max, fabs(e));
		w->sq += e * e;
		o->lag_max = fmax(o->lag_max, fabs(sp - p->axis[a].actual));
		o->vel_ratio = fmax(o->vel_ratio, fabs(sp - w->prev_sp[a]) /
				    T / w->vmax[a]);
	}
	for (a = 0; a < SH2000_AXES; a++)
		w->prev_sp[a] = p->axis[a].fine_cmd + off[a];
	sh2000_fw_tool_position(s->fw, w->prev_tool);
	if (w->have_prev)
		o->cycles++;
	w->have_prev = 1;
}

/* The program: a star of lines in X-Y with Z going up and down, every
 * point reached at rest, at 40 mm/s, within +-0.9 half of the reference. */
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
		r = sh2000_param_get(s->h, (int)a, SH2000_P_VMAX, &w.vmax[a]);
		w.vmax[a] *= s->scale[a];	/* mm/s to counts/s */
	}
	if (!r)
		r = sh2000_sim_set_observer(s->h, observe, &w);
	if (!r)
		r = run_program(s, half, &out->rest_max);
	sh2000_sim_set_observer(s->h, NULL, NULL);
	out->geo_rms = out->cycles ? sqrt(w.sq / (3.0 * (double)out->cycles)) : 0.0;
	return r;
}
