// SPDX-License-Identifier: MIT
/*
 * The planner's public face: configuration, validation of every primitive
 * (complete before anything of it is queued), turning primitives into
 * blocks with their speed limits, junction speeds and the look-ahead's
 * backward pass. The controller that runs the blocks is in control.c.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "planner.h"

static const char axis_name[SH2000_AXES] = { 'X', 'Y', 'Z', 'A' };

/* Radii, NURBS start points: what "the same point" means, mm. */
#define GEOM_TOL 0.001

void sh2000_path_config_default(struct sh2000_path_config *cfg)
{
	unsigned int a;

	memset(cfg, 0, sizeof(*cfg));
	cfg->period_s = 0.002;
	cfg->fine_steps = 20;
	for (a = 0; a < SH2000_AXES; a++) {
		cfg->vmax[a] = 500.0;
		cfg->amax[a] = 50000.0;
	}
	cfg->jerk = 5e6;
	cfg->profile = SH2000_PROFILE_SCURVE;
	cfg->output = SH2000_OUTPUT_COMPENSATED;
	cfg->corner_tol = 0.01;
	cfg->chord_tol = 0.01;
	cfg->centripetal_share = 0.5;
	cfg->margin = 0.95;
	cfg->window = 256;
	cfg->comp_window = 12;
}

int pl_err(struct sh2000_path *p, int code, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(p->err, sizeof(p->err), fmt, ap);
	va_end(ap);
	return code;
}

void *pl_alloc(struct sh2000_path *p, size_t n)
{
	void *ptr = calloc(1, n ? n : 1);

	if (ptr) {
		p->mem += n;
		if (p->mem > p->mem_peak)
			p->mem_peak = p->mem;
	}
	return ptr;
}

void pl_free(struct sh2000_path *p, void *ptr, size_t n)
{
	if (!ptr)
		return;
	p->mem -= n;
	free(ptr);
}

const char *sh2000_path_error(const struct sh2000_path *p)
{
	return p->err;
}

void sh2000_path_set_seq(struct sh2000_path *p, uint32_t seq)
{
	p->seq = seq;
}

void sh2000_path_end_position(const struct sh2000_path *p, double pos[SH2000_AXES])
{
	memcpy(pos, p->qend, sizeof(p->qend));
}

static int cfg_check(const struct sh2000_path_config *c, char *e, size_t n)
{
	unsigned int a;

#define BAD(...) do { if (e && n) snprintf(e, n, __VA_ARGS__); return -EINVAL; } while (0)
	if (!(c->period_s >= 1e-4 && c->period_s <= 0.1))
		BAD("config: period %g s is outside 0.0001..0.1", c->period_s);
	if (c->fine_steps < 1 || c->fine_steps > 1000)
		BAD("config: fine_steps %u is outside 1..1000", c->fine_steps);
	for (a = 0; a < SH2000_AXES; a++) {
		if (!(c->vmax[a] > 0.0 && isfinite(c->vmax[a])))
			BAD("config: vmax of axis %c must be > 0: got %g",
			    axis_name[a], c->vmax[a]);
		if (!(c->amax[a] > 0.0 && isfinite(c->amax[a])))
			BAD("config: amax of axis %c must be > 0: got %g",
			    axis_name[a], c->amax[a]);
		if (!(c->counts_per_mm[a] >= 0.0 && isfinite(c->counts_per_mm[a])))
			BAD("config: counts_per_mm of axis %c must be >= 0: got %g",
			    axis_name[a], c->counts_per_mm[a]);
		if (!isfinite(c->start[a]))
			BAD("config: start position of axis %c is not finite",
			    axis_name[a]);
	}
	if (c->profile != SH2000_PROFILE_SCURVE &&
	    c->profile != SH2000_PROFILE_TRAPEZOID)
		BAD("config: unknown profile %d", (int)c->profile);
	if (c->profile == SH2000_PROFILE_SCURVE &&
	    !(c->jerk > 0.0 && isfinite(c->jerk)))
		BAD("config: jerk must be > 0 for the S-curve: got %g", c->jerk);
	if (c->output != SH2000_OUTPUT_COMPENSATED &&
	    c->output != SH2000_OUTPUT_RAW)
		BAD("config: unknown output mode %d", (int)c->output);
	if (!(c->corner_tol >= 0.0 && isfinite(c->corner_tol)))
		BAD("config: corner_tol must be >= 0: got %g", c->corner_tol);
	if (!(c->chord_tol > 0.0 && isfinite(c->chord_tol)))
		BAD("config: chord_tol must be > 0: got %g", c->chord_tol);
	if (!(c->centripetal_share > 0.0 && c->centripetal_share < 1.0))
		BAD("config: centripetal_share must be in (0, 1): got %g",
		    c->centripetal_share);
	if (!(c->margin > 0.0 && c->margin <= 1.0))
		BAD("config: margin must be in (0, 1]: got %g", c->margin);
	if (c->window < 2 || c->window > 1000000)
		BAD("config: window %u is outside 2..1000000", c->window);
	if (c->comp_window < 1 || c->comp_window > 64)
		BAD("config: comp_window %u is outside 1..64", c->comp_window);
#undef BAD
	return 0;
}

