// SPDX-License-Identifier: MIT
/*
 * The planner against its contract: limits never exceeded on the
 * records and on the card's fine points, end points exact, arcs and NURBS
 * within tolerance of the exact geometry, constant memory, bad geometry
 * rejected with a clear message and nothing emitted.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "plcheck.h"
#include "planner.h"
#include "sh2000/bspline.h"

/* Headroom the checks allow: the records must stay within the limits; the
 * plan uses `margin` of them. */
#define LIMIT 1.0

static struct sh2000_path_config cfg_of(int raw, int trap)
{
	struct sh2000_path_config c;

	sh2000_path_config_default(&c);
	if (raw)
		c.output = SH2000_OUTPUT_RAW;
	if (trap)
		c.profile = SH2000_PROFILE_TRAPEZOID;
	return c;
}

static struct sh2000_path *mk(const struct sh2000_path_config *c,
			      struct rec *r)
{
	struct sh2000_path *p;
	char e[256] = "";
	int ret;

	rec_init(r, c->start);
	ret = sh2000_path_create(&p, c, rec_sink, r, e, sizeof(e));
	if (ret)
		print_error("create: %s\n", e);
	assert_int_equal(ret, 0);
	return p;
}

static void check_limits(const struct rec *r,
			 const struct sh2000_path_config *c)
{
	struct fd_result fd = fd_check(r, c);
	struct fine_fd ff;

	if (fd.v_ratio > LIMIT || fd.a_ratio > LIMIT)
		print_error("records: v %.4f (at %zu) a %.4f (at %zu) of the limits\n",
			    fd.v_ratio, fd.v_at, fd.a_ratio, fd.a_at);
	assert_true(fd.v_ratio <= LIMIT);
	assert_true(fd.a_ratio <= LIMIT);
	memset(&ff, 0, sizeof(ff));
	ff.c = c;
	ff.h = c->period_s / c->fine_steps;
	fine_path(r, c->fine_steps, fine_fd_fn, &ff);
	if (ff.v_ratio > LIMIT || ff.a_ratio > LIMIT)
		print_error("fine: v %.4f a %.4f of the limits\n",
			    ff.v_ratio, ff.a_ratio);
	assert_true(ff.v_ratio <= LIMIT);
	assert_true(ff.a_ratio <= LIMIT);
}

static void assert_end(const struct rec *r, const double e[4])
{
	unsigned int ax;

	assert_true(r->n > 0);
	assert_true(r->flags[r->n - 1] & SH2000_PATH_F_END);
	for (ax = 0; ax < 4; ax++)
		assert_true(r->x[r->n - 1][ax] == e[ax]);
}

/* ---- lines, corners, profiles ------------------------------------------ */

static const double zig[][4] = {
	{ 10, 0, 0, 0 }, { 10, 10, 0, 0 }, { 12, 11, 1, 0.5 },
	{ 30, 11, 1, 0.5 }, { 30.2, 11.1, 1, 0.5 }, { 30.3, 11.3, 1, 0.5 },
	{ 0, 0, 0, 0 },
};

static void run_zigzag(int raw, int trap)
{
	struct sh2000_path_config c = cfg_of(raw, trap);
	struct rec r;
	struct sh2000_path *p = mk(&c, &r);
	unsigned int i;

	for (i = 0; i < sizeof(zig) / sizeof(zig[0]); i++)
		assert_int_equal(sh2000_path_line(p, zig[i], 400), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, zig[6]);
	sh2000_path_destroy(p);
	rec_free(&r);
}

static void test_lines_scurve_comp(void **s) { (void)s; run_zigzag(0, 0); }
static void test_lines_scurve_raw(void **s) { (void)s; run_zigzag(1, 0); }
static void test_lines_trap_comp(void **s) { (void)s; run_zigzag(0, 1); }
static void test_lines_trap_raw(void **s) { (void)s; run_zigzag(1, 1); }

/* The path of a line program stays on the polyline (corners within the
 * corner tolerance) after the card's fine interpolation. */
struct poly_dev {
	const double (*v)[4];
	unsigned int n;
	double start[4];
	double max;
};

static void poly_fn(void *ctx, const double x[4])
{
	struct poly_dev *d = ctx;
	double m = dist_seg(x, d->start, d->v[0]);
	unsigned int i;

	for (i = 1; i < d->n; i++)
		m = fmin(m, dist_seg(x, d->v[i - 1], d->v[i]));
	d->max = fmax(d->max, m);
}

static void test_corner_tolerance(void **s)
{
	int raw;

	(void)s;
	for (raw = 0; raw <= 1; raw++) {
		struct sh2000_path_config c = cfg_of(raw, 0);
		struct rec r;
		struct sh2000_path *p = mk(&c, &r);
		struct poly_dev d = { zig, 7, { 0 }, 0 };
		unsigned int i;

		for (i = 0; i < 7; i++)
			assert_int_equal(sh2000_path_line(p, zig[i], 400), 0);
		assert_int_equal(sh2000_path_finish(p), 0);
		fine_path(&r, c.fine_steps, poly_fn, &d);
		if (d.max > c.corner_tol)
			print_error("%s: %.5f mm off the polyline\n",
				    raw ? "raw" : "comp", d.max);
		assert_true(d.max <= c.corner_tol);
		sh2000_path_destroy(p);
		rec_free(&r);
	}
}

/* Short point-to-point moves never reach cruise, still end exactly. */
static void test_short_moves(void **s)
{
	static const double lens[] = { 1e-4, 0.003, 0.05, 0.4, 2.0, 50.0 };
	int trap;

	(void)s;
	for (trap = 0; trap <= 1; trap++) {
		unsigned int i;

		for (i = 0; i < sizeof(lens) / sizeof(lens[0]); i++) {
			struct sh2000_path_config c = cfg_of(0, trap);
			struct rec r;
			struct sh2000_path *p = mk(&c, &r);
			double e[4] = { lens[i], 0, 0, 0 };
			struct fd_result fd;

			assert_int_equal(sh2000_path_move_abs(p, e, 300), 0);
			assert_int_equal(sh2000_path_finish(p), 0);
			check_limits(&r, &c);
			assert_end(&r, e);
			fd = fd_check(&r, &c);
			/* a move too short for cruise stays below the feed */
			if (lens[i] < 0.5)
				assert_true(fd.vmax_seen < 250);
			else if (lens[i] > 10)
				assert_true(fd.vmax_seen > 290);
			sh2000_path_destroy(p);
			rec_free(&r);
		}
	}
}

