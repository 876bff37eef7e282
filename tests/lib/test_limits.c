/* SPDX-License-Identifier: MIT */
/*
 * Soft limits are judged on the card's fine set-points (run/setpoints.c):
 * a fast circle tangent to SOFT_MAX runs (its compensated records lie
 * beyond the limit, the set-points touch it and never pass it, the card
 * accepts every record and latches nothing); one that passes the limit by
 * 10 um is refused, naming the set-point, before the card gets near it.
 * And the policy itself on exact compensated records of a circle whose
 * records pass the limit by 12 um: judged on the records (the old rule,
 * sh2000_limits_apply) it is refused, on the set-points it runs.
 *
 * The ends and extremes of the primitives are judged when they are added
 * (the runner gives the planner the limits with the slack, its bounds): a
 * line or an arc beyond them is refused then, nothing queued and nothing
 * moved, a line to the limit plus the slack runs; a NURBS is refused at a
 * point of its curve beyond them, not for a control point alone. And
 * sh2000_run_error() says the last failure: the run's, until a planner
 * call fails later.
 */
#include <errno.h>
#include <math.h>

#include "simtest.h"
#include "setpoints.h"
#include "sh2000/bspline.h"
#include "sh2000/run.h"

#define LIMIT_MM	100.0
#define AMAX		40000.0	/* mm/s^2 */

struct seen {
	double max_cmd;		/* highest X set-point of any servo cycle */
};

static void on_sample(void *ctx, const struct sh2000_run_sample *s)
{
	struct seen *o = ctx;

	if (s->cmd[0] > o->max_cmd)
		o->max_cmd = s->cmd[0];
}

static struct sh2000_run *start(struct sh2000 *h, struct seen *o)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_run *r;
	char msg[256];

	CHECK(sh2000_param_set(h, 0, SH2000_P_SOFT_MAX, LIMIT_MM));
	/* accelerations that make the compensation's overshoot plain */
	CHECK(sh2000_param_set(h, 0, SH2000_P_AMAX, AMAX));
	CHECK(sh2000_param_set(h, 1, SH2000_P_AMAX, AMAX));
	CHECK(sh2000_enable(h, 0xf));
	CHECK(sh2000_run_path_config(h, &pc));
	sh2000_run_config_default(&rc);
	rc.sample = on_sample;
	rc.ctx = o;
	o->max_cmd = -INFINITY;
	if (sh2000_run_create(&r, h, &pc, &rc, msg, sizeof(msg)) < 0)
		fail_msg("run_create: %s", msg);
	return r;
}

/* Along -R from X 0 to the circle's lowest point, and on round the full
 * circle (ccw, entered on its tangent): it touches X = centre + radius. */
static int add_circle(struct sh2000_path *p, double centre, double radius,
		      double feed)
{
	const double a[4] = { 0, -radius, 0, 0 }, b[4] = { centre, -radius, 0, 0 };
	struct sh2000_path_arc arc;
	int e;

	e = sh2000_path_line(p, a, feed);
	if (!e)
		e = sh2000_path_line(p, b, feed);
	if (e)
		return e;
	memset(&arc, 0, sizeof(arc));
	arc.plane = SH2000_PLANE_XY;
	memcpy(arc.end, b, sizeof(arc.end));
	arc.ccw = 1;
	arc.centre[0] = centre;
	arc.centre[1] = 0.0;
	return sh2000_path_arc(p, &arc, feed);
}

static int circle(struct sh2000_run *r, double centre, double radius,
		  double feed)
{
	int e = add_circle(sh2000_run_path(r), centre, radius, feed);

	return e ? e : sh2000_run_finish(r);
}

static int max_sink(void *ctx, const struct sh2000_path_point *pt)
{
	double *m = ctx;

	if (pt->mm[0] > *m)
		*m = pt->mm[0];
	return 0;
}

/* The highest X record the planner makes of the circle: the records the
 * card gets before the limits are applied. */
static double records_max(struct sh2000 *h, double centre, double radius,
			  double feed)
{
	struct sh2000_path_config pc;
	struct sh2000_path *p;
	double m = -INFINITY;
	char msg[256];

	CHECK(sh2000_run_path_config(h, &pc));
	if (sh2000_path_create(&p, &pc, max_sink, &m, msg, sizeof(msg)))
		fail_msg("path: %s", msg);
	CHECK(add_circle(p, centre, radius, feed));
	CHECK(sh2000_path_finish(p));
	sh2000_path_destroy(p);
	return m;
}

