// SPDX-License-Identifier: MIT
/*
 * Calibrating the simulated machine (docs/compensation.md "Calibration on
 * sim"): the interferometer is zeroed where the machine stands; each axis
 * is stepped along its travel (one step beyond each end) with the others
 * at the reference, and the plane X-Y over a grid, every point measured at
 * rest. Errors are the tool's travel from the reference less the nominal
 * travel; the corrections are their negatives, added to the tables found
 * so far (a second pass measures with the first pass' tables on and takes
 * out what is left).
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "calib.h"
#include "sh2000/run.h"

/* Dwell before a measurement, samples averaged and their spacing. */
#define SETTLE_NS	30000000ull
#define SAMPLES		128
#define SAMPLE_NS	2000000ull
#define SWITCH_WAIT_MS	3000

void cal_config_default(struct cal_config *c)
{
	unsigned int a;

	memset(c, 0, sizeof(*c));
	for (a = 0; a < SH2000_AXES; a++) {
		c->lo[a] = -250.0;
		c->hi[a] = 250.0;
	}
	c->step_mm = 1.0;
	c->grid_mm = 25.0;
	c->feed = 50.0;
	c->passes = 2;
}

int cal_move(struct cal_sim *s, const double target[SH2000_AXES], double feed)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_run *run = NULL;
	char err[256];
	int r;

	sh2000_run_config_default(&rc);
	r = sh2000_run_path_config(s->h, &pc);
	if (!r)
		r = sh2000_run_create(&run, s->h, &pc, &rc, err, sizeof(err));
	if (!r)
		r = sh2000_path_move_abs(sh2000_run_path(run), target, feed);
	if (r >= 0 && run)
		r = sh2000_run_finish(run);
	sh2000_run_destroy(run);
	if (r >= 0)
		memcpy(s->at, target, sizeof(s->at));
	return r < 0 ? r : 0;
}

int cal_tool_avg(struct cal_sim *s, double tool[SH2000_AXES])
{
	double t[SH2000_AXES];
	unsigned int a, k;
	int r = sh2000_sleep_ns(s->h, SETTLE_NS);

	memset(tool, 0, SH2000_AXES * sizeof(tool[0]));
	for (k = 0; !r && k < SAMPLES; k++) {
		r = sh2000_sim_tool_position(s->h, t);
		for (a = 0; a < SH2000_AXES; a++)
			tool[a] += t[a] / SAMPLES;
		if (!r)
			r = sh2000_sleep_ns(s->h, SAMPLE_NS);
	}
	return r;
}

int cal_measure(struct cal_sim *s, double err[SH2000_AXES])
{
	double tool[SH2000_AXES];
	unsigned int a;
	int r = cal_tool_avg(s, tool);

	for (a = 0; !r && a < SH2000_AXES; a++)
		err[a] = (tool[a] - s->ref_tool[a]) - (s->at[a] - s->ref_nom[a]);
	return r;
}

int cal_sim_open(struct cal_sim *s, const struct sh2000_sim_config *cfg,
		 const struct sh2000_geometry *g, const char *tmp, char *msg,
		 size_t len)
{
	struct sh2000_path_config pc;
	struct sh2000_geometry def;
	unsigned int a;
	int r;

	memset(s, 0, sizeof(*s));
	s->tmp = tmp;
	r = sh2000_sim_open(&s->h, cfg, msg, len);
	if (r < 0)
		return r;
	s->fw = sh2000_cardsim_fw(sh2000_sim_card(s->h));
	sh2000_geometry_default(&def);
	s->geom = g ? *g : def;
	r = sh2000_sim_set_geometry(s->h, &s->geom);
	if (!r)
		r = sh2000_enable(s->h, (1u << SH2000_AXES) - 1u);
	if (!r)
		r = sh2000_run_path_config(s->h, &pc);
	for (a = 0; !r && a < SH2000_AXES; a++) {
		s->scale[a] = pc.counts_per_mm[a];
		s->ref_nom[a] = s->at[a] = pc.start[a];
	}
	if (!r)
		r = cal_reference(s);
	if (r < 0) {
		snprintf(msg, len, "sim: %s", sh2000_last_error(s->h));
		cal_sim_close(s);
	}
	return r;
}

void cal_sim_close(struct cal_sim *s)
{
	sh2000_close(s->h);
	s->h = NULL;
}

int cal_load(struct cal_sim *s, const struct cal_tables *t)
{
	int r = cal_tables_save(t, s->tmp, "calibration pass");

	if (!r)
		r = sh2000_comp_load_file(s->h, s->tmp);
	return r ? r : cal_wait_switch(s);
}

int cal_wait_switch(struct cal_sim *s)
{
	struct sh2000_comp_status st;
	int r = 0, waited;

	for (waited = 0; !r && waited < SWITCH_WAIT_MS; waited += 10) {
		r = sh2000_comp_status(s->h, &st);
		if (r || st.state != SH2000_COMP_SWITCHING)
			break;
		r = sh2000_sleep_ns(s->h, 10000000ull);
	}
	return r;
}
