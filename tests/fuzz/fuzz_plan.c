// SPDX-License-Identifier: MIT
/*
 * Reader and planner together, as sh2000-upload plans a program before it
 * moves anything: the first byte picks the format ('G' G-code, 'C' rs274
 * canonical output, 'V' CSV, 'J' NURBS JSON; any other byte by its value),
 * the rest is the program. Every block the reader accepts goes to a
 * planner whose sink checks each point and throws it away, twice: with
 * the planner's default limits, and with the card model's (400 mm/s,
 * 5000 mm/s^2), where the S-curve ramps within two periods and the
 * controller holds one jerk a period; and once more at the card model's
 * with the axes the program never moves held still (hold_still()).
 *
 * Promises checked: a rejected block says why (sh2000_path_error), every
 * point is finite, and the plan has no more points than the program's own
 * duration allows: the time at the slowest speed the geometry and the
 * limits can ask for, plus a start and a stop per block, with a factor 8
 * of room. Weird but valid geometry that needs more is an explosion the
 * planner must refuse with an error. Every program is planned, but only
 * its first POINTS_CAP points (a long program is cut there, not failed).
 *
 * The points are also checked where the card uses them: the card's fine
 * set-points (its four-point window through sh2000_bspline, spcheck.h)
 * keep every axis within its velocity, acceleration and jerk limits, and
 * stay within the program's tolerance of its own path (geo_tol()).
 * SH2000_FUZZ_VERBOSE=1 prints the reader's diagnostics, the count of
 * points and what the checks measured (to look at one input).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sh2000/run.h>

#include "fuzz.h"
#include "spcheck.h"

/* Points planned at most (4 s at 2 ms): every kind of geometry fits, and
 * thousands of runs a second (the planner's points and their fine
 * set-points are most of a run's time). A program that lasts longer is
 * planned up to here. */
#define POINTS_CAP		2000
/* Headroom of the point budget over the program's duration. */
#define BUDGET_FACTOR		8.0
/* A start and a stop: (v/A + A/J) twice, at most, with the defaults. */
#define BLOCK_OVERHEAD_S	0.05
/* What the sink returns to stop a plan at POINTS_CAP. */
#define CAPPED			(-1000001)
/*
 * mm a fine set-point may be off the path besides the program's own
 * tolerances: a compensated stop rings about J T^3 / 70 = 0.6 um along
 * its path (docs/planner.md "Known limits"); the rest is rounding.
 */
#define GEO_SLACK_MM		0.001
/*
 * The jerk the card's compensated spline may reach, over the planner's
 * path jerk (margin * jerk). The spline through the planned points is the
 * plan itself where the controller holds one jerk a whole period (the
 * card model's limits, on straight moves); elsewhere (the planner's
 * default limits, whose jerk switches inside a period) it filters the
 * plan, and the compensation filter overshoots a step of the jerk by
 * 2r/(1 + r) of the step (r = 2 - sqrt 3; docs/planner.md "Known
 * limits"). A step from 0 to J reaches 1.42 J; a move too short to hold
 * its acceleration turns the jerk from +J to -J, a step of 2J, which
 * reaches 1.85 J. So 1.35 and 1.75 times the configured jerk at the
 * default margin.
 */
#define COMP_JERK_STEP		1.4226497308103743
#define COMP_JERK_REVERSAL	1.8452994616207485

struct plan_check {
	struct sh2000_path_config cfg;
	double j_overshoot;	/* compensated output: the jerk allowed */
	double budget;		/* points allowed */
	uint64_t points;
	struct sp_check sp;
	struct sp_path path;
};

static enum sh2000_prog_format format_of(uint8_t b)
{
	switch (b) {
	case 'G':
		return SH2000_PROG_GCODE;
	case 'C':
		return SH2000_PROG_CANON;
	case 'V':
		return SH2000_PROG_CSV;
	case 'J':
		return SH2000_PROG_NURBS_JSON;
	default:
		return (enum sh2000_prog_format)(SH2000_PROG_GCODE + b % 4);
	}
}

/* The slowest the planner may go on a curve of curvature kappa (its own
 * rule, pl_curve_vlim, with every axis at full share). */