int sh2000_path_create(struct sh2000_path **out,
		       const struct sh2000_path_config *cfg,
		       sh2000_path_sink_fn sink, void *ctx,
		       char *errbuf, size_t errlen)
{
	struct sh2000_path *p;
	double amin = INFINITY, share;
	unsigned int a;
	int r;

	*out = NULL;
	if (!cfg || !sink) {
		if (errbuf && errlen)
			snprintf(errbuf, errlen, "config and sink are required");
		return -EINVAL;
	}
	r = cfg_check(cfg, errbuf, errlen);
	if (r)
		return r;
	p = calloc(1, sizeof(*p));
	if (!p)
		return -ENOMEM;
	p->mem = p->mem_peak = sizeof(*p);
	p->cfg = *cfg;
	p->sink = sink;
	p->ctx = ctx;
	p->override = 1.0;
	p->substeps = 4;
	for (a = 0; a < SH2000_AXES; a++)
		amin = fmin(amin, cfg->amax[a]);
	p->amin = amin;
	share = cfg->centripetal_share;
	p->lim.A = (1.0 - share) * cfg->margin * amin;
	p->lim.J = cfg->profile == SH2000_PROFILE_SCURVE ?
		   cfg->jerk * cfg->margin : INFINITY;
	/* A step in the acceleration overshoots by (1 + 2r/(1 + r)) times
	 * through the compensation filter (r = 2 - sqrt 3): only the
	 * trapezoid has such steps. */
	if (cfg->profile == SH2000_PROFILE_TRAPEZOID &&
	    cfg->output == SH2000_OUTPUT_COMPENSATED)
		p->lim.A /= 1.75;
	p->cap = cfg->window;
	p->blk = pl_alloc(p, p->cap * sizeof(*p->blk));
	if (!p->blk) {
		free(p);
		return -ENOMEM;
	}
	p->cons = pl_alloc(p, 2 * (p->cap + 1) * sizeof(double));
	if (!p->cons) {
		free(p->blk);
		free(p);
		return -ENOMEM;
	}
	if (cfg->output == SH2000_OUTPUT_COMPENSATED) {
		r = sh2000_bscomp_create(&p->comp, cfg->comp_window, SH2000_AXES);
		if (r) {
			free(p->cons);
			free(p->blk);
			free(p);
			return r;
		}
		/* its size, for the accounting */
		p->mem += (2u * cfg->comp_window + 3u) * 2u * SH2000_AXES * sizeof(double);
		p->mem_peak = p->mem;
	}
	memcpy(p->qend, cfg->start, sizeof(p->qend));
	memcpy(p->pos, cfg->start, sizeof(p->pos));
	p->stop_next = 1;
	*out = p;
	return 0;
}

static void drop_blocks(struct sh2000_path *p)
{
	while (p->count) {
		struct pl_block *b = &p->blk[p->head];

		if (b->type == BLK_NURBS)
			pl_nurbs_put(p, b->g.nurbs.nb);
		p->head = (p->head + 1) % p->cap;
		p->count--;
	}
	if (p->pending) {
		struct pl_nurbs *nb = p->pending;

		p->pending = NULL;
		nb->expanded = 1;
		nb->refs++;
		pl_nurbs_put(p, nb);
	}
}

