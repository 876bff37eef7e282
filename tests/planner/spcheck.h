/* SPDX-License-Identifier: MIT */
/*
 * The card's fine set-points of a planned program, checked as they stream
 * out of the planner's sink: every axis' velocity, acceleration and jerk
 * against its limits (finite differences over the servo cycle), and the
 * distance of every set-point from the program's own geometry.
 *
 * The fine set-points are what the card makes of the records: a window of
 * four through sh2000_bspline, starting full of the start point and padded
 * with the end point after every END (as tests/planner/plcheck.h's
 * card_seq, but streaming, so a planner's sink can feed it point by point).
 * The geometry is the program's motion blocks flattened to a polyline
 * (arcs and NURBS refined until a segment's middle is within SP_FLAT_MM of
 * its chord); a set-point is on the path when it lies within the tolerance
 * of one of its segments.
 *
 * Header-only: tests/planner (regression tests) and tests/fuzz (the
 * reader + planner harness) share it.
 */
#ifndef SH2000_SPCHECK_H
#define SH2000_SPCHECK_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sh2000/bspline.h"
#include "sh2000/geometry.h"
#include "sh2000/path.h"
#include "sh2000/program.h"

/* mm: a flattened arc or NURBS segment's middle from its chord, at most */
#define SP_FLAT_MM	1e-5
/* vertices of a program's polyline, at most (more: coarser flattening,
 * its error measured and allowed for) */
#define SP_MAX_VERTS	400000

struct sp_path {
	double (*v)[SH2000_AXES];	/* vertices */
	unsigned char *brk;	/* 1: no segment from vertex i - 1 to i */
	size_t n, cap;
	double flat;		/* largest flattening error, mm */
	size_t cur;		/* the segment the last query matched */
};

struct sp_check {
	struct sh2000_path_config cfg;
	unsigned int F;		/* fine steps per period */
	double h;		/* servo cycle, s */
	double w[4][SH2000_AXES];	/* the card's window */
	double x[3][SH2000_AXES];	/* the last three fine points */
	unsigned long long fine;	/* fine points so far */
	const struct sp_path *path;	/* NULL: no geometry check */
	double tol;		/* mm from the path a set-point may be */
	/* worst seen: ratios to the limits, distance, and where (fine index);
	 * the distance stops at the first point further than tol from the
	 * path: the points after it are measured to the near segments only,
	 * an upper bound that a set-point 0.011 mm off the path once turned
	 * into 3.37 mm, so they are left out */
	double v_ratio, a_ratio, j_ratio, dev;
	unsigned long long v_at, a_at, j_at, dev_at;
	double dev_point[SH2000_AXES];
	/* called with every fine set-point, if set */
	void (*each)(void *ctx, const double y[SH2000_AXES]);
	void *each_ctx;
};

/* ---- the program's geometry ---- */

static inline int sp_add(struct sp_path *g, const double x[SH2000_AXES],
			 int brk)
{
	if (g->n == g->cap) {
		size_t cap = g->cap ? 2 * g->cap : 256;
		void *v = realloc(g->v, cap * sizeof(*g->v));
		void *b;

		if (!v)
			return -1;
		g->v = v;
		b = realloc(g->brk, cap);
		if (!b)
			return -1;
		g->brk = b;
		g->cap = cap;
	}
	memcpy(g->v[g->n], x, sizeof(g->v[0]));
	g->brk[g->n++] = (unsigned char)brk;
	return 0;
}

static inline double sp_dist_seg(const double p[SH2000_AXES],
				 const double a[SH2000_AXES],
				 const double b[SH2000_AXES])
{
	double ab = 0, ap = 0, t, d = 0;
	unsigned int k;

	for (k = 0; k < SH2000_AXES; k++) {
		ab += (b[k] - a[k]) * (b[k] - a[k]);
		ap += (p[k] - a[k]) * (b[k] - a[k]);
	}
	t = ab > 0 ? fmin(fmax(ap / ab, 0.0), 1.0) : 0.0;
	for (k = 0; k < SH2000_AXES; k++) {
		double q = a[k] + t * (b[k] - a[k]) - p[k];

		d += q * q;
	}
	return sqrt(d);
}

