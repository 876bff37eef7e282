// SPDX-License-Identifier: MIT
/*
 * Compensation tables (protocol 1.5): an image's layout, its evaluation and
 * the check against the axes' limits, shared by the card model (every servo
 * cycle, and at COMP_COMMIT) and the host (before it sends a file), so both
 * refuse the same tables.
 *
 * Interpolation: cubic Hermite between the points with the three-point
 * tangents (exact for a parabola; one-sided at the ends), so the correction
 * is continuous in position and in its first derivative (the set-point's
 * velocity never steps as a point is crossed). A grid is the tensor
 * product of the same along both directions. At a table's ends the tangent
 * is the end segment's chord; beyond them the slope runs out linearly to 0
 * over SH2000_COMP_RUNOUT end segments and the correction then holds: C1
 * everywhere, bounded however far an axis travels, and bending no harder
 * than the table (a slope cut to 0 at the end point would bend the end
 * segment hard enough to ask an axis at full speed for a few % of its
 * acceleration).
 */
#include <math.h>
#include <string.h>

#include "sh2000/comp.h"
#include "sh2000/sh2000_protocol.h"

static int32_t i32_at(const uint16_t *w, size_t i)
{
	return (int32_t)((uint32_t)w[i] | ((uint32_t)w[i + 1] << 16));
}

static double f32_at(const uint16_t *w, size_t i)
{
	return sh2000_f32_value((uint32_t)w[i] | ((uint32_t)w[i + 1] << 16));
}

/* ---- one Hermite segment ---- */

/* f, f', f'' at t in [0,1] of the segment of length h from (y0, m0) to
 * (y1, m1) (m: slopes per unit of x). */
static void herm(double y0, double y1, double m0, double m1, double h,
		 double t, double out[3])
{
	double t2 = t * t, t3 = t2 * t, dy = y1 - y0;

	out[0] = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * h * m0 +
		 (-2 * t3 + 3 * t2) * y1 + (t3 - t2) * h * m1;
	out[1] = (6 * t - 6 * t2) * dy / h + (3 * t2 - 4 * t + 1) * m0 +
		 (3 * t2 - 2 * t) * m1;
	out[2] = ((6 - 12 * t) * dy / h + (6 * t - 4) * m0 +
		  (6 * t - 2) * m1) / h;
}

/* Three-point tangent at the middle of (xa, ya), (xb, yb), (xc, yc). */
static double tangent3(double xa, double xb, double xc, double ya, double yb,
		       double yc)
{
	double h0 = xb - xa, h1 = xc - xb;

	return (h0 * (yc - yb) / h1 + h1 * (yb - ya) / h0) / (h0 + h1);
}

/* Beyond a table's end at (xe, ye) with slope m, d >= 0 past it
 * (dir -1: before the first point, +1: after the last): the slope runs
 * out over r. */
static void runout(double ye, double m, double d, double r, int dir,
		   double out[3])
{
	if (d >= r) {
		out[0] = ye + dir * m * 0.5 * r;
		out[1] = out[2] = 0.0;
		return;
	}
	out[0] = ye + dir * m * (d - d * d / (2.0 * r));
	out[1] = m * (1.0 - d / r);
	out[2] = -dir * m / r;
}

/*
 * The curve at p in the segment from point 1 to point 2 of the window
 * x[0..3], y[0..3]; first: point 0 does not exist (the segment starts the
 * table), last: point 3 does not (it ends it). Out: f, f', f''. Beyond
 * the segment only from an end segment: the run-out.
 */
static void segment(const double x[4], const double y[4], int first,
		    int last, double p, double out[3])
{
	double h = x[2] - x[1], chord = (y[2] - y[1]) / h;
	double m0 = first ? chord : tangent3(x[0], x[1], x[2], y[0], y[1], y[2]);
	double m1 = last ? chord : tangent3(x[1], x[2], x[3], y[1], y[2], y[3]);

	if (p < x[1] && first)
		runout(y[1], m0, x[1] - p, SH2000_COMP_RUNOUT * h, -1, out);
	else if (p > x[2] && last)
		runout(y[2], m1, p - x[2], SH2000_COMP_RUNOUT * h, 1, out);
	else
		herm(y[1], y[2], m0, m1, h, fmin(1.0, fmax(0.0, (p - x[1]) / h)),
		     out);
}

