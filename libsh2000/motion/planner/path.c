// SPDX-License-Identifier: MIT
/*
 * The planner's public face: configuration, creation, and the calls that
 * steer a running plan (override, pause, stop, reset, statistics). The
 * primitives are in primitives.c, the window in queue.c, the controller
 * that runs it in control.c.
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "planner.h"

/* The compensated spline's acceleration ringing over J T (below). */
#define PL_RING_K 0.1
/* the same where the controller holds one jerk a period (below) */
#define PL_RING_QUANT_K 0.02
/* How far one jerk a period may fall short of bringing the least amax
 * down within a period and every block still be capped to what it does
 * (below). */
#define PL_LAND_SHORT 1.1

static const char axis_name[] = SH2000_AXIS_LETTERS;

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

int sh2000_path_set_mode(struct sh2000_path *p, enum sh2000_path_mode mode,
			 double tolerance, double naive_tolerance)
{
	struct sh2000_path_config *c = &p->cfg;

	if (!(tolerance >= 0.0 && isfinite(tolerance)) ||
	    !(naive_tolerance >= 0.0 && isfinite(naive_tolerance)))
		return pl_err(p, -EINVAL,
			      "path mode: tolerances must be >= 0 and finite: got P %g, Q %g",
			      tolerance, naive_tolerance);
	switch (mode) {
	case SH2000_PATH_BLEND:
		c->corner_tol = tolerance > 0.0 ? tolerance : INFINITY;
		c->chord_tol = tolerance > 0.0 ? tolerance : p->base.chord_tol;
		c->naive_tol = naive_tolerance;
		break;
	case SH2000_PATH_EXACT_PATH:
	case SH2000_PATH_EXACT_STOP:
		c->corner_tol = 0.0;
		c->chord_tol = p->base.chord_tol;
		c->naive_tol = 0.0;
		break;
	default:
		return pl_err(p, -EINVAL, "path mode: unknown mode %d",
			      (int)mode);
	}
	c->mode = mode;
	return 0;
}