/* An arc: enough points that each chord's sagitta is SP_FLAT_MM. */
static inline int sp_add_arc(struct sp_path *g,
			     const struct sh2000_prog_block *b)
{
	const struct sh2000_arc *a = &b->u.arc;
	double r = fmax(a->r0, a->r1), step = sqrt(8.0 * SP_FLAT_MM / r);
	double n = ceil(fabs(a->sweep) / step), x[SH2000_AXES];
	size_t i, N;

	if (n > SP_MAX_VERTS / 4)
		n = SP_MAX_VERTS / 4;
	N = n < 1 ? 1 : (size_t)n;
	g->flat = fmax(g->flat, r * (1 - cos(fabs(a->sweep) / N / 2)));
	for (i = 1; i <= N; i++) {
		sh2000_arc_point(a, b->start, b->end, (double)i / N, x);
		if (sp_add(g, x, 0))
			return -1;
	}
	return 0;
}

/* A NURBS span [u0, u1] (the point at u0 is in already): halved until the
 * middle is within SP_FLAT_MM of the chord, at least 4 pieces. */
static inline int sp_add_nurbs_span(struct sp_path *g,
				    const struct sh2000_nurbs *n, double u0,
				    const double c0[SH2000_AXES], double u1,
				    const double c1[SH2000_AXES],
				    unsigned int depth)
{
	double um = 0.5 * (u0 + u1), cm[SH2000_AXES], d;

	sh2000_nurbs_eval(n, um, cm, NULL, NULL);
	d = sp_dist_seg(cm, c0, c1);
	if ((d > SP_FLAT_MM || depth < 2) && depth < 40 &&
	    g->n < SP_MAX_VERTS && um > u0 && um < u1) {
		if (sp_add_nurbs_span(g, n, u0, c0, um, cm, depth + 1))
			return -1;
		return sp_add_nurbs_span(g, n, um, cm, u1, c1, depth + 1);
	}
	/* a piece left coarser than wanted: allow for it (twice its middle's
	 * distance bounds a smooth piece's) */
	if (d > SP_FLAT_MM)
		g->flat = fmax(g->flat, 2 * d);
	return sp_add(g, c1, 0);
}

static inline int sp_add_nurbs(struct sp_path *g,
			       const struct sh2000_nurbs *n)
{
	const double *U = n->knots;
	double c0[SH2000_AXES], c1[SH2000_AXES];
	size_t i;

	for (i = n->degree; i < n->npoints; i++) {
		if (U[i] >= U[i + 1])
			continue;
		sh2000_nurbs_eval(n, U[i], c0, NULL, NULL);
		sh2000_nurbs_eval(n, U[i + 1], c1, NULL, NULL);
		if (sp_add_nurbs_span(g, n, U[i], c0, U[i + 1], c1, 0))
			return -1;
	}
	return 0;
}

/* The polyline of a program's motion blocks, each from its start. */
static inline int sp_path_build(struct sp_path *g,
				const struct sh2000_program *prog)
{
	size_t i;
	int r = 0;

	memset(g, 0, sizeof(*g));
	for (i = 0; i < prog->count && !r; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];
		int connected = g->n &&
				sp_dist_seg(b->start, g->v[g->n - 1],
					    g->v[g->n - 1]) == 0;

		switch (b->kind) {
		case SH2000_PROG_RAPID:
		case SH2000_PROG_LINE:
		case SH2000_PROG_ARC:
		case SH2000_PROG_NURBS:
			break;
		default:
			continue;
		}
		if (!connected)
			r = sp_add(g, b->start, 1);
		if (r)
			break;
		if (b->kind == SH2000_PROG_ARC)
			r = sp_add_arc(g, b);
		else if (b->kind == SH2000_PROG_NURBS)
			r = sp_add_nurbs(g, &b->u.nurbs);
		else
			r = sp_add(g, b->end, 0);
	}
	return r;
}

static inline void sp_path_free(struct sp_path *g)
{
	free(g->v);
	free(g->brk);
	memset(g, 0, sizeof(*g));
}

/* Distance from x to the path: the segments near the last match first, a
 * whole scan only when they are further than tol and `whole` is set. */