/* The segment k (points k, k+1) of n points got by get(ctx, i, &x, &y),
 * at p. */
typedef void (*point_fn)(const void *ctx, unsigned int i, double *x,
			 double *y);

static void curve(point_fn get, const void *ctx, unsigned int n,
		  unsigned int k, double p, double out[3])
{
	double x[4], y[4];
	int first = k == 0, last = k + 2 >= n;
	unsigned int i;

	for (i = 0; i < 4; i++) {
		unsigned int j = k + i;	/* point k - 1 + i */

		if ((i == 0 && first) || (i == 3 && last)) {
			x[i] = y[i] = 0.0;
			continue;
		}
		get(ctx, j - 1, &x[i], &y[i]);
	}
	segment(x, y, first, last, p, out);
}

/* Largest k <= n - 2 with x_k <= p (0 when p is before the first). */
static unsigned int find_segment(point_fn get, const void *ctx,
				 unsigned int n, double p)
{
	unsigned int lo = 0, hi = n - 1;

	while (hi - lo > 1) {
		unsigned int mid = lo + (hi - lo) / 2;
		double x, y;

		get(ctx, mid, &x, &y);
		if (x <= p)
			lo = mid;
		else
			hi = mid;
	}
	return lo;
}

/* ---- TABLE: positions and corrections ---- */

struct table_ctx {
	const uint16_t *w;
	size_t data;
	unsigned int n;
};

static void table_point(const void *c, unsigned int i, double *x, double *y)
{
	const struct table_ctx *t = c;

	*x = (double)i32_at(t->w, t->data + 2u * i);
	*y = f32_at(t->w, t->data + 2u * t->n + 2u * i);
}

/* ---- GRID: a row along SRC1, then across the rows along SRC2 ---- */

struct row_ctx {
	const uint16_t *w;
	size_t vals;		/* first correction's word */
	unsigned int n1, row;
	double u0, du;
};

static void row_point(const void *c, unsigned int i, double *x, double *y)
{
	const struct row_ctx *r = c;

	*x = r->u0 + r->du * i;
	*y = f32_at(r->w, r->vals + 2u * ((size_t)r->row * r->n1 + i));
}

/* Values along SRC2 at one u: the rows' f (or f', f'') at base..base+3. */
struct col_ctx {
	const double *y;
	unsigned int base;
	double v0, dv;
};

static void col_point(const void *c, unsigned int j, double *x, double *y)
{
	const struct col_ctx *k = c;

	*x = k->v0 + k->dv * j;
	*y = k->y[j - k->base];
}

static double grid_at(const uint16_t *w, const struct sh2000_comp_desc *t,
		      double u, double v, double d[2], double dd[3])
{
	struct row_ctx r = { w, t->data + 8u, t->n1, 0,
			     (double)i32_at(w, t->data), 0.0 };
	struct col_ctx c = { NULL, 0, (double)i32_at(w, t->data + 4u),
			     (double)i32_at(w, t->data + 6u) };
	double g[3][4], out[3], ou[3], ouu[3];
	unsigned int ku, kv, j, lo;

	r.du = (double)i32_at(w, t->data + 2u);
	ku = find_segment(row_point, &r, t->n1, u);
	kv = (v <= c.v0) ? 0 : (unsigned int)fmin(floor((v - c.v0) / c.dv),
						  (double)(t->n2 - 2u));
	lo = kv ? kv - 1u : 0u;
	for (j = lo; j < lo + 4u && j < t->n2; j++) {
		double o[3];

		r.row = j;
		curve(row_point, &r, t->n1, ku, u, o);
		g[0][j - lo] = o[0];
		g[1][j - lo] = o[1];
		g[2][j - lo] = o[2];
	}
	c.base = lo;
	c.y = g[0];
	curve(col_point, &c, t->n2, kv, v, out);
	c.y = g[1];
	curve(col_point, &c, t->n2, kv, v, ou);
	c.y = g[2];
	curve(col_point, &c, t->n2, kv, v, ouu);
	d[0] = ou[0];
	d[1] = out[1];
	dd[0] = ouu[0];
	dd[1] = out[2];
	dd[2] = ou[1];
	return out[0];
}