void sh2000_path_destroy(struct sh2000_path *p)
{
	if (!p)
		return;
	drop_blocks(p);
	sh2000_bscomp_destroy(p->comp);
	free(p->cons);
	free(p->blk);
	free(p);
}

/* ---- limits ----------------------------------------------------------- */

double pl_curve_vlim(const struct sh2000_path *p, const double t[SH2000_AXES],
		     double kappa)
{
	const struct sh2000_path_config *c = &p->cfg;
	double v = INFINITY;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		if (fabs(t[a]) > 1e-12)
			v = fmin(v, c->margin * c->vmax[a] / fabs(t[a]));
	if (kappa > 1e-12) {
		double share = c->centripetal_share * c->margin;

		v = fmin(v, sqrt(share * p->amin / kappa));
		v = fmin(v, sqrt(8.0 * c->chord_tol / kappa) / c->period_s);
		if (!isinf(p->lim.J))
			v = fmin(v, cbrt(share * p->lim.J / (kappa * kappa)));
	}
	return v;
}

double pl_cap(const struct sh2000_path *p, const struct pl_block *b)
{
	return fmin(b->vlim, b->feed * p->override);
}

/* Speed allowed through the corner between tangents t1 (in) and t0 (out). */
static double junction(const struct sh2000_path *p, const double t1[SH2000_AXES],
		       const double t0[SH2000_AXES])
{
	const struct sh2000_path_config *c = &p->cfg;
	double dot = 0.0, v = INFINITY, ch, sh, T = c->period_s;
	double k = c->output == SH2000_OUTPUT_COMPENSATED ? sqrt(3.0) : 1.0;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		dot += t1[a] * t0[a];
	if (dot > 1.0 - 1e-12)
		return INFINITY;
	/* the corner tolerance: a circle through the corner that deviates
	 * by corner_tol, at the path acceleration */
	ch = sqrt(fmax(0.0, 0.5 * (1.0 + dot)));	/* cos(turn/2) */
	sh = sqrt(fmax(0.0, 0.5 * (1.0 - dot)));	/* sin(turn/2) */
	if (ch < 1e-9)
		return 0.0;
	v = sqrt(p->lim.A * c->corner_tol * ch / (1.0 - ch));
	/* the card's spline rounds the corner by about vT sin(turn/2) / 3;
	 * half of that, for the speed changing around it */
	v = fmin(v, 1.5 * c->corner_tol / (T * sh));
	for (a = 0; a < SH2000_AXES; a++) {
		double dt = fabs(t0[a] - t1[a]);
		double room = c->margin * c->amax[a] - p->lim.A;

		if (dt < 1e-12)
			continue;
		/* the jump in axis speed is an acceleration over one
		 * period, sqrt 3 times larger after compensation */
		v = fmin(v, fmax(room, 0.0) * T / (k * dt));
		/* and the compensation overshoots a speed step by 0.37 */
		if (k > 1.0)
			v = fmin(v, c->margin * c->vmax[a] /
				    (fmax(fabs(t0[a]), fabs(t1[a])) + 0.37 * dt));
	}
	return v;
}

/* vb of block i (ring offset) from its own limits and the next block. */
static double vb_of(struct sh2000_path *p, unsigned int i)
{
	struct pl_block *b = &p->blk[(p->head + i) % p->cap];
	struct pl_block *prev = &p->blk[(p->head + i - 1) % p->cap];
	double next = 0.0, v;

	if (i + 1 < p->count)
		next = p->blk[(p->head + i + 1) % p->cap].vb;
	v = fmin(b->vj, fmin(pl_cap(p, b), pl_cap(p, prev)));
	return fmin(v, pl_reach_back(&p->lim, next, b->L));
}

void pl_backward_all(struct sh2000_path *p)
{
	unsigned int i;

	for (i = p->count; i-- > 1;)
		p->blk[(p->head + i) % p->cap].vb = vb_of(p, i);
}