static void test_tangent(void **state)
{
	struct sh2000 *h = simtest_open();
	struct seen o;
	struct sh2000_run *r = start(h, &o);
	struct sh2000_status st;

	double rec;

	(void)state;
	/* 300 mm/s on R 10: 9000 mm/s^2, records ~6 um beyond the path */
	rec = records_max(h, LIMIT_MM - 10.0, 10.0, 300.0);
	assert_true(rec > LIMIT_MM);	/* the records pass the limit */
	print_message("highest X record %.6f mm\n", rec);
	assert_int_equal(circle(r, LIMIT_MM - 10.0, 10.0, 300.0), 0);
	print_message("highest X set-point %.6f mm (limit %.4f)\n", o.max_cmd,
		      LIMIT_MM);
	/* the path reached the limit and the set-points never passed it */
	assert_true(o.max_cmd > LIMIT_MM - 0.01);
	assert_true(o.max_cmd <= LIMIT_MM + 1e-6);
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_int_equal(st.card_faults, 0);
	sh2000_run_destroy(r);
	sh2000_close(h);
}

/* The card at rest where it was, nothing queued, nothing latched. */
static void card_still(struct sh2000 *h, double x, double y)
{
	struct sh2000_status st;

	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_int_equal(st.card_faults, 0);
	assert_int_equal(st.queue_fill, 0);
	assert_true(fabs(st.axis[0].cmd_mm - x) < 1e-6);
	assert_true(fabs(st.axis[1].cmd_mm - y) < 1e-6);
}

/*
 * The set-points of a circle that passes the limit by 10 um, with the
 * planner's bounds taken off (its arc is refused when added otherwise):
 * the guard on the set-points still finds it. sh2000_run_error() keeps
 * the run's words through a later finish with nothing left and a later
 * successful motion, and gives the planner's once a planner call fails.
 */
static void test_beyond(void **state)
{
	struct sh2000 *h = simtest_open();
	struct seen o;
	struct sh2000_run *r = start(h, &o);
	struct sh2000_status st;
	const double back[4] = { 1, 0, 0, 0 };
	char first[512];

	(void)state;
	CHECK(sh2000_path_set_bounds(sh2000_run_path(r), NULL, NULL));
	assert_int_equal(circle(r, LIMIT_MM - 10.0, 10.01, 300.0),
			 -SH2000_ELIMIT);
	print_message("%s\n", sh2000_run_error(r));
	assert_non_null(strstr(sh2000_run_error(r),
			       "is beyond the soft limit 100.0000 mm"));
	assert_non_null(strstr(sh2000_run_error(r), "set-point"));
	snprintf(first, sizeof(first), "%s", sh2000_run_error(r));
	/* the records the card got were inside, and so was the card */
	assert_true(o.max_cmd <= LIMIT_MM + 1e-6);
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_faults, 0);
	assert_int_equal(st.queue_fill, 0);
	/* nothing left: 0, and the words stay the run's (not the planner's
	 * "the sink failed" of the same failure) */
	assert_int_equal(sh2000_run_finish(r), 0);
	assert_string_equal(sh2000_run_error(r), first);
	CHECK(sh2000_path_line(sh2000_run_path(r), back, 50.0));
	assert_int_equal(sh2000_run_finish(r), 0);
	assert_string_equal(sh2000_run_error(r), first);
	/* a planner call that fails later has the last word */
	assert_int_equal(sh2000_path_line(sh2000_run_path(r), back, -1.0),
			 -EINVAL);
	assert_string_equal(sh2000_run_error(r), "feed must be > 0: got -1");
	sh2000_run_destroy(r);
	sh2000_close(h);
}

/* A line beyond the limit is refused when it is added: nothing queued,
 * the card where it was; the planner takes the next one, and one to the
 * limit plus the slack runs and ends on the limit. */
static void test_line_at_add(void **state)
{
	struct sh2000 *h = simtest_open();
	struct seen o;
	struct sh2000_run *r = start(h, &o);
	struct sh2000_run_stats rs;
	const double far[4] = { LIMIT_MM + 5.0, 0, 0, 0 };
	const double edge[4] = { LIMIT_MM + SH2000_LIMIT_SLACK_MM, 0, 0, 0 };

	(void)state;
	assert_int_equal(sh2000_path_line(sh2000_run_path(r), far, 50.0),
			 -SH2000_ELIMIT);
	print_message("%s\n", sh2000_run_error(r));
	assert_string_equal(sh2000_run_error(r),
			    "line: end X 105.000000 mm is beyond the soft limit: the bound is 100.002000 mm");
	assert_int_equal(sh2000_run_finish(r), 0);
	sh2000_run_stats(r, &rs);
	assert_int_equal(rs.points, 0);
	card_still(h, 0.0, 0.0);
	CHECK(sh2000_path_line(sh2000_run_path(r), edge, 300.0));
	assert_int_equal(sh2000_run_finish(r), 0);
	card_still(h, LIMIT_MM, 0.0);
	assert_true(o.max_cmd <= LIMIT_MM + 1e-6);
	sh2000_run_destroy(r);
	sh2000_close(h);
}