void sh2000_comp_table_span(const uint16_t *w,
			    const struct sh2000_comp_desc *t, int second,
			    double span[2])
{
	double x0, xa, xb, x1;

	if (t->kind == SH2000_COMP_TABLE) {
		x0 = i32_at(w, t->data);
		xa = i32_at(w, t->data + 2u);
		xb = i32_at(w, t->data + 2u * (t->n1 - 2u));
		x1 = i32_at(w, t->data + 2u * (t->n1 - 1u));
	} else if (t->kind == SH2000_COMP_GRID) {
		/* origin and step of SRC1 at data + 0, 2; of SRC2 at + 4, 6 */
		double o = i32_at(w, t->data + (second ? 4u : 0u));
		double d = i32_at(w, t->data + (second ? 6u : 2u));
		unsigned int n = second ? t->n2 : t->n1;

		x0 = o;
		xa = o + d;
		xb = o + d * (n - 2u);
		x1 = o + d * (n - 1u);
	} else {
		span[0] = -INFINITY;
		span[1] = INFINITY;
		return;
	}
	span[0] = x0 - SH2000_COMP_RUNOUT * (xa - x0);
	span[1] = x1 + SH2000_COMP_RUNOUT * (x1 - xb);
}

double sh2000_comp_eval_table(const uint16_t *w,
			      const struct sh2000_comp_desc *t,
			      const double pos[SH2000_AXES], double d[2],
			      double dd[3])
{
	double out[3];

	d[0] = d[1] = dd[0] = dd[1] = dd[2] = 0.0;
	switch (t->kind) {
	case SH2000_COMP_TABLE: {
		struct table_ctx c = { w, t->data, t->n1 };
		double p = pos[t->src1];

		curve(table_point, &c, t->n1,
		      find_segment(table_point, &c, t->n1, p), p, out);
		d[0] = out[1];
		dd[0] = out[2];
		return out[0];
	}
	case SH2000_COMP_SQUARE:
		d[0] = f32_at(w, t->data);
		return d[0] * pos[t->src1];
	case SH2000_COMP_GRID:
		return grid_at(w, t, pos[t->src1], pos[t->src2], d, dd);
	default:
		return 0.0;
	}
}

void sh2000_comp_eval(const uint16_t *w, const struct sh2000_comp_index *ix,
		      const double pos[SH2000_AXES], double off[SH2000_AXES])
{
	unsigned int a, i;
	double d[2], dd[3];

	for (a = 0; a < SH2000_AXES; a++)
		off[a] = 0.0;
	for (i = 0; i < ix->tables; i++)
		off[ix->t[i].target] +=
			sh2000_comp_eval_table(w, &ix->t[i], pos, d, dd);
}

/* ---- the layout ---- */

static int fault(struct sh2000_comp_fault *why, int table, int point,
		 enum sh2000_comp_reason r)
{
	why->table = table;
	why->point = point;
	why->reason = r;
	return -1;
}

/* Words of a table's data; 0 for an unknown kind. */
static size_t data_words(const struct sh2000_comp_desc *t)
{
	switch (t->kind) {
	case SH2000_COMP_TABLE:
		return 4u * (size_t)t->n1;
	case SH2000_COMP_SQUARE:
		return 2u;
	case SH2000_COMP_GRID:
		return 8u + 2u * (size_t)t->n1 * t->n2;
	default:
		return 0;
	}
}

/* The descriptor's own rules: kind, axes, counts. */
static int desc_ok(const struct sh2000_comp_desc *t, int i,
		   struct sh2000_comp_fault *why)
{
	int grid = t->kind == SH2000_COMP_GRID;