static double curve_speed(const struct sh2000_path_config *c, double kappa)
{
	double v = c->margin * c->vmax[0];	/* |tangent| <= 1 on each axis */
	double share = c->centripetal_share * c->margin;
	double amin = c->amax[0], J = c->jerk * c->margin;

	if (kappa > 1e-12) {
		v = fmin(v, sqrt(share * amin / kappa));
		v = fmin(v, sqrt(8.0 * c->chord_tol / kappa) / c->period_s);
		v = fmin(v, cbrt(share * J / (kappa * kappa)));
	}
	return v;
}

static double dist(const double *a, const double *b)
{
	double s = 0;

	for (unsigned int k = 0; k < SH2000_AXES; k++)
		s += (a[k] - b[k]) * (a[k] - b[k]);
	return sqrt(s);
}

/* Largest curvature of a NURBS, sampled (finite differences): its speed
 * bound holds for the whole curve, which can only overestimate time. */
static double nurbs_kappa(const struct sh2000_nurbs *n)
{
	double u0 = sh2000_nurbs_umin(n), u1 = sh2000_nurbs_umax(n);
	double kmax = 0, p[3][SH2000_AXES];
	unsigned int steps = 16 * (unsigned int)n->npoints;

	if (steps > 1024)
		steps = 1024;
	for (unsigned int i = 1; i < steps; i++) {
		double u = u0 + (u1 - u0) * i / steps, h = (u1 - u0) / steps / 4;
		double a, b, c, s;

		sh2000_nurbs_eval(n, u - h, p[0], NULL, NULL);
		sh2000_nurbs_eval(n, u, p[1], NULL, NULL);
		sh2000_nurbs_eval(n, u + h, p[2], NULL, NULL);
		/* circle through three points: 4 area / (a b c) */
		a = dist(p[0], p[1]);
		b = dist(p[1], p[2]);
		c = dist(p[0], p[2]);
		s = (a + b + c) * (-a + b + c) * (a - b + c) * (a + b - c);
		if (a > 0 && b > 0 && c > 0 && s > 0)
			kmax = fmax(kmax, sqrt(s) / (a * b * c));
	}
	return kmax;
}

static double polygon_length(const struct sh2000_nurbs *n)
{
	double L = 0;

	for (size_t i = 1; i < n->npoints; i++)
		L += dist(n->points[i - 1], n->points[i]);
	return L;
}

/* How long block b may take at most, in seconds. */
static double block_seconds(const struct sh2000_path_config *c,
			    const struct sh2000_prog_block *b)
{
	double L = dist(b->start, b->end), v, feed = b->feed;

	switch (b->kind) {
	case SH2000_PROG_RAPID:
		v = curve_speed(c, 0);
		break;
	case SH2000_PROG_LINE:
		v = fmin(feed, curve_speed(c, 0));
		break;
	case SH2000_PROG_ARC: {
		const struct sh2000_arc *a = &b->u.arc;
		double r = fmin(a->fit_radius, fmin(a->r0, a->r1));
		double planar = fabs(a->sweep) * fmax(a->r0, a->r1);

		L = planar + L;
		v = fmin(feed, curve_speed(c, 1.0 / r));
		break;
	}
	case SH2000_PROG_NURBS:
		/* the curve is no longer than its control polygon */
		L = polygon_length(&b->u.nurbs);
		v = fmin(feed, curve_speed(c, nurbs_kappa(&b->u.nurbs)));
		break;
	default:
		return 0;
	}
	return L / v + BLOCK_OVERHEAD_S;
}

static int sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct plan_check *pc = ctx;

	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if (!isfinite(pt->mm[a]))
			fz_fail("point %llu: axis %u is %g",
				(unsigned long long)pc->points, a, pt->mm[a]);
	sp_point(&pc->sp, pt);
	if (++pc->points > pc->budget)
		fz_fail("the plan exploded: more than %.0f points for a program of at most %.0f",
			pc->budget, pc->budget / BUDGET_FACTOR);
	return pc->points >= POINTS_CAP ? CAPPED : 0;
}

/* How far the program lets its path be cut, mm: the largest G64 P (or the
 * planner's corner and chord tolerances, 0.01 mm), G64 Q on top; G64
 * without P bounds a blend only by its moves (a blend arc takes at most
 * half of either move, and its middle is no further from the corner than
 * that), so then half the longest straight move, a rapid included (rapids
 * blend with rapids). */