static void test_p2p_rel_jog(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct rec r;
	struct sh2000_path *p = mk(&c, &r);
	double d[4] = { 1, -2, 3, 0.5 }, e[4], pos[4];
	struct sh2000_path_stats st;

	(void)s;
	assert_int_equal(sh2000_path_move_rel(p, d, 0), 0);
	assert_int_equal(sh2000_path_move_rel(p, d, 100), 0);
	assert_int_equal(sh2000_path_jog(p, 2, -50, 4), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	e[0] = 2;
	e[1] = -4;
	e[2] = 2;
	e[3] = 1;
	assert_end(&r, e);
	sh2000_path_end_position(p, pos);
	assert_memory_equal(pos, e, sizeof(e));
	/* each point-to-point move stops: three motions would be 1 END each
	 * only if the planner ran dry; finish runs them as one motion with
	 * exact stops, so the speed must touch 0 between them */
	check_limits(&r, &c);
	sh2000_path_stats(p, &st);
	assert_int_equal(st.motions, 1);
	assert_int_equal(sh2000_path_jog(p, 4, 1, 1), -EINVAL);
	assert_int_equal(sh2000_path_jog(p, 0, 0, 1), -EINVAL);
	sh2000_path_destroy(p);
	rec_free(&r);
}

/* ---- arcs --------------------------------------------------------------- */

struct circ_dev {
	unsigned int i, j;
	double c[2], R;
	double lin_from, lin_to;	/* region to measure: plane angle */
	double max;
	int only_arc;
	double zlo, zhi;
	unsigned int zax;
};

static void circ_fn(void *ctx, const double x[4])
{
	struct circ_dev *d = ctx;
	double r = hypot(x[d->i] - d->c[0], x[d->j] - d->c[1]);

	d->max = fmax(d->max, fabs(r - d->R));
}

static void arc_case(int raw, unsigned int plane, int ccw, double R,
		     double tol)
{
	struct sh2000_path_config c = cfg_of(raw, 0);
	struct rec r;
	struct sh2000_path *p;
	struct sh2000_path_arc a;
	struct circ_dev d;
	unsigned int i, j, n;

	/* plane 0, 1, 2: G17, G18, G19 (first, second axis as geometry.h) */
	assert_int_equal(sh2000_plane_axes(SH2000_PLANE_XY + plane, &i, &j, &n), 0);
	c.start[i] = R;
	p = mk(&c, &r);
	memset(&a, 0, sizeof(a));
	a.plane = SH2000_PLANE_XY + plane;
	memcpy(a.end, c.start, sizeof(a.end));
	a.ccw = ccw;
	a.centre[0] = 0;
	a.centre[1] = 0;
	assert_int_equal(sh2000_path_arc(p, &a, 300), 0);	/* full circle */
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, c.start);
	/* ccw: from the plane's first axis towards its second */
	{
		size_t k = 0;

		while (k < r.n && fabs(r.x[k][j]) < 1e-3)
			k++;
		assert_true(k < r.n);
		assert_true(ccw ? r.x[k][j] > 0 : r.x[k][j] < 0);
	}
	memset(&d, 0, sizeof(d));
	d.i = i;
	d.j = j;
	d.R = R;
	fine_path(&r, c.fine_steps, circ_fn, &d);
	if (d.max > tol)
		print_error("arc plane %u %s R %.1f: %.6f mm off\n", plane,
			    raw ? "raw" : "comp", R, d.max);
	assert_true(d.max <= tol);
	sh2000_path_destroy(p);
	rec_free(&r);
}

static void test_arc_circle_compensated(void **s)
{
	unsigned int pl;

	(void)s;
	for (pl = 0; pl < 3; pl++) {
		arc_case(0, pl, 1, 5.0, 0.0005);
		arc_case(0, pl, 0, 5.0, 0.0005);
	}
	arc_case(0, 0, 1, 0.5, 0.0005);
	arc_case(0, 0, 1, 50.0, 0.0005);
}

static void test_arc_circle_raw_cuts_inward(void **s)
{
	(void)s;
	/* raw: about (vT)^2 / 6R inward, within chord_tol */
	arc_case(1, 0, 1, 5.0, 0.02);
}

