// SPDX-License-Identifier: MIT
/*
 * Feed exact on the card: the card model's fine set-points (every servo
 * cycle), projected onto the exact geometry of the program, move along it
 * no faster than the programmed feed plus 0.01 %, measured as arc length
 * over 10 ms windows (and reported per servo cycle), and no axis exceeds
 * its vmax or amax -- on lines, arcs and NURBS, with speed changes, in
 * compensated and raw output. Measured where the user sees it: on what the
 * card commands, not on the planned points.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "plcard.h"

#define WINDOW 100		/* servo cycles: 10 ms at 100 us */
#define FEED_SLACK 1e-4		/* 0.01 % */

/* ---- the exact geometry ------------------------------------------------ */

enum seg_kind { SEG_LINE, SEG_ARC, SEG_NURBS };

struct seg {
	enum seg_kind kind;
	double feed, s0, len;	/* mm/s; arc length at its start; length */
	double p0[4], p1[4];
	struct sh2000_arc arc;	/* SEG_ARC */
	struct sh2000_nurbs nurbs;	/* SEG_NURBS */
};

struct model {
	struct seg seg[16];
	unsigned int n;
	double end[4];		/* where the last segment ends */
	/* the projection's state */
	unsigned int cur;
	double u, s;		/* NURBS parameter, arc length so far */
};

static double norm4(const double *x)
{
	return sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3]);
}

static double nurbs_speed(const struct sh2000_nurbs *n, double u)
{
	double c[4], d[4];

	sh2000_nurbs_eval(n, u, c, d, NULL);
	return norm4(d);
}

/* Arc length of a NURBS between u0 and u1: 5-point Gauss-Legendre on
 * pieces of at most 1/64 of the domain. */
static double nurbs_len(const struct sh2000_nurbs *n, double u0, double u1)
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
			s += w[i] * nurbs_speed(n, m + 0.5 * h * x[i]) * 0.5 * h;
	}
	return s;
}

static void add_seg(struct model *m, struct seg *g, double feed)
{
	g->feed = feed;
	g->s0 = m->n ? m->seg[m->n - 1].s0 + m->seg[m->n - 1].len : 0;
	memcpy(g->p0, m->end, sizeof(g->p0));
	memcpy(m->end, g->p1, sizeof(m->end));
	m->seg[m->n++] = *g;
}

static void model_line(struct model *m, const double e[4], double feed)
{
	struct seg g = { .kind = SEG_LINE };
	double d[4];

	memcpy(g.p1, e, sizeof(g.p1));
	for (unsigned int a = 0; a < 4; a++)
		d[a] = e[a] - m->end[a];
	g.len = norm4(d);
	add_seg(m, &g, feed);
}

static void model_arc(struct model *m, const struct sh2000_path_arc *a,
		      double feed)
{
	struct seg g = { .kind = SEG_ARC };

	assert_int_equal(sh2000_arc_resolve(&g.arc, a->plane, m->end, a->end,
					    a->centre, a->ccw, 1, 0, 0, NULL, 0),
			 0);
	memcpy(g.p1, a->end, sizeof(g.p1));
	/* a planar arc (the tests keep the other axes still) */
	g.len = fabs(g.arc.sweep) * g.arc.r0;
	add_seg(m, &g, feed);
}

static void model_nurbs(struct model *m, const struct sh2000_nurbs *n,
			double feed)
{
	struct seg g = { .kind = SEG_NURBS, .nurbs = *n };

	sh2000_nurbs_eval(n, sh2000_nurbs_umax(n), g.p1, NULL, NULL);
	g.len = nurbs_len(n, sh2000_nurbs_umin(n), sh2000_nurbs_umax(n));
	if (getenv("FEED_DEBUG")) {
		double acc = 0;
		for (int k = 0; k < 1000; k++)
			acc += nurbs_len(n, k / 1000.0, (k + 1) / 1000.0);
		print_message("nurbs len %.9f, in 1000 steps %.9f\n", g.len, acc);
	}
	add_seg(m, &g, feed);
}

/* Arc length along segment g of the point nearest to x (the segment's own
 * parameter: NURBS by Newton from the last u). */
