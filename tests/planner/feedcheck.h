/* SPDX-License-Identifier: MIT */
/*
 * The feed where the user sees it: a program run through the card model
 * (plcard.h), every servo cycle's fine set-point projected onto the
 * program's exact geometry (lines, arcs, NURBS) and the arc length
 * travelled recorded, together with the largest axis velocity and
 * acceleration against their limits, and the servo cycles the set-point
 * moved in. The feed test (test_feed.c) and the feed benchmark (bench/feed)
 * measure with it, so both measure the same way. Header-only; no test
 * framework: errors are returned.
 *
 * FEED_DEBUG=1 in the environment prints the NURBS lengths and jumps of
 * the projection, FEED_WHERE=1 where the fastest window lies.
 */
#ifndef SH2000_FEEDCHECK_H
#define SH2000_FEEDCHECK_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plcard.h"
#include "sh2000/geometry.h"
#include "sh2000/path.h"

#define FC_WINDOW 100		/* servo cycles: 10 ms at 100 us */
/* the NURBS projection's first search: FC_GRID + 1 samples over about
 * 0.25 mm of the curve, the nearest refined by Newton (32 gave the same
 * figures in test_feed and bench_feed, the test taking half as long
 * again) */
#define FC_GRID 8

/* ---- the exact geometry ------------------------------------------------ */

enum fc_seg_kind { FC_LINE, FC_ARC, FC_NURBS };

struct fc_seg {
	enum fc_seg_kind kind;
	double feed, s0, len;	/* mm/s; arc length at its start; length */
	double p0[4], p1[4];
	struct sh2000_arc arc;	/* FC_ARC */
	struct sh2000_nurbs nurbs;	/* FC_NURBS */
};

struct fc_model {
	struct fc_seg seg[16];
	unsigned int n;
	double end[4];		/* where the last segment ends */
	/* the projection's state */
	unsigned int cur;
	double u, s;		/* NURBS parameter, arc length so far */
};

static inline double fc_norm4(const double *x)
{
	return sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3]);
}

static inline double fc_nurbs_speed(const struct sh2000_nurbs *n, double u)
{
	double c[4], d[4];

	sh2000_nurbs_eval(n, u, c, d, NULL);
	return fc_norm4(d);
}

/* Arc length of a NURBS between u0 and u1: 5-point Gauss-Legendre on
 * pieces of at most 1/64 of the domain. */
static inline double fc_nurbs_len(const struct sh2000_nurbs *n, double u0,
				  double u1)
{
	static const double x[5] = { 0, 0.5384693101056831, -0.5384693101056831,
				     0.9061798459386640, -0.9061798459386640 };
	static const double w[5] = { 0.5688888888888889, 0.4786286704993665,
				     0.4786286704993665, 0.2369268850561891,
				     0.2369268850561891 };
	double span = (sh2000_nurbs_umax(n) - sh2000_nurbs_umin(n)) / 64;
	unsigned int k, pieces = (unsigned int)ceil(fabs(u1 - u0) / span) + 1;
	double s = 0, h = (u1 - u0) / pieces;

	for (k = 0; k < pieces; k++) {
		double m = u0 + h * (k + 0.5);

		for (unsigned int i = 0; i < 5; i++)
			s += w[i] * fc_nurbs_speed(n, m + 0.5 * h * x[i]) *
			     0.5 * h;
	}
	return s;
}

/* A model starting at o. */
static inline void fc_model_init(struct fc_model *m, const double o[4])
{
	memset(m, 0, sizeof(*m));
	memcpy(m->end, o, sizeof(m->end));
}

static inline int fc_add_seg(struct fc_model *m, struct fc_seg *g,
			     double feed)
{
	if (m->n == sizeof(m->seg) / sizeof(m->seg[0]))
		return -1;
	g->feed = feed;
	g->s0 = m->n ? m->seg[m->n - 1].s0 + m->seg[m->n - 1].len : 0;
	memcpy(g->p0, m->end, sizeof(g->p0));
	memcpy(m->end, g->p1, sizeof(m->end));
	m->seg[m->n++] = *g;
	return 0;
}