void pl_push_block(struct sh2000_path *p, struct pl_block *b)
{
	unsigned int i;
	double nt = 0.0;

	b->seq = p->seq;
	for (i = 0; i < SH2000_AXES; i++)
		nt += p->tend[i] * p->tend[i];
	if (p->stop_next || nt < 0.5)
		b->vj = 0.0;
	else
		b->vj = junction(p, p->tend, b->t0);
	b->corner = !isinf(b->vj);
	if (b->feed == 0.0)
		b->feed = INFINITY;
	p->stop_next = b->stop_after;
	memcpy(p->tend, b->t1, sizeof(p->tend));
	memcpy(p->qend, b->p1, sizeof(p->qend));
	p->blk[(p->head + p->count) % p->cap] = *b;
	p->count++;
	p->blocks++;
	/* the backward pass, as far as anything changes */
	for (i = p->count; i-- > 1;) {
		struct pl_block *k = &p->blk[(p->head + i) % p->cap];
		double v = vb_of(p, i);

		if (i + 1 < p->count && v == k->vb)
			break;
		k->vb = v;
	}
}

/* ---- validation helpers ------------------------------------------------ */

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

static int check_point(struct sh2000_path *p, const char *what,
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
	if (p->count == p->cap)
		return pl_make_room(p);
	return 0;
}

/* ---- lines and point-to-point ----------------------------------------- */