	/* the kind alone: a TABLE of no points has no data words either,
	 * and is too few points, not an unknown kind */
	if (t->kind != SH2000_COMP_TABLE && t->kind != SH2000_COMP_SQUARE && !grid)
		return fault(why, i, -1, SH2000_COMP_R_KIND);
	if (t->target >= SH2000_AXES || t->src1 >= SH2000_AXES ||
	    (grid && (t->src2 >= SH2000_AXES || t->src2 == t->src1)) ||
	    (!grid && t->src2 != 0))
		return fault(why, i, -1, SH2000_COMP_R_AXIS);
	if (t->kind == SH2000_COMP_SQUARE && (t->n1 || t->n2))
		return fault(why, i, -1, SH2000_COMP_R_POINTS);
	if (t->kind == SH2000_COMP_TABLE && (t->n1 < 2 || t->n2))
		return fault(why, i, -1, SH2000_COMP_R_POINTS);
	if (grid && (t->n1 < 2 || t->n2 < 2))
		return fault(why, i, -1, SH2000_COMP_R_POINTS);
	return 0;
}

/* The data's rules: increasing positions, positive steps, finite values. */
static int data_ok(const uint16_t *w, const struct sh2000_comp_desc *t,
		   int i, struct sh2000_comp_fault *why)
{
	size_t vals = t->data, nv = 1, k;

	if (t->kind == SH2000_COMP_TABLE) {
		for (k = 1; k < t->n1; k++)
			if (i32_at(w, t->data + 2 * k) <=
			    i32_at(w, t->data + 2 * (k - 1)))
				return fault(why, i, (int)k, SH2000_COMP_R_ORDER);
		vals = t->data + 2u * t->n1;
		nv = t->n1;
	} else if (t->kind == SH2000_COMP_GRID) {
		if (i32_at(w, t->data + 2) <= 0 || i32_at(w, t->data + 6) <= 0)
			return fault(why, i, -1, SH2000_COMP_R_ORDER);
		vals = t->data + 8u;
		nv = (size_t)t->n1 * t->n2;
	}
	for (k = 0; k < nv; k++)
		if (!isfinite(f32_at(w, vals + 2 * k)))
			return fault(why, i, (int)k, SH2000_COMP_R_VALUE);
	return 0;
}

int sh2000_comp_parse(const uint16_t *w, size_t n,
		      struct sh2000_comp_index *ix,
		      struct sh2000_comp_fault *why)
{
	size_t at = SH2000_COMP_HEADER_WORDS;
	unsigned int i;

	memset(ix, 0, sizeof(*ix));
	if (n > SH2000_COMP_MAX_WORDS)
		return fault(why, -1, -1, SH2000_COMP_R_SIZE);
	if (n < SH2000_COMP_HEADER_WORDS || w[SH2000_CI_MAGIC] != SH2000_COMP_MAGIC ||
	    w[SH2000_CI_FORMAT] != SH2000_COMP_FORMAT || w[SH2000_CI_RESERVED])
		return fault(why, -1, -1, SH2000_COMP_R_HEADER);
	if (w[SH2000_CI_TABLES] > SH2000_COMP_MAX_TABLES)
		return fault(why, -1, -1, SH2000_COMP_R_SIZE);
	ix->id = (uint32_t)i32_at(w, SH2000_CI_ID_LO);
	ix->tables = w[SH2000_CI_TABLES];
	for (i = 0; i < ix->tables; i++) {
		struct sh2000_comp_desc *t = &ix->t[i];

		if (at + SH2000_COMP_DESC_WORDS > n)
			return fault(why, (int)i, -1, SH2000_COMP_R_SIZE);
		t->kind = w[at + SH2000_CT_KIND];
		t->target = w[at + SH2000_CT_TARGET];
		t->src1 = w[at + SH2000_CT_SRC1];
		t->src2 = w[at + SH2000_CT_SRC2];
		t->n1 = w[at + SH2000_CT_N1];
		t->n2 = w[at + SH2000_CT_N2];
		t->data = at + SH2000_COMP_DESC_WORDS;
		if (desc_ok(t, (int)i, why))
			return -1;
		at = t->data + data_words(t);
		if (at > n)
			return fault(why, (int)i, -1, SH2000_COMP_R_SIZE);
		if (data_ok(w, t, (int)i, why))
			return -1;
	}
	if (at != n)
		return fault(why, -1, -1, SH2000_COMP_R_SIZE);
	return 0;
}