static inline int fc_model_line(struct fc_model *m, const double e[4],
				double feed)
{
	struct fc_seg g = { .kind = FC_LINE };
	double d[4];

	memcpy(g.p1, e, sizeof(g.p1));
	for (unsigned int a = 0; a < 4; a++)
		d[a] = e[a] - m->end[a];
	g.len = fc_norm4(d);
	return fc_add_seg(m, &g, feed);
}

/* A planar arc (the programs keep the other axes still). */
static inline int fc_model_arc(struct fc_model *m,
			       const struct sh2000_path_arc *a, double feed)
{
	struct fc_seg g = { .kind = FC_ARC };

	if (sh2000_arc_resolve(&g.arc, a->plane, m->end, a->end, a->centre,
			       a->ccw, 1, 0, 0, NULL, 0))
		return -1;
	memcpy(g.p1, a->end, sizeof(g.p1));
	g.len = fabs(g.arc.sweep) * g.arc.r0;
	return fc_add_seg(m, &g, feed);
}

/* A NURBS; its arrays must outlive the model. */
static inline int fc_model_nurbs(struct fc_model *m,
				 const struct sh2000_nurbs *n, double feed)
{
	struct fc_seg g = { .kind = FC_NURBS, .nurbs = *n };

	sh2000_nurbs_eval(n, sh2000_nurbs_umax(n), g.p1, NULL, NULL);
	g.len = fc_nurbs_len(n, sh2000_nurbs_umin(n), sh2000_nurbs_umax(n));
	if (getenv("FEED_DEBUG")) {
		double acc = 0;

		for (int k = 0; k < 1000; k++)
			acc += fc_nurbs_len(n, k / 1000.0, (k + 1) / 1000.0);
		printf("nurbs len %.9f, in 1000 steps %.9f\n", g.len, acc);
	}
	return fc_add_seg(m, &g, feed);
}

/* Arc length along segment g of the point nearest to x (the segment's own
 * parameter: NURBS by Newton from the last u). */
static inline double fc_seg_project(struct fc_model *m, const struct fc_seg *g,
				    const double x[4], double foot[4])
{
	double c[4], d1[4], d2[4], u = m->u;
	unsigned int a, it;

	switch (g->kind) {
	case FC_LINE: {
		double t = 0;

		for (a = 0; a < 4; a++)
			t += (x[a] - g->p0[a]) * (g->p1[a] - g->p0[a]);
		t = g->len > 0 ? fmin(fmax(t / g->len, 0), g->len) : 0;
		for (a = 0; a < 4; a++)
			foot[a] = g->p0[a] + (g->p1[a] - g->p0[a]) *
				  (g->len > 0 ? t / g->len : 0);
		return t;
	}
	case FC_ARC: {
		double th = atan2(x[g->arc.second] - g->arc.centre[1],
				  x[g->arc.first] - g->arc.centre[0]);
		double d = th - g->arc.th0, sgn = g->arc.sweep > 0 ? 1 : -1;

		d = fmod(sgn * d + 4 * M_PI, 2 * M_PI);
		/* past the end by more than the gap to the start: before it */
		if (d > 0.5 * (fabs(g->arc.sweep) + 2 * M_PI))
			d -= 2 * M_PI;
		d = fmin(fmax(d, 0), fabs(g->arc.sweep));
		sh2000_arc_point(&g->arc, g->p0, g->p1, d / fabs(g->arc.sweep),
				 foot);
		return d * g->arc.r0;
	}
	default: {
		/* the set-point moves at most vmax * tau (0.05 mm) a cycle:
		 * the nearest point is within 0.2 mm ahead of the last one;
		 * sample there (FC_GRID), then refine by Newton inside the
		 * bracket */
		const struct sh2000_nurbs *n = &g->nurbs;
		double umin = sh2000_nurbs_umin(n), umax = sh2000_nurbs_umax(n);
		double du = 0.2 / fmax(fc_nurbs_speed(n, u), 1e-9);
		double lo = fmax(u - du / 4, umin), hi = fmin(u + du, umax);
		double best = INFINITY, ub = u;

		for (it = 0; it <= FC_GRID; it++) {
			double uu = lo + (hi - lo) * it / FC_GRID, dd = 0;

			sh2000_nurbs_eval(n, uu, c, NULL, NULL);
			for (a = 0; a < 4; a++)
				dd += (c[a] - x[a]) * (c[a] - x[a]);
			if (dd < best) {
				best = dd;
				ub = uu;
			}
		}
		lo = fmax(ub - (hi - lo) / FC_GRID, umin);
		hi = fmin(ub + (hi - lo) / FC_GRID, umax);
		u = ub;
		for (it = 0; it < 30; it++) {
			double f = 0, fp = 0;

			sh2000_nurbs_eval(n, u, c, d1, d2);
			for (a = 0; a < 4; a++) {
				f += (c[a] - x[a]) * d1[a];
				fp += d1[a] * d1[a] + (c[a] - x[a]) * d2[a];
			}
			if (fp <= 0)
				break;
			u = fmin(fmax(u - f / fp, lo), hi);
			if (fabs(f / fp) < 1e-14)
				break;
		}
		m->s += fc_nurbs_len(&g->nurbs, m->u, u);
		m->u = u;
		sh2000_nurbs_eval(n, u, foot, NULL, NULL);
		return m->s;
	}
	}
}

