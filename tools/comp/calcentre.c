// SPDX-License-Identifier: MIT
/*
 * Measuring a point to a fraction of a count (calib.h). The card's loop
 * closes on its observer's reading, finer than a count, and holds the
 * reading at rest in the middle of the set-point S's count, S + 1/2
 * (docs/cardmodel.md "Controller and defaults"), whatever S's fraction:
 * where the card's correction should put the tool, so the measurement is
 * taken as it is. The reference and the first pass are still held under
 * a table of half a count on every axis (later passes under the tables
 * found so far), as before: the same set-points as the benchmark's
 * perfect machine.
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

/* The tool at rest, against where it should be: as measured. No axis'
 * measurement is loose (the reading holds in the middle of the count,
 * not anywhere in it). */
int cal_measure_centred(struct cal_sim *s, double err[SH2000_AXES],
			unsigned int *loose)
{
	*loose = 0;
	return cal_measure(s, err);
}

/* The interferometer zeroed with the machine held on the half-count
 * table (its reading in the middle of the reference's count); then the
 * tables cleared again. */
int cal_reference(struct cal_sim *s)
{
	struct cal_tables *t = calloc(1, sizeof(*t));
	double off[SH2000_AXES];
	unsigned int a;
	int r = t ? 0 : -ENOMEM;

	if (!r) {
		cal_half_count(t, s);
		r = cal_load(s, t);
	}
	if (!r)
		r = cal_tool_avg(s, s->ref_tool);
	sh2000_fw_comp_offset(s->fw, off);
	for (a = 0; a < SH2000_AXES; a++)
		s->ref_sp[a] = s->at[a] * s->scale[a] + off[a];
	if (!r)
		r = sh2000_comp_clear(s->h);
	if (!r)
		r = cal_wait_switch(s);
	free(t);
	return r;
}