static void test_arc_forms_and_helix(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct rec r;
	struct sh2000_path *p;
	struct sh2000_path_arc a;
	double e[4];

	(void)s;
	p = mk(&c, &r);
	memset(&a, 0, sizeof(a));
	/* radius form, short ccw arc of 90 degrees: (0,0) -> (5,5), R 5 */
	a.plane = SH2000_PLANE_XY;
	a.radius_form = 1;
	a.radius = 5;
	a.ccw = 0;
	a.end[0] = 5;
	a.end[1] = 5;
	assert_int_equal(sh2000_path_arc(p, &a, 200), 0);
	/* long arc with a negative radius back to (0, 0)... of 270 deg */
	a.radius = -5;
	a.ccw = 1;
	a.end[0] = 10;
	a.end[1] = 0;
	assert_int_equal(sh2000_path_arc(p, &a, 200), 0);
	/* helix: two turns in XY around (5,0) rising 4 mm in Z, A along */
	memset(&a, 0, sizeof(a));
	a.plane = SH2000_PLANE_XY;
	a.centre[0] = 5;
	a.centre[1] = 0;
	a.ccw = 1;
	a.turns = 2;
	a.end[0] = 10;
	a.end[1] = 0;
	a.end[2] = 4;
	a.end[3] = 2;
	assert_int_equal(sh2000_path_arc(p, &a, 250), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	memcpy(e, a.end, sizeof(e));
	assert_end(&r, e);
	sh2000_path_destroy(p);
	rec_free(&r);
}

/* Radius form: the four choices of direction and sign pick the four
 * centres, and the path is on that circle. */
static void test_arc_radius_form(void **s)
{
	static const struct { int ccw; double r, cx, cy; } k[4] = {
		{ 0, 5, 5, 0 }, { 1, 5, 0, 5 }, { 0, -5, 0, 5 }, { 1, -5, 5, 0 },
	};
	unsigned int i;

	(void)s;
	for (i = 0; i < 4; i++) {
		struct sh2000_path_config c = cfg_of(0, 0);
		struct rec r;
		struct sh2000_path *p = mk(&c, &r);
		struct sh2000_path_arc a;
		struct circ_dev d;

		memset(&a, 0, sizeof(a));
		a.plane = SH2000_PLANE_XY;
		a.radius_form = 1;
		a.radius = k[i].r;
		a.ccw = k[i].ccw;
		a.end[0] = 5;
		a.end[1] = 5;
		assert_int_equal(sh2000_path_arc(p, &a, 200), 0);
		assert_int_equal(sh2000_path_finish(p), 0);
		check_limits(&r, &c);
		assert_end(&r, a.end);
		memset(&d, 0, sizeof(d));
		d.c[0] = k[i].cx;
		d.c[1] = k[i].cy;
		d.R = 5;
		d.i = 0;
		d.j = 1;
		fine_path(&r, c.fine_steps, circ_fn, &d);
		if (d.max > 0.0005)
			print_error("radius form %u: %.5f mm off\n", i, d.max);
		assert_true(d.max <= 0.0005);
		sh2000_path_destroy(p);
		rec_free(&r);
	}
}

/* ---- NURBS ------------------------------------------------------------- */

/* The exact circle of radius 5 around the origin as a rational quadratic
 * NURBS (9 control points, 4 double interior knots). */
static const double circ_ctrl[9][4] = {
	{ 5, 0, 0, 0 }, { 5, 5, 0, 0 }, { 0, 5, 0, 0 }, { -5, 5, 0, 0 },
	{ -5, 0, 0, 0 }, { -5, -5, 0, 0 }, { 0, -5, 0, 0 }, { 5, -5, 0, 0 },
	{ 5, 0, 0, 0 },
};
static const double circ_w[9] = { 1, M_SQRT1_2, 1, M_SQRT1_2, 1, M_SQRT1_2,
				  1, M_SQRT1_2, 1 };
static const double circ_k[12] = { 0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75,
				   0.75, 1, 1, 1 };

static void nurbs_circle(int raw, double tol)
{
	struct sh2000_path_config c = cfg_of(raw, 0);
	struct sh2000_nurbs n = { 2, 9, circ_ctrl, circ_w, circ_k };
	struct rec r;
	struct sh2000_path *p;
	struct circ_dev d;
	struct sh2000_path_stats st;

	c.start[0] = 5;
	p = mk(&c, &r);
	assert_int_equal(sh2000_path_nurbs(p, &n, 300), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, c.start);
	memset(&d, 0, sizeof(d));
	d.R = 5;
	d.i = 0;
	d.j = 1;
	fine_path(&r, c.fine_steps, circ_fn, &d);
	if (d.max > tol)
		print_error("nurbs circle %s: %.6f mm off\n",
			    raw ? "raw" : "comp", d.max);
	assert_true(d.max <= tol);
	sh2000_path_stats(p, &st);
	print_message("nurbs circle %s: %.6f mm, %llu steps, chord error %.6f mm, feed fluctuation %.2g\n",
		      raw ? "raw" : "comp", d.max,
		      (unsigned long long)st.nurbs_steps, st.nurbs_chord_error,
		      st.nurbs_feed_fluctuation);
	assert_true(st.nurbs_steps > 40);
	assert_true(st.nurbs_chord_error <= c.chord_tol);
	assert_true(st.nurbs_feed_fluctuation < 1e-6);
	sh2000_path_destroy(p);
	rec_free(&r);
}

static void test_nurbs_circle(void **s)
{
	(void)s;
	nurbs_circle(0, 0.0005);
	nurbs_circle(1, 0.02);
}

/* A free-form cubic: the fine path against a dense sampling of the curve. */
static const double ff_ctrl[8][4] = {
	{ 0, 0, 0, 0 }, { 5, 10, 0, 0 }, { 10, -5, 1, 0 }, { 15, 8, 2, 0 },
	{ 20, 0, 2, 0 }, { 22, 12, 1, 0 }, { 30, 5, 0, 0 }, { 32, 0, 0, 0 },
};
static const double ff_w[8] = { 1, 2, 0.5, 1, 3, 1, 1, 1 };
static const double ff_k[12] = { 0, 0, 0, 0, 0.2, 0.4, 0.5, 0.8, 1, 1, 1, 1 };

struct curve_dev {
	double (*pts)[4];
	size_t n;
	double max;
	size_t hint;
};

static void curve_fn(void *ctx, const double x[4])
{
	struct curve_dev *d = ctx;
	double m = INFINITY;
	size_t i, lo = d->hint > 400 ? d->hint - 400 : 0;
	size_t hi = d->hint + 400 < d->n ? d->hint + 400 : d->n;

	for (i = lo + 1; i < hi; i++) {
		double dd = dist_seg(x, d->pts[i - 1], d->pts[i]);

		if (dd < m) {
			m = dd;
			d->hint = i;
		}
	}
	d->max = fmax(d->max, m);
}

static int dense_sink(void *ctx, const struct sh2000_path_point *pt)
{
	return rec_sink(ctx, pt);
}

static void test_nurbs_freeform(void **s)
{
	struct sh2000_nurbs n = { 3, 8, ff_ctrl, ff_w, ff_k };
	struct sh2000_path_config c = cfg_of(0, 0), cd;
	struct rec r, dense;
	struct sh2000_path *p, *pd;
	struct curve_dev d;

	(void)s;
	p = mk(&c, &r);
	assert_int_equal(sh2000_path_nurbs(p, &n, 300), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, ff_ctrl[7]);
	/* the exact curve, densely: the same planner, raw, tiny period */
	cd = cfg_of(1, 0);
	cd.period_s = 1e-4;
	cd.chord_tol = 1e-7;
	rec_init(&dense, cd.start);
	assert_int_equal(sh2000_path_create(&pd, &cd, dense_sink, &dense,
					    NULL, 0), 0);
	assert_int_equal(sh2000_path_nurbs(pd, &n, 20), 0);
	assert_int_equal(sh2000_path_finish(pd), 0);
	memset(&d, 0, sizeof(d));
	d.pts = dense.x;
	d.n = dense.n;
	fine_path(&r, c.fine_steps, curve_fn, &d);
	if (d.max > 0.001)
		print_error("free-form: %.6f mm off\n", d.max);
	assert_true(d.max <= 0.001);
	sh2000_path_destroy(p);
	sh2000_path_destroy(pd);
	rec_free(&r);
	rec_free(&dense);
}

/* A cusp inside a knot span: the derivative passes through zero and the
 * curve turns back. Found by fuzz_plan: the planner went through at full
 * speed (steps of 2.7 mm in one period, the arc length's Newton thrown
 * off by |C'| = 0), then, once it stopped there, stayed at rest for ever.
 * It must stop at the cusp, reverse within the limits and finish. */
struct closest {
	const double *to;
	double d;
};

static void closest_fn(void *ctx, const double x[4])
{
	struct closest *c = ctx;
	double d = 0.0;

	for (unsigned int ax = 0; ax < 4; ax++)
		d += (x[ax] - c->to[ax]) * (x[ax] - c->to[ax]);
	c->d = fmin(c->d, sqrt(d));
}

static void cusp_case(const struct sh2000_nurbs *n, const double start[4],
		      const double cusp[4], const double end[4], int raw)
{
	struct sh2000_path_config c = cfg_of(raw, 0);
	struct closest cl = { cusp, INFINITY };
	struct sh2000_path *p;
	struct rec r;

	memcpy(c.start, start, sizeof(c.start));
	p = mk(&c, &r);
	if (sh2000_path_nurbs(p, n, 62))
		fail_msg("%s", sh2000_path_error(p));
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, end);
	/* the card's fine path gets there */
	fine_path(&r, c.fine_steps, closest_fn, &cl);
	print_message("cusp at (%g, %g), %s: %zu records, the card's path within %.3g mm of it\n",
		      cusp[0], cusp[1], raw ? "raw" : "compensated", r.n, cl.d);
	assert_true(cl.d < 0.001);
	assert_true(r.n < 200);		/* 0.4 s at most: no creeping */
	sh2000_path_destroy(p);
	rec_free(&r);
}