static int line_block(struct sh2000_path *p, const double end[SH2000_AXES],
		      double feed, int p2p)
{
	struct pl_block b;
	double len = 0.0;
	unsigned int a;
	int r;

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
	memcpy(b.p1, end, sizeof(b.p1));
	for (a = 0; a < SH2000_AXES; a++)
		b.g.line.d[a] = b.t0[a] = b.t1[a] = (end[a] - p->qend[a]) / len;
	b.vlim = pl_curve_vlim(p, b.t0, 0.0);
	if (p2p) {
		p->stop_next = 1;
		b.stop_after = 1;
	}
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
	return line_block(p, end, feed, 0);
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
	return line_block(p, target, speed, 1);
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

/* ---- arcs ------------------------------------------------------------- */

static const unsigned int plane_axes[3][2] = { { 0, 1 }, { 0, 2 }, { 1, 2 } };

int sh2000_path_arc(struct sh2000_path *p, const struct sh2000_path_arc *arc,
		    double feed)
{
	struct pl_block b;
	unsigned int i, j, a;
	double s0[2], e0[2], c[2], r0, r1, th0, th1, dth, lin2 = 0.0;
	double planar, kmax, kappa, tt[SH2000_AXES];
	int r, full = 0;

	if (!arc)
		return pl_err(p, -EINVAL, "arc: no description");
	if ((unsigned int)arc->plane > SH2000_PLANE_YZ)
		return pl_err(p, -EINVAL, "arc: unknown plane %d",
			      (int)arc->plane);
	r = check_point(p, "arc: end", arc->end);
	if (r)
		return r;
	r = check_feed(p, "feed", feed, 0);
	if (r)
		return r;
	if (arc->turns > 1000)
		return pl_err(p, -EINVAL, "arc: %u turns is more than 1000",
			      arc->turns);
	i = plane_axes[arc->plane][0];
	j = plane_axes[arc->plane][1];
	s0[0] = p->qend[i];
	s0[1] = p->qend[j];
	e0[0] = arc->end[i];
	e0[1] = arc->end[j];
	if (!arc->radius_form) {
		if (isnan(arc->centre[0]) || isnan(arc->centre[1]))
			return pl_err(p, -EINVAL, "arc: centre is NaN");
		if (!isfinite(arc->centre[0]) || !isfinite(arc->centre[1]))
			return pl_err(p, -EINVAL, "arc: centre is infinite");
		c[0] = arc->centre[0];
		c[1] = arc->centre[1];
	} else {
		double R = fabs(arc->radius), dx = e0[0] - s0[0];
		double dy = e0[1] - s0[1], d = hypot(dx, dy), h, side;

		if (isnan(arc->radius))
			return pl_err(p, -EINVAL, "arc: radius is NaN");
		if (!(R > 0.0) || !isfinite(R))
			return pl_err(p, -EINVAL,
				      "arc: radius must be non-zero and finite: got %g",
				      arc->radius);
		if (d < GEOM_TOL)
			return pl_err(p, -EINVAL,
				      "arc: the radius form cannot make a full circle (end == start); give the centre");
		if (d > 2.0 * R + GEOM_TOL)
			return pl_err(p, -EINVAL,
				      "arc: radius %.3f is too small for the %.3f mm chord",
				      R, d);
		h = sqrt(fmax(0.0, R * R - d * d / 4.0));
		/* centre left of the chord for a short ccw arc */
		side = (arc->ccw ? 1.0 : -1.0) * (arc->radius > 0.0 ? 1.0 : -1.0);
		c[0] = s0[0] + dx / 2.0 - side * h * dy / d;
		c[1] = s0[1] + dy / 2.0 + side * h * dx / d;
	}
	r0 = hypot(s0[0] - c[0], s0[1] - c[1]);
	r1 = hypot(e0[0] - c[0], e0[1] - c[1]);
	if (r0 < GEOM_TOL)
		return pl_err(p, -EINVAL,
			      "arc: the start is on the centre (radius %.4f mm)",
			      r0);
	if (fabs(r0 - r1) > GEOM_TOL)
		return pl_err(p, -EINVAL,
			      "arc: start radius %.3f and end radius %.3f differ by more than %.3f mm",
			      r0, r1, GEOM_TOL);
	th0 = atan2(s0[1] - c[1], s0[0] - c[0]);
	th1 = atan2(e0[1] - c[1], e0[0] - c[0]);
	if (hypot(e0[0] - s0[0], e0[1] - s0[1]) < 1e-9)
		full = 1;
	if (arc->ccw) {
		dth = th1 - th0;
		while (dth <= 0.0)
			dth += 2.0 * M_PI;
		if (full)
			dth = 2.0 * M_PI;
		dth += 2.0 * M_PI * arc->turns;
	} else {
		dth = th1 - th0;
		while (dth >= 0.0)
			dth -= 2.0 * M_PI;
		if (full)
			dth = -2.0 * M_PI;
		dth -= 2.0 * M_PI * arc->turns;
	}
	r = ready(p);
	if (r)
		return r;
	memset(&b, 0, sizeof(b));
	b.type = BLK_ARC;
	b.feed = feed;
	b.g.arc.i = i;
	b.g.arc.j = j;
	b.g.arc.c[0] = c[0];
	b.g.arc.c[1] = c[1];
	b.g.arc.r0 = r0;
	b.g.arc.r1 = r1;
	b.g.arc.th0 = th0;
	b.g.arc.dth = dth;
	memcpy(b.p0, p->qend, sizeof(b.p0));
	memcpy(b.p1, arc->end, sizeof(b.p1));
	for (a = 0; a < SH2000_AXES; a++)
		if (a != i && a != j)
			lin2 += (arc->end[a] - p->qend[a]) *
				(arc->end[a] - p->qend[a]);
	planar = fabs(dth) * 0.5 * (r0 + r1);
	b.L = sqrt(planar * planar + lin2);
	/* tangents; the speed limit from the worst direction of the plane
	 * axes (each reaches |t| = planar / L somewhere on a long arc) */
	{
		double sgn = dth > 0.0 ? 1.0 : -1.0, f = planar / b.L;
		double th1r = th0 + dth;

		for (a = 0; a < SH2000_AXES; a++) {
			double l = (a != i && a != j) ?
				   (arc->end[a] - p->qend[a]) / b.L : 0.0;

			b.t0[a] = b.t1[a] = l;
			tt[a] = l;
		}
		b.t0[i] = -sgn * f * sin(th0);
		b.t0[j] = sgn * f * cos(th0);
		b.t1[i] = -sgn * f * sin(th1r);
		b.t1[j] = sgn * f * cos(th1r);
		tt[i] = f;
		tt[j] = f;
		/* helix curvature: (planar share)^2 / r */
		kmax = f * f / fmin(r0, r1);
		kappa = kmax;
	}
	b.vlim = pl_curve_vlim(p, tt, kappa);
	pl_push_block(p, &b);
	return 0;
}

/* ---- NURBS ------------------------------------------------------------ */

int sh2000_path_nurbs(struct sh2000_path *p, const struct sh2000_path_nurbs *n,
		      double feed)
{
	struct pl_nurbs tmp, *nb;
	unsigned int i, a, deg, cnt, nk, w;
	double c[SH2000_AXES], d = 0.0, tt[SH2000_AXES], ks;
	int r;

	if (!n)
		return pl_err(p, -EINVAL, "nurbs: no description");
	deg = n->degree;
	cnt = n->count;
	if (deg < 1)
		return pl_err(p, -EINVAL, "nurbs: degree must be >= 1: got %u",
			      deg);
	if (deg > 32)
		return pl_err(p, -EINVAL, "nurbs: degree %u is above 32", deg);
	if (cnt < deg + 1)
		return pl_err(p, -EINVAL,
			      "nurbs: %u control points are too few for degree %u (need %u)",
			      cnt, deg, deg + 1);
	if (cnt > 10000000)
		return pl_err(p, -EINVAL, "nurbs: %u control points is too many",
			      cnt);
	if (!n->ctrl || !n->knots)
		return pl_err(p, -EINVAL, "nurbs: control points and knots are required");
	r = check_feed(p, "feed", feed, 0);
	if (r)
		return r;
	nk = cnt + deg + 1;
	for (i = 0; i < nk; i++) {
		if (!isfinite(n->knots[i]))
			return pl_err(p, -EINVAL, "nurbs: knot %u is %s", i,
				      isnan(n->knots[i]) ? "NaN" : "infinite");
		if (i > 0 && n->knots[i] < n->knots[i - 1])
			return pl_err(p, -EINVAL, "nurbs: knot %u (%g) < knot %u (%g)",
				      i, n->knots[i], i - 1, n->knots[i - 1]);
	}
	if (!(n->knots[deg] < n->knots[cnt]))
		return pl_err(p, -EINVAL,
			      "nurbs: empty parameter range: knot %u (%g) == knot %u (%g)",
			      deg, n->knots[deg], cnt, n->knots[cnt]);
	for (i = deg + 1; i < cnt; i++) {
		unsigned int m = 1;

		while (i + m < cnt && n->knots[i + m] == n->knots[i])
			m++;
		if (m > deg)
			return pl_err(p, -EINVAL,
				      "nurbs: interior knot %g has multiplicity %u > degree %u (the curve would break)",
				      n->knots[i], m, deg);
		i += m - 1;
	}
	for (i = 0; i < cnt; i++) {
		char what[48];

		snprintf(what, sizeof(what), "nurbs: control point %u", i);
		r = check_point(p, what, n->ctrl[i]);
		if (r)
			return r;
		if (n->weights && !(n->weights[i] > 0.0 &&
				    isfinite(n->weights[i])))
			return pl_err(p, -EINVAL,
				      "nurbs: weight %u is %g, must be > 0 and finite",
				      i, n->weights[i]);
	}
	/* a temporary view on the caller's data to check the geometry */
	memset(&tmp, 0, sizeof(tmp));
	tmp.p = deg;
	tmp.n = cnt;
	w = (deg > 2 ? deg : 2) + 1;
	tmp.bytes = ((deg + 1) * (deg + 1) + 2 * (deg + 1) + 2 * w +
		     3 * (deg + 1)) * sizeof(double);
	nb = pl_alloc(p, sizeof(*nb));
	if (!nb)
		return pl_err(p, -ENOMEM, "nurbs: out of memory");
	*nb = tmp;
	nb->U = pl_alloc(p, nk * sizeof(double));
	nb->Pw = pl_alloc(p, cnt * 5 * sizeof(double));
	nb->scratch = pl_alloc(p, tmp.bytes);
	if (!nb->U || !nb->Pw || !nb->scratch) {
		nb->expanded = 1;
		nb->refs = 1;
		pl_nurbs_put(p, nb);
		return pl_err(p, -ENOMEM, "nurbs: out of memory");
	}
	memcpy(nb->U, n->knots, nk * sizeof(double));
	for (i = 0; i < cnt; i++) {
		double wt = n->weights ? n->weights[i] : 1.0;

		for (a = 0; a < SH2000_AXES; a++)
			nb->Pw[5 * i + a] = wt * n->ctrl[i][a];
		nb->Pw[5 * i + SH2000_AXES] = wt;
	}
	nb->umin = nb->U[deg];
	nb->umax = nb->U[cnt];
	nb->span = deg;
	nb->id = ++p->nurbs_ids;
	pl_nurbs_eval(nb, nb->umin, c, NULL, NULL);
	for (a = 0; a < SH2000_AXES; a++)
		d += (c[a] - p->qend[a]) * (c[a] - p->qend[a]);
	d = sqrt(d);
	r = 0;
	if (d > GEOM_TOL)
		r = pl_err(p, -EINVAL,
			   "nurbs: the curve starts at (%.4f, %.4f, %.4f, %.4f), %.4f mm from the current position (%.4f, %.4f, %.4f, %.4f)",
			   c[0], c[1], c[2], c[3], d, p->qend[0], p->qend[1],
			   p->qend[2], p->qend[3]);
	/* the arc-length parametrisation needs C' != 0 */
	for (i = deg; !r && i < cnt; i++) {
		unsigned int k;

		if (nb->U[i] >= nb->U[i + 1])
			continue;
		for (k = 0; k <= 8; k++) {
			double u = nb->U[i] + (nb->U[i + 1] - nb->U[i]) * k / 8.0;

			if (pl_nurbs_frame(nb, u, tt, &ks) < 1e-9 *
			    (1.0 + fabs(nb->umax - nb->umin)))
				r = pl_err(p, -EINVAL,
					   "nurbs: the curve stands still (zero derivative) at u = %g",
					   u);
		}
	}
	if (!r)
		r = ready(p);
	if (r) {
		nb->expanded = 1;
		nb->refs = 1;
		pl_nurbs_put(p, nb);
		return r;
	}
	/* feed travels with every block of the curve */
	nb->refs = 0;
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

/* ---- control ----------------------------------------------------------- */

int sh2000_path_set_override(struct sh2000_path *p, double factor)
{
	if (!(factor > 0.0 && factor <= 2.0))
		return pl_err(p, -EINVAL, "override must be in (0, 2]: got %g",
			      factor);
	p->override = factor;
	pl_backward_all(p);
	return 0;
}

int sh2000_path_pause(struct sh2000_path *p)
{
	p->paused = 1;
	return 0;
}

int sh2000_path_resume(struct sh2000_path *p)
{
	p->paused = 0;
	return 0;
}

int sh2000_path_stop(struct sh2000_path *p)
{
	if (!p->moving) {
		drop_blocks(p);
		memcpy(p->qend, p->pos, sizeof(p->qend));
		memset(p->tend, 0, sizeof(p->tend));
		p->stop_next = 1;
		p->s = p->v = p->a = 0.0;
		p->paused = 0;
		return 0;
	}
	p->stopping = 1;
	return 0;
}

/* Called by the controller once a stop has come to rest. */
void pl_stopped(struct sh2000_path *p)
{
	drop_blocks(p);
	memcpy(p->qend, p->pos, sizeof(p->qend));
	memset(p->tend, 0, sizeof(p->tend));
	p->stop_next = 1;
	p->stopping = 0;
	p->paused = 0;
	p->s = p->v = p->a = 0.0;
}

int sh2000_path_reset(struct sh2000_path *p, const double pos[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		if (!pos || !isfinite(pos[a]))
			return pl_err(p, -EINVAL, "reset: position %c is not finite",
				      axis_name[a]);
	drop_blocks(p);
	memcpy(p->pos, pos, sizeof(p->pos));
	p->fail = 0;
	p->paused = 0;
	p->moving = 0;
	p->comp_started = 0;
	pl_stopped(p);
	return 0;
}

void sh2000_path_stats(const struct sh2000_path *p, struct sh2000_path_stats *st)
{
	memset(st, 0, sizeof(*st));
	st->points = p->points;
	st->motions = p->motions;
	st->blocks = p->blocks;
	st->velocity = p->v;
	st->moving = p->moving;
	st->paused = p->paused;
	st->nurbs_chord_error = p->chord_err;
	st->nurbs_feed_fluctuation = p->feed_fluct;
	st->nurbs_steps = p->nurbs_steps;
	st->nurbs_corrections = p->nurbs_corr;
	st->nurbs_feed_fluctuation_predicted = p->feed_fluct_pred;
	st->mem_bytes = p->mem;
	st->mem_peak = p->mem_peak;
}