static inline double fc_dist4(const double *a, const double *b)
{
	double d[4];

	for (unsigned int k = 0; k < 4; k++)
		d[k] = a[k] - b[k];
	return fc_norm4(d);
}

/* Arc length of x along the whole program (moving forward only): on the
 * current segment, or on the next once x is nearer to that. */
static inline double fc_project(struct fc_model *m, const double x[4])
{
	for (;;) {
		const struct fc_seg *g = &m->seg[m->cur], *nx;
		struct fc_model probe;
		double foot[4], foot2[4], s, sn;

		s = fc_seg_project(m, g, x, foot);
		if (m->cur + 1 == m->n || s < g->len - 1.0)
			return g->s0 + s;
		nx = &m->seg[m->cur + 1];
		probe = *m;
		probe.cur++;
		probe.u = nx->kind == FC_NURBS ? sh2000_nurbs_umin(&nx->nurbs) : 0;
		probe.s = 0;
		sn = fc_seg_project(&probe, nx, x, foot2);
		if (sn <= 1e-9 || fc_dist4(foot2, x) >= fc_dist4(foot, x))
			return g->s0 + s;
		*m = probe;
	}
}

/* The highest feed over arc lengths [s0, s1]. */
static inline double fc_feed_over(const struct fc_model *m, double s0,
				  double s1)
{
	double f = 0;

	for (unsigned int i = 0; i < m->n; i++)
		if (m->seg[i].s0 <= s1 && m->seg[i].s0 + m->seg[i].len >= s0)
			f = fmax(f, m->seg[i].feed);
	return f;
}

/* The program's length. */
static inline double fc_length(const struct fc_model *m)
{
	return m->n ? m->seg[m->n - 1].s0 + m->seg[m->n - 1].len : 0;
}

/* ---- the measurement on the card's set-points --------------------------- */

/* The program: queued on p, every motion also added to m, from o. */
typedef int (*fc_program_fn)(struct sh2000_path *p, struct fc_model *m,
			     const double o[4]);

struct fc_run {
	struct plcard pc;
	struct sh2000_path_config cfg;
	struct sh2000_path *p;
	struct fc_model m;
	double tau;			/* servo period */
	double *s;			/* arc length per servo cycle */
	size_t n, cap;
	double prev[2][4];		/* the last two set-points */
	double v_ratio, a_ratio;	/* per axis, of vmax and amax */
	/* the first and the last servo cycle whose set-point moved */
	size_t moved0, moved1;
	int moved, nomem;
	char msg[512];
};

