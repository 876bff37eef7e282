// SPDX-License-Identifier: MIT
/*
 * Measuring a point to a fraction of a count (calib.h). The card's loop
 * closes on the counter, the floor of the scale's reading; at rest it
 * holds the counter's mean on the set-point S, so with S between two
 * counts it hunts across the edge ceil(S) and the reading stays there,
 * while with S on a whole count the carriage may rest anywhere in that
 * count (up to a count off, and differently at every point). So the
 * calibration holds every point, and the reference, on a set-point with a
 * fraction: the reference and the first pass under a table of half a
 * count on every axis, later passes under the tables found so far. The
 * tool then stands at the edge ceil(S), which the host knows (S is the
 * nominal point plus the correction the card applies there), and the
 * measurement is moved by ceil(S) - S - 1/2 to the middle of S's count,
 * where the card's correction should put the tool.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "calib.h"

/* Every axis corrected by half a count, everywhere (two points, flat). */
void cal_half_count(struct cal_tables *t, const struct cal_sim *s)
{
	unsigned int a;

	memset(t, 0, sizeof(*t));
	for (a = 0; a < SH2000_AXES; a++) {
		struct cal_line *l = &t->pitch[a];

		l->n = 2;
		l->pos[0] = s->ref_nom[a] - 1.0;
		l->pos[1] = s->ref_nom[a] + 1.0;
		l->corr[0] = l->corr[1] = 0.5 / s->scale[a];
	}
}

/* A set-point this close to a whole count does not make the loop hunt
 * on the edge above it: the reading may rest anywhere in the count. */
#define EDGE_MARGIN	0.2

/* Where the reading holds, against the middle of the set-point's count,
 * in mm: ceil(S) - S - 1/2 counts, S the corrected set-point at rest.
 * Returns the axes (a bit each) whose S is within EDGE_MARGIN of a whole
 * count. */
static unsigned int edge_offset(const struct cal_sim *s,
				double q[SH2000_AXES])
{
	double off[SH2000_AXES];
	unsigned int a, loose = 0;

	sh2000_fw_comp_offset(s->fw, off);
	for (a = 0; a < SH2000_AXES; a++) {
		double S = s->at[a] * s->scale[a] + off[a];
		double f = S - floor(S);

		q[a] = (ceil(S) - S - 0.5) / s->scale[a];
		if (f < EDGE_MARGIN || f > 1.0 - EDGE_MARGIN)
			loose |= 1u << a;
	}
	return loose;
}

int cal_measure_centred(struct cal_sim *s, double err[SH2000_AXES],
			unsigned int *loose)
{
	double q[SH2000_AXES];
	unsigned int a;
	int r = cal_measure(s, err);

	*loose = edge_offset(s, q);
	for (a = 0; !r && a < SH2000_AXES; a++)
		err[a] -= q[a];
	return r;
}

/* The interferometer zeroed with the machine held on the half-count
 * table (its reading on the edge above the reference), moved to the
 * middle of the reference's count; then the tables cleared again. */
int cal_reference(struct cal_sim *s)
{
	struct cal_tables *t = calloc(1, sizeof(*t));
	double q[SH2000_AXES], off[SH2000_AXES];
	unsigned int a;
	int r = t ? 0 : -ENOMEM;

	if (!r) {
		cal_half_count(t, s);
		r = cal_load(s, t);
	}
	if (!r)
		r = cal_tool_avg(s, s->ref_tool);
	edge_offset(s, q);
	sh2000_fw_comp_offset(s->fw, off);
	for (a = 0; a < SH2000_AXES; a++) {
		s->ref_tool[a] -= q[a];
		s->ref_sp[a] = s->at[a] * s->scale[a] + off[a];
	}
	if (!r)
		r = sh2000_comp_clear(s->h);
	if (!r)
		r = cal_wait_switch(s);
	free(t);
	return r;
}
