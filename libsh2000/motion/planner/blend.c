// SPDX-License-Identifier: MIT
/*
 * Corner blending within the path tolerance (G64 P): where two straight
 * moves meet at a corner, the corner is cut by a circular arc tangent to
 * both, as deep as the tolerance allows (its middle is the tolerance from
 * the corner; without a tolerance, G64 alone, as deep as the moves allow)
 * and no longer than half of either move, in the plane of the two moves
 * whatever their axes. The path stays within the tolerance and
 * the corner is taken at the arc's speed instead of the speed at which
 * the axes can turn in one period. LinuxCNC's trajectory planner blends
 * the same way.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

/* Blends narrower than this are not worth a block. */
#define BLEND_MIN_MM 1e-6
/* What the arc itself may take of the tolerance: the rest is for the
 * card's spline, which passes the curvature steps at the arc's ends within
 * about half a micrometre when compensated (a micrometre is kept; at most
 * half the tolerance), and cuts the arc inwards by (vT)^2 / 6R when raw
 * (half the tolerance; the arc's speed keeps the cut within it). */
#define BLEND_SPLINE_MM 0.001
#define BLEND_SHARE_RAW 0.5

/* The last block queued, if it is a line that can still be shortened. */
static struct pl_block *tail_line(struct sh2000_path *p)
{
	struct pl_block *t;

	if (!p->count || p->count + 2 > p->cap)
		return NULL;
	t = (struct pl_block *)pl_block_at(p, p->count - 1);
	if (t->type != BLK_LINE || t->stop_after)
		return NULL;
	/* the controller may be in it: leave what it is about to reach */
	if (p->count == 1 && p->moving)
		return NULL;
	return t;
}

/* The arc block from the tangent point on the tail to the one on b. */
static void arc_block(struct sh2000_path *p, const struct pl_block *t,
		      const struct pl_block *b, double R, double phi,
		      struct pl_block *k)
{
	const double *t1 = t->g.line.d, *t2 = b->g.line.d;
	double c = pl_dot(t1, t2), n, w[SH2000_AXES], tt[SH2000_AXES];
	unsigned int a;

	memset(k, 0, sizeof(*k));
	k->type = BLK_BLEND;
	k->feed = fmin(t->feed, b->feed);
	/* w: the direction towards the centre, in the plane of t1 and t2 */
	for (a = 0; a < SH2000_AXES; a++)
		w[a] = t2[a] - c * t1[a];
	n = sqrt(pl_dot(w, w));
	for (a = 0; a < SH2000_AXES; a++) {
		w[a] /= n;
		k->p0[a] = t->p1[a];
		k->g.blend.c[a] = t->p1[a] + R * w[a];
		k->g.blend.u[a] = -w[a];	/* centre to start */
		k->g.blend.w[a] = t1[a];	/* start's tangent */
		k->t0[a] = t1[a];
		k->t1[a] = t2[a];
		/* the most of axis a's share the turning tangent reaches */
		tt[a] = sqrt(w[a] * w[a] + t1[a] * t1[a]);
	}
	k->g.blend.R = R;
	k->g.blend.phi = phi;
	k->L = R * phi;
	k->vlim = pl_curve_vlim(p, tt, 1.0 / R);
}

int pl_blend_corner(struct sh2000_path *p, struct pl_block *b,
		    struct pl_block *arc)
{
	int raw = p->cfg.output == SH2000_OUTPUT_RAW;
	double tol = p->cfg.corner_tol, c, phi, R, d, share;
	struct pl_block *t;
	unsigned int a;

	if (b->type != BLK_LINE || p->cfg.mode != SH2000_PATH_BLEND ||
	    !(tol > 0.0) || p->stop_next)
		return 0;
	t = tail_line(p);
	if (!t || memcmp(t->p1, b->p0, sizeof(t->p1)))
		return 0;
	c = fmax(-1.0, fmin(1.0, pl_dot(t->g.line.d, b->g.line.d)));
	phi = acos(c);		/* the turn */
	if (phi < 1e-6 || phi > M_PI - 1e-3)
		return 0;	/* straight on, or back along itself */
	/* deviation at the arc's middle R (1 / cos(phi/2) - 1) = tol; no
	 * tolerance (G64 alone): as wide as the moves allow */
	share = raw ? BLEND_SHARE_RAW :
		pl_max(0.5, pl_min(0.95, 1.0 - BLEND_SPLINE_MM / tol));
	R = isinf(tol) ? INFINITY :
	    share * tol * cos(phi / 2) / (1.0 - cos(phi / 2));
	d = R * tan(phi / 2);
	if (d > 0.5 * fmin(t->L, b->L)) {
		d = 0.5 * fmin(t->L, b->L);
		R = d / tan(phi / 2);
	}
	if (d < BLEND_MIN_MM)
		return 0;
	t->L -= d;
	for (a = 0; a < SH2000_AXES; a++) {
		t->p1[a] -= d * t->g.line.d[a];
		b->p0[a] += d * b->g.line.d[a];
	}
	b->L -= d;
	arc_block(p, t, b, R, phi, arc);
	memcpy(arc->p1, b->p0, sizeof(arc->p1));
	if (raw && !isinf(tol))
		arc->vlim = fmin(arc->vlim, sqrt(6.0 * R * (1.0 - share) * 0.9 *
						 tol) / p->cfg.period_s);
	return 1;
}