/* ---- the check against the axes' limits ---- */

/* The worst of one table over its samples: the set-point velocity and
 * acceleration it adds with every source at its VMAX and AMAX, its
 * largest correction, and the points nearest each. */
struct worst {
	double vel, acc, off;
	int vpoint, apoint, opoint;
};

static void sample(const uint16_t *w, const struct sh2000_comp_desc *t,
		   const struct sh2000_comp_limits *lim, double p1, double p2,
		   int point, struct worst *s)
{
	double pos[SH2000_AXES] = { 0 }, d[2], dd[3], f, v1, v2, vel, acc;

	pos[t->src1] = p1;
	if (t->kind == SH2000_COMP_GRID)
		pos[t->src2] = p2;
	f = sh2000_comp_eval_table(w, t, pos, d, dd);
	v1 = lim->vmax[t->src1];
	v2 = t->kind == SH2000_COMP_GRID ? lim->vmax[t->src2] : 0.0;
	vel = fabs(d[0]) * v1 + fabs(d[1]) * v2;
	acc = fabs(dd[0]) * v1 * v1 + fabs(dd[1]) * v2 * v2 +
	      2.0 * fabs(dd[2]) * v1 * v2 + fabs(d[0]) * lim->amax[t->src1] +
	      (v2 > 0.0 ? fabs(d[1]) * lim->amax[t->src2] : 0.0);
	if (vel > s->vel) {
		s->vel = vel;
		s->vpoint = point;
	}
	if (acc > s->acc) {
		s->acc = acc;
		s->apoint = point;
	}
	if (fabs(f) > s->off) {
		s->off = fabs(f);
		s->opoint = point;
	}
}

/* Within each segment (cell): the second
 * derivative of a Hermite cubic is linear in a segment, so its ends
 * (sampled just inside) bound it. */
static const double frac[] = { 0.0, 0.25, 0.5, 0.75, 0.999 };
#define NFRAC (sizeof(frac) / sizeof(frac[0]))

static void worst_table(const uint16_t *w, const struct sh2000_comp_desc *t,
			const struct sh2000_comp_limits *lim, struct worst *s)
{
	struct table_ctx c = { w, t->data, t->n1 };
	unsigned int k, f;
	double x0, x1 = 0.0, y, r;

	/* the run-outs: their bend is constant, their offset largest at
	 * their far ends */
	table_point(&c, 0, &x0, &y);
	table_point(&c, 1, &x1, &y);
	r = SH2000_COMP_RUNOUT * (x1 - x0);
	sample(w, t, lim, x0 - 0.5 * r, 0.0, 0, s);
	sample(w, t, lim, x0 - r, 0.0, 0, s);
	table_point(&c, t->n1 - 2, &x0, &y);
	table_point(&c, t->n1 - 1, &x1, &y);
	r = SH2000_COMP_RUNOUT * (x1 - x0);
	sample(w, t, lim, x1 + 0.5 * r, 0.0, (int)t->n1 - 1, s);
	sample(w, t, lim, x1 + r, 0.0, (int)t->n1 - 1, s);
	for (k = 0; k + 1 < t->n1; k++) {
		table_point(&c, k, &x0, &y);
		table_point(&c, k + 1, &x1, &y);
		for (f = 0; f < NFRAC; f++)
			sample(w, t, lim, x0 + frac[f] * (x1 - x0), 0.0,
			       (int)(frac[f] < 0.5 ? k : k + 1), s);
	}
	sample(w, t, lim, x1, 0.0, (int)t->n1 - 1, s);
}