/* An arc whose ends are inside and whose bulge is 2 mm beyond: refused
 * when added; the line queued before it runs. */
static void test_arc_at_add(void **state)
{
	struct sh2000 *h = simtest_open();
	struct seen o;
	struct sh2000_run *r = start(h, &o);
	const double a[4] = { LIMIT_MM - 3.0, -5.0, 0, 0 };
	struct sh2000_path_arc arc;

	(void)state;
	CHECK(sh2000_path_line(sh2000_run_path(r), a, 100.0));
	memset(&arc, 0, sizeof(arc));
	arc.plane = SH2000_PLANE_XY;
	arc.end[0] = LIMIT_MM - 3.0;
	arc.end[1] = 5.0;
	arc.ccw = 1;
	arc.centre[0] = LIMIT_MM - 3.0;
	assert_int_equal(sh2000_path_arc(sh2000_run_path(r), &arc, 100.0),
			 -SH2000_ELIMIT);
	print_message("%s\n", sh2000_run_error(r));
	assert_string_equal(sh2000_run_error(r),
			    "arc: passes X 102.000000 mm is beyond the soft limit: the bound is 100.002000 mm");
	card_still(h, 0.0, 0.0);
	assert_int_equal(sh2000_run_finish(r), 0);
	card_still(h, LIMIT_MM - 3.0, -5.0);
	sh2000_run_destroy(r);
	sh2000_close(h);
}

static int discard(void *ctx, const struct sh2000_path_point *pt)
{
	(void)ctx;
	(void)pt;
	return 0;
}

/* Back to (99, 0) and a quadratic NURBS from there over (xm, 1) to
 * (99, 2): its curve reaches X (99 + xm) / 2 at u = 0.5. */
static int add_nurbs(struct sh2000_path *p, double xm)
{
	const double pts[3][SH2000_AXES] = {
		{ 99, 0, 0, 0 }, { xm, 1, 0, 0 }, { 99, 2, 0, 0 } };
	const double knots[6] = { 0, 0, 0, 1, 1, 1 };
	struct sh2000_nurbs n = { .degree = 2, .npoints = 3, .points = pts,
				  .knots = knots };
	int e = sh2000_path_line(p, pts[0], 50.0);

	return e ? e : sh2000_path_nurbs(p, &n, 50.0);
}

/* The planner alone: a NURBS whose control point is beyond the bound
 * but whose curve only touches it is taken; one whose curve passes it is
 * refused, naming where; bad bounds are refused and change nothing. */
static void test_nurbs_bounds(void **state)
{
	struct sh2000_path_config pc;
	struct sh2000_path *p;
	double lo[SH2000_AXES], hi[SH2000_AXES];
	unsigned int a;

	(void)state;
	sh2000_path_config_default(&pc);
	pc.start[0] = 99.0;
	assert_int_equal(sh2000_path_create(&p, &pc, discard, NULL, NULL, 0), 0);
	for (a = 0; a < SH2000_AXES; a++) {
		lo[a] = -1000.0;
		hi[a] = 1000.0;
	}
	hi[0] = LIMIT_MM;
	assert_int_equal(sh2000_path_set_bounds(p, lo, hi), 0);
	assert_int_equal(add_nurbs(p, 101.0), 0);	/* touches 100 */
	assert_int_equal(sh2000_path_finish(p), 0);
	assert_int_equal(add_nurbs(p, 101.2), -SH2000_ELIMIT);
	print_message("%s\n", sh2000_path_error(p));
	assert_string_equal(sh2000_path_error(p),
			    "nurbs: the curve at u = 0.5 X 100.100000 mm is beyond the soft limit: the bound is 100.000000 mm");
	/* one side only, lo > hi, NaN: refused, the bounds stay */
	assert_int_equal(sh2000_path_set_bounds(p, lo, NULL), -EINVAL);
	hi[1] = -2000.0;
	assert_int_equal(sh2000_path_set_bounds(p, lo, hi), -EINVAL);
	hi[1] = NAN;
	assert_int_equal(sh2000_path_set_bounds(p, lo, hi), -EINVAL);
	assert_int_equal(add_nurbs(p, 101.2), -SH2000_ELIMIT);
	/* none: taken */
	assert_int_equal(sh2000_path_set_bounds(p, NULL, NULL), 0);
	assert_int_equal(add_nurbs(p, 101.2), 0);
	assert_int_equal(sh2000_path_finish(p), 0);
	sh2000_path_destroy(p);
}