static double seg_project(struct model *m, const struct seg *g,
			  const double x[4], double foot[4])
{
	double c[4], d1[4], d2[4], u = m->u;
	unsigned int a, it;

	switch (g->kind) {
	case SEG_LINE: {
		double t = 0;

		for (a = 0; a < 4; a++)
			t += (x[a] - g->p0[a]) * (g->p1[a] - g->p0[a]);
		t = g->len > 0 ? fmin(fmax(t / g->len, 0), g->len) : 0;
		for (a = 0; a < 4; a++)
			foot[a] = g->p0[a] + (g->p1[a] - g->p0[a]) *
				  (g->len > 0 ? t / g->len : 0);
		return t;
	}
	case SEG_ARC: {
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
		 * sample there, then refine by Newton inside the bracket */
		const struct sh2000_nurbs *n = &g->nurbs;
		double umin = sh2000_nurbs_umin(n), umax = sh2000_nurbs_umax(n);
		double du = 0.2 / fmax(nurbs_speed(n, u), 1e-9), best = INFINITY;
		double lo = fmax(u - du / 4, umin), hi = fmin(u + du, umax), ub = u;

		for (it = 0; it <= 32; it++) {
			double uu = lo + (hi - lo) * it / 32, d2 = 0;

			sh2000_nurbs_eval(n, uu, c, NULL, NULL);
			for (a = 0; a < 4; a++)
				d2 += (c[a] - x[a]) * (c[a] - x[a]);
			if (d2 < best) {
				best = d2;
				ub = uu;
			}
		}
		lo = fmax(ub - (hi - lo) / 32, umin);
		hi = fmin(ub + (hi - lo) / 32, umax);
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
		m->s += nurbs_len(&g->nurbs, m->u, u);
		m->u = u;
		sh2000_nurbs_eval(n, u, foot, NULL, NULL);
		return m->s;
	}
	}
}

static double dist4(const double *a, const double *b)
{
	double d[4];

	for (unsigned int k = 0; k < 4; k++)
		d[k] = a[k] - b[k];
	return norm4(d);
}

/* Arc length of x along the whole program (moving forward only): on the
 * current segment, or on the next once x is nearer to that. */
static double project(struct model *m, const double x[4])
{
	for (;;) {
		const struct seg *g = &m->seg[m->cur], *nx;
		struct model probe;
		double foot[4], foot2[4], s, sn;

		s = seg_project(m, g, x, foot);
		if (m->cur + 1 == m->n || s < g->len - 1.0)
			return g->s0 + s;
		nx = &m->seg[m->cur + 1];
		probe = *m;
		probe.cur++;
		probe.u = nx->kind == SEG_NURBS ? sh2000_nurbs_umin(&nx->nurbs) : 0;
		probe.s = 0;
		sn = seg_project(&probe, nx, x, foot2);
		if (sn <= 1e-9 || dist4(foot2, x) >= dist4(foot, x))
			return g->s0 + s;
		*m = probe;
	}
}

/* The highest feed over arc lengths [s0, s1]. */
static double feed_over(const struct model *m, double s0, double s1)
{
	double f = 0;

	for (unsigned int i = 0; i < m->n; i++)
		if (m->seg[i].s0 <= s1 && m->seg[i].s0 + m->seg[i].len >= s0)
			f = fmax(f, m->seg[i].feed);
	return f;
}

/* ---- the measurement on the card's set-points --------------------------- */

struct feed_meas {
	struct model *m;
	const struct sh2000_path_config *c;
	double tau;			/* servo period */
	double *s;			/* arc length per servo cycle */
	size_t n, cap;
	double prev[2][4];
	double v_ratio, a_ratio;	/* per axis, of vmax and amax */
};

static void on_fine(void *ctx, const double x[4], const double act[4])
{
	struct feed_meas *f = ctx;
	unsigned int a;

	(void)act;
	if (f->n == f->cap) {
		f->cap = f->cap ? 2 * f->cap : 65536;
		f->s = realloc(f->s, f->cap * sizeof(*f->s));
		assert_non_null(f->s);
	}
	f->s[f->n] = project(f->m, x);
	if (getenv("FEED_DEBUG") && f->n && f->s[f->n] - f->s[f->n - 1] > 0.1)
		print_message("jump at %zu: s %g -> %g x %g %g %g cur %u u %g\n",
			      f->n, f->s[f->n - 1], f->s[f->n], x[0], x[1], x[2],
			      f->m->cur, f->m->u);
	for (a = 0; f->n >= 1 && a < 4; a++)
		f->v_ratio = fmax(f->v_ratio, fabs(x[a] - f->prev[1][a]) /
				  f->tau / f->c->vmax[a]);
	for (a = 0; f->n >= 2 && a < 4; a++)
		f->a_ratio = fmax(f->a_ratio,
				  fabs(x[a] - 2 * f->prev[1][a] + f->prev[0][a]) /
				  (f->tau * f->tau) / f->c->amax[a]);
	memcpy(f->prev[0], f->prev[1], sizeof(f->prev[0]));
	memcpy(f->prev[1], x, sizeof(f->prev[1]));
	f->n++;
}