static double geo_tol(const struct sh2000_program *prog,
		      const struct sh2000_path_config *c)
{
	double tol = fmax(c->corner_tol, c->chord_tol), q = 0, longest = 0;
	int unbounded = 0;

	for (size_t i = 0; i < prog->count; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];

		if (b->kind == SH2000_PROG_LINE || b->kind == SH2000_PROG_RAPID)
			longest = fmax(longest, dist(b->start, b->end));
		if (b->kind != SH2000_PROG_PATH_MODE ||
		    b->u.path.mode != SH2000_PATH_BLEND)
			continue;
		if (b->u.path.tolerance > 0)
			tol = fmax(tol, b->u.path.tolerance);
		else
			unbounded = 1;
		q = fmax(q, b->u.path.naive_tolerance);
	}
	if (unbounded)
		tol = fmax(tol, longest / 2);
	return tol + q + GEO_SLACK_MM;
}

/* Whether a line turns from the one before by more than the planner
 * treats as straight on (1e-6 rad). */
static int turns(const struct sh2000_prog_block *a,
		 const struct sh2000_prog_block *b)
{
	double da = dist(a->start, a->end), db = dist(b->start, b->end), d = 0;

	for (unsigned int k = 0; k < SH2000_AXES; k++)
		d += (a->end[k] - a->start[k]) * (b->end[k] - b->start[k]);
	return da > 0 && db > 0 && d / (da * db) < cos(1e-6);
}

/*
 * Whether the plan's jerk is bounded: only then the card's set-points are
 * held to the jerk limit. Curvature that steps at speed is not bounded in
 * jerk by any rule of the planner yet (docs/planner.md "Known limits"):
 * junctions into and out of arcs and NURBS, and the ends of the arcs that
 * blend a corner between two lines. So: straight moves only, and every
 * corner between two feed lines, or between two rapids (which are blended
 * with each other as LinuxCNC blends them; a rapid and a feed move meet at
 * rest), taken at rest (G61, G61.1).
 */
static int jerk_bounded(const struct sh2000_program *prog,
			const struct sh2000_path_config *c)
{
	const struct sh2000_prog_block *prev = NULL;
	int blend = c->mode == SH2000_PATH_BLEND;

	for (size_t i = 0; i < prog->count; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];

		switch (b->kind) {
		case SH2000_PROG_ARC:
		case SH2000_PROG_NURBS:
			return 0;
		case SH2000_PROG_PATH_MODE:
			blend = b->u.path.mode == SH2000_PATH_BLEND;
			break;
		case SH2000_PROG_LINE:
		case SH2000_PROG_RAPID:
			if (prev && prev->kind == b->kind && blend &&
			    turns(prev, b))
				return 0;
			prev = b;
			break;
		case SH2000_PROG_FEED:
			break;
		default:	/* dwells, pauses: from rest */
			prev = NULL;
		}
	}
	return 1;
}

/* The card's fine set-points within the limits and on the path. */
static void check_setpoints(const struct plan_check *pc,
			    const struct sh2000_program *prog)
{
	const struct sp_check *sp = &pc->sp;
	int jerk = pc->cfg.profile == SH2000_PROFILE_SCURVE &&
		   jerk_bounded(prog, &pc->cfg);
	double jmax = pc->cfg.margin *
		      (pc->cfg.output == SH2000_OUTPUT_COMPENSATED ?
		       pc->j_overshoot : 1.0);

	if (sp->v_ratio > 1.0)
		fz_fail("fine set-point %llu: an axis at %.4f of its vmax",
			sp->v_at, sp->v_ratio);
	if (sp->a_ratio > 1.0)
		fz_fail("fine set-point %llu: an axis at %.4f of its amax",
			sp->a_at, sp->a_ratio);
	if (jerk && sp->j_ratio > jmax)
		fz_fail("fine set-point %llu: an axis at %.4f of the jerk limit (allowed %.4f)",
			sp->j_at, sp->j_ratio, jmax);
	if (sp->dev > sp->tol)
		fz_fail("fine set-point %llu (%g, %g, %g, %g), the first off the path: %.6f mm from it (allowed %.6f)",
			sp->dev_at, sp->dev_point[0], sp->dev_point[1],
			sp->dev_point[2], sp->dev_point[3], sp->dev, sp->tol);
}

