// SPDX-License-Identifier: MIT
/*
 * The primitives: lines, point-to-point moves, jogs, arcs and NURBS. Each
 * is validated completely before any of it is queued, so a rejected
 * primitive leaves nothing behind; arcs and NURBS are resolved by the one
 * geometry of sh2000/geometry.h.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "planner.h"
#include "sh2000/sh2000.h"

static const char axis_name[] = SH2000_AXIS_LETTERS;

/* NURBS start points: what "the same point" means, mm. */
#define GEOM_TOL 0.001
/* An arc within about 10 degrees of the tangent it is entered along. */
#define ARC_TANGENT_COS 0.985


static int check_feed(struct sh2000_path *p, const char *what, double feed,
		      int zero_ok)
{
	if (zero_ok ? !(feed >= 0.0) : !(feed > 0.0))
		return pl_err(p, -EINVAL, "%s must be %s 0: got %g", what,
			      zero_ok ? ">=" : ">", feed);
	if (isinf(feed))
		return pl_err(p, -EINVAL, "%s must be finite", what);
	return 0;
}

/* Within the caller's bounds (sh2000_path_set_bounds()), if any. */
static int check_bounds(struct sh2000_path *p, const char *what,
			const double x[SH2000_AXES])
{
	unsigned int a;

	if (!p->bounded)
		return 0;
	for (a = 0; a < SH2000_AXES; a++) {
		double b = x[a] < p->bound_lo[a] ? p->bound_lo[a] :
			   x[a] > p->bound_hi[a] ? p->bound_hi[a] : x[a];

		if (b != x[a])
			return pl_err(p, -SH2000_ELIMIT,
				      "%s %c %.6f mm is beyond the soft limit: the bound is %.6f mm",
				      what, axis_name[a], x[a], b);
	}
	return 0;
}

/* Finite and within the count range. */
static int check_value(struct sh2000_path *p, const char *what,
		       const double x[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		double sc = p->cfg.counts_per_mm[a];

		if (isnan(x[a]))
			return pl_err(p, -EINVAL, "%s %c is NaN", what,
				      axis_name[a]);
		if (!isfinite(x[a]))
			return pl_err(p, -EINVAL, "%s %c is infinite", what,
				      axis_name[a]);
		if (sc > 0.0 && fabs(x[a] * sc) > 2147483000.0)
			return pl_err(p, -ERANGE,
				      "%s %c %.3f mm is beyond the int32 count range (+-%.3f mm)",
				      what, axis_name[a], x[a],
				      2147483000.0 / sc);
	}
	return 0;
}

/* A point the primitive passes: a value, and within the bounds. */
static int check_point(struct sh2000_path *p, const char *what,
		       const double x[SH2000_AXES])
{
	int r = check_value(p, what, x);

	return r ? r : check_bounds(p, what, x);
}

/* The axes point x is away from where the queue ends, by more than
 * SH2000_PATH_STILL_TOL_MM. */
static unsigned int axes_off(const struct sh2000_path *p,
			     const double x[SH2000_AXES])
{
	unsigned int a, m = 0;

	for (a = 0; a < SH2000_AXES; a++)
		if (!(fabs(x[a] - p->qend[a]) <= SH2000_PATH_STILL_TOL_MM))
			m |= 1u << a;
	return m;
}

/* A primitive that moves an axis the configuration holds still is
 * refused: that axis' limits did not bound the plan. m: the axes it moves,
 * by sh2000_prog_block_axes()'s rule. */
static int check_still(struct sh2000_path *p, const char *what,
		       unsigned int m)
{
	unsigned int a;

	m &= p->cfg.still_axes;
	for (a = 0; a < SH2000_AXES; a++)
		if (m & (1u << a))
			return pl_err(p, -EINVAL,
				      "%s moves %c, which the configuration holds still (still_axes 0x%x): its vmax and amax did not bound the plan",
				      what, axis_name[a], p->cfg.still_axes);
	return 0;
}

/* End point x with the still axes held exactly where they stand (x was
 * within SH2000_PATH_STILL_TOL_MM of it: check_still()). */