/*
 * Control points P = c + kappa (Q - c), kappa = 3 / (2 + cos step), of
 * points Q on a circle are exactly the compensated records: the card's
 * spline passes through every Q. R 5, 0.6 mm per record (300 mm/s at
 * 2 ms): the records lie 12 um outside the circle.
 */
static void test_policy(void **state)
{
	const double r = 5.0, c = LIMIT_MM - r, step = 0.6 / r;
	const double kappa = 3.0 / (2.0 + cos(step));
	struct sh2000_limits l;
	struct sh2000_setpoints sp;
	double mm[SH2000_AXES], old[SH2000_AXES], hi = -INFINITY;
	unsigned int a, i, n = (unsigned int)(2.0 * M_PI / step) + 1;
	int old_refused = 0, clamped = 0, e;
	char msg[256];

	(void)state;
	for (a = 0; a < SH2000_AXES; a++) {
		l.lo[a] = -1000.0;
		l.hi[a] = 1000.0;
	}
	l.hi[0] = LIMIT_MM;
	sh2000_setpoints_init(&sp, &l);
	for (i = 0; i <= n; i++) {
		double th = M_PI + step * (double)i;

		memset(mm, 0, sizeof(mm));
		mm[0] = c + kappa * r * cos(th);
		mm[1] = kappa * r * sin(th);
		if (mm[0] > hi)
			hi = mm[0];
		memcpy(old, mm, sizeof(old));
		old_refused |= sh2000_limits_apply(&l, old, NULL, 0) < 0;
		e = sh2000_setpoints_point(&sp, mm, i == n, msg, sizeof(msg));
		if (e < 0)
			fail_msg("record %u: %s", i, msg);
		clamped += e;
		assert_true(mm[0] <= LIMIT_MM);
	}
	print_message("records up to %.6f mm: old rule %s, %d put on the limit\n",
		      hi, old_refused ? "refused" : "ran", clamped);
	assert_true(hi > LIMIT_MM + 0.01);
	assert_true(old_refused);
	assert_true(clamped > 0);
	/* 20 um further out the set-points pass the limit too */
	sh2000_setpoints_init(&sp, &l);
	for (i = 0, e = 0; i <= n && e >= 0; i++) {
		double th = M_PI + step * (double)i;

		memset(mm, 0, sizeof(mm));
		mm[0] = c + 0.02 + kappa * r * cos(th);
		mm[1] = kappa * r * sin(th);
		e = sh2000_setpoints_point(&sp, mm, i == n, msg, sizeof(msg));
	}
	assert_int_equal(e, -SH2000_ELIMIT);
	assert_non_null(strstr(msg, "X 100.0"));
	assert_non_null(strstr(msg, "beyond the soft limit 100.0000 mm"));
	assert_non_null(strstr(msg, "set-point"));
}

/* A gantry pair's rule (pair.c) over the same stream: the sides may
 * stand apart (the beam's squaring) and move the same distance, to a
 * count; further apart is refused, naming both; a plan without a pair,
 * or with one side only, judges nothing. No soft limits here: the rule
 * holds without them (a program's first pass may have none). */
static void test_gantry_pair(void **state)
{
	struct sh2000_path_config pc;
	struct sh2000_setpoints c;
	double p[SH2000_AXES] = { 0, 10.0, 10.5, 0 };
	char msg[256];

	(void)state;
	sh2000_path_config_default(&pc);
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		pc.counts_per_mm[a] = 1e5;
	memcpy(pc.start, p, sizeof(p));
	pc.gantry_pair = 0x6;	/* y and z */
	sh2000_setpoints_init(&c, NULL);
	sh2000_setpoints_rest(&c, pc.start);
	sh2000_setpoints_pair(&c, &pc);
	p[1] = 11.0;
	p[2] = 11.5 + 0.9e-5;	/* under a count apart */
	assert_int_equal(sh2000_setpoints_point(&c, p, 0, msg, sizeof(msg)), 0);
	p[2] = 11.5 + 2e-5;
	assert_int_equal(sh2000_setpoints_point(&c, p, 0, msg, sizeof(msg)),
			 -SH2000_EGANTRY);
	assert_non_null(strstr(msg, "Y and Z are one gantry beam (gantry_pair): here Y has moved 1.000000 mm and Z 1.000020 mm since the motion began, 0.000020 mm apart"));
	/* the end of a motion is where the next one's distances count from */
	p[2] = 11.5;
	assert_int_equal(sh2000_setpoints_point(&c, p, 1, msg, sizeof(msg)), 0);
	p[1] = 12.0;
	p[2] = 11.5;
	assert_int_equal(sh2000_setpoints_point(&c, p, 0, msg, sizeof(msg)),
			 -SH2000_EGANTRY);
	/* one side only, or none: no pair to judge */
	for (unsigned int mask = 0; mask <= 0x4; mask += 0x4) {
		pc.gantry_pair = mask;
		sh2000_setpoints_init(&c, NULL);
		sh2000_setpoints_rest(&c, pc.start);
		sh2000_setpoints_pair(&c, &pc);
		assert_int_equal(sh2000_setpoints_point(&c, p, 0, msg, sizeof(msg)), 0);
	}
}