/* The largest speed over the programmed feed, as a fraction, over
 * windows of w cycles. */
static double overshoot(const struct feed_meas *f, size_t w)
{
	double worst = -1;
	size_t wi = 0;

	for (size_t i = 0; i + w < f->n; i++) {
		double v = (f->s[i + w] - f->s[i]) / (w * f->tau);
		double feed = feed_over(f->m, f->s[i], f->s[i + w]);

		if (feed > 0 && f->s[i + w] - f->s[i] > 1e-9) {
			if (getenv("FEED_DEBUG") && v / feed - 1 > 0.5)
				print_message("i %zu s %g -> %g feed %g\n", i,
					      f->s[i], f->s[i + w], feed);
			if (v / feed - 1 > worst)
				wi = i;
			worst = fmax(worst, v / feed - 1);
		}
	}
	if (getenv("FEED_WHERE"))
		print_message("worst at cycle %zu of %zu, s %.4f..%.4f\n", wi,
			      f->n, f->s[wi], f->s[wi + w]);
	return worst;
}

typedef int (*program_fn)(struct sh2000_path *p, struct model *m,
			  const double o[4]);

/* amax: every axis' (0: the planner's default). Returns the fastest
 * 10 ms window's speed over the feed (a fraction). */
static double measure_cfg(const char *name, program_fn prog, int raw,
			  int trap, double amax)
{
	static struct plcard pc;
	struct sh2000_path_config c;
	struct sh2000_path *p;
	struct feed_meas f;
	struct model m;
	double o[4], win, cyc;

	sh2000_path_config_default(&c);
	for (unsigned int a = 0; amax > 0 && a < 4; a++)
		c.amax[a] = amax;
	assert_int_equal(plcard_open(&pc, c.vmax, c.amax, 1, o), 0);
	c.output = raw ? SH2000_OUTPUT_RAW : SH2000_OUTPUT_COMPENSATED;
	if (trap)
		c.profile = SH2000_PROFILE_TRAPEZOID;
	memcpy(c.start, o, sizeof(c.start));
	memset(&m, 0, sizeof(m));
	memcpy(m.end, o, sizeof(m.end));
	memset(&f, 0, sizeof(f));
	f.m = &m;
	f.c = &c;
	f.tau = c.period_s / c.fine_steps;
	pc.fn = on_fine;
	pc.ctx = &f;
	assert_int_equal(sh2000_path_create(&p, &c, plcard_sink, &pc, NULL, 0), 0);
	pc.record = 1;
	assert_int_equal(prog(p, &m, o), 0);
	if (sh2000_path_finish(p))
		fail_msg("%s: %s / %s", name, sh2000_path_error(p), pc.msg);
	assert_int_equal(plcard_idle(&pc), 0);
	win = overshoot(&f, WINDOW);
	cyc = overshoot(&f, 1);
	print_message("%-24s %-11s %-9s %5.0f feed over programmed: %+.5f %% (10 ms), %+.4f %% (one cycle); axis v %.3f, a %.3f of the limits\n",
		      name, raw ? "raw" : "compensated",
		      trap ? "trapezoid" : "S-curve", c.amax[0], win * 100,
		      cyc * 100, f.v_ratio, f.a_ratio);
	if (win > FEED_SLACK)
		fail_msg("%s: the card's set-points run %.4f %% over the feed",
			 name, win * 100);
	assert_true(f.v_ratio <= 1.0);
	assert_true(f.a_ratio <= 1.0);
	sh2000_path_destroy(p);
	plcard_close(&pc);
	free(f.s);
	return win;
}

static void measure(const char *name, program_fn prog, int raw)
{
	(void)measure_cfg(name, prog, raw, 0, 0);
}

/* ---- programs ------------------------------------------------------------ */

/* Collinear lines at 300, 100, 250, 50 and 300 mm/s: every speed change
 * happens on a straight path, the feeds exactly programmed. */
static int prog_lines(struct sh2000_path *p, struct model *m, const double o[4])
{
	static const double feeds[5] = { 300, 100, 250, 50, 300 };
	double e[4];

	memcpy(e, o, sizeof(e));
	for (unsigned int i = 0; i < 5; i++) {
		e[0] += 20;
		e[1] += 10;
		model_line(m, e, feeds[i]);
		if (sh2000_path_line(p, e, feeds[i]))
			return -1;
	}
	return 0;
}

