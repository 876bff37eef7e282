// SPDX-License-Identifier: MIT
/*
 * How far a set of tables moves each axis inside its soft limits, and
 * whether the corrected position at a soft limit lies beyond it. The card
 * judges soft limits on the nominal set-point and adds the tables'
 * correction after (docs/compensation.md "Soft limits and the
 * corrections"), so a positive correction at soft_max puts the tool
 * beyond it and no fault says so. Every front end that puts tables on a
 * card (sh2000ctl comp load, hal_sh2000's comp=, sh2000-comp) asks this
 * file. The tables are evaluated by the card's own code
 * (sh2000_comp_eval_table()); here they are only sampled.
 */
#include <ctype.h>
#include <math.h>
#include <stdio.h>

#include "sh2000/comp.h"
#include "sh2000/sh2000_protocol.h"

/* Samples across a window: the tables' slope is at most
 * SH2000_COMP_VMAX_SHARE, so a sample step s misses at most 0.02 s of a
 * peak (0.2 um over a 1 m window). */
#define REACH_SAMPLES	20001u
#define GRID_SAMPLES	401u

static int lo_set(const struct sh2000_comp_window *win, unsigned int a)
{
	return win->soft_min[a] != INT32_MIN;
}

static int hi_set(const struct sh2000_comp_window *win, unsigned int a)
{
	return win->soft_max[a] != INT32_MAX;
}

/* A source axis' range for one table: its soft limits, where one is off
 * where the table changes (sh2000_comp_table_span(); a squareness, which
 * changes everywhere, over a metre either way). */
static void source_range(const uint16_t *w, const struct sh2000_comp_desc *t,
			 int second, const struct sh2000_comp_window *win,
			 double r[2])
{
	unsigned int a = second ? t->src2 : t->src1;
	double span[2];

	sh2000_comp_table_span(w, t, second, span);
	if (isinf(span[0]) || isinf(span[1])) {
		span[0] = -1000.0 * win->scale[a];
		span[1] = 1000.0 * win->scale[a];
	}
	r[0] = lo_set(win, a) ? win->soft_min[a] : span[0];
	r[1] = hi_set(win, a) ? win->soft_max[a] : span[1];
	/* one limit off and the table beyond the other: it holds there */
	if (!lo_set(win, a))
		r[0] = fmin(r[0], r[1]);
	if (!hi_set(win, a))
		r[1] = fmax(r[1], r[0]);
}

/* The smallest and largest correction of table t (counts) with its
 * sources in their ranges, the target axis held at `at` when it is one
 * of them (NAN: not held). */
static void table_range(const uint16_t *w, const struct sh2000_comp_desc *t,
			const struct sh2000_comp_window *win, double at,
			double mm[2])
{
	double r1[2], r2[2] = { 0, 0 }, pos[SH2000_AXES] = { 0 }, d[2], dd[3];
	int grid = t->kind == SH2000_COMP_GRID;
	unsigned int n1 = grid ? GRID_SAMPLES : REACH_SAMPLES;
	unsigned int n2 = grid ? GRID_SAMPLES : 1u;

	source_range(w, t, 0, win, r1);
	if (grid)
		source_range(w, t, 1, win, r2);
	if (!isnan(at) && t->src1 == t->target)
		r1[0] = r1[1] = at;
	if (!isnan(at) && grid && t->src2 == t->target)
		r2[0] = r2[1] = at;
	mm[0] = INFINITY;
	mm[1] = -INFINITY;
	for (unsigned int j = 0; j < n2; j++)
		for (unsigned int i = 0; i < n1; i++) {
			double c;

			pos[t->src1] = r1[0] + (r1[1] - r1[0]) * i / (n1 - 1u);
			if (grid)
				pos[t->src2] = r2[0] + (r2[1] - r2[0]) * j / (n2 - 1u);
			c = sh2000_comp_eval_table(w, t, pos, d, dd);
			mm[0] = fmin(mm[0], c);
			mm[1] = fmax(mm[1], c);
		}
}

/* Axis a's correction range: all its tables' ranges added (exact for one
 * table, a bound for several), the axis held at `at` (or NAN). The
 * number of tables that correct it. */
static unsigned int axis_range(const uint16_t *w,
			       const struct sh2000_comp_index *ix,
			       const struct sh2000_comp_window *win,
			       unsigned int a, double at, double sum[2])
{
	unsigned int tables = 0;

	sum[0] = sum[1] = 0.0;
	for (unsigned int i = 0; i < ix->tables; i++) {
		double mm[2];

		if (ix->t[i].target != a)
			continue;
		table_range(w, &ix->t[i], win, at, mm);
		sum[0] += mm[0];
		sum[1] += mm[1];
		tables++;
	}
	return tables;
}

/* How far the corrected position at soft limit `side` of axis a lies
 * beyond it (counts), 0 within the slack. */
static double beyond_at(const uint16_t *w, const struct sh2000_comp_index *ix,
			const struct sh2000_comp_window *win, unsigned int a,
			unsigned int side)
{
	double s[2], b;

	if (side ? !hi_set(win, a) : !lo_set(win, a))
		return 0.0;
	axis_range(w, ix, win, a, side ? win->soft_max[a] : win->soft_min[a], s);
	b = side ? s[1] : -s[0];
	return b > SH2000_COMP_REACH_SLACK ? b : 0.0;
}

int sh2000_comp_reach(const uint16_t *w, const struct sh2000_comp_index *ix,
		      const struct sh2000_comp_window *win,
		      struct sh2000_comp_reach reach[SH2000_AXES])
{
	int axes = 0;

	if (!w || !ix || !win || !reach)
		return -1;
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		struct sh2000_comp_reach *r = &reach[a];
		double s[2];

		*r = (struct sh2000_comp_reach){ 0 };
		r->tables = axis_range(w, ix, win, a, NAN, s);
		if (!r->tables)
			continue;
		r->lo = s[0];
		r->hi = s[1];
		r->beyond[0] = beyond_at(w, ix, win, a, 0);
		r->beyond[1] = beyond_at(w, ix, win, a, 1);
		axes++;
	}
	return axes;
}

int sh2000_comp_reach_warning(const struct sh2000_comp_window *win,
			      const struct sh2000_comp_reach reach[SH2000_AXES],
			      unsigned int axis, unsigned int side, char *msg,
			      size_t len)
{
	double lim, k, b;

	if (len)
		msg[0] = '\0';
	if (!win || !reach || axis >= SH2000_AXES || side > 1u ||
	    !(reach[axis].beyond[side] > 0.0))
		return 0;
	lim = side ? win->soft_max[axis] : win->soft_min[axis];
	k = win->scale[axis];
	b = reach[axis].beyond[side];
	return snprintf(msg, len, "axis %c at its %s %.6f mm: the tables put the tool up to %.6f mm beyond it (at %.6f mm): the card judges soft limits on nominal positions, then adds the correction",
			tolower((unsigned char)SH2000_AXIS_LETTERS[axis]),
			side ? "soft_max" : "soft_min", lim / k, b / k,
			(lim + (side ? b : -b)) / k);
}