static void test_nurbs_cusp(void **s)
{
	/* rational, on one axis: x goes 2 -> 1.4404 -> 3 (fuzz_plan's
	 * input, tests/fuzz/corpus/plan/J-cusp.json) */
	static const double pts1[3][4] = { { 2, 0 }, { 1, 0 }, { 3, 0 } };
	static const double w1[3] = { 2, 3, 1 };
	static const double k1[6] = { 0, 0, 0, 1, 1, 1 };
	static const double s1[4] = { 2, 0 }, c1[4] = { 1.44039465, 0 },
			    e1[4] = { 3, 0 };
	/* the planar cubic with a cusp at its middle: B'(1/2) = 0 */
	static const double pts2[4][4] = { { 0, 0 }, { 1, 1 }, { 0, 1 },
					   { 1, 0 } };
	static const double k2[8] = { 0, 0, 0, 0, 1, 1, 1, 1 };
	static const double s2[4] = { 0, 0 }, c2[4] = { 0.5, 0.75 },
			    e2[4] = { 1, 0 };
	struct sh2000_nurbs n1 = { 2, 3, pts1, w1, k1 };
	struct sh2000_nurbs n2 = { 3, 4, pts2, NULL, k2 };

	/* standing still over a whole span is refused, with where */
	static const double pts3[4][4] = { { 0, 0 }, { 0, 0 }, { 0, 0 },
					   { 1, 0 } };
	static const double k3[7] = { 0, 0, 0, 0.5, 1, 1, 1 };
	struct sh2000_nurbs n3 = { 2, 4, pts3, NULL, k3 };
	struct sh2000_path_config c = cfg_of(0, 0);
	struct sh2000_path *p;
	struct rec r;

	(void)s;
	for (int raw = 0; raw <= 1; raw++) {
		cusp_case(&n1, s1, c1, e1, raw);
		cusp_case(&n2, s2, c2, e2, raw);
	}
	p = mk(&c, &r);
	assert_int_equal(sh2000_path_nurbs(p, &n3, 62), -EINVAL);
	assert_non_null(strstr(sh2000_path_error(p), "stands still"));
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_int_equal(r.n, 0);
	sh2000_path_destroy(p);
	rec_free(&r);
}

/* A heavy weight on the last point crowds a tight turn into a thousandth
 * of a knot span. Found by fuzz_plan: the turn's low speed limit held a
 * whole 4 mm block back, 5 s at 0.7 mm/s for a 70 mm/s program. The
 * expansion halves blocks whose limit varies a lot. */
static void test_nurbs_heavy_weight(void **s)
{
	static const double pts[4][4] = { { 2, 0 }, { 1, 0 }, { 1, 1, 0, 8 },
					  { 2, 1 } };
	static const double w[4] = { 1, 3, 5, 4444 };
	static const double k[7] = { 0, 0, 0, 1, 2, 2, 2 };
	static const double start[4] = { 2, 0 }, end[4] = { 2, 1 };
	struct sh2000_nurbs n = { 2, 4, pts, w, k };
	struct sh2000_path_config c = cfg_of(0, 0);
	struct sh2000_path *p;
	struct rec r;
	double L = 0.0;

	(void)s;
	memcpy(c.start, start, sizeof(c.start));
	p = mk(&c, &r);
	assert_int_equal(sh2000_path_nurbs(p, &n, 70), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, end);
	for (size_t i = 1; i < r.n; i++) {
		double d = 0.0;

		for (unsigned int ax = 0; ax < 4; ax++)
			d += (r.x[i][ax] - r.x[i - 1][ax]) *
			     (r.x[i][ax] - r.x[i - 1][ax]);
		L += sqrt(d);
	}
	print_message("heavy weight: %.3f mm in %zu records (%.1f mm/s on average)\n",
		      L, r.n, L / (r.n * c.period_s));
	/* 10.6 mm at up to 70 mm/s: well under a second, not seconds */
	assert_true(L > 10.0);
	assert_true(r.n * c.period_s < 1.0);
	sh2000_path_destroy(p);
	rec_free(&r);
}

/* Degree 1 (a polyline with corners) and degree 5; a pause in the middle
 * of a NURBS resumes on the curve. */