static void worst_grid(const uint16_t *w, const struct sh2000_comp_desc *t,
		       const struct sh2000_comp_limits *lim, struct worst *s)
{
	double u0 = i32_at(w, t->data), du = i32_at(w, t->data + 2);
	double v0 = i32_at(w, t->data + 4), dv = i32_at(w, t->data + 6);
	unsigned int i, j, fi, fj;

	for (j = 0; j < t->n2; j++)
		for (i = 0; i < t->n1; i++)
			for (fj = 0; fj < (j + 1 < t->n2 ? NFRAC : 1); fj++)
				for (fi = 0; fi < (i + 1 < t->n1 ? NFRAC : 1); fi++)
					sample(w, t, lim, u0 + du * (i + frac[fi]),
					       v0 + dv * (j + frac[fj]),
					       (int)(i + (frac[fi] >= 0.5) +
						     t->n1 * (j + (frac[fj] >= 0.5))),
					       s);
}

static void worst_of(const uint16_t *w, const struct sh2000_comp_desc *t,
		     const struct sh2000_comp_limits *lim, struct worst *s)
{
	memset(s, 0, sizeof(*s));
	if (t->kind == SH2000_COMP_TABLE)
		worst_table(w, t, lim, s);
	else if (t->kind == SH2000_COMP_GRID)
		worst_grid(w, t, lim, s);
	else	/* a line: its slope is the same everywhere; its offset
		 * grows with the travel, which is the user's to bound */
		sample(w, t, lim, 0.0, 0.0, -1, s);
}

int sh2000_comp_check(const uint16_t *w, const struct sh2000_comp_index *ix,
		      const struct sh2000_comp_limits *lim,
		      struct sh2000_comp_fault *why)
{
	double vel[SH2000_AXES] = { 0 }, acc[SH2000_AXES] = { 0 };
	double off[SH2000_AXES] = { 0 };
	unsigned int i;

	for (i = 0; i < ix->tables; i++) {
		const struct sh2000_comp_desc *t = &ix->t[i];
		unsigned int a = t->target;
		struct worst s;

		worst_of(w, t, lim, &s);
		vel[a] += s.vel;
		acc[a] += s.acc;
		off[a] += s.off;
		/* the table that takes its target over is the one named; a
		 * jump first (it also makes the curve overshoot) */
		if (vel[a] > SH2000_COMP_VMAX_SHARE * lim->vmax[a])
			return fault(why, (int)i, s.vpoint, SH2000_COMP_R_SLOPE);
		if (acc[a] > SH2000_COMP_AMAX_SHARE * lim->amax[a])
			return fault(why, (int)i, s.apoint, SH2000_COMP_R_ACCEL);
		if (off[a] > SH2000_COMP_MAX_OFFSET)
			return fault(why, (int)i, s.opoint, SH2000_COMP_R_OFFSET);
	}
	return 0;
}

const char *sh2000_comp_reason_name(unsigned int reason)
{
	static const char *const names[] = {
		[SH2000_COMP_R_OK] = "ok",
		[SH2000_COMP_R_HEADER] = "not a table image (header)",
		[SH2000_COMP_R_SIZE] = "larger than the card holds, or its words do not add up",
		[SH2000_COMP_R_KIND] = "unknown kind of table",
		[SH2000_COMP_R_AXIS] = "an axis the card does not have",
		[SH2000_COMP_R_POINTS] = "too few points",
		[SH2000_COMP_R_ORDER] = "positions not strictly increasing",
		[SH2000_COMP_R_VALUE] = "a correction that is not a finite number",
		[SH2000_COMP_R_OFFSET] = "a correction larger than 1 mm (100000 counts)",
		[SH2000_COMP_R_SLOPE] = "a jump larger than the axis can follow (slope beyond 2 % of its vmax)",
		[SH2000_COMP_R_ACCEL] = "bends faster than the axis can follow (beyond 4 % of its amax)",
		[SH2000_COMP_R_SUM] = "the image's sum does not match",
		[SH2000_COMP_R_PAGES] = "pages missing or out of order",
	};

	if (reason < sizeof(names) / sizeof(names[0]) && names[reason])
		return names[reason];
	return "unknown reason";
}