static void hold_still(const struct sh2000_path *p, const double x[SH2000_AXES],
		       double out[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		out[a] = p->cfg.still_axes & (1u << a) ? p->qend[a] : x[a];
}

/* Entry of every primitive: the planner must be able to take one. */
static int ready(struct sh2000_path *p)
{
	int r;

	if (p->fail)
		return pl_err(p, p->fail,
			      "the sink failed (%d); reset the planner", p->fail);
	while (p->pending) {
		if (pl_nurbs_expand(p))
			break;
		r = pl_make_room(p);
		if (r)
			return r;
	}
	if (p->count + pl_room(p) > p->cap)
		return pl_make_room(p);
	return 0;
}


/* ---- lines and point-to-point ----------------------------------------- */

/* What a straight move is: a feed move, point-to-point (from rest to
 * rest) or a rapid. */
enum { LINE_FEED, LINE_P2P, LINE_RAPID };

static int line_block(struct sh2000_path *p, const double to[SH2000_AXES],
		      double feed, int kind)
{
	static const char *const name[] = { "line", "move", "rapid" };
	struct pl_block b;
	double len = 0.0, end[SH2000_AXES];
	unsigned int a;
	int r;

	r = check_still(p, name[kind], axes_off(p, to));
	if (r)
		return r;
	hold_still(p, to, end);
	memset(&b, 0, sizeof(b));
	for (a = 0; a < SH2000_AXES; a++)
		len += (end[a] - p->qend[a]) * (end[a] - p->qend[a]);
	len = sqrt(len);
	if (len < 1e-9)
		return 0;	/* nothing to do is not an error */
	r = ready(p);
	if (r)
		return r;
	b.type = BLK_LINE;
	b.L = len;
	b.feed = feed;
	memcpy(b.p0, p->qend, sizeof(b.p0));
	memcpy(b.c0, p->qend, sizeof(b.c0));
	memcpy(b.p1, end, sizeof(b.p1));
	for (a = 0; a < SH2000_AXES; a++)
		b.g.line.d[a] = b.t0[a] = b.t1[a] = (end[a] - p->qend[a]) / len;
	b.vlim = pl_curve_vlim(p, b.t0, 0.0);
	if (kind == LINE_P2P) {
		p->stop_next = 1;
		b.stop_after = 1;
	}
	b.rapid = kind == LINE_RAPID;
	pl_push_block(p, &b);
	return 0;
}

int sh2000_path_line(struct sh2000_path *p, const double end[SH2000_AXES], double feed)
{
	int r;

	if (!end)
		return pl_err(p, -EINVAL, "line: no end point");
	r = check_point(p, "line: end", end);
	if (!r)
		r = check_feed(p, "feed", feed, 0);
	if (r)
		return r;
	return line_block(p, end, feed, LINE_FEED);
}

int sh2000_path_move_abs(struct sh2000_path *p, const double target[SH2000_AXES],
			 double speed)
{
	int r;

	if (!target)
		return pl_err(p, -EINVAL, "move: no target");
	r = check_point(p, "move: target", target);
	if (!r)
		r = check_feed(p, "speed", speed, 1);
	if (r)
		return r;
	return line_block(p, target, speed, LINE_P2P);
}

int sh2000_path_rapid(struct sh2000_path *p, const double target[SH2000_AXES])
{
	int r;

	if (!target)
		return pl_err(p, -EINVAL, "rapid: no target");
	r = check_point(p, "rapid: target", target);
	if (r)
		return r;
	return line_block(p, target, 0.0, LINE_RAPID);
}

int sh2000_path_move_rel(struct sh2000_path *p, const double delta[SH2000_AXES],
			 double speed)
{
	double t[SH2000_AXES];
	unsigned int a;

	if (!delta)
		return pl_err(p, -EINVAL, "move: no delta");
	for (a = 0; a < SH2000_AXES; a++) {
		if (!isfinite(delta[a]))
			return pl_err(p, -EINVAL, "move: delta %c is %s",
				      axis_name[a],
				      isnan(delta[a]) ? "NaN" : "infinite");
		t[a] = p->qend[a] + delta[a];
	}
	return sh2000_path_move_abs(p, t, speed);
}

int sh2000_path_jog(struct sh2000_path *p, unsigned int axis,
		    double velocity, double travel)
{
	double d[SH2000_AXES] = { 0 };

	if (axis >= SH2000_AXES)
		return pl_err(p, -EINVAL, "jog: axis %u does not exist (0..3)",
			      axis);
	if (!isfinite(velocity) || velocity == 0.0)
		return pl_err(p, -EINVAL,
			      "jog: velocity must be non-zero and finite: got %g",
			      velocity);
	if (!(travel > 0.0) || !isfinite(travel))
		return pl_err(p, -EINVAL, "jog: travel must be > 0: got %g",
			      travel);
	d[axis] = velocity > 0.0 ? travel : -travel;
	return sh2000_path_move_rel(p, d, fabs(velocity));
}


/* ---- arcs ---------------------------------------------------------------- */

/* The centre in plane coordinates, given or from the radius. */
static int arc_centre(struct sh2000_path *p, const struct sh2000_path_arc *arc,
		      const struct sh2000_arc *ax, double c[2])
{
	double s[2], e[2];
	char m[160];
	int r;

	if (!arc->radius_form) {
		if (isnan(arc->centre[0]) || isnan(arc->centre[1]))
			return pl_err(p, -EINVAL, "arc: centre is NaN");
		if (!isfinite(arc->centre[0]) || !isfinite(arc->centre[1]))
			return pl_err(p, -EINVAL, "arc: centre is infinite");
		c[0] = arc->centre[0];
		c[1] = arc->centre[1];
		return 0;
	}
	if (isnan(arc->radius))
		return pl_err(p, -EINVAL, "arc: radius is NaN");
	s[0] = p->qend[ax->first];
	s[1] = p->qend[ax->second];
	e[0] = arc->end[ax->first];
	e[1] = arc->end[ax->second];
	r = sh2000_arc_centre_from_radius(s, e, arc->radius, arc->ccw, c, m,
					  sizeof(m));
	return r ? pl_err(p, r, "arc: %s", m) : 0;
}

/* The arc's extremes in its plane (where its angle passes a multiple of
 * 90 degrees, at the larger radius) within the count range: only its end
 * points are checked otherwise, and a long arc of a large radius can pass
 * far beyond them. */
static int arc_range(struct sh2000_path *p, const struct sh2000_arc *g)
{
	double sgn = g->sweep < 0.0 ? -1.0 : 1.0, rmax = fmax(g->r0, g->r1);
	double x[SH2000_AXES];
	unsigned int k;
	int r;

	memcpy(x, p->qend, sizeof(x));
	for (k = 0; k < 4; k++) {
		double phi = k * M_PI_2;
		double t = fmod(sgn * (phi - g->th0), 2.0 * M_PI);

		if (t < 0.0)
			t += 2.0 * M_PI;
		if (t > fabs(g->sweep))
			continue;
		x[g->first] = g->centre[0] + rmax * cos(phi);
		x[g->second] = g->centre[1] + rmax * sin(phi);
		r = check_point(p, "arc: passes", x);
		if (r)
			return r;
	}
	return 0;
}

/* The centripetal share an arc may take: more where it carries on near
 * tangentially from the move before under a blending mode (a spiral of
 * arcs: the speed carries over, so the arc runs at its limit and seldom
 * needs the tangential acceleration it gives up); the configured share
 * where it starts from rest or after a corner, to speed up within it. */
static double arc_smax(const struct sh2000_path *p, const struct pl_block *b)
{
	if (p->cfg.mode != SH2000_PATH_BLEND || p->stop_next ||
	    pl_dot(p->tend, b->t0) < ARC_TANGENT_COS)
		return 0.0;
	return PL_SHARE_MAX;
}

/* A block for a resolved arc from the current end to `end`. */
static void arc_block(struct sh2000_path *p, const struct sh2000_arc *g,
		      const double end[SH2000_AXES], double feed,
		      struct pl_block *b)
{
	double tt[SH2000_AXES], f;
	unsigned int i = g->first, j = g->second, a;

	memset(b, 0, sizeof(*b));
	b->type = BLK_ARC;
	b->feed = feed;
	b->g.arc = *g;
	memcpy(b->p0, p->qend, sizeof(b->p0));
	memcpy(b->p1, end, sizeof(b->p1));
	pl_arc_frame(b);
	/* the speed limit from the worst direction of the plane axes (each
	 * reaches |t| = planar / L somewhere on a long arc) */
	f = hypot(b->t0[i], b->t0[j]);
	for (a = 0; a < SH2000_AXES; a++)
		tt[a] = (a != i && a != j) ? b->t0[a] : f;
	/* helix curvature: (planar share)^2 / r */
	pl_curve_block_vlim(p, b, tt, f * f / fmin(g->r0, g->r1),
			    arc_smax(p, b));
}

int sh2000_path_arc(struct sh2000_path *p, const struct sh2000_path_arc *arc,
		    double feed)
{
	struct sh2000_arc g;
	struct pl_block b;
	double c[2], end[SH2000_AXES];
	char m[320];
	int r;

	if (!arc)
		return pl_err(p, -EINVAL, "arc: no description");
	if (sh2000_plane_axes(arc->plane, &g.first, &g.second, &g.normal))
		return pl_err(p, -EINVAL, "arc: unknown plane %d",
			      (int)arc->plane);
	r = check_point(p, "arc: end", arc->end);
	if (!r)
		r = check_feed(p, "feed", feed, 0);
	if (!r)
		r = check_still(p, "arc", axes_off(p, arc->end) |
				1u << g.first | 1u << g.second);
	if (r)
		return r;
	hold_still(p, arc->end, end);
	if (arc->turns > 1000)
		return pl_err(p, -EINVAL, "arc: %u turns is more than 1000",
			      arc->turns);
	r = arc_centre(p, arc, &g, c);
	if (r)
		return r;
	r = sh2000_arc_resolve(&g, arc->plane, p->qend, end, c, arc->ccw,
			       arc->turns ? arc->turns : 1, arc->tolerance, 0,
			       m, sizeof(m));
	if (r)
		return pl_err(p, r, "arc: %s", m);
	r = arc_range(p, &g);
	if (r)
		return r;
	r = ready(p);
	if (r)
		return r;
	arc_block(p, &g, end, feed, &b);
	pl_push_block(p, &b);
	return 0;
}

/* ---- NURBS ----------------------------------------------------------------- */

/* The copy starts where the planner is and never stands still over a
 * stretch: a piece of zero length has no direction to plan along. A cusp,
 * where C' passes through zero at one parameter and the curve turns
 * back, is geometry like a corner: the expansion finds it and the
 * carriage stops there (expand.c). */
static int nurbs_geometry(struct sh2000_path *p, const struct pl_nurbs *nb)
{
	double c[SH2000_AXES], tt[SH2000_AXES], ks, d = 0.0;
	double still = 1e-9 * (1.0 + fabs(nb->umax - nb->umin));
	const double *U = nb->c.knots;
	unsigned int a, k;
	size_t i;

	pl_nurbs_eval(nb, nb->umin, c, NULL, NULL);
	for (a = 0; a < SH2000_AXES; a++)
		d += (c[a] - p->qend[a]) * (c[a] - p->qend[a]);
	d = sqrt(d);
	if (d > GEOM_TOL)
		return pl_err(p, -EINVAL,
			      "nurbs: the curve starts at (%.4f, %.4f, %.4f, %.4f), %.4f mm from the current position (%.4f, %.4f, %.4f, %.4f)",
			      c[0], c[1], c[2], c[3], d, p->qend[0],
			      p->qend[1], p->qend[2], p->qend[3]);
	for (i = nb->c.degree; i < nb->c.npoints; i++) {
		double h = (U[i + 1] - U[i]) / 8.0;
		int was_still = 0;

		if (U[i] >= U[i + 1])
			continue;
		for (k = 0; k <= 8; k++) {
			/* the span's ends from inside it: a C0 knot's other
			 * side belongs to the next span */
			double u = k == 0 ? U[i] + h * 1e-9 :
				   k == 8 ? U[i + 1] - h * 1e-9 : U[i] + h * k;
			int is_still = pl_nurbs_frame(nb, u, tt, &ks) < still;

			if (is_still && was_still)
				return pl_err(p, -EINVAL,
					      "nurbs: the curve stands still (zero derivative) from u = %g to u = %g: repeated control points?",
					      u - h, u);
			was_still = is_still;
		}
	}
	return 0;
}

/* Samples per knot span where the control polygon leaves the bounds. */
#define NURBS_BOUND_SAMPLES 64u

/* Whether a control point is within the bounds. */
static int nurbs_point_in(const struct sh2000_path *p, const double *x)
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		if (x[a] < p->bound_lo[a] || x[a] > p->bound_hi[a])
			return 0;
	return 1;
}