static void plan(const struct sh2000_program *prog, struct plan_check *pc)
{
	struct sh2000_path *p;
	char err[256];
	int r = 0;

	if (sh2000_path_create(&p, &pc->cfg, sink, pc, err, sizeof(err)))
		fz_fail("planner: %s", err);
	for (size_t i = 0; i < prog->count && !r; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];

		if (b->kind == SH2000_PROG_END)
			break;
		/* as the front ends plan it: an M1 goes on (optional_stop
		 * off, sh2000_program_plan()) */
		if (b->kind == SH2000_PROG_PAUSE && b->u.optional)
			continue;
		if (b->kind == SH2000_PROG_DWELL || b->kind == SH2000_PROG_PAUSE) {
			r = sh2000_path_finish(p);
			continue;
		}
		sh2000_path_set_seq(p, (uint32_t)i);
		r = sh2000_path_add_block(p, b);
	}
	if (!r)
		r = sh2000_path_finish(p);
	if (r && r != CAPPED && !sh2000_path_error(p)[0])
		fz_fail("the planner failed (%d) without saying why", r);
	if (r && strstr(sh2000_path_error(p), "holds still"))
		fz_fail("a block sh2000_prog_block_axes() left still moved an axis: %s",
			sh2000_path_error(p));
	sh2000_path_destroy(p);
}

/* The card model's default axis limits (docs/cardmodel.md): there the
 * S-curve ramps to amax within two periods, and the planner holds one
 * jerk a period; the planner's own defaults (50000 mm/s^2) do not. */
#define CARD_VMAX	400.0
#define CARD_AMAX	5000.0

/*
 * The axes prog never moves held still, as sh2000_program_axes() holds
 * them, with a tenth of the others' limits: the scan's rule and the
 * planner's refusal agree (no block it planned is refused for moving a
 * still axis), and a still axis does not move (its set-points within its
 * lower limits).
 */
static void hold_still(const struct sh2000_program *prog,
		       struct sh2000_path_config *cfg)
{
	unsigned int moves = 0;

	for (size_t i = 0; i < prog->count; i++) {
		if (prog->blocks[i].kind == SH2000_PROG_END)
			break;
		moves |= sh2000_prog_block_axes(&prog->blocks[i], cfg->start);
	}
	cfg->still_axes = ~moves & ((1u << SH2000_AXES) - 1u);
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if (cfg->still_axes & (1u << a)) {
			cfg->vmax[a] /= 10.0;
			cfg->amax[a] /= 10.0;
		}
}

/* The input as read: its format and text (the check reads it again). */
struct input {
	enum sh2000_prog_format fmt;
	const char *text;
	size_t len;
};

static void read_options(struct sh2000_prog_options *po)
{
	sh2000_prog_options_default(po);
	po->feed_mm_s = 20.0;
}

/*
 * The margin the first pass as the front ends run it plans with
 * (sh2000_program_check(): where the set-points pass an axis' amax, it
 * plans the whole program again with a smaller one), into cfg. 1: the
 * front ends refuse the program (the check found another error, or no
 * margin kept amax: that is a failure here).
 */
static int fit_margin(const struct input *in, struct sh2000_path_config *cfg)
{
	struct sh2000_path_config c = *cfg;
	struct sh2000_program_plan plan;
	struct sh2000_prog_options po;
	struct sh2000_prog_reader *r;
	struct sh2000_prog_diags d;
	int e;

	read_options(&po);
	sh2000_prog_diags_init(&d);
	e = sh2000_prog_reader_open_text(&r, in->fmt, "fuzz", in->text,
					 in->len, &po, &d);
	if (e)
		fz_fail("the reader opened the program once, not twice (%d)", e);
	e = sh2000_program_check(r, &c, NULL, &plan);
	sh2000_prog_reader_close(r);
	sh2000_prog_diags_free(&d);
	if (e == -ERANGE && plan.accel_over)
		fz_fail("no margin down to %.3f kept amax (%u plans): %s",
			plan.margin, plan.replans + 1, plan.error);
	if (e)
		return 1;
	cfg->margin = c.margin;
	return 0;
}

