// SPDX-License-Identifier: MIT
/*
 * The calibration's passes on the simulated machine (calib.h): each axis'
 * line (pitch, and the straightness the other axis of the X-Y plane shows
 * along it), then the X-Y grid (flatness in Z); the squareness is the
 * straight-line part of X's error along Y.
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "calib.h"

/* Points from lo - step to hi + step: the card's tables have slope 0 at
 * their ends, so the travel's ends are inner points. */
static unsigned int points(double lo, double hi, double step)
{
	return (unsigned int)floor((hi - lo) / step + 0.5) + 3u;
}

static double worst(const double *e, unsigned int n)
{
	double m = 0.0;
	unsigned int i;

	for (i = 0; i < n; i++)
		m = fmax(m, fabs(e[i]));
	return m;
}

/* The share of this measurement a table takes: none for an axis whose
 * set-point stood too near a whole count to be centred (calcentre.c): its
 * point keeps what the earlier passes found. */
static double share(unsigned int loose, unsigned int a, double w)
{
	return (loose & (1u << a)) ? 0.0 : w;
}

static int line_pass(struct cal_sim *s, const struct cal_config *c,
		     unsigned int a, double w, double base,
		     struct cal_tables *t)
{
	unsigned int n = points(c->lo[a], c->hi[a], c->step_mm), i;
	double target[SH2000_AXES], e[SH2000_AXES], ea[CAL_MAX_POINTS];
	unsigned int loose = 0;
	int r = n > CAL_MAX_POINTS ? -E2BIG : 0;

	memcpy(target, s->ref_nom, sizeof(target));
	for (i = 0; !r && i < n; i++) {
		target[a] = c->lo[a] - c->step_mm + i * c->step_mm;
		r = cal_move(s, target, c->feed);
		if (!r)
			r = cal_measure_centred(s, e, &loose);
		if (r)
			break;
		ea[i] = e[a];
		t->pitch[a].pos[i] = target[a];
		t->pitch[a].corr[i] += share(loose, a, w) * (base - e[a]);
		if (a == 0) {
			t->cross_yx.pos[i] = target[a];
			t->cross_yx.corr[i] -= share(loose, 1, w) * e[1];
		} else if (a == 1) {
			t->raw_xy.pos[i] = target[a];
			t->raw_xy.corr[i] -= share(loose, 0, w) * e[0];
		}
	}
	t->pitch[a].n = n;
	if (a == 0)
		t->cross_yx.n = n;
	if (a == 1)
		t->raw_xy.n = n;
	if (!r && c->verbose)
		fprintf(stderr, "sh2000-comp: axis %c: %u points, largest error %.1f nm\n",
			SH2000_AXIS_LETTERS[a], n, 1e6 * worst(ea, n));
	return r ? r : cal_move(s, s->ref_nom, c->feed);
}

static int grid_pass(struct cal_sim *s, const struct cal_config *c,
		     double w, struct cal_tables *t)
{
	unsigned int n1 = points(c->lo[0], c->hi[0], c->grid_mm);
	unsigned int n2 = points(c->lo[1], c->hi[1], c->grid_mm), i, j;
	double target[SH2000_AXES], e[SH2000_AXES], big = 0.0;
	unsigned int loose = 0;
	int r = (n1 > CAL_MAX_GRID || n2 > CAL_MAX_GRID) ? -E2BIG : 0;

	memcpy(target, s->ref_nom, sizeof(target));
	t->gn1 = n1;
	t->gn2 = n2;
	t->gu0 = c->lo[0] - c->grid_mm;
	t->gv0 = c->lo[1] - c->grid_mm;
	t->gdu = t->gdv = c->grid_mm;
	for (j = 0; !r && j < n2; j++)
		for (i = 0; !r && i < n1; i++) {
			/* a serpentine: every row from where the last ended */
			unsigned int k = (j & 1) ? n1 - 1 - i : i;

			target[0] = t->gu0 + k * t->gdu;
			target[1] = t->gv0 + j * t->gdv;
			r = cal_move(s, target, c->feed);
			if (!r)
				r = cal_measure_centred(s, e, &loose);
			if (!r) {
				t->grid[j * n1 + k] -= share(loose, 2, w) * e[2];
				big = fmax(big, fabs(e[2]));
			}
		}
	if (!r && c->verbose)
		fprintf(stderr, "sh2000-comp: grid Z by X, Y: %u x %u points, largest error %.1f nm\n",
			n1, n2, 1e6 * big);
	return r ? r : cal_move(s, s->ref_nom, c->feed);
}

/* X's corrections along Y: the least-squares line through them is the
 * squareness, the rest the straightness table. */
static void split_square(struct cal_tables *t)
{
	const struct cal_line *raw = &t->raw_xy;
	double sx = 0, sy = 0, sxx = 0, sxy = 0, n = raw->n, k;
	unsigned int i;

	for (i = 0; i < raw->n; i++) {
		sx += raw->pos[i];
		sy += raw->corr[i];
		sxx += raw->pos[i] * raw->pos[i];
		sxy += raw->pos[i] * raw->corr[i];
	}
	k = (n * sxy - sx * sy) / (n * sxx - sx * sx);
	t->square_xy = k;
	t->cross_xy.n = raw->n;
	for (i = 0; i < raw->n; i++) {
		t->cross_xy.pos[i] = raw->pos[i];
		t->cross_xy.corr[i] = raw->corr[i] - k * raw->pos[i];
	}
}

int cal_run(struct cal_sim *s, const struct cal_config *c,
	    struct cal_tables *t)
{
	unsigned int pass, a;
	int r;

	/* the first pass under half a count on every axis, which its
	 * pitch tables keep (calcentre.c) */
	cal_half_count(t, s);
	r = cal_load(s, t);
	memset(t, 0, sizeof(*t));
	for (pass = 0; !r && pass < c->passes; pass++) {
		/* each pass measures what the tables so far leave, with the
		 * counter's own noise (where in its count the servo holds
		 * each point); taking 1/(pass+1) of it keeps the tables the
		 * mean of every pass' estimate instead of the last one's */
		double w = 1.0 / (pass + 1.0);

		if (c->verbose)
			fprintf(stderr, "sh2000-comp: pass %u of %u\n", pass + 1,
				c->passes);
		for (a = 0; !r && a < SH2000_AXES; a++)
			r = line_pass(s, c, a, w,
				      pass ? 0.0 : 0.5 / s->scale[a], t);
		if (!r)
			r = grid_pass(s, c, w, t);
		if (!r) {
			split_square(t);
			r = cal_load(s, t);
		}
	}
	return r;
}
