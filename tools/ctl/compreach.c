// SPDX-License-Identifier: MIT
/*
 * sh2000ctl comp load: how far the loaded tables move each axis inside
 * its soft limits. The card judges soft limits on the nominal set-point
 * and adds the tables' correction after (docs/compensation.md "Soft
 * limits"), so a positive correction at soft_max puts the tool beyond it.
 * This says, per corrected axis, the range of its correction over the
 * soft-limit window of its source axes, and warns when the corrected
 * position at a soft limit lies beyond it. The tables are evaluated by
 * the protocol's own code (sh2000_comp_eval_table(), the card's); here
 * they are only sampled.
 */
#include <math.h>
#include <stdint.h>

#include <sh2000/sh2000_protocol.h>

#include "ctl.h"

/* Samples across a window: the tables' slope is at most
 * SH2000_COMP_VMAX_SHARE, so a sample step s misses at most 0.02 s of a
 * peak (0.2 um over a 1 m window). */
#define REACH_SAMPLES	20001u
#define GRID_SAMPLES	401u

struct window {
	double lo[SH2000_AXES], hi[SH2000_AXES];	/* counts */
	int lo_set[SH2000_AXES], hi_set[SH2000_AXES];	/* not off */
	double scale[SH2000_AXES];
};

/* A source axis' range for one table: its soft limits, where one is off
 * where the table changes (sh2000_comp_table_span(); a squareness, which
 * changes everywhere, over a metre either way). */
static void source_range(const uint16_t *w, const struct sh2000_comp_desc *t,
			 int second, const struct window *win, double r[2])
{
	unsigned int a = second ? t->src2 : t->src1;
	double span[2];

	sh2000_comp_table_span(w, t, second, span);
	if (isinf(span[0]) || isinf(span[1])) {
		span[0] = -1000.0 * win->scale[a];
		span[1] = 1000.0 * win->scale[a];
	}
	r[0] = win->lo_set[a] ? win->lo[a] : span[0];
	r[1] = win->hi_set[a] ? win->hi[a] : span[1];
	/* one limit off and the table beyond the other: it holds there */
	if (!win->lo_set[a])
		r[0] = fmin(r[0], r[1]);
	if (!win->hi_set[a])
		r[1] = fmax(r[1], r[0]);
}

/* The smallest and largest correction of table t (counts) with its
 * sources in their ranges, the target axis held at `at` when it is one
 * of them (NAN: not held). */
static void table_range(const uint16_t *w, const struct sh2000_comp_desc *t,
			const struct window *win, double at, double mm[2])
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
 * table, a bound for several), the axis held at `at` (or NAN). 0 when no
 * table corrects it. */
static int axis_range(const uint16_t *w, const struct sh2000_comp_index *ix,
		      const struct window *win, unsigned int a, double at,
		      double sum[2])
{
	int tables = 0;

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

static int window_get(struct ctl *c, struct window *win)
{
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		double lo, hi;
		int r = sh2000_param_get(c->h, (int)a, SH2000_P_SCALE, &win->scale[a]);

		if (!r)
			r = sh2000_param_get(c->h, (int)a, SH2000_P_SOFT_MIN, &lo);
		if (!r)
			r = sh2000_param_get(c->h, (int)a, SH2000_P_SOFT_MAX, &hi);
		if (r < 0)
			return r;
		win->lo[a] = nearbyint(lo * win->scale[a]);
		win->hi[a] = nearbyint(hi * win->scale[a]);
		win->lo_set[a] = win->lo[a] > (double)INT32_MIN;
		win->hi_set[a] = win->hi[a] < (double)INT32_MAX;
	}
	return 0;
}

/* Warn when the corrected position at soft limit `lim` (counts) lies
 * beyond it by more than half a count. */
static void warn_at(const uint16_t *w, const struct sh2000_comp_index *ix,
		    const struct window *win, unsigned int a, int upper)
{
	double lim = upper ? win->hi[a] : win->lo[a], k = win->scale[a], s[2];
	double beyond;

	axis_range(w, ix, win, a, lim, s);
	beyond = upper ? s[1] : -s[0];
	if (beyond <= 0.5)
		return;
	sh2000_tool_msg("warning: axis %c at its %s %.6f mm: the tables put the tool up to %.6f mm beyond it (at %.6f mm): the card judges soft limits on nominal positions, then adds the correction",
			sh2000_tool_axis_name(a), upper ? "soft_max" : "soft_min",
			lim / k, beyond / k, (lim + (upper ? beyond : -beyond)) / k);
}

int ctl_comp_reach(struct ctl *c, const char *file)
{
	struct sh2000_comp_file *f = NULL;
	struct sh2000_comp_index ix;
	struct sh2000_comp_fault why;
	struct window win;
	const uint16_t *w;
	char msg[512];
	size_t n;
	int r = window_get(c, &win);

	if (r < 0)
		return sh2000_tool_fail(c->h, r, "comp load");
	if (sh2000_comp_file_read(&f, file, win.scale, msg, sizeof(msg)) < 0)
		return 0;	/* loaded a moment ago: nothing to say */
	w = sh2000_comp_file_image(f, &n);
	if (sh2000_comp_parse(w, n, &ix, &why) == 0)
		for (unsigned int a = 0; a < SH2000_AXES; a++) {
			double s[2], k = win.scale[a];

			if (!axis_range(w, &ix, &win, a, NAN, s))
				continue;
			printf("axis %c: the tables correct it by %+.6f..%+.6f mm inside the soft limits\n",
			       sh2000_tool_axis_name(a), s[0] / k, s[1] / k);
			if (win.lo_set[a])
				warn_at(w, &ix, &win, a, 0);
			if (win.hi_set[a])
				warn_at(w, &ix, &win, a, 1);
		}
	sh2000_comp_file_free(f);
	return 0;
}