static inline void fc_on_fine(void *ctx, const double x[4],
			      const double act[4])
{
	struct fc_run *f = ctx;
	unsigned int a;

	(void)act;
	if (f->nomem)
		return;
	if (f->n == f->cap) {
		size_t cap = f->cap ? 2 * f->cap : 65536;
		double *s = realloc(f->s, cap * sizeof(*f->s));

		if (!s) {
			f->nomem = 1;
			return;
		}
		f->s = s;
		f->cap = cap;
	}
	f->s[f->n] = fc_project(&f->m, x);
	if (getenv("FEED_DEBUG") && f->n && f->s[f->n] - f->s[f->n - 1] > 0.1)
		printf("jump at %zu: s %g -> %g x %g %g %g cur %u u %g\n",
		       f->n, f->s[f->n - 1], f->s[f->n], x[0], x[1], x[2],
		       f->m.cur, f->m.u);
	for (a = 0; f->n >= 1 && a < 4; a++) {
		f->v_ratio = fmax(f->v_ratio, fabs(x[a] - f->prev[1][a]) /
				  f->tau / f->cfg.vmax[a]);
		if (x[a] != f->prev[1][a]) {
			if (!f->moved)
				f->moved0 = f->n;
			f->moved = 1;
			f->moved1 = f->n;
		}
	}
	for (a = 0; f->n >= 2 && a < 4; a++)
		f->a_ratio = fmax(f->a_ratio,
				  fabs(x[a] - 2 * f->prev[1][a] + f->prev[0][a]) /
				  (f->tau * f->tau) / f->cfg.amax[a]);
	memcpy(f->prev[0], f->prev[1], sizeof(f->prev[0]));
	memcpy(f->prev[1], x, sizeof(f->prev[1]));
	f->n++;
}

/*
 * Run prog through the card model with configuration c (the card gets its
 * vmax and amax, feed-forward on; the path starts at the card's
 * set-point), measuring every servo cycle until the card is at rest.
 * 0, or -1 with the reason in f->msg. fc_close() in either case.
 */
static inline int fc_run(struct fc_run *f, const struct sh2000_path_config *c,
			 fc_program_fn prog)
{
	double o[4];

	memset(f, 0, sizeof(*f));
	f->cfg = *c;
	if (plcard_open(&f->pc, c->vmax, c->amax, 1, o)) {
		snprintf(f->msg, sizeof(f->msg), "card: %s", f->pc.msg);
		return -1;
	}
	memcpy(f->cfg.start, o, sizeof(f->cfg.start));
	fc_model_init(&f->m, o);
	f->tau = f->cfg.period_s / f->cfg.fine_steps;
	f->pc.fn = fc_on_fine;
	f->pc.ctx = f;
	if (sh2000_path_create(&f->p, &f->cfg, plcard_sink, &f->pc, f->msg,
			       sizeof(f->msg)))
		return -1;
	f->pc.record = 1;
	if (prog(f->p, &f->m, o)) {
		snprintf(f->msg, sizeof(f->msg), "program: %s",
			 sh2000_path_error(f->p));
		return -1;
	}
	if (sh2000_path_finish(f->p)) {
		snprintf(f->msg, sizeof(f->msg), "%s / %s",
			 sh2000_path_error(f->p), f->pc.msg);
		return -1;
	}
	if (plcard_idle(&f->pc)) {
		snprintf(f->msg, sizeof(f->msg), "idle: %s", f->pc.msg);
		return -1;
	}
	if (f->nomem) {
		snprintf(f->msg, sizeof(f->msg), "out of memory");
		return -1;
	}
	return 0;
}

static inline void fc_close(struct fc_run *f)
{
	if (f->p)
		sh2000_path_destroy(f->p);
	f->p = NULL;
	if (f->pc.h)
		plcard_close(&f->pc);
	free(f->s);
	f->s = NULL;
}

/* The mean speed over the w cycles from cycle i, mm/s. */
static inline double fc_speed(const struct fc_run *f, size_t i, size_t w)
{
	return (f->s[i + w] - f->s[i]) / (w * f->tau);
}

/* The largest speed over the programmed feed, as a fraction, over
 * windows of w cycles. */
static inline double fc_overshoot(const struct fc_run *f, size_t w)
{
	double worst = -1;
	size_t wi = 0;

	for (size_t i = 0; i + w < f->n; i++) {
		double v = fc_speed(f, i, w);
		double feed = fc_feed_over(&f->m, f->s[i], f->s[i + w]);

		if (feed > 0 && f->s[i + w] - f->s[i] > 1e-9) {
			if (getenv("FEED_DEBUG") && v / feed - 1 > 0.5)
				printf("i %zu s %g -> %g feed %g\n", i,
				       f->s[i], f->s[i + w], feed);
			if (v / feed - 1 > worst)
				wi = i;
			worst = fmax(worst, v / feed - 1);
		}
	}
	if (getenv("FEED_WHERE") && f->n > w)
		printf("worst at cycle %zu of %zu, s %.4f..%.4f\n", wi,
		       f->n, f->s[wi], f->s[wi + w]);
	return worst;
}

#endif /* SH2000_FEEDCHECK_H */