int sh2000_path_set_bounds(struct sh2000_path *p, const double lo[SH2000_AXES],
			   const double hi[SH2000_AXES])
{
	unsigned int a;

	if (!lo && !hi) {
		p->bounded = 0;
		return 0;
	}
	if (!lo || !hi)
		return pl_err(p, -EINVAL, "bounds: give both lo and hi, or neither");
	for (a = 0; a < SH2000_AXES; a++)
		if (!(lo[a] <= hi[a]))
			return pl_err(p, -EINVAL,
				      "bounds: %c %g..%g mm: need lo <= hi, not NaN",
				      axis_name[a], lo[a], hi[a]);
	memcpy(p->bound_lo, lo, sizeof(p->bound_lo));
	memcpy(p->bound_hi, hi, sizeof(p->bound_hi));
	p->bounded = 1;
	return 0;
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
	if (c->still_axes >> SH2000_AXES)
		BAD("config: still_axes 0x%x names an axis beyond the card's %u (0x%x)",
		    c->still_axes, SH2000_AXES, (1u << SH2000_AXES) - 1u);
	if (c->profile != SH2000_PROFILE_SCURVE &&
	    c->profile != SH2000_PROFILE_TRAPEZOID)
		BAD("config: unknown profile %d", (int)c->profile);
	if (c->profile == SH2000_PROFILE_SCURVE &&
	    !(c->jerk > 0.0 && isfinite(c->jerk)))
		BAD("config: jerk must be > 0 for the S-curve: got %g", c->jerk);
	if (c->output != SH2000_OUTPUT_COMPENSATED &&
	    c->output != SH2000_OUTPUT_RAW)
		BAD("config: unknown output mode %d", (int)c->output);
	if (!(c->corner_tol >= 0.0))
		BAD("config: corner_tol must be >= 0: got %g", c->corner_tol);
	if (!(c->naive_tol >= 0.0 && isfinite(c->naive_tol)))
		BAD("config: naive_tol must be >= 0: got %g", c->naive_tol);
	if (c->mode != SH2000_PATH_BLEND && c->mode != SH2000_PATH_EXACT_PATH &&
	    c->mode != SH2000_PATH_EXACT_STOP)
		BAD("config: unknown path mode %d", (int)c->mode);
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

/*
 * The least amax of the axes the plan may move (those not held still, or
 * all when all are: then nothing moves), and the norm of theirs, which
 * bounds what a line can get (a_top, below) but is never taken below
 * what four axes at that least amax give (2 amin). The controller's
 * landings take a_top to be at least one jerk a period held for a
 * period, which 2 amin always is where it holds one jerk a period; the
 * norm of two moving axes is not: an XY program braked X at 1.25 amax
 * (a fuzz_plan input).
 */
static double moving_amax(const struct sh2000_path_config *cfg, double *norm)
{
	unsigned int a, still = cfg->still_axes;
	double amin = INFINITY;

	if (still == (1u << SH2000_AXES) - 1u)
		still = 0;
	*norm = 0.0;
	for (a = 0; a < SH2000_AXES; a++)
		if (!(still & (1u << a))) {
			amin = fmin(amin, cfg->amax[a]);
			*norm += cfg->amax[a] * cfg->amax[a];
		}
	*norm = fmax(sqrt(*norm), 2.0 * amin);
	return amin;
}

_Static_assert(offsetof(struct sh2000_path_config, still_axes) ==
	       offsetof(struct sh2000_path_config, gantry_pair) +
	       sizeof(unsigned int) &&
	       sizeof(((struct sh2000_path_config *)0)->reserved) ==
	       16 * sizeof(uint64_t),
	       "the fields added to struct sh2000_path_config stay in its room to grow");

/* The limits the controller plans with, from the configuration: path
 * jerk, the accelerations of the block kinds, what the card's spline
 * needs (ringing, feed margin and zone), the control steps. */
static void derive_limits(struct sh2000_path *p)
{
	const struct sh2000_path_config *cfg = &p->cfg;
	double amin, norm, share;

	/* two control steps a period: the limits are checked exactly in
	 * each; more steps follow the time-optimal profile a few per cent
	 * more closely at twice the cost (bench/planner) */
	p->substeps = 2;
	amin = moving_amax(cfg, &norm);
	p->amin = amin;
	share = cfg->centripetal_share;
	p->lim.J = cfg->profile == SH2000_PROFILE_SCURVE ?
		   cfg->jerk * cfg->margin : INFINITY;
	/* A step in the acceleration overshoots by (1 + 2r/(1 + r)) times
	 * through the compensation filter (r = 2 - sqrt 3): only the
	 * trapezoid has such steps. */
	p->a_scale = cfg->profile == SH2000_PROFILE_TRAPEZOID &&
		     cfg->output == SH2000_OUTPUT_COMPENSATED ? 1.0 / 1.75 : 1.0;
	/* next to a corner that is not blended: the share the corner's
	 * axis-speed jump leaves (limits.c) */
	p->lim.A = (1.0 - share) * cfg->margin * amin * p->a_scale;
	/* along a curve, tangential and centripetal acceleration are at
	 * right angles: with the centripetal share s of the smallest amax,
	 * sqrt(1 - s^2) of it along the path keeps their sum within it */
	/* the compensated spline rings above an acceleration the S-curve
	 * reaches within about a period by up to 0.1 J T on the card's
	 * servo cycles (950 mm/s^2 at the defaults: 5500 on a line planned
	 * at 4750 without it; tests/planner test_blend, test_accel) */
	p->a_ring = cfg->profile == SH2000_PROFILE_SCURVE &&
		    cfg->output == SH2000_OUTPUT_COMPENSATED ?
		    PL_RING_K * p->lim.J * cfg->period_s : 0.0;
	/* Where a ramp to the smallest amax takes two periods or less (the
	 * card model's 5000 mm/s^2 at the default jerk: 1 ms), that ringing
	 * is most of what the S-curve gives away: the controller then holds
	 * one jerk a whole period and lands its transitions in whole
	 * periods (control.c, quant.c), and the card's spline through the
	 * points is the planned motion itself along a line. What still rings
	 * is where the path turns: braking along a line that ends in a
	 * short blend took an axis to 1.015 amax (fuzz_plan's random6 at the
	 * card model's limits), so 0.02 J T (190 mm/s^2) is kept. A slower
	 * ramp loses more to the coarser jerk than the allowance costs it
	 * (the zigzag of test_tolerance at 50000 mm/s^2: 6 % longer), and
	 * keeps the two substeps. */
	p->quant = cfg->profile == SH2000_PROFILE_SCURVE &&
		   cfg->output == SH2000_OUTPUT_COMPENSATED &&
		   cfg->margin * amin <= 2.0 * p->lim.J * cfg->period_s;
	if (p->quant) {
		p->substeps = 1;
		/* One jerk a period of 2 margin amin / T already takes the
		 * smallest amax from -A to +A within a period; a higher jerk
		 * buys nothing there but more ringing to allow for (0.02 J T
		 * grows without bound) and a coarser search: at the card
		 * model's limits a jerk of 5e7 planned 3D_Chips 8 % slower
		 * than 5e6 and arcspiral passed amax (1.019), and at 50000
		 * mm/s^2 a jerk of 5e8 stood still for ever a count before
		 * a stop. So the controller plans with at most that jerk
		 * (the card model's 4.75e6 at its defaults: unchanged). */
		p->lim.J = fmin(p->lim.J,
				2.0 * cfg->margin * amin / cfg->period_s);
		p->a_ring = PL_RING_QUANT_K * p->lim.J * cfg->period_s;
	}
	p->a_curve = pl_accel_room(p, sqrt(1.0 - share * share) *
				   cfg->margin * amin * p->a_scale);
	/* the most a line can get (min_i amax_i / |d_i| never exceeds the
	 * norm of the amax vector) */
	p->a_top = norm * cfg->margin * p->a_scale;
	/* Where one jerk a period brings the least amax down within a
	 * period, the controller lands its transitions in whole periods
	 * (control.c, land_target()); a line along a diagonal allows up to
	 * sqrt(axes) times that, and a block whose A passes J T cannot be
	 * landed on: the motion planned by a landing was handed to the
	 * braking model of two periods mid-way and passed the stop at its
	 * end at 56 mm/s (a 0.7 mm line at 7500 mm/s^2: 4.57 amax on the
	 * card's set-points). So no block allows more than J T there (at
	 * the card model's limits J T is already the most: unchanged).
	 * Likewise where J T is short of the least amax by up to
	 * PL_LAND_SHORT: at 10500 mm/s^2 (9975 against 9500) lines could
	 * not be landed on and the blends between them could, and 3D_Chips
	 * braked into a blend too fast (1.20 amax); capped, 1.0004 at 0.07 %
	 * more time. Further short, the cap would cost more than the
	 * landings buy (at 15000 mm/s^2 the benchmark programs took 4 to 8 %
	 * longer). */
	if (p->quant &&
	    cfg->margin * amin <= PL_LAND_SHORT * p->lim.J * cfg->period_s)
		p->a_top = fmin(p->a_top, p->lim.J * cfg->period_s);
	/* A jerk held over a control step never needs to move the
	 * acceleration further than from -a_top to +a_top: more only
	 * coarsens the controller's search, whose step is 2 J / 65536
	 * (control.c). Raw output at a jerk of 5e8 stood still for ever
	 * a hair before a stop it could no longer step to. */
	p->lim.J = fmin(p->lim.J, 2.0 * p->a_top * p->substeps /
				  cfg->period_s);
	/* The card's compensated spline rings above the speed a transition
	 * ends at, by about 0.004 J T^2 (0.007 A T for the trapezoid's
	 * acceleration steps), measured on its fine set-points (the feed test
	 * in tests/planner); the cruise keeps 25-40 % more below the feed. A
	 * change spreads over the spline's two periods either side, and the
	 * compensation's ringing over about six. */
	if (cfg->output == SH2000_OUTPUT_COMPENSATED && !p->quant)
		p->feed_margin = isinf(p->lim.J) ?
				 0.010 * p->a_top * cfg->period_s :
				 0.005 * p->lim.J * cfg->period_s * cfg->period_s;
	p->feed_zone = cfg->period_s *
		       (cfg->output == SH2000_OUTPUT_RAW ? 2.0 : 6.0);
}

int sh2000_path_create(struct sh2000_path **out,
		       const struct sh2000_path_config *cfg,
		       sh2000_path_sink_fn sink, void *ctx,
		       char *errbuf, size_t errlen)
{
	struct sh2000_path *p;
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
	p->base = *cfg;
	p->sink = sink;
	p->ctx = ctx;
	p->override = 1.0;
	derive_limits(p);
	p->cap = cfg->window;
	p->blk = pl_alloc(p, p->cap * sizeof(*p->blk));
	if (!p->blk) {
		free(p);
		return -ENOMEM;
	}
	p->cons = pl_alloc(p, (PL_CONS + PL_DROP) * (p->cap + 2) *
			   sizeof(double));
	p->drops = p->cons ? p->cons + PL_CONS * (p->cap + 2) : NULL;
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

void sh2000_path_destroy(struct sh2000_path *p)
{
	if (!p)
		return;
	pl_drop_blocks(p);
	sh2000_bscomp_destroy(p->comp);
	free(p->cons);
	free(p->blk);
	free(p);
}

int sh2000_path_set_override(struct sh2000_path *p, double factor)
{
	if (!(factor > 0.0 && factor <= 2.0))
		return pl_err(p, -EINVAL, "override must be in (0, 2]: got %g",
			      factor);
	p->override = factor;
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
		pl_drop_blocks(p);
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

int sh2000_path_reset(struct sh2000_path *p, const double pos[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		if (!pos || !isfinite(pos[a]))
			return pl_err(p, -EINVAL, "reset: position %c is not finite",
				      axis_name[a]);
	pl_drop_blocks(p);
	memcpy(p->pos, pos, sizeof(p->pos));
	p->fail = 0;
	p->outq_n = 0;
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