/* The first pass's acceleration guard: the second difference of the
 * records over T^2 (the spline's acceleration at a knot, exactly), from
 * the rest window and through the END padding, against amax (the records
 * as planned, before they are rounded to counts); the largest is kept as a
 * fraction of amax; without sh2000_setpoints_accel() nothing is judged. */
static void feed_x(struct sh2000_setpoints *c, const double *x, size_t n,
		   int accel, int want, const char *msg_part)
{
	struct sh2000_path_config pc;
	double p[SH2000_AXES] = { 0 };
	char msg[512] = "";
	int e = 0;

	sh2000_path_config_default(&pc);
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		pc.counts_per_mm[a] = 1e5;
		pc.amax[a] = 5000;
	}
	pc.period_s = 0.002;
	pc.margin = 0.95;
	sh2000_setpoints_init(c, NULL);
	sh2000_setpoints_rest(c, pc.start);
	if (accel)
		sh2000_setpoints_accel(c, &pc);
	for (size_t i = 0; i < n && !e; i++) {
		p[0] = x[i];
		e = sh2000_setpoints_point(c, p, i + 1 == n, msg, sizeof(msg));
	}
	assert_int_equal(e, want);
	if (msg_part)
		assert_non_null(strstr(msg, msg_part));
}

static void test_accel_guard(void **state)
{
	/* rest to rest at 2500 mm/s^2, and at amax (5000) exactly */
	static const double ok[] = { 0.01, 0.03, 0.05, 0.06, 0.06 };
	static const double at[] = { 0.02, 0.06, 0.1, 0.12, 0.12 };
	/* then 0.3: 17500 mm/s^2 at the fifth knot */
	static const double jump[] = { 0.01, 0.04, 0.09, 0.16, 0.3 };
	/* ends moving at 35 mm/s: the padding stops it within a period */
	static const double halt[] = { 0.01, 0.04, 0.09, 0.16 };
	/* amax, then two counts over it where the padding stops the
	 * motion: 5005 mm/s^2 */
	static const double over[] = { 0.02, 0.04002 };
	struct sh2000_setpoints c;

	(void)state;
	feed_x(&c, ok, 5, 1, 0, NULL);
	assert_float_equal(c.accel_peak, 0.5, 1e-9);
	feed_x(&c, at, 5, 1, 0, NULL);
	assert_float_equal(c.accel_peak, 1.0, 1e-9);
	assert_int_equal(c.accel_axis, 0);
	feed_x(&c, jump, 5, 1, -ERANGE,
	       "axis X: the planned set-points accelerate at 17500 mm/s^2 at 0.010 s, over its amax of 5000 mm/s^2 (planned with the margin 0.950");
	assert_float_equal(c.accel_peak, 3.5, 1e-9);
	feed_x(&c, jump, 5, 0, 0, NULL);
	feed_x(&c, halt, 4, 1, -ERANGE,
	       "accelerate at 17500 mm/s^2 at 0.010 s");
	feed_x(&c, over, 1, 1, 0, NULL);
	feed_x(&c, over, 2, 1, -ERANGE, "at 5005 mm/s^2 at 0.006 s");
	assert_float_equal(c.accel_peak, 1.001, 1e-9);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_tangent),
		cmocka_unit_test(test_beyond),
		cmocka_unit_test(test_line_at_add),
		cmocka_unit_test(test_arc_at_add),
		cmocka_unit_test(test_nurbs_bounds),
		cmocka_unit_test(test_policy),
		cmocka_unit_test(test_gantry_pair),
		cmocka_unit_test(test_accel_guard),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