/* Two half circles R 10 at 300 then 120 mm/s, and back at 300. */
static int prog_arcs(struct sh2000_path *p, struct model *m, const double o[4])
{
	static const double feeds[3] = { 300, 120, 300 };
	struct sh2000_path_arc a;

	memset(&a, 0, sizeof(a));
	a.plane = SH2000_PLANE_XY;
	memcpy(a.end, o, sizeof(a.end));
	for (unsigned int i = 0; i < 3; i++) {
		a.ccw = 1;
		a.centre[0] = m->end[0] + (i % 2 ? -10 : 10);
		a.centre[1] = m->end[1];
		a.end[0] = m->end[0] + (i % 2 ? -20 : 20);
		model_arc(m, &a, feeds[i]);
		if (sh2000_path_arc(p, &a, feeds[i]))
			return -1;
	}
	return 0;
}

/* The free-form curve of the planner's tests at 25 mm/s (where the
 * curvature changes the speed) and then at 150 mm/s. */
static const double ff_ctrl[8][4] = {
	{ 0, 0, 0, 0 }, { 5, 10, 0, 0 }, { 10, -5, 1, 0 }, { 15, 8, 2, 0 },
	{ 20, 0, 2, 0 }, { 22, 12, 1, 0 }, { 30, 5, 0, 0 }, { 32, 0, 0, 0 },
};
static const double ff_w[8] = { 1, 2, 0.5, 1, 3, 1, 1, 1 };
static const double ff_k[12] = { 0, 0, 0, 0, 0.2, 0.4, 0.5, 0.8, 1, 1, 1, 1 };

static int prog_nurbs(struct sh2000_path *p, struct model *m, const double o[4])
{
	static double pts[2][8][4];
	static const double feeds[2] = { 25, 150 };

	for (unsigned int k = 0; k < 2; k++) {
		struct sh2000_nurbs n = { 3, 8, (const double (*)[4])pts[k],
					  ff_w, ff_k };

		for (unsigned int i = 0; i < 8; i++)
			for (unsigned int a = 0; a < 4; a++)
				pts[k][i][a] = (k ? m->end[a] : o[a]) +
					       ff_ctrl[i][a];
		m->u = 0;
		model_nurbs(m, &n, feeds[k]);
		if (sh2000_path_nurbs(p, &n, feeds[k]))
			return -1;
	}
	return 0;
}

static void test_feed_lines(void **s)
{
	(void)s;
	measure("lines, 5 feeds", prog_lines, 0);
	measure("lines, 5 feeds", prog_lines, 1);
	(void)measure_cfg("lines, 5 feeds", prog_lines, 0, 1, 0);
	(void)measure_cfg("lines, 5 feeds", prog_lines, 1, 1, 0);
}

static void test_feed_arcs(void **s)
{
	(void)s;
	measure("arcs R 10, 3 feeds", prog_arcs, 0);
	measure("arcs R 10, 3 feeds", prog_arcs, 1);
	(void)measure_cfg("arcs R 10, 3 feeds", prog_arcs, 0, 1, 0);
}

static void test_feed_nurbs(void **s)
{
	(void)s;
	measure("free-form NURBS, 25/150", prog_nurbs, 0);
	measure("free-form NURBS, 25/150", prog_nurbs, 1);
}

/* At the card model's 5000 mm/s^2, where the S-curve ramps within a
 * period and the controller holds one jerk a whole period (control.c):
 * the compensated spline then follows the plan itself, and the cruise is
 * the programmed feed, which the card's set-points reach within 0.01 %
 * (the fastest 10 ms window) as well as never pass by more. */
static void test_feed_period_jerk(void **s)
{
	(void)s;
	assert_true(measure_cfg("lines, 5 feeds", prog_lines, 0, 0, 5000) >=
		    -FEED_SLACK);
	assert_true(measure_cfg("arcs R 10, 3 feeds", prog_arcs, 0, 0,
				5000) >= -FEED_SLACK);
	assert_true(measure_cfg("free-form NURBS, 25/150", prog_nurbs, 0, 0,
				5000) >= -FEED_SLACK);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_feed_lines),
		cmocka_unit_test(test_feed_arcs),
		cmocka_unit_test(test_feed_nurbs),
		cmocka_unit_test(test_feed_period_jerk),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