static void test_nurbs_degrees_and_pause(void **s)
{
	static const double poly[5][4] = {
		{ 0, 0, 0, 0 }, { 4, 0, 0, 0 }, { 4, 3, 0, 0 }, { 8, 3, 1, 0 },
		{ 8, 8, 1, 0 },
	};
	static const double k1[7] = { 0, 0, 1, 2, 3, 4, 4 };
	static const double k5[14] = { 0, 0, 0, 0, 0, 0, 0.3, 0.7,
					1, 1, 1, 1, 1, 1 };
	struct sh2000_nurbs n1 = { 1, 5, poly, NULL, k1 };
	struct sh2000_nurbs n5 = { 5, 8, ff_ctrl, NULL, k5 };
	struct sh2000_path_config c = cfg_of(0, 0);
	struct sh2000_nurbs nc = { 2, 9, circ_ctrl, circ_w, circ_k };
	struct rec r;
	struct sh2000_path *p;
	struct poly_dev d = { poly + 1, 4, { 0 }, 0 };
	struct circ_dev cd;

	(void)s;
	p = mk(&c, &r);
	assert_int_equal(sh2000_path_nurbs(p, &n1, 300), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, poly[4]);
	fine_path(&r, c.fine_steps, poly_fn, &d);
	assert_true(d.max <= c.corner_tol);
	sh2000_path_destroy(p);
	rec_free(&r);

	p = mk(&c, &r);
	assert_int_equal(sh2000_path_nurbs(p, &n5, 300), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, ff_ctrl[7]);
	sh2000_path_destroy(p);
	rec_free(&r);

	c.start[0] = 5;
	p = mk(&c, &r);
	assert_int_equal(sh2000_path_nurbs(p, &nc, 300), 0);
	assert_int_equal(sh2000_path_run(p, 30), 30);
	assert_int_equal(sh2000_path_pause(p), 0);
	assert_true(sh2000_path_run(p, 1000) > 0);
	assert_true(r.flags[r.n - 1] & SH2000_PATH_F_END);
	assert_int_equal(sh2000_path_resume(p), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	check_limits(&r, &c);
	assert_end(&r, c.start);
	memset(&cd, 0, sizeof(cd));
	cd.R = 5;
	cd.j = 1;
	fine_path(&r, c.fine_steps, circ_fn, &cd);
	assert_true(cd.max <= 0.0005);
	sh2000_path_destroy(p);
	rec_free(&r);
}

/* Random programs (fixed seeds): lines, arcs, NURBS and point-to-point
 * moves with override changes, pauses and resumes in between, both
 * profiles and both outputs: every record and fine point within the
 * limits, every motion ending where the program says. */
static unsigned int rnd(unsigned int *st)
{
	*st = *st * 1103515245u + 12345u;
	return (*st >> 8) & 0xffffff;
}

static double frnd(unsigned int *st, double lo, double hi)
{
	return lo + (hi - lo) * rnd(st) / 16777216.0;
}

static void test_random_programs(void **s)
{
	unsigned int seed;

	(void)s;
	for (seed = 1; seed <= 8; seed++) {
		struct sh2000_path_config c = cfg_of(seed & 1, (seed >> 1) & 1);
		unsigned int st = seed * 7919u, i;
		struct rec r;
		struct sh2000_path *p = mk(&c, &r);
		double pos[4], e[4];

		for (i = 0; i < 60; i++) {
			unsigned int k = rnd(&st) % 6, a;
			double feed = frnd(&st, 5, 450);

			sh2000_path_end_position(p, pos);
			for (a = 0; a < 4; a++)
				e[a] = pos[a] + frnd(&st, -3, 3) *
					(rnd(&st) % 3 ? 1 : 0.01);
			if (k <= 1) {
				assert_int_equal(sh2000_path_line(p, e, feed), 0);
			} else if (k == 2) {
				struct sh2000_path_arc arc;
				double R = frnd(&st, 0.2, 8), th = frnd(&st, 0, 6.28);
				enum sh2000_plane pl = SH2000_PLANE_XY + rnd(&st) % 3;
				unsigned int ii, jj, nn;

				sh2000_plane_axes(pl, &ii, &jj, &nn);
				memset(&arc, 0, sizeof(arc));
				arc.plane = pl;
				arc.ccw = rnd(&st) & 1;
				arc.centre[0] = pos[ii] - R * cos(th);
				arc.centre[1] = pos[jj] - R * sin(th);
				memcpy(arc.end, e, sizeof(arc.end));
				th += frnd(&st, -4, 4);
				arc.end[ii] = arc.centre[0] + R * cos(th);
				arc.end[jj] = arc.centre[1] + R * sin(th);
				assert_int_equal(sh2000_path_arc(p, &arc, feed), 0);
			} else if (k == 3) {
				double ctrl[6][4];
				static const double kn[10] = { 0, 0, 0, 0, 0.3,
							       0.6, 1, 1, 1, 1 };
				struct sh2000_nurbs n = { 3, 6,
					(const double (*)[4])ctrl, NULL, kn };
				unsigned int j;

				memcpy(ctrl[0], pos, sizeof(pos));
				for (j = 1; j < 6; j++)
					for (a = 0; a < 4; a++)
						ctrl[j][a] = ctrl[j - 1][a] +
							     frnd(&st, -4, 4) *
							     (a < 3 ? 1 : 0.1);
				assert_int_equal(sh2000_path_nurbs(p, &n, feed), 0);
			} else if (k == 4) {
				assert_int_equal(sh2000_path_move_abs(p, e,
					rnd(&st) & 1 ? 0 : feed), 0);
			} else {
				assert_int_equal(sh2000_path_set_override(p,
					frnd(&st, 0.1, 2.0)), 0);
				assert_true(sh2000_path_run(p, rnd(&st) % 40) >= 0);
				if (rnd(&st) % 3 == 0) {
					assert_int_equal(sh2000_path_pause(p), 0);
					assert_true(sh2000_path_run(p, rnd(&st) % 400) >= 0);
					assert_int_equal(sh2000_path_resume(p), 0);
				}
			}
		}
		assert_int_equal(sh2000_path_finish(p), 0);
		sh2000_path_end_position(p, e);
		check_limits(&r, &c);
		assert_end(&r, e);
		sh2000_path_destroy(p);
		rec_free(&r);
	}
}

/* ---- bad input --------------------------------------------------------- */

static void expect_err(struct sh2000_path *p, int ret, int code,
		       const char *needle)
{
	if (ret != code || !strstr(sh2000_path_error(p), needle))
		print_error("got %d '%s', wanted %d '%s'\n", ret,
			    sh2000_path_error(p), code, needle);
	assert_int_equal(ret, code);
	assert_non_null(strstr(sh2000_path_error(p), needle));
}

static void test_bad_geometry(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct rec r;
	struct sh2000_path *p = mk(&c, &r);
	struct sh2000_path_arc a;
	struct sh2000_nurbs n = { 2, 9, circ_ctrl, circ_w, circ_k };
	double bad_k[12], bad_w[9], e[4] = { 1, 2, 3, 0 };
	double nan_pt[4] = { 1, NAN, 0, 0 };

	(void)s;
	memset(&a, 0, sizeof(a));
	a.plane = SH2000_PLANE_XY;
	a.centre[0] = 5;
	a.end[0] = 10.2;	/* start radius 5, end radius 5.2 */
	a.ccw = 1;
	expect_err(p, sh2000_path_arc(p, &a, 100), -EINVAL,
		   "arc: radius to end of arc differs from radius to start: start=(X0.0000,Y0.0000) centre=(X5.0000,Y0.0000) end=(X10.2000,Y0.0000) r1=5.0000 r2=5.2000 mm");
	a.end[0] = 10;
	a.centre[1] = NAN;
	expect_err(p, sh2000_path_arc(p, &a, 100), -EINVAL, "arc: centre is NaN");
	a.centre[1] = 0;
	expect_err(p, sh2000_path_arc(p, &a, 0), -EINVAL,
		   "feed must be > 0: got 0");
	a.radius_form = 1;
	a.radius = 1;
	expect_err(p, sh2000_path_arc(p, &a, 10), -EINVAL,
		   "arc: arc radius 1.0000 mm too small to reach the end point (half chord 5.0000 mm)");
	expect_err(p, sh2000_path_line(p, nan_pt, 100), -EINVAL,
		   "line: end Y is NaN");
	expect_err(p, sh2000_path_line(p, e, -10), -EINVAL,
		   "feed must be > 0: got -10");
	expect_err(p, sh2000_path_line(p, e, NAN), -EINVAL,
		   "feed must be > 0: got nan");
	expect_err(p, sh2000_path_move_abs(p, e, -1), -EINVAL,
		   "speed must be >= 0: got -1");
	/* NURBS: unsorted knots, bad weights, degree, start point */
	memcpy(bad_k, circ_k, sizeof(bad_k));
	bad_k[4] = 0.3;
	bad_k[3] = 0.5;
	n.knots = bad_k;
	expect_err(p, sh2000_path_nurbs(p, &n, 100), -EINVAL,
		   "nurbs: knots[4]: 0.3 is less than knots[3] = 0.5");
	n.knots = circ_k;
	memcpy(bad_w, circ_w, sizeof(bad_w));
	bad_w[3] = 0;
	n.weights = bad_w;
	expect_err(p, sh2000_path_nurbs(p, &n, 100), -EINVAL,
		   "nurbs: weights[3]: 0 is not a positive finite weight");
	n.weights = circ_w;
	n.degree = 0;
	expect_err(p, sh2000_path_nurbs(p, &n, 100), -EINVAL,
		   "nurbs: degree: 0 is outside 1..31");
	n.degree = 2;
	n.npoints = 2;
	expect_err(p, sh2000_path_nurbs(p, &n, 100), -EINVAL,
		   "nurbs: points: 2 control points, a degree 2 curve needs at least 3");
	n.npoints = 9;
	/* the circle starts at (5, 0), the planner is at the origin */
	expect_err(p, sh2000_path_nurbs(p, &n, 100), -EINVAL,
		   "nurbs: the curve starts at (5.0000, 0.0000, 0.0000, 0.0000), 5.0000 mm from the current position");
	/* nothing of any of it was queued or emitted */
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_int_equal(r.n, 0);
	/* and the planner still works */
	assert_int_equal(sh2000_path_line(p, e, 100), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_end(&r, e);
	{
		struct sh2000_path_stats st;

		sh2000_path_stats(p, &st);
		assert_int_equal(st.mem_bytes, st.mem_peak > 0 ? st.mem_bytes : 0);
	}
	sh2000_path_destroy(p);
	rec_free(&r);
}

static void test_bad_config(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct sh2000_path *p;
	struct rec r;
	char e[256];

	(void)s;
	rec_init(&r, c.start);
	c.vmax[2] = -1;
	assert_int_equal(sh2000_path_create(&p, &c, rec_sink, &r, e, sizeof(e)),
			 -EINVAL);
	assert_non_null(strstr(e, "vmax of axis Z must be > 0: got -1"));
	assert_null(p);
	c = cfg_of(0, 0);
	c.jerk = 0;
	assert_int_equal(sh2000_path_create(&p, &c, rec_sink, &r, e, sizeof(e)),
			 -EINVAL);
	assert_non_null(strstr(e, "jerk"));
}

/* ---- streaming and memory --------------------------------------------- */

struct count_sink {
	uint64_t n, ends;
	double last[4], prev[4], prev2[4];
	double amax, vmax;
	double T;
};

static int count_fn(void *ctx, const struct sh2000_path_point *pt)
{
	struct count_sink *c = ctx;
	unsigned int ax;

	for (ax = 0; ax < 4; ax++) {
		double v = fabs(pt->mm[ax] - c->last[ax]) / c->T;
		double a = fabs(pt->mm[ax] - 2 * c->last[ax] + c->prev[ax]) /
			   (c->T * c->T);

		c->vmax = fmax(c->vmax, v);
		if (c->n >= 1)
			c->amax = fmax(c->amax, a);
	}
	memcpy(c->prev, c->last, sizeof(c->last));
	memcpy(c->last, pt->mm, sizeof(c->last));
	c->n++;
	if (pt->flags & SH2000_PATH_F_END)
		c->ends++;
	return 0;
}

static void test_constant_memory(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct count_sink cs;
	struct sh2000_path *p;
	struct sh2000_path_stats st;
	size_t peak_early = 0;
	unsigned int i, N = 1000000;

	(void)s;
	memset(&cs, 0, sizeof(cs));
	cs.T = c.period_s;
	assert_int_equal(sh2000_path_create(&p, &c, count_fn, &cs, NULL, 0), 0);
	for (i = 0; i < N; i++) {
		/* a gentle zig-zag of 0.2 mm steps */
		double e[4] = { 0.2 * (i + 1), (i & 1) ? 0.01 : 0.0, 0, 0 };

		assert_int_equal(sh2000_path_line(p, e, 200), 0);
		if (i == 999) {
			sh2000_path_stats(p, &st);
			peak_early = st.mem_peak;
		}
	}
	assert_int_equal(sh2000_path_finish(p), 0);
	sh2000_path_stats(p, &st);
	print_message("1e6 segments: %llu points, peak %zu bytes (after 1000: %zu)\n",
		      (unsigned long long)cs.n, st.mem_peak, peak_early);
	assert_int_equal(st.mem_peak, peak_early);
	assert_int_equal(cs.ends, 1);
	assert_true(cs.last[0] == 0.2 * N);
	assert_true(cs.vmax <= c.vmax[0]);
	assert_true(cs.amax <= c.amax[1]);
	sh2000_path_destroy(p);
}

static void test_nurbs_memory_released(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct sh2000_nurbs n = { 2, 9, circ_ctrl, circ_w, circ_k };
	struct count_sink cs;
	struct sh2000_path *p;
	struct sh2000_path_stats st0, st;
	unsigned int i;

	(void)s;
	memset(&cs, 0, sizeof(cs));
	cs.T = c.period_s;
	c.start[0] = 5;
	c.window = 32;	/* smaller than one circle's blocks */
	assert_int_equal(sh2000_path_create(&p, &c, count_fn, &cs, NULL, 0), 0);
	sh2000_path_stats(p, &st0);
	for (i = 0; i < 50; i++)
		assert_int_equal(sh2000_path_nurbs(p, &n, 300), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	sh2000_path_stats(p, &st);
	assert_int_equal(st.mem_bytes, st0.mem_bytes);
	/* at most two curves alive at a time */
	assert_true(st.mem_peak < st0.mem_bytes + 2 * 2048);
	sh2000_path_destroy(p);
}

/* ---- override, pause, resume, stop ---------------------------------------- */

struct mono {
	double last, back;
};

static void mono_fn(void *ctx, const double x[4])
{
	struct mono *m = ctx;

	m->back = fmax(m->back, m->last - x[0]);
	m->last = fmax(m->last, x[0]);
}

static void test_override_pause_resume(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct rec r;
	struct sh2000_path *p = mk(&c, &r);
	double e[4] = { 100, 0, 0, 0 }, v;
	size_t n0, i;
	struct sh2000_path_stats st;

	(void)s;
	assert_int_equal(sh2000_path_line(p, e, 300), 0);
	assert_int_equal(sh2000_path_run(p, 60), 60);
	assert_int_equal(sh2000_path_set_override(p, 0.5), 0);
	assert_int_equal(sh2000_path_run(p, 60), 60);
	n0 = r.n;
	v = (r.x[n0 - 1][0] - r.x[n0 - 2][0]) / c.period_s;
	assert_true(fabs(v - 150) < 0.5);
	assert_int_equal(sh2000_path_set_override(p, 0), -EINVAL);
	assert_int_equal(sh2000_path_set_override(p, 1.0), 0);
	assert_int_equal(sh2000_path_run(p, 30), 30);
	/* pause: decelerate to rest, END, no more points */
	assert_int_equal(sh2000_path_pause(p), 0);
	assert_true(sh2000_path_run(p, 1000) > 0);
	assert_true(r.flags[r.n - 1] & SH2000_PATH_F_END);
	assert_true(r.x[r.n - 1][0] < 100);
	n0 = r.n;
	assert_int_equal(sh2000_path_run(p, 1000), 0);
	assert_int_equal(sh2000_path_finish(p), -EAGAIN);
	assert_int_equal(r.n, n0);
	sh2000_path_stats(p, &st);
	assert_int_equal(st.moving, 0);
	/* resume and finish on the end point */
	assert_int_equal(sh2000_path_resume(p), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_end(&r, e);
	check_limits(&r, &c);
	/* the card's path never runs back (by more than rounding) */
	{
		struct mono m = { -1, 0 };

		fine_path(&r, c.fine_steps, mono_fn, &m);
		/* the interpolating spline rings a little at a stop: the
		 * S-curve's last jerk step, about J T^3 / 70 (0.6 um) */
		print_message("fine path ran back at most %.3g mm\n", m.back);
		assert_true(m.back <= c.jerk * pow(c.period_s, 3) / 40);
	}
	(void)i;
	sh2000_path_destroy(p);
	rec_free(&r);
}

static void test_stop_discards(void **s)
{
	struct sh2000_path_config c = cfg_of(0, 0);
	struct rec r;
	struct sh2000_path *p = mk(&c, &r);
	double e[4] = { 100, 0, 0, 0 }, e2[4] = { 100, 50, 0, 0 }, pos[4];
	double zero[4] = { 0, 0, 0, 0 };

	(void)s;
	assert_int_equal(sh2000_path_line(p, e, 300), 0);
	assert_int_equal(sh2000_path_line(p, e2, 300), 0);
	assert_int_equal(sh2000_path_run(p, 50), 50);
	assert_int_equal(sh2000_path_stop(p), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_true(r.flags[r.n - 1] & SH2000_PATH_F_END);
	assert_true(r.x[r.n - 1][0] < 100);
	sh2000_path_end_position(p, pos);
	assert_memory_equal(pos, r.x[r.n - 1], sizeof(pos));
	check_limits(&r, &c);
	/* a new motion from there */
	assert_int_equal(sh2000_path_line(p, e, 300), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_end(&r, e);
	check_limits(&r, &c);
	/* stop while paused at rest ends the pause too */
	assert_int_equal(sh2000_path_line(p, e2, 300), 0);
	assert_int_equal(sh2000_path_run(p, 20), 20);
	assert_int_equal(sh2000_path_pause(p), 0);
	assert_true(sh2000_path_run(p, 1000) > 0);
	assert_int_equal(sh2000_path_stop(p), 0);
	assert_int_equal(sh2000_path_line(p, zero, 300), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_end(&r, zero);
	check_limits(&r, &c);
	sh2000_path_destroy(p);
	rec_free(&r);
}

static void test_sink_failure(void **s)
{
	struct sh2000_path_config c = cfg_of(1, 0);
	struct rec r;
	struct sh2000_path *p = mk(&c, &r);
	double e[4] = { 10, 0, 0, 0 }, z[4] = { 0 };

	(void)s;
	r.fail_at = 5;
	assert_int_equal(sh2000_path_line(p, e, 100), 0);
	assert_int_equal(sh2000_path_finish(p), -5);
	assert_int_equal(sh2000_path_line(p, z, 100), -5);
	assert_non_null(strstr(sh2000_path_error(p), "sink"));
	assert_int_equal(sh2000_path_reset(p, r.x[r.n - 1]), 0);
	r.fail_at = 0;
	assert_int_equal(sh2000_path_line(p, z, 100), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_end(&r, z);
	sh2000_path_destroy(p);
	rec_free(&r);
}

/* ---- the compensation filter alone --------------------------------------- */

/* Rest points split the stream: three legs from rest to rest (a corner,
 * then on along the same line), each a smooth step of 40 points. The
 * card's spline over [start x3, P..., end x3] stays on the legs to the
 * rounding, stops exactly on each rest point, never turns back, and
 * passes through every point not next to a rest. */
#define RL 40
static const double rest_pts[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 1, 2 } };

static double rest_polyline(const double x[2], double *along)
{
	double best = INFINITY, s = 0.0;
	unsigned int i;

	for (i = 0; i < 3; i++) {
		const double *a = rest_pts[i], *b = rest_pts[i + 1];
		double dx = b[0] - a[0], dy = b[1] - a[1], t, d;

		t = ((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / (dx * dx + dy * dy);
		t = fmin(fmax(t, 0.0), 1.0);
		d = hypot(x[0] - a[0] - t * dx, x[1] - a[1] - t * dy);
		if (d < best - 1e-15) {
			best = d;
			*along = s + t;
		}
		s += 1.0;
	}
	return best;
}

static void test_bscomp_rests(void **s)
{
	static double q[3 * RL][2], P[3 * RL + 40][2], seq[3 * RL + 50][2];
	struct sh2000_bscomp *bc;
	double x[2], dev = 0.0, back = 0.0, prev = 0.0, knot_err = 0.0;
	unsigned int n = 0, m = 0, i, k, leg, stops = 0;
	int last = 0;

	(void)s;
	for (leg = 0; leg < 3; leg++)
		for (i = 1; i <= RL; i++) {
			double t = (double)i / RL, u = t * t * t * (10 - 15 * t + 6 * t * t);

			for (k = 0; k < 2; k++)
				q[leg * RL + i - 1][k] = rest_pts[leg][k] +
					u * (rest_pts[leg + 1][k] - rest_pts[leg][k]);
		}
	assert_int_equal(sh2000_bscomp_create(&bc, 12, 2), 0);
	pl_bscomp_exact(bc, 1);
	sh2000_bscomp_start(bc, rest_pts[0]);
	for (i = 0; i < 3 * RL; i++)
		if (pl_bscomp_push(bc, q[i], i % RL == RL - 1, x))
			memcpy(P[n++], x, sizeof(x));
	while (sh2000_bscomp_flush(bc, x, &last))
		memcpy(P[n++], x, sizeof(x));
	sh2000_bscomp_destroy(bc);
	assert_true(last);
	for (k = 0; k < 3; k++)
		memcpy(seq[m++], rest_pts[0], sizeof(x));
	for (k = 0; k < n; k++)
		memcpy(seq[m++], P[k], sizeof(x));
	for (k = 0; k < 3; k++)
		memcpy(seq[m++], rest_pts[3], sizeof(x));
	for (k = 0; k + 3 < m; k++) {
		unsigned int f, j;

		for (f = 0; f < 20; f++) {
			double y[2], along = 0.0;

			for (j = 0; j < 2; j++)
				y[j] = sh2000_bspline(seq[k][j], seq[k + 1][j],
						      seq[k + 2][j], seq[k + 3][j],
						      f / 20.0);
			dev = fmax(dev, rest_polyline(y, &along));
			back = fmax(back, prev - along);
			prev = fmax(prev, along);
		}
	}
	/* a knot on each rest point, exactly */
	for (i = 1; i < 4; i++)
		for (k = 0; k + 2 < m; k++)
			if (hypot((seq[k][0] + 4 * seq[k + 1][0] + seq[k + 2][0]) / 6 - rest_pts[i][0],
				  (seq[k][1] + 4 * seq[k + 1][1] + seq[k + 2][1]) / 6 - rest_pts[i][1]) < 1e-12) {
				stops++;
				break;
			}
	/* every point not next to a rest on a knot */
	for (i = 0; i < 3 * RL; i++) {
		double best = INFINITY;

		if (i % RL < 1 || i % RL >= RL - 2)
			continue;
		for (k = 0; k + 2 < m; k++)
			best = fmin(best, hypot((seq[k][0] + 4 * seq[k + 1][0] + seq[k + 2][0]) / 6 - q[i][0],
						(seq[k][1] + 4 * seq[k + 1][1] + seq[k + 2][1]) / 6 - q[i][1]));
		knot_err = fmax(knot_err, best);
	}
	print_message("rests: %u records for %u points, off the legs %.2g mm, back %.2g mm, %u of 3 rests on a knot, other points within %.2g mm\n",
		      n, 3 * RL, dev, back, stops, knot_err);
	assert_true(dev < 1e-12);
	assert_true(back < 1e-12);
	assert_int_equal(stops, 3);
	assert_true(knot_err < 3e-7);
}

static void test_bscomp_stream(void **s)
{
	struct sh2000_bscomp *bc;
	double q[300], P[400], x, rest0 = 1.0, rest1;
	unsigned int n = 0, i, nq = 300;
	int last = 0;

	(void)s;
	assert_int_equal(sh2000_bscomp_create(&bc, 12, 1), 0);
	for (i = 0; i < nq; i++) {
		double t = (double)i / (nq - 1);

		/* rest to rest, smooth */
		q[i] = 1.0 + 3.0 * t * t * t * (10 - 15 * t + 6 * t * t) +
		       0.2 * sin(20 * t) * t * t * (1 - t) * (1 - t);
	}
	rest1 = q[nq - 1];
	sh2000_bscomp_start(bc, &rest0);
	for (i = 0; i < nq; i++)
		if (sh2000_bscomp_push(bc, &q[i], &x))
			P[n++] = x;
	while (sh2000_bscomp_flush(bc, &x, &last))
		P[n++] = x;
	assert_true(last);
	assert_true(P[n - 1] == rest1);
	/* The knots of the card's B-spline over [rest x3, P..., end x3]
	 * are (P[k-1] + 4 P[k] + P[k+1]) / 6; at the right alignment they
	 * are the extended Q (rest before, end after) to within 1e-7. */
	{
		double seq[420], best = INFINITY;
		unsigned int m = 0, k, off;

		for (k = 0; k < 3; k++)
			seq[m++] = rest0;
		for (k = 0; k < n; k++)
			seq[m++] = P[k];
		for (k = 0; k < 3; k++)
			seq[m++] = rest1;
		for (off = 0; off < 40; off++) {
			double worst = 0;

			for (k = 1; k + 1 < m; k++) {
				double knot = (seq[k - 1] + 4 * seq[k] +
					       seq[k + 1]) / 6;
				int j = (int)k - (int)off;
				double want = j < 0 ? rest0 :
					      j >= (int)nq ? rest1 : q[j];

				worst = fmax(worst, fabs(knot - want));
			}
			best = fmin(best, worst);
		}
		print_message("compensation: knots within %.2g of the points\n",
			      best);
		assert_true(best < 3e-7);
	}
	sh2000_bscomp_destroy(bc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_lines_scurve_comp),
		cmocka_unit_test(test_lines_scurve_raw),
		cmocka_unit_test(test_lines_trap_comp),
		cmocka_unit_test(test_lines_trap_raw),
		cmocka_unit_test(test_corner_tolerance),
		cmocka_unit_test(test_short_moves),
		cmocka_unit_test(test_p2p_rel_jog),
		cmocka_unit_test(test_arc_circle_compensated),
		cmocka_unit_test(test_arc_circle_raw_cuts_inward),
		cmocka_unit_test(test_arc_forms_and_helix),
		cmocka_unit_test(test_arc_radius_form),
		cmocka_unit_test(test_nurbs_circle),
		cmocka_unit_test(test_nurbs_freeform),
		cmocka_unit_test(test_nurbs_degrees_and_pause),
		cmocka_unit_test(test_random_programs),
		cmocka_unit_test(test_bad_geometry),
		cmocka_unit_test(test_bad_config),
		cmocka_unit_test(test_constant_memory),
		cmocka_unit_test(test_nurbs_memory_released),
		cmocka_unit_test(test_nurbs_cusp),
		cmocka_unit_test(test_nurbs_heavy_weight),
		cmocka_unit_test(test_override_pause_resume),
		cmocka_unit_test(test_stop_discards),
		cmocka_unit_test(test_sink_failure),
		cmocka_unit_test(test_bscomp_stream),
		cmocka_unit_test(test_bscomp_rests),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