/* Plan prog with pc->cfg and check its fine set-points. */
static void plan_checked(const struct sh2000_program *prog,
			 struct plan_check *pc)
{
	double seconds = 0;

	pc->points = 0;
	for (size_t i = 0; i < prog->count; i++)
		seconds += block_seconds(&pc->cfg, &prog->blocks[i]);
	pc->budget = BUDGET_FACTOR * seconds / pc->cfg.period_s + 1000.0;
	sp_init(&pc->sp, &pc->cfg, pc->cfg.start, &pc->path,
		geo_tol(prog, &pc->cfg) + pc->path.flat);
	plan(prog, pc);
}

/* Plan prog with every axis at vmax and amax (0: the planner's defaults),
 * the axes it never moves held still if hold, and check its fine
 * set-points: with the margin the front ends plan it with (fit_margin(),
 * asked only when the configured one passes amax: it plans all of a
 * program, not POINTS_CAP points). */
static void check_at(const struct input *in,
		     const struct sh2000_program *prog, double vmax,
		     double amax, int hold, int verbose)
{
	struct plan_check pc;

	memset(&pc, 0, sizeof(pc));
	sh2000_path_config_default(&pc.cfg);
	/* one jerk a period at the card's limits: a reversal is two steps */
	pc.j_overshoot = vmax > 0 ? COMP_JERK_STEP : COMP_JERK_REVERSAL;
	/* the card's usual scale: the planner refuses what counts cannot
	 * hold */
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		pc.cfg.counts_per_mm[a] = 1000.0;
		if (vmax > 0) {
			pc.cfg.vmax[a] = vmax;
			pc.cfg.amax[a] = amax;
		}
	}
	if (hold)
		hold_still(prog, &pc.cfg);
	if (sp_path_build(&pc.path, prog) == 0) {
		plan_checked(prog, &pc);
		if (pc.sp.a_ratio > 1.0) {
			double m = pc.cfg.margin;

			if (fit_margin(in, &pc.cfg))
				goto out;
			if (verbose)
				fprintf(stderr, "amax %g: %.4f of amax at the margin %.3f: planned with %.3f (sh2000_program_check)\n",
					pc.cfg.amax[0], pc.sp.a_ratio, m,
					pc.cfg.margin);
			plan_checked(prog, &pc);
		}
		if (verbose)
			fprintf(stderr, "amax %g: fine set-points: v %.4f a %.4f j %.4f of the limits, %.6f mm from the path (allowed %.6f)\n",
				pc.cfg.amax[0], pc.sp.v_ratio, pc.sp.a_ratio,
				pc.sp.j_ratio, pc.sp.dev, pc.sp.tol);
		check_setpoints(&pc, prog);
	}
out:
	sp_path_free(&pc.path);
	if (verbose)
		fprintf(stderr, "amax %g: %zu blocks, %llu points\n",
			pc.cfg.amax[0], prog->count,
			(unsigned long long)pc.points);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static int verbose = -1;
	struct sh2000_prog_options po;
	struct sh2000_prog_diags d;
	struct sh2000_program prog;
	int r;

	if (verbose < 0)
		verbose = getenv("SH2000_FUZZ_VERBOSE") != NULL;
	if (size < 1)
		return 0;
	read_options(&po);
	sh2000_program_init(&prog);
	sh2000_prog_diags_init(&d);
	r = sh2000_program_read(&prog, format_of(data[0]), "fuzz",
				(const char *)data + 1, size - 1, &po, &d);
	if (verbose)
		sh2000_prog_diags_print(&d, stderr);
	sh2000_prog_diags_free(&d);
	if (r == 0) {
		/* the planner's own defaults, then the card model's limits,
		 * where the controller holds one jerk a period */
		const struct input in = {
			format_of(data[0]), (const char *)data + 1, size - 1
		};

		check_at(&in, &prog, 0, 0, 0, verbose);
		check_at(&in, &prog, CARD_VMAX, CARD_AMAX, 0, verbose);
		check_at(&in, &prog, CARD_VMAX, CARD_AMAX, 1, verbose);
	}
	sh2000_program_free(&prog);
	return 0;
}