/* Samples of the span u0..u1: the furthest beyond a bound is refused. */
static int nurbs_span_bounds(struct sh2000_path *p, const struct pl_nurbs *nb,
			     double u0, double u1)
{
	double c[SH2000_AXES], worst = 0.0, uw = u0;
	char what[80];
	unsigned int k, a;

	for (k = 0; k <= NURBS_BOUND_SAMPLES; k++) {
		double u = u0 + (u1 - u0) * k / NURBS_BOUND_SAMPLES;

		pl_nurbs_eval(nb, u, c, NULL, NULL);
		for (a = 0; a < SH2000_AXES; a++) {
			double d = fmax(p->bound_lo[a] - c[a],
					c[a] - p->bound_hi[a]);

			if (d > worst) {
				worst = d;
				uw = u;
			}
		}
	}
	if (!(worst > 0.0))
		return 0;
	pl_nurbs_eval(nb, uw, c, NULL, NULL);
	snprintf(what, sizeof(what), "nurbs: the curve at u = %g", uw);
	return check_bounds(p, what, c);
}

/*
 * The curve within the bounds. With positive weights a NURBS stays in the
 * convex hull of its control points, and a span in that of its degree + 1
 * points: a span whose points are all inside is inside. A point outside
 * does not prove the curve leaves (a control polygon lies outside the
 * curve it shapes), so such a span is sampled and refused only at a point
 * of the curve beyond a bound; what a sample misses the runner's check of
 * the set-points still finds.
 */