static inline double sp_path_dist(struct sp_path *g,
				  const double x[SH2000_AXES], double tol,
				  int whole)
{
	double best = INFINITY;
	size_t i, k, last = whole ? 2 * g->n : 16, c = g->cur, at = c;

	if (g->n == 0)
		return 0.0;
	if (g->n == 1)
		return sp_dist_seg(x, g->v[0], g->v[0]);
	/* the walk goes out from where the last query matched, which stays
	 * put until the walk is over: moved to each better match on the way,
	 * the walk skipped the segments between the old and the new centre
	 * (a set-point 6 um from a dense stretch of path was measured 17 um
	 * from it) */
	for (k = 0; k <= last; k++) {
		/* c, c + 1, c - 1, c + 2, ... */
		size_t off = (k + 1) / 2;

		if (k % 2 ? c + off >= g->n : c < off)
			continue;
		i = k % 2 ? c + off : c - off;
		if (i == 0)
			continue;
		{
			double d = g->brk[i] ? sp_dist_seg(x, g->v[i], g->v[i]) :
				   sp_dist_seg(x, g->v[i - 1], g->v[i]);

			if (d < best) {
				best = d;
				at = i;
			}
		}
		if (best <= tol && k > 8)
			break;
	}
	g->cur = at;
	return best;
}

/* ---- the card's fine set-points ---- */

static inline void sp_init(struct sp_check *c,
			   const struct sh2000_path_config *cfg,
			   const double start[SH2000_AXES],
			   const struct sp_path *path, double tol)
{
	unsigned int k;

	memset(c, 0, sizeof(*c));
	c->cfg = *cfg;
	c->F = cfg->fine_steps;
	c->h = cfg->period_s / cfg->fine_steps;
	for (k = 0; k < 4; k++)
		memcpy(c->w[k], start, sizeof(c->w[0]));
	for (k = 0; k < 3; k++)
		memcpy(c->x[k], start, sizeof(c->x[0]));
	c->path = path;
	c->tol = tol;
}

/* One fine set-point: its differences against the limits, its distance
 * from the path. */
static inline void sp_fine(struct sp_check *c, const double y[SH2000_AXES])
{
	unsigned int k;

	for (k = 0; k < SH2000_AXES; k++) {
		double v = (y[k] - c->x[2][k]) / c->h;
		double a = (y[k] - 2 * c->x[2][k] + c->x[1][k]) / (c->h * c->h);
		double j = (y[k] - 3 * c->x[2][k] + 3 * c->x[1][k] - c->x[0][k]) /
			   (c->h * c->h * c->h);

		if (fabs(v) / c->cfg.vmax[k] > c->v_ratio) {
			c->v_ratio = fabs(v) / c->cfg.vmax[k];
			c->v_at = c->fine;
		}
		if (fabs(a) / c->cfg.amax[k] > c->a_ratio) {
			c->a_ratio = fabs(a) / c->cfg.amax[k];
			c->a_at = c->fine;
		}
		if (fabs(j) / c->cfg.jerk > c->j_ratio) {
			c->j_ratio = fabs(j) / c->cfg.jerk;
			c->j_at = c->fine;
		}
	}
	if (c->path) {
		/* once a point is known to be off the path, the rest need only
		 * the near segments: the check has failed either way, and a
		 * whole scan for each point of a long stretch off the path
		 * takes minutes (those distances are bounds: not kept) */
		int whole = c->dev <= c->tol;
		double d = sp_path_dist((struct sp_path *)c->path, y, c->tol,
					whole);

		if (whole && d > c->dev) {
			c->dev = d;
			c->dev_at = c->fine;
			memcpy(c->dev_point, y, sizeof(c->dev_point));
		}
	}
	if (c->each)
		c->each(c->each_ctx, y);
	memmove(c->x[0], c->x[1], 2 * sizeof(c->x[0]));
	memcpy(c->x[2], y, sizeof(c->x[2]));
	c->fine++;
}

/* A record into the card's window and the fine set-points it makes. */
static inline void sp_record(struct sp_check *c, const double x[SH2000_AXES])
{
	unsigned int f, k;

	memmove(c->w[0], c->w[1], 3 * sizeof(c->w[0]));
	memcpy(c->w[3], x, sizeof(c->w[3]));
	for (f = 1; f <= c->F; f++) {
		double t = (double)f / c->F, y[SH2000_AXES];

		for (k = 0; k < SH2000_AXES; k++)
			y[k] = sh2000_bspline(c->w[0][k], c->w[1][k], c->w[2][k],
					      c->w[3][k], t);
		sp_fine(c, y);
	}
}

/* A point from the planner's sink; after an END the card pads its window
 * with the end point. */
static inline void sp_point(struct sp_check *c,
			    const struct sh2000_path_point *pt)
{
	unsigned int k;

	sp_record(c, pt->mm);
	if (pt->flags & SH2000_PATH_F_END)
		for (k = 0; k < 3; k++)
			sp_record(c, pt->mm);
}

#endif /* SH2000_SPCHECK_H */