static int nurbs_bounds(struct sh2000_path *p, const struct pl_nurbs *nb)
{
	const struct sh2000_nurbs *n = &nb->c;
	const double *U = n->knots;
	size_t i, out = 0;	/* points outside among the span's */
	int r;

	if (!p->bounded)
		return 0;
	for (i = 0; i < n->npoints; i++) {
		out += !nurbs_point_in(p, n->points[i]);
		if (i > n->degree)
			out -= !nurbs_point_in(p, n->points[i - n->degree - 1]);
		if (i < n->degree || !out || U[i] >= U[i + 1])
			continue;
		r = nurbs_span_bounds(p, nb, U[i], U[i + 1]);
		if (r)
			return r;
	}
	return 0;
}

int sh2000_path_nurbs(struct sh2000_path *p, const struct sh2000_nurbs *n,
		      double feed)
{
	struct pl_nurbs *nb;
	char m[200];
	size_t i;
	int r;

	if (!n)
		return pl_err(p, -EINVAL, "nurbs: no description");
	r = sh2000_nurbs_check(n, m, sizeof(m));
	if (r)
		return pl_err(p, r, "nurbs: %s", m);
	if (n->npoints > 10000000)
		return pl_err(p, -EINVAL, "nurbs: %zu control points is too many",
			      n->npoints);
	r = check_feed(p, "feed", feed, 0);
	for (i = 0; !r && i < n->npoints; i++) {
		snprintf(m, sizeof(m), "nurbs: points[%zu]", i);
		r = check_value(p, m, n->points[i]);
		if (!r)
			r = check_still(p, m, axes_off(p, n->points[i]));
	}
	if (r)
		return r;
	nb = pl_nurbs_new(p, n);
	if (!nb)
		return pl_err(p, -ENOMEM, "nurbs: out of memory");
	nb->id = ++p->nurbs_ids;
	r = nurbs_geometry(p, nb);
	if (!r)
		r = nurbs_bounds(p, nb);
	if (!r)
		r = ready(p);
	if (r) {
		nb->expanded = 1;
		nb->refs = 1;
		pl_nurbs_put(p, nb);
		return r;
	}
	/* feed travels with every block of the curve */
	p->pending = nb;
	p->pending_feed = feed;
	while (!pl_nurbs_expand(p)) {
		r = pl_make_room(p);
		if (r == -EAGAIN)
			return 0;	/* queued; the rest follows on resume */
		if (r)
			return r;
	}
	return 0;
}
