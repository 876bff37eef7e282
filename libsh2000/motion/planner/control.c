// SPDX-License-Identifier: MIT
/*
 * The controller: moves along the queued blocks in time, one coarse period
 * at a time, and hands the points out.
 *
 * Each period is cut into a few substeps. In each substep the controller
 * picks the largest jerk (S-curve) or acceleration (trapezoid) that keeps
 * it able to honour every speed limit ahead: the current block's, each
 * later block's entry limit (corners, slower blocks) and a stop at the end
 * of what is queued. "Able" is exact: the
 * time-optimal transition from the state reached to the limit's speed must
 * fit in the distance left before it (profile.c). So the motion accelerates
 * across blocks, never reaches cruise on a short move, always can stop at
 * the end of the window, and a lower override or a pause (speed limit 0)
 * is met by the same transitions: within the limits by construction.
 * When no choice is safe (a limit just dropped), it follows the transition
 * to the lowest violated speed exactly.
 *
 * A speed limit holds a little before it drops and after it rises, and
 * the cruise stays a hair below the programmed feed (feed_zone and
 * feed_margin, set in path.c): the card's spline spreads every change over
 * a few periods, and the feed is measured on what the card does. Samples
 * on a NURBS come from nurbs_step.c.
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "planner.h"

#define V_EPS 1e-9

/* Periods a ramp to the full acceleration takes in the braking the
 * controller plans with, when it holds one jerk a period (quant.c). */
#define QUANT_RAMP 2.0

/* The jerk braking at acceleration A is planned with: the configured
 * one, or with one jerk a period, no more than a ramp to A in QUANT_RAMP
 * periods. The landing (quant.c) may use the configured jerk: the
 * difference is its room to end on a period. */
static double model_jerk(const struct sh2000_path *p, double A)
{
	if (!p->quant)
		return p->lim.J;
	return pl_min(p->lim.J, A / (QUANT_RAMP * p->cfg.period_s));
}

void pl_block_pos(const struct pl_block *b, double s, double pos[SH2000_AXES])
{
	double f = b->L > 0.0 ? s / b->L : 1.0;
	unsigned int a;

	if (f <= 0.0) {
		memcpy(pos, b->p0, sizeof(b->p0));
		return;
	}
	if (f >= 1.0) {
		memcpy(pos, b->p1, sizeof(b->p1));
		return;
	}
	switch (b->type) {
	case BLK_LINE:
		for (a = 0; a < SH2000_AXES; a++)
			pos[a] = b->p0[a] + b->g.line.d[a] * s;
		break;
	case BLK_ARC:
		sh2000_arc_point(&b->g.arc, b->p0, b->p1, f, pos);
		break;
	case BLK_BLEND: {
		double th = b->g.blend.phi * f;

		for (a = 0; a < SH2000_AXES; a++)
			pos[a] = b->g.blend.c[a] +
				 b->g.blend.R * (cos(th) * b->g.blend.u[a] +
						 sin(th) * b->g.blend.w[a]);
		break;
	}
	default:
		pl_nurbs_eval(b->g.nurbs.nb, b->g.nurbs.u0 +
			      (b->g.nurbs.u1 - b->g.nurbs.u0) * f, pos, NULL,
			      NULL);
		break;
	}
}

/* ---- one substep ------------------------------------------------------- */

struct ctl {
	struct pl_limits lim;	/* the head block's: |a| <= lim.A now */
	int trap;
	/* one jerk a whole period (quant.c): compensated S-curve */
	int quant;
	double jmax;	/* the jerk allowed; lim.J is the one planned with */
	struct sh2000_path *p;	/* the landing under way (qj, qi, qn) */
	double h, v, a, vcur;
	/* the limits ahead: (distance, speed, the acceleration allowed up to
	 * there as acc_at() reads it), PL_CONS each */
	const double *cons;
	unsigned int n;
	/* the first of them checked here: 1 where the first is left to the
	 * exact landing (land_step()) */
	unsigned int first;
	/* where the acceleration allowed drops: (distance, the acceleration
	 * as acc_at() reads it), PL_DROP each */
	const double *drops;
	unsigned int nd;
	/* the head block's acceleration at a speed (a blend's grows as the
	 * speed falls); lim.A is its value at the state the step starts
	 * from, and the limits ahead hold the others' alone */
	struct pl_accel_fn af;
};

static double peak_speed(const struct ctl *c, double v, double a);
static double peak_at(const struct ctl *c, double v, double a, double J);

/* The fastest the motion from (v, a) gets before it brakes (its speed
 * only falls then). */
static double state_top(const struct ctl *c, double v, double a)
{
	return !c->trap && a > 0.0 ? peak_speed(c, v, a) : v;
}

/* The head block's acceleration for the motion from (v, a): a blend's at
 * the fastest the motion gets before braking, brought down at the jerk
 * its own A (the least it allows) is planned with, in the substep's
 * reading of lim.A and in every check alike. Read in the checks at the
 * jerk of the acceleration the substep found (higher), a step at 3190
 * mm/s^2 in a 3.9 mm blend at 266 mm/s passed the 3114 the next period
 * allowed (zigzags of 3 mm moves turning 10 degrees at G64 P0.1: 1.039
 * amax on the card's set-points); read consistently at that higher
 * jerk, that zigzag still reached 1.0385. */
static double head_accel(const struct ctl *c, double v, double a)
{
	double top = v;

	if (!c->af.dyn)
		return c->lim.A;
	if (!c->trap && a > 0.0)
		top = peak_at(c, v, a, model_jerk(c->p, c->af.A));
	return pl_accel_at(c->p, &c->af, top);
}

/* The least acceleration of the blocks after the head up to a limit or a
 * drop, at speeds up to v: x = (the least of those whose A is constant,
 * the least floor of the short blends' (pl_accel_fn) and their largest
 * curvature); each blend allows at least its floor and at least what that
 * curvature leaves at v (pl_accel_curv()), so this bounds them all. */
static double acc_at(const struct sh2000_path *p, const double x[3],
		     double v)
{
	if (isinf(x[1]))
		return x[0];
	return pl_min(x[0], pl_max(x[1], pl_accel_curv(p, v, x[2])));
}

/* The acceleration of limit i, from (v, a): the head's and those after. */
static double cons_accel(const struct ctl *c, unsigned int i, double v,
			 double a)
{
	return pl_min(acc_at(c->p, c->cons + PL_CONS * i + 2,
			     state_top(c, v, a)),
		      head_accel(c, v, a));
}

/*
 * Distance to slow from (v, a) to speed V at A, the acceleration allowed
 * on the way to a limit (cons_accel()). A braking beyond that (the head allows more than a block
 * ahead) is brought down to it first, at full jerk: held to the end, as
 * pl_trans_plan() holds an acceleration beyond its A, it was counted
 * across the block that does not allow it. The room to a limit beyond a
 * blend of 3210 mm/s^2 then read 0 while the motion, braking at 4823 on
 * the line before it, could no longer meet that limit through the
 * blend; it braked at the line's 6255 up to the junction and into the
 * blend (a 106 mm line, then 3.6, 19.6, 3.1 and 3.6 mm into the end at
 * G64 P0.1: 1.42 amax on the card's set-points).
 */
static double cons_brake(const struct ctl *c, double A, double v, double a,
			 double V)
{
	struct pl_limits L = { A, model_jerk(c->p, A) };
	double d = 0.0;

	if (c->trap) {
		a = 0.0;
	} else if (a < -A && A < head_accel(c, v, a)) {
		pl_integrate(&d, &v, &a, L.J, (-A - a) / L.J);
		a = -A;
		if (v <= V)
			return d;
	}
	return d + pl_brake_dist(&L, v, a, V);
}

/* The distance the motion from (v, a) covers in time t with its
 * acceleration coming down at jerk J. */
static double ramp_dist(double v, double a, double J, double t)
{
	double s = 0.0;

	pl_integrate(&s, &v, &a, -J, t);
	return s;
}

/* The least speed V1 from which a braking at Ad, from a = -Ad, reaches
 * limit x's speed at the limit and starts two substeps at V1 before drop
 * y (drop_room()), and where it starts into *d: at Ad it covers
 * (V1^2 - vb^2) / 2Ad + R (vb the speed its last ramp from -Ad starts
 * at, R that ramp), at least x[0] - y[0] + 2 V1 h. */
static double switch_speed(const struct sh2000_path *p, const double *x,
			   const double *y, double h, double Ad, double *d)
{
	double Jd = model_jerk(p, Ad), vb = x[1] + Ad * Ad / (2.0 * Jd);
	double R = ramp_dist(vb, -Ad, -Jd, Ad / Jd), c = 2.0 * h * Ad;
	double q = vb * vb + 2.0 * Ad * (x[0] - y[0] - R);
	double V1 = pl_max(c * c + q > 0.0 ? c + sqrt(c * c + q) : vb, vb);

	*d = x[0] - (V1 * V1 - vb * vb) / (2.0 * Ad) - R;
	return V1;
}

/*
 * Where the allowed acceleration drops to Ad at limit x itself (a line
 * braking into a blend that allows less: the drop y lies at the limit or
 * just past it), drop_room() holds the braking within Ad from two
 * periods before the drop on, where a braking at the limit's own A,
 * ending at a = 0 on the limit, is still coming down from A. Ridden that
 * way, the braking was cut to Ad late and the motion came to the limit
 * too fast: a 1.8 mm line braking at 4438 mm/s^2 into a blend of 3202
 * entered the zigzag of 0.08 mm moves after it at 22 mm/s for 16.6 (G64
 * P0.01, the card model's limits: 1.64 amax on the card's set-points).
 *
 * So such a braking runs in two parts: at A until it passes -Ad at the
 * speed V1 where it must (two periods at V1 before the drop), then at Ad
 * to the limit. The point the braking at A to V1 - Ad^2 / 2J ends on
 * (past its ramp from -Ad: a limit like the others) into *d, *V; 0 where
 * the braking at A passes -Ad in time (or A <= Ad).
 */
static int pass_at(const struct sh2000_path *p, const double *x,
		   const double *y, double h, double A, double Ad, double *d,
		   double *V)
{
	double JA = model_jerk(p, A), Vp, V1;

	if (Ad >= A)
		return 0;
	/* the braking at A passes -Ad on its last ramp at Vp */
	Vp = x[1] + Ad * Ad / (2.0 * JA);
	if (x[0] - ramp_dist(Vp, -Ad, -JA, Ad / JA) <= y[0] - 2.0 * Vp * h)
		return 0;
	V1 = switch_speed(p, x, y, h, Ad, d);
	*d += ramp_dist(V1, -Ad, -JA, Ad / JA);
	*V = V1 - Ad * Ad / (2.0 * JA);
	return 1;
}

/* For limit x beyond the first drop of the acceleration (at x[5]): the
 * fastest the motion may pass the drop at, with a = 0, and still slow to
 * it at the least acceleration of the blocks up to it, read at the
 * fastest the motion can be in this substep of length h (as
 * limits_ahead() bounds it). */
static double drop_speed(const struct sh2000_path *p, const double *x,
			 double h)
{
	double vtop = p->v + p->a_top * h, A, Ad, v1 = -1.0, d, V;
	const double *y;
	struct pl_limits L;

	if (!isinf(p->lim.J))
		vtop += p->a_top * p->a_top / (2.0 * model_jerk(p, p->lim.A));
	A = acc_at(p, x + 2, vtop);
	L.A = A;
	L.J = model_jerk(p, A);
	if (x[8] < 0.0)
		return pl_reach_back(&L, x[1], x[0] - x[5]);
	/* a drop at the limit (pass_at()): at A to the point its braking
	 * passes, where that braking from the drop (a = 0) gets to -Ad on
	 * its way, or at Ad all the way from the drop */
	y = p->drops + PL_DROP * (unsigned int)x[8];
	Ad = pl_min(acc_at(p, y + 1, vtop), A);
	if (!pass_at(p, x, y, h, A, Ad, &d, &V))
		return pl_reach_back(&L, x[1], x[0] - x[5]);
	if (d > x[5]) {
		v1 = pl_reach_back(&L, V, d - x[5]);
		if (L.J * (v1 - V) < Ad * Ad)
			v1 = -1.0;
	}
	L.A = Ad;
	L.J = model_jerk(p, Ad);
	return pl_max(v1, pl_reach_back(&L, x[1], x[0] - x[5]));
}

/* The distance the motion from (v, a > 0) covers bringing a down to 0
 * at full jerk. Not where the controller holds one jerk a period and
 * can land in one (J h >= A): there the landing (quant.c) brings a down
 * on whole periods, and counted here (over at least a period) it moved
 * the card-limit sweeps both ways (zigzag, 10 degrees, 3 mm, P0.1:
 * 1.0094 amax to 0.984; spiral, 10 degrees, 1.5 mm, P0.01: 0.976 to
 * 1.0022, a limit just before a short blend missed as before). Where a
 * ramp to A takes longer than a period (15000 mm/s^2 at the default
 * jerk) there is no landing to count on: left out, a blend reached the
 * arc after it still accelerating, under the speed from which the arc
 * could stop but too late to settle, and took the stop at its end at 80
 * mm/s (cds.ngc: 4.1 amax on the card's set-points). */
static double settle_dist(const struct ctl *c, double v, double a)
{
	if (a <= 0.0 || (c->quant && c->jmax * c->h >= c->lim.A))
		return 0.0;
	return ramp_dist(v, a, c->lim.J, a / c->lim.J);
}

/* Whether a braking at A from (v, a) to speed V (cons_brake()) gets to
 * -Ad on its way. */
static int brakes_past(const struct ctl *c, double A, double v, double a,
		       double V, double Ad)
{
	double J = model_jerk(c->p, A);

	if (v <= V || (a > 0.0 && v + a * a / (2.0 * J) <= V))
		return 0;
	return a <= -Ad || (2.0 * J * (v - V) + a * a) / 2.0 >= Ad * Ad;
}

/* A braking to a limit (two_part_room()): where it ends (INFINITY: not on
 * a point to land on), at what speed and acceleration, and the room it
 * leaves. */
struct goal {
	double d, V, A, room;
};

/*
 * Room left, after a step to (s, v, a), to slow to limit i all the way at
 * the least acceleration A of the blocks up to it, that braking into g if
 * asked. Where the acceleration drops to Ad at the limit itself
 * (pass_at(), Ad read at the state as drop_room() reads it), the larger
 * of two: at A to the point which that braking passes at -Ad where it
 * must, and at Ad all the way (a braking beyond it brought to it first at
 * full jerk, as drop_room() reads it). The first only where the braking
 * at A gets to -Ad on its way down: from a state slower than the point,
 * at a = 0, the point's speed says nothing of the limit's (a zigzag of
 * 0.2 mm moves turning 60 degrees in turn took a blend at 1.7 amax when
 * its room read it so).
 */
static double two_part_room(const struct ctl *c, unsigned int i, double s,
			    double v, double a, struct goal *g)
{
	const double *x = c->p->cons + PL_CONS * i, *y;
	double A = cons_accel(c, i, v, a), r, d = 0.0, V;
	struct goal k = { x[0], x[1], A, 0.0 };
	struct pl_limits L;

	y = x[8] < 0.0 ? NULL : c->drops + PL_DROP * (unsigned int)x[8];
	L.A = y ? pl_min(acc_at(c->p, y + 1, state_top(c, v, a)), A) : A;
	if (!y || !pass_at(c->p, x, y, c->h, A, L.A, &d, &V)) {
		k.room = x[0] - s - cons_brake(c, A, v, a, x[1]);
		goto out;
	}
	L.J = model_jerk(c->p, L.A);
	r = brakes_past(c, A, v, a, V, L.A) ?
	    d - s - cons_brake(c, A, v, a, V) : -INFINITY;
	k.d = d;
	k.V = V;
	d = 0.0;
	if (a < -L.A) {
		pl_integrate(&d, &v, &a, c->lim.J, (-L.A - a) / c->lim.J);
		a = -L.A;
	}
	k.room = x[0] - s - d - pl_brake_dist(&L, v, a, x[1]);
	if (r > k.room) {
		/* at A towards the point: a braking passes it, not one to
		 * land on */
		k.d = INFINITY;
		k.room = r;
	} else {
		k.d = x[0];
		k.V = x[1];
		k.A = L.A;
	}
out:
	if (g)
		*g = k;
	return k.room;
}

/* Room left, after a step to (s, v, a), to slow to limit i ahead (at its
 * distance d - s > 0): negative when it no longer can. Either all the way
 * at the least acceleration of the blocks up to it, or, while the motion
 * is before the first drop of the acceleration, by slowing at the head's
 * (every block before the drop allows as much) to the speed from which
 * the blocks after the drop can still slow to the limit at theirs, on
 * the drop with a = 0 (limits_ahead()): the acceleration comes down to 0
 * before the drop too (the speed may be under that one while a > 0, and
 * a that is still climbing there took the three lines of G64 P0.1 at
 * amax 50000 to 3.2 amax braking into the stop); once past the drop, the first way
 * holds from there, since that speed is its own braking curve. */
static double cons_room(const struct ctl *c, unsigned int i, double s,
			double v, double a)
{
	double *x = c->p->cons + PL_CONS * i;
	double r = two_part_room(c, i, s, v, a, NULL);

	if (r < 0.0 && x[5] - s > 0.0 && isnan(x[6]))
		x[6] = drop_speed(c->p, x, c->h);
	if (x[5] - s > 0.0 && x[6] >= 0.0 && r < 0.0) {
		double A = head_accel(c, v, a), aa = c->trap ? 0.0 : a;
		struct pl_limits L = { A, model_jerk(c->p, A) };

		r = pl_max(r, x[5] - s - pl_max(pl_brake_dist(&L, v, aa, x[6]),
						settle_dist(c, v, aa)));
	}
	/* a nearer limit that implies this one, still ahead: its room */
	if (r < 0.0 && x[7] >= 0.0 && c->cons[PL_CONS * (unsigned int)x[7]] > s)
		r = pl_max(r, cons_room(c, (unsigned int)x[7], s, v, a));
	return r;
}

/* Room left, after a step to (s, v, a), to bring the acceleration down to
 * drop i's before it: negative when it no longer can. The step that
 * crosses a drop is checked only at its end, so the drop counts two
 * substeps early. Braking (a < 0) counts too where the controller holds
 * one jerk a whole period: a period's braking into a block that allows
 * less would take its axes past their amax (3D_Chips: 1.3 amax); the
 * substeps of the other mode keep that overshoot within a half period. */
static double drop_room(const struct ctl *c, unsigned int i, double s,
			double v, double a)
{
	const double *x = c->drops + PL_DROP * i;
	double Ad = acc_at(c->p, x + 1, state_top(c, v, a)), J = c->lim.J, t;
	double dd = x[0] - s - 2.0 * v * c->h;

	if (a <= Ad && (!c->quant || a >= -Ad))
		return INFINITY;
	if (c->trap)
		return dd;
	t = (fabs(a) - Ad) / J;	/* at full jerk to Ad, covering ... */
	if (a < 0.0)		/* ... at most the speed now (braking) */
		return dd - t * v;
	return dd - ramp_dist(v, a, J, t);
}

/* The speed reached from (v, a > 0) bringing a down to 0: at full jerk,
 * or with one jerk a period, in a whole period at least (a a period
 * later: v + a h / 2), which is what the landing can do. */
static double peak_speed(const struct ctl *c, double v, double a)
{
	return peak_at(c, v, a, c->lim.J);
}

/* The same with the acceleration brought down at jerk J. */
static double peak_at(const struct ctl *c, double v, double a, double J)
{
	double dv = a * a / (2.0 * J);

	if (c->quant)
		dv = pl_max(dv, a * c->h / 2.0);
	return v + dv;
}

/* The speed's room under a limit already in force (its zone began behind:
 * a lower feed's feed_zone, a corner's): its speed V less the speed now
 * and, while accelerating, less the peak the motion reaches; negative
 * when the limit is passed. Such a limit binds the speed alone. */
static double in_force_slack(const struct ctl *c, double V, double v,
			     double a)
{
	double m = V + V_EPS - v;

	if (!c->trap && a > 0.0)
		m = pl_min(m, V + V_EPS - peak_speed(c, v, a));
	return m;
}

static void step_state(const struct ctl *c, double j, double *s, double *v,
		       double *a)
{
	*s = 0.0;
	*v = c->v;
	*a = c->trap ? j : c->a;
	pl_integrate(s, v, a, c->trap ? 0.0 : j, c->h);
}

/* Never backwards: higher j is better here. */
static int lower_ok(const struct ctl *c, double j)
{
	double s, v, a;
	unsigned int i;

	step_state(c, j, &s, &v, &a);
	if (v < -V_EPS)
		return 0;
	if (!c->trap && a < -c->lim.A * (1.0 + 1e-12))
		return 0;
	if (!c->trap) {
		if (j > 0.0 && c->a < 0.0 && -c->a / j < c->h &&
		    c->v - c->a * c->a / (2.0 * j) < -V_EPS)
			return 0;
		if (a < 0.0 && v - a * a / (2.0 * c->lim.J) < -V_EPS)
			return 0;
	}
	for (i = 0; i < c->nd && a < 0.0; i++)
		if (drop_room(c, i, s, v, a) < 0.0)
			return 0;
	return 1;
}

/* The limits ahead, from the state reached after advancing s. */
static int cons_ok(const struct ctl *c, double s, double v, double a)
{
	unsigned int i;

	if (c->af.dyn && !c->trap &&
	    a > head_accel(c, v, a) * (1.0 + 1e-12))
		return 0;
	for (i = c->first; i < c->n; i++) {
		double d = c->cons[PL_CONS * i] - s, V = c->cons[PL_CONS * i + 1];

		if (d <= 0.0) {
			if (v > V + V_EPS)
				return 0;
			if (!c->trap && a > 0.0 &&
			    peak_speed(c, v, a) > V + V_EPS)
				return 0;
		} else if (cons_room(c, i, s, v, a) < -1e-12) {
			return 0;
		}
	}
	for (i = 0; i < c->nd; i++)
		if (drop_room(c, i, s, v, a) < 0.0)
			return 0;
	return 1;
}

/* Every limit ahead can still be met after a step with jerk j (lower j is
 * better here) when this is >= 0: the least room any of the conditions
 * leaves (no acceleration above A, no speed above the current limit
 * within the step or on the way to a = 0, cons_ok() on the state
 * reached). The rooms are speeds or distances; only their signs and their
 * zeros, where the binding condition is just met, matter to the search. */
static double upper_slack(const struct ctl *c, double j)
{
	double s, v, a, pk, m;
	unsigned int i;

	step_state(c, j, &s, &v, &a);
	m = c->trap ? INFINITY : c->lim.A * (1.0 + 1e-12) - a;
	if (c->af.dyn && !c->trap)
		m = pl_min(m, head_accel(c, v, a) * (1.0 + 1e-12) - a);
	/* the speed at the start counts only when it is too high: as a
	 * constant room it would hide how the others change with j */
	if (c->v > c->vcur + V_EPS)
		m = pl_min(m, c->vcur + V_EPS - c->v);
	pk = v;
	if (!c->trap && c->a > 0.0 && a < 0.0)
		pk = pl_max(pk, c->v + c->a * c->a / (2.0 * fabs(j)));
	m = pl_min(m, c->vcur + V_EPS - pk);
	if (!c->trap && a > 0.0)
		m = pl_min(m, c->vcur + V_EPS - peak_speed(c, v, a));
	for (i = c->first; i < c->n && m >= 0.0; i++) {
		double d = c->cons[PL_CONS * i] - s, V = c->cons[PL_CONS * i + 1];

		if (d > 0.0) {
			m = pl_min(m, 1e-12 + cons_room(c, i, s, v, a));
			continue;
		}
		m = pl_min(m, in_force_slack(c, V, v, a));
	}
	for (i = 0; i < c->nd && m >= 0.0 && a > 0.0; i++)
		m = pl_min(m, drop_room(c, i, s, v, a));
	return m;
}

static double slack_at(const void *c, double j)
{
	return upper_slack(c, j);
}

/* The highest jerk in [lo, hi] with upper_slack() >= 0, lo passing (flo)
 * and hi failing (fhi), to 2J / 65536 (search.c). */
static double highest_jerk(const struct ctl *c, double lo, double hi,
			   double flo, double fhi)
{
	return pl_highest_pass(slack_at, c, lo, hi, flo, fhi,
			       (hi - lo) / 65536.0);
}

/*
 * Where the lowest jerk fails too, some between may still pass: braking
 * hardest passes a drop's acceleration or a later limit's (drop_room(),
 * cons_room() with the braking beyond A), braking least a limit ahead,
 * and a band between keeps all. 16 jerks from lo to hi: the highest that
 * passes, and the next above it as the bracket's top (*hi, *fhi), its
 * slack in *flo; lo (its slack negative in *flo) if none. Left to
 * brake() instead, 10 moves of 0.2 mm into a stop (G64 P0.01, F24000)
 * reached the end point at 8 mm/s and were held there: 1.90 amax.
 */
static double passing_jerk(const struct ctl *c, double lo, double hi,
			   double *flo, double *fhi, double *top)
{
	double best = lo, fb = *flo, above = hi, fa = *fhi;

	for (unsigned int k = 1; k < 16; k++) {
		double j = lo + (hi - lo) * k / 16.0, f = upper_slack(c, j);

		if (f >= 0.0 && lower_ok(c, j)) {
			best = j;
			fb = f;
			above = k < 15 ? lo + (hi - lo) * (k + 1) / 16.0 : hi;
			fa = k < 15 ? upper_slack(c, above) : *fhi;
		}
	}
	if (!(fb >= 0.0) || fa >= 0.0)
		return lo;
	*flo = fb;
	*fhi = fa;
	*top = above;
	return best;
}

/* The speed of the limit that binds: the current one if it is exceeded,
 * else the one ahead with the least room left (the braking curve the
 * controller is riding); in *A the acceleration to ride it with. */
static double danger(const struct ctl *c, double *A, double *d)
{
	double vt = c->vcur, slack = INFINITY;
	unsigned int i;

	*A = c->lim.A;
	*d = INFINITY;
	if (c->v > c->vcur + V_EPS || (!c->trap && c->a > 0.0 &&
	    peak_speed(c, c->v, c->a) > c->vcur + V_EPS))
		return c->vcur;
	for (i = c->first; i < c->n; i++) {
		const double *x = c->cons + PL_CONS * i;
		double r;
		/* slowing to the speed at the drop where that is what holds */
		int at_drop;
		struct goal g;

		/* a limit in force binds the speed alone: met, it has no
		 * distance to run out of. Read by its room (negative behind
		 * the carriage), a feed lowered by 1 mm/min into a short
		 * blend bound the braking to the program's end to the
		 * blend's speed, which took the stop past its end point
		 * (8.1 amax at the card model's limits) */
		if (x[0] <= 0.0 && in_force_slack(c, x[1], c->v, c->a) >= 0.0)
			continue;
		r = cons_room(c, i, 0.0, c->v, c->a);
		at_drop = x[0] > 0.0 &&
			  two_part_room(c, i, 0.0, c->v, c->a, &g) < r;

		if (r < slack) {
			slack = r;
			vt = fmin(c->vcur, at_drop ? x[6] : g.V);
			*A = at_drop ? c->lim.A : pl_min(g.A, c->lim.A);
			/* a limit already in force binds the speed alone */
			*d = vt < (at_drop ? x[6] : g.V) || x[0] <= 0.0 ?
			     INFINITY : at_drop ? x[5] : g.d;
		}
	}
	return vt;
}

/* Follow the exact time-optimal transition to speed vt at acceleration A
 * for one substep. */
static void follow(const struct ctl *c, double vt, double A, double *ds,
		   double *v, double *a)
{
	struct pl_limits L = { A, model_jerk(c->p, A) };
	struct pl_trans tr;
	double t = c->h;
	unsigned int i;

	*ds = 0.0;
	*v = c->v;
	*a = c->trap ? 0.0 : c->a;
	/* a positive acceleration comes down at the head's jerk, as
	 * peak_speed() counted it: at a lower limit's (a short blend's
	 * 2185 mm/s^2 after a line at 5922) the speed passed that limit */
	if (!c->trap && *a > 0.0 && c->lim.J > L.J && vt < *v) {
		double t0 = pl_min(*a / c->lim.J, t);

		pl_integrate(ds, v, a, -c->lim.J, t0);
		t -= t0;
		if (t <= 0.0)
			return;
		*a = 0.0;
	}
	pl_trans_plan(&L, *v, *a, vt, &tr);
	for (i = 0; i < (unsigned int)tr.n && t > 0.0; i++) {
		double dt = pl_min(tr.dur[i], t);

		if (c->trap)
			*a = tr.acc[i];
		pl_integrate(ds, v, a, tr.jerk[i], dt);
		t -= dt;
		if (dt == tr.dur[i] && i + 1 == (unsigned int)tr.n) {
			*v = vt;
			*a = 0.0;
		}
	}
	if (t > 0.0) {
		*a = 0.0;
		pl_integrate(ds, v, a, 0.0, t);
	}
	if (c->trap)
		*a = 0.0;
}

static void pop_head(struct sh2000_path *p)
{
	struct pl_block *b = &p->blk[p->head];

	if (b->type == BLK_NURBS)
		pl_nurbs_put(p, b->g.nurbs.nb);
	p->a_prev = b->A;
	p->land_line = NULL;
	p->head = (p->head + 1) % p->cap;
	p->count--;
	if (p->pending)
		pl_nurbs_expand(p);
}

static struct pl_block *head(struct sh2000_path *p)
{
	return &p->blk[p->head];
}

/*
 * The limits ahead that can matter in a substep of length h from the
 * current state, into p->cons as (distance, speed, acceleration) triples:
 * a descending staircase, since a limit no lower than a nearer one is met
 * by meeting that one and holding the speed, and nothing further than any
 * stop from the fastest this substep can lead to. Each block's limit is
 * local: its junction and the feeds of it and of the block before; the
 * controller checks every limit ahead from the exact state, so no
 * backward pass is needed. A stop at the end of what is queued closes the
 * list.
 *
 * The acceleration differs from block to block (pl_block_accel()): each
 * limit is checked at the smallest acceleration of the blocks before it
 * (A0: the head's), where the braking curve to it runs (it ends at a = 0
 * where the limit starts), so it holds wherever it runs,
 * and where that smallest acceleration drops, the drop goes into
 * p->drops (distance, acceleration), a staircase too: the controller
 * brings its acceleration down before it gets there. Next to a corner
 * that is not blended, over the two periods of its speed, the
 * acceleration is lim.A: the corner's turn takes the rest of the axes'.
 */
/* The acceleration of the blocks so far, as acc_at() reads it. */
struct acc_run {
	double x[3];
};

/* Block k into the run (Ak: its A, or with fixed set the A of the
 * corner zone at its start, which holds whatever the speed); 1 if that
 * lowered what the run allows at some speed. */
static int acc_run_add(struct acc_run *r, const struct pl_block *k,
		       double Ak, int fixed)
{
	double kappa;

	if (!pl_accel_dyn(k) || fixed) {
		if (Ak >= r->x[0])
			return 0;
		r->x[0] = Ak;
		return 1;
	}
	kappa = 1.0 / k->g.blend.R;
	if (k->A >= r->x[0] || (k->A >= r->x[1] && kappa <= r->x[2]))
		return 0;
	r->x[1] = pl_min(r->x[1], k->A);
	r->x[2] = pl_max(r->x[2], kappa);
	return 1;
}

/*
 * For each of the n limits ahead, the nearest one before it that implies
 * it (x[7], -1 if none): one of nearly its speed (within 5 %) from which
 * the motion can still slow to this one's in the distance between, at
 * the least acceleration on the way to this one (which bounds the blocks
 * between), where a block on the way allows less than those up to the
 * nearer one. Such a limit can be met wherever the nearer one can
 * (cons_room()): its own room, at the least acceleration of all its
 * blocks, counts one that may lie beyond the nearer limit, where the
 * motion is slow already. Once a braking was no longer counted beyond a
 * block's acceleration (cons_brake()), a corner of the surfacing program
 * at 7.85 mm/s with another at 7.84 mm/s 1 mm beyond it past a block of
 * 3202 mm/s^2 had the controller ride the later one's braking at 3202
 * from 260 mm/s and lose the nearer: 11 amax.
 *
 * Further apart in speed, a limit's own room is what keeps the motion
 * from speeding into a short blend: read through the nearer limit, a 10
 * degree zigzag of 1.5 mm moves at G64 P0.1 reached 1.018 amax. And only
 * where the controller holds one jerk a period: there a braking is within
 * a block's acceleration before the motion enters it (drop_room()), so
 * the motion that meets the nearer limit can take the blocks between at
 * theirs; in the other mode it may enter one braking harder for up to
 * half a period, and stops beyond a blend at 50000 mm/s^2 passed amax
 * (test_safe, test_planner's random programs).
 */
static void implied_by(struct sh2000_path *p, unsigned int n)
{
	unsigned int i, k;

	for (i = 0; i < n; i++) {
		double *x = p->cons + PL_CONS * i;

		x[7] = -1.0;
		for (k = i; p->quant && k-- > 0;) {
			const double *y = p->cons + PL_CONS * k;
			/* read at the faster one's speed: a short blend
			 * allows less the faster the motion */
			double A = acc_at(p, x + 2, y[1]);
			struct pl_limits L = { A, model_jerk(p, A) };

			/* only where a block between allows less: else the
			 * limit's own room is as good, and read through the
			 * nearer one, the spiral of short arcs to rest
			 * (arcspiral.ngc's end) swung its acceleration
			 * between them to 1.04 amax */
			if (y[1] >= x[1] && x[1] >= 0.95 * y[1] &&
			    A < 0.999 * acc_at(p, y + 2, y[1]) &&
			    x[0] - y[0] >= pl_brake_dist(&L, y[1], 0.0, x[1])) {
				x[7] = k;
				break;
			}
		}
	}
}

/*
 * For limit x, the first drop of the acceleration its run does not hold
 * (x[8] on entry: the drops before it are in the run), where that drop
 * lies at the limit or just past it (within two substeps at the fastest
 * the motion can be: what drop_room() counts before a drop), in x[8];
 * -1 if none. Only where the controller holds one jerk a period: only
 * there does drop_room() hold a braking (pass_at()).
 */
static void near_drop(const struct sh2000_path *p, double *x, double h,
		      unsigned int m)
{
	double vtop = p->v + p->a_top * h;
	unsigned int k = (unsigned int)x[8];

	x[8] = -1.0;
	if (!p->quant || !(x[0] > 0.0) || k >= m)
		return;
	vtop += p->a_top * p->a_top / (2.0 * model_jerk(p, p->lim.A));
	if (p->drops[PL_DROP * k] < x[0] + 2.0 * vtop * h)
		x[8] = k;
}

static unsigned int limits_ahead(struct sh2000_path *p, double h,
				 double level, int halt, double A0,
				 unsigned int *nd)
{
	/* lim.A is the least any block has: the longest braking */
	const struct pl_limits L = { p->lim.A, model_jerk(p, p->lim.A) };
	const struct pl_limits *lim = &L;
	int trap = isinf(lim->J);
	double zone = 2.0 * p->cfg.period_s, vup = p->v + p->a_top * h, dh, d;
	struct acc_run run = { { A0, INFINITY, 0.0 } };
	unsigned int i, n = 0, m = 0;

	dh = vup * (h + zone) +
	     pl_brake_dist(lim, vup, trap ? 0.0 : p->a_top, 0.0) + 1e-9;
	level = fmin(level, vup + (trap ? 0.0 : p->a_top * p->a_top /
				   (2.0 * lim->J)));
	d = head(p)->L - p->s;
	for (i = 1; i < p->count && d <= dh; i++) {
		const struct pl_block *k = pl_block_at(p, i);
		double V = halt ? 0.0 : pl_entry_limit(p, i);
		/* the card's spline spans two periods either side of a
		 * corner: the corner speed holds over them */
		double t = k->corner ? zone : 0.0, Ak = k->A;
		int fixed = k->corner && k->vj > 0.0;
		double *x;

		if (fixed)
			Ak = fmin(Ak, lim->A);
		/* a line to rest out of a curve: its ring zone at its start,
		 * as a corner's zone (the line's own A once past it) */
		if (pl_ring_zone(p, k, 0.0)) {
			fixed = 1;
			Ak = pl_accel_room(p, Ak);
		}
		if (V < level) {
			/* a lower feed holds from feed_zone before; the
			 * braking to it runs in the blocks before, at their
			 * acceleration, ending at a = 0 where a corner's
			 * zone starts (the zone's lim.A is a drop there,
			 * which a = 0 meets) */
			if (k->feed < k->prev_feed)
				t = fmax(t, p->feed_zone);
			x = p->cons + PL_CONS * n++;
			x[0] = d - t * V;
			x[1] = V;
			memcpy(x + 2, run.x, sizeof(run.x));
			x[8] = m;	/* the drops not in its run */
			level = V;
		}
		if (acc_run_add(&run, k, Ak, fixed)) {
			x = p->drops + PL_DROP * m++;
			x[0] = d - (k->corner ? zone : 0.0) * V;
			memcpy(x + 1, run.x, sizeof(run.x));
		}
		d += k->L;
	}
	if (i == p->count && d <= dh && level > 0.0) {
		double *x = p->cons + PL_CONS * n++;

		x[0] = d;
		x[1] = 0.0;
		memcpy(x + 2, run.x, sizeof(run.x));
		x[8] = m;
	}
	implied_by(p, n);
	for (i = 0; i < n; i++)
		near_drop(p, p->cons + PL_CONS * i, h, m);
	for (i = 0; i < n; i++) {	/* cons_room(): when it needs them */
		p->cons[PL_CONS * i + 5] = m ? p->drops[0] : 0.0;
		p->cons[PL_CONS * i + 6] = m && p->drops[0] > 0.0 &&
					   p->cons[PL_CONS * i] > p->drops[0] ?
					   NAN : -1.0;
	}
	*nd = m;
	return n;
}

/* The first of n periods of constant jerk that land on speed vt at
 * acceleration 0 (n = 2), at distance d as well (n = 3), into (ds, v, a):
 * 1 if every period keeps |j| <= J, |a| <= A (Aend at the last
 * PL_LAND_END period ends: a drop at d) and the speed between the
 * start's and vt. */
static int quant_try(const struct ctl *c, unsigned int n, double d,
		     double vt, const double A[2], double *ds, double *v,
		     double *a)
{
	double j[PL_QUANT_MAX], s = 0.0, vv = c->v, aa = c->a, h = c->h;
	double lo = pl_min(c->v, vt) - V_EPS, hi = pl_max(c->v, vt) + V_EPS;
	unsigned int k;

	if (pl_quant_solve(h, c->v, c->a, n, !isinf(d), d, vt, j))
		return 0;
	for (k = 0; k < n; k++) {
		double t = j[k] != 0.0 ? -aa / j[k] : -1.0;

		if (fabs(j[k]) > c->jmax * (1.0 + 1e-9))
			return 0;
		/* the speed's extreme inside the period */
		if (t > 0.0 && t < h) {
			double ve = vv - aa * aa / (2.0 * j[k]);

			if (ve < lo || ve > hi)
				return 0;
		}
		pl_integrate(&s, &vv, &aa, j[k], h);
		if (fabs(aa) > A[k + 1 + PL_LAND_END >= n] * (1.0 + 1e-12) ||
		    vv < lo || vv > hi)
			return 0;
		if (k == 0) {
			*ds = s;
			*v = vv;
			*a = aa;
		}
	}
	memcpy(c->p->qj, j, n * sizeof(j[0]));
	c->p->qi = 1;
	c->p->qn = n;
	/* landed: exactly */
	if (fabs(*v - vt) < 1e-9 && fabs(*a) < 1e-6) {
		*v = vt;
		*a = 0.0;
	}
	return 1;
}

/* The fewest periods (up to PL_QUANT_MAX) that land that way. */
static int quant_step(const struct ctl *c, double d, double vt, double A,
		      double *ds, double *v, double *a)
{
	const double caps[2] = { A, A };
	unsigned int n;

	for (n = isinf(d) ? 2 : 3; n <= PL_QUANT_MAX; n++)
		if (quant_try(c, n, d, vt, caps, ds, v, a))
			return 1;
	return 0;
}

/* Brake towards the binding speed; if that still leaves a limit ahead
 * out of reach, towards the lowest such one. */
static void brake(const struct ctl *c, double *ds, double *v, double *a)
{
	double A, d, vt = danger(c, &A, &d);
	unsigned int i, k;


	if (c->quant && quant_step(c, d, vt, A, ds, v, a)) {
		if (cons_ok(c, *ds, *v, *a))
			return;
		/* not taken: its jerks, kept by quant_try(), must not go on
		 * from a state they were not planned from (they ran a stop
		 * below zero speed: tests/planner test_stop_landing) */
		c->p->qn = 0;
	}

	for (i = 0; i <= c->n; i++) {
		double lowest = vt;
		int lowered = 0;

		follow(c, vt, A, ds, v, a);
		for (k = c->first; k < c->n; k++) {
			double dd = c->cons[PL_CONS * k] - *ds;
			double V = c->cons[PL_CONS * k + 1];

			if (V < lowest &&
			    (dd <= 0.0 ? *v > V + V_EPS :
			     cons_room(c, k, *ds, *v, *a) < -1e-12)) {
				lowest = V;
				/* at the acceleration of the nearest such
				 * limit: a later one's least may lie beyond
				 * it (corners of 4.05 and 4.03 mm/s, the
				 * second past a block of 3202 mm/s^2:
				 * braking at that lost the first, 6.8 amax) */
				if (!lowered)
					A = pl_min(A, cons_accel(c, k, c->v,
								 c->a));
				lowered = 1;
			}
		}
		if (lowest == vt)
			break;
		vt = lowest;
	}
	/* the same acceleration at the period's end by one jerk, where that
	 * still meets every limit ahead (a switch inside the period rings) */
	if (c->quant) {
		double s1, v1, a1;

		step_state(c, (*a - c->a) / c->h, &s1, &v1, &a1);
		if (v1 >= -V_EPS && cons_ok(c, s1, v1, a1)) {
			*ds = s1;
			*v = v1;
			*a = a1;
		}
	}
}

/* The bisection for the extreme jerk that passes ok(), between lo and hi;
 * want_low: the lowest that passes, else the highest. 16 halvings leave
 * the jerk within 2J / 65536 of the extreme, far below what the
 * profile's other roundings give away. */
static double bisect(const struct ctl *c, int (*ok)(const struct ctl *, double),
		     double lo, double hi, int want_low)
{
	unsigned int i;

	for (i = 0; i < 16; i++) {
		double m = 0.5 * (lo + hi);

		if (ok(c, m) == want_low)
			hi = m;
		else
			lo = m;
	}
	return want_low ? hi : lo;
}

/*
 * The step of this substep: the largest jerk (S-curve) or acceleration
 * (trapezoid) that keeps every limit ahead reachable and never runs
 * backwards. Cheap cases first: full jerk, then the exact transition to
 * the current limit (cruise, and no chattering around it); the bisection
 * only when neither will do.
 */
static void greedy_step(const struct ctl *c, double *ds, double *v, double *a)
{
	double J = c->trap ? c->lim.A : c->jmax, jl, jh, fJ, fl;

	/* a landing under way goes on while the limits ahead allow it */
	if (c->quant && c->p->qi < c->p->qn) {
		step_state(c, c->p->qj[c->p->qi], ds, v, a);
		if (*v >= -V_EPS && fabs(*a) <= c->lim.A * (1.0 + 1e-12) &&
		    cons_ok(c, *ds, *v, *a)) {
			c->p->qi++;
			return;
		}
	}
	c->p->qn = 0;

	fJ = upper_slack(c, J);
	if (fJ >= 0.0 && lower_ok(c, J)) {
		step_state(c, J, ds, v, a);
		if (c->trap)
			*a = J;
		return;
	}
	if (c->v <= c->vcur + V_EPS) {
		/* in whole periods where they land (no switch inside one),
		 * else the search, whose jerk holds a whole period */
		const double caps[2] = { c->lim.A, c->lim.A };

		if (c->quant ? quant_try(c, 2, INFINITY, c->vcur, caps,
					 ds, v, a) :
		    (follow(c, c->vcur, c->lim.A, ds, v, a), 1))
			if (cons_ok(c, *ds, *v, *a)) {
				return;
			}
	}
	/* the lowest jerk that does not run backwards ... */
	jl = lower_ok(c, -J) ? -J : bisect(c, lower_ok, -J, J, 1);
	/* ... and the highest that keeps every limit reachable */
	fl = upper_slack(c, jl);
	jh = fl >= 0.0 ? highest_jerk(c, jl, J, fl, fJ) : NAN;
	if (isnan(jh) || !lower_ok(c, jh)) {
		brake(c, ds, v, a);
		if (!(fl >= 0.0) && !cons_ok(c, *ds, *v, *a)) {
			/* brake() leaves a limit out of reach: a jerk between
			 * that keeps them all, if there is one */
			jl = passing_jerk(c, jl, J, &fl, &fJ, &J);
			if (fl >= 0.0) {
				c->p->qn = 0;
				step_state(c, highest_jerk(c, jl, J, fl, fJ),
					   ds, v, a);
			}
		}
		return;
	}
	step_state(c, jh, ds, v, a);
	if (c->trap)
		*a = jh;
}

/* The most periods the motion may stand still on its way (a corner taken
 * at rest takes one): more is a fault, not a plan. */
#define PL_STILL_MAX 10000

/* The most periods an exact landing may take (400 mm/s at 475 mm/s^2
 * takes 422). */
#define PL_LAND_MAX 1024

/* A head block whose end the controller may land on: a line or an arc;
 * a blend only where it ends at a tangent junction into a line or a
 * blend whose curvature steps there (S-bends: braking late inside the
 * blend and then held at the junction's speed, the acceleration swung
 * from -2300 to +1150 mm/s^2 in the period before the flip, 1.045 amax
 * on the card's set-points). Not a NURBS (it re-synchronises its
 * distance to its samples), nor a blend into an arc or a corner: landed
 * there, blends whose curvature flips reached 1.06 amax. */
static int land_head(struct sh2000_path *p)
{
	const struct pl_block *b = head(p), *n;

	if (b->type == BLK_LINE || b->type == BLK_ARC)
		return 1;
	if (b->type != BLK_BLEND || p->count < 2)
		return 0;
	n = pl_block_at(p, 1);
	return n->type != BLK_ARC && !n->corner && !isinf(n->vj);
}

/* A limit to land on: its distance and speed, and the acceleration
 * allowed on the way (cap[0]) and over the last PL_LAND_END periods
 * (cap[1]: lower where the allowed acceleration drops at the limit). */
struct land {
	double d, V, cap[2];
	const double *drop;	/* that drop (as p->drops), or NULL */
};

/* The accelerations a landing on t from (v, a) brakes within, read at
 * the fastest the motion gets from there (a blend's grows as the speed
 * falls). A landing checked from a step's state reads them at that
 * state: read at the state before, a line's step towards a short blend
 * at its full acceleration left a landing the next period no longer had
 * (the blend's then 2185 against 3758 mm/s^2), and the motion entered
 * the blend 40 % over its speed (S-bends of 0.3 mm moves, G64 P0.01:
 * 1.057 amax on the card's set-points). */
static void land_caps(const struct ctl *c0, struct land *t, double v,
		      double a)
{
	struct ctl cc = *c0;
	const struct ctl *c = &cc;

	/* the fastest as the next substep reads it (substep(): a blend's
	 * at the jerk of its own A; read at the jerk of the A it allows
	 * now, a landing from a step at 3900 mm/s^2 into a 0.13 mm blend
	 * found 3900 where the next period found 3573, and the motion
	 * passed the blend's exit limit at 1.6 times it: 1.95 amax on a
	 * spiral of 0.1 mm moves turning 45 degrees at G64 P0.01) */
	if (cc.af.dyn)
		cc.lim.J = model_jerk(c0->p, head(c0->p)->A);
	t->cap[0] = cons_accel(c, 0, v, a);
	t->cap[1] = t->cap[0];
	if (t->drop) {
		/* at the fastest the landing can be over those periods */
		double top = pl_min(state_top(c, v, a),
				    t->V + PL_LAND_END * c->h * t->cap[0]);

		t->cap[1] = pl_min(t->cap[0], acc_at(c->p, t->drop + 1, top));
	}
}

/* How far a landing on speed V may end: at the end of the head block,
 * or, braking (V below the speed now), at the end of a line after it
 * shorter than a period at the speed now, the limit at its end no arc's
 * nor a corner's. The blends leave such lines of a few hundredths of a
 * millimetre of a move; with the limit just past the head, the braking
 * left to the greedy step reached its speed a period early at up to
 * -2800 mm/s^2 and swung back up (S-bends of 1.1 mm moves, G64 P0.1:
 * 1.0066 amax on the card's set-points). Not towards a higher speed: a
 * step towards one before a drop into a blend reached 1.13 amax. Once a
 * landing reached to such a line, it still does while the head is the
 * same (p->land_line), however slow the motion: read at the falling
 * speed, the line turned longer than a period half way through the
 * landing, which was dropped for a braking too late for the reversal at
 * the line's end (1.93 amax on the card's set-points). */
static double land_reach(const struct ctl *c, double V)
{
	struct sh2000_path *p = c->p;
	double rem = head(p)->L - p->s;
	const struct pl_block *n, *k;

	if (!(V < c->v) || p->count < 3)
		return rem;
	n = pl_block_at(p, 1);
	k = pl_block_at(p, 2);
	if (n->type != BLK_LINE || n->corner ||
	    (n->L >= c->v * c->h && n != p->land_line) ||
	    k->type == BLK_ARC || k->corner || isinf(k->vj))
		return rem;
	p->land_line = n;
	return rem + n->L;
}

/* Whether the state a landing on t ends in, (V, a = 0) on the limit,
 * still keeps every limit beyond it: each period of a landing is checked
 * from its own end, but the rest of the landing is taken as it was
 * planned. Landed on a corner's speed with a stop 1.8 mm past it, the
 * motion came to the corner too fast to stop, reached the end point at
 * 21 mm/s and was held there: 4.19 amax on the card's set-points (two
 * moves, 8 mm and 1.55 mm at 6.2 degrees, G64 P0.01, F24000). */
static int land_end_ok(const struct ctl *c, const struct land *t)
{
	struct ctl g = *c;

	g.first = 1;
	return cons_ok(&g, t->d, t->V, 0.0);
}

/* The first limit ahead, to be landed on exactly in whole periods
 * (pl_quant_land()): a stop or a lower speed (a corner's, a blend's or an
 * arc's, a slower block's, where the curvature steps) at the end of the
 * head block (land_head()), where the controller holds one jerk a period
 * with J h >= A, and not while it pauses or stops (that brakes at once,
 * wherever the motion comes to rest); 0 if not. Where the allowed
 * acceleration drops at the limit itself (a line into a blend that
 * allows less), the landing brakes within the lower one over the periods
 * before it, where drop_room() holds the motion to it: landed at the
 * line's, a 60 degree zigzag of 1.2 mm moves at G64 P0.01 entered its
 * blends 26 % over their speed (1.11 amax on the card's set-points). */
static int land_target(const struct ctl *c, struct land *t)
{
	if (!c->quant || c->trap || !c->n ||
	    c->jmax * c->h < c->lim.A || c->p->paused || c->p->stopping)
		return 0;
	t->d = c->cons[0];
	t->V = c->cons[1];
	if (!(t->d > 0.0) || (c->nd && c->drops[0] < t->d) ||
	    !land_head(c->p) || t->d > land_reach(c, t->V) + 1e-9)
		return 0;
	t->drop = c->nd && c->drops[0] <= t->d ? c->drops : NULL;
	land_caps(c, t, c->v, c->a);
	return land_end_ok(c, t);
}

/* The first period of the fewest that land on the limit (d, V) at
 * acceleration A, into (ds, v, a), if it keeps the current speed limit
 * within the period and every other limit ahead (c->first = 1): how
 * many periods they are, 0 if none. */
static int land_first(const struct ctl *c, const struct land *t,
		      double *ds, double *v, double *a)
{
	unsigned int n;
	double a1, j, d = t->d, V = t->V;
	int r = pl_quant_land(c->h, c->v, c->a, V, d, t->cap[0], t->cap[1],
			      c->jmax, 0, PL_LAND_MAX, &n, &a1);

	if (r < 0)
		return 0;
	if (n == 1 && !r) {
		/* landed: on the limit itself (a stop a hair past it, so
		 * that the block ends there) */
		*ds = V > 0.0 ? d : d + 1e-12;
		*v = V;
		*a = 0.0;
		return 1;
	}
	/* as smooth as the least-squares jerks where they land as soon */
	if (!r && n >= 3 && n <= PL_QUANT_MAX &&
	    quant_try(c, n, d, V, t->cap, ds, v, a) && cons_ok(c, *ds, *v, *a))
		return (int)n;
	c->p->qn = 0;
	j = (a1 - c->a) / c->h;
	step_state(c, j, ds, v, a);
	*a = a1;
	if (*v > c->vcur + V_EPS ||
	    (c->a > 0.0 && j < 0.0 && -c->a / j < c->h &&
	     c->v - c->a * c->a / (2.0 * j) > c->vcur + V_EPS))
		return 0;
	return cons_ok(c, *ds, *v, *a) ? (int)n : 0;
}

/* pl_quant_land() on t from the state (s, v, a) a step reaches, with
 * t's accelerations read at that state. */
static int land_from(const struct ctl *c, const struct land *t, double s,
		     double v, double a, unsigned int *n)
{
	struct land at = *t;
	double a1;

	land_caps(c, &at, v, a);
	return pl_quant_land(c->h, v, a, at.V, at.d - s, at.cap[0], at.cap[1],
			     c->jmax, 1, PL_LAND_MAX, n, &a1);
}

/* The highest jerk above jl from whose state a landing is left (by
 * bisection on whether every landing from it passes the limit), within
 * J, A and the current speed limit (v + a h / 2 at the period's end: a
 * landing brings a down to 0 within a period at most), into (ds, v, a):
 * the periods to the landing that way, 0 if none. The greedy step
 * plans its braking with a ramp of two periods: a short move from rest
 * then accelerated too little (10 mm/s over 0.035 mm: 5 periods, not 4),
 * or, where no landing was left from its step, too much. */
static int land_climb(const struct ctl *c, const struct land *t,
		      double jl, double *ds, double *v, double *a)
{
	double h = c->h, lo = pl_max(-c->a / h, jl), s1, v1, a1;
	double hi = pl_min(pl_min(c->jmax, (t->cap[0] - c->a) / h),
			   (c->vcur - c->v - 1.5 * c->a * h) / (h * h));
	unsigned int i, n;

	if (c->a < 0.0 || !(hi > lo))
		return 0;
	step_state(c, lo, &s1, &v1, &a1);
	if (land_from(c, t, s1, v1, a1, &n) == -2)
		return 0;
	for (i = 0; i < 24; i++) {
		double m = 0.5 * (lo + hi);

		step_state(c, m, &s1, &v1, &a1);
		if (land_from(c, t, s1, v1, a1, &n) == -2)
			hi = m;
		else
			lo = m;
	}
	step_state(c, lo, ds, v, a);
	if (land_from(c, t, *ds, *v, *a, &n) < 0)
		return 0;
	return *v <= c->vcur + V_EPS && cons_ok(c, *ds, *v, *a) ?
	       (int)n + 1 : 0;
}

/*
 * The step of this substep. Where the first limit ahead can be landed on
 * exactly in whole periods (land_target()), the fewest periods to it of:
 * the greedy step, which leaves it out, where a landing is left from the
 * state it reaches; the highest jerk from whose state one is
 * (land_climb()); the first period of the fewest that land from here.
 * The braking the greedy step plans with (a ramp of QUANT_RAMP periods)
 * is longer than that landing: braking to a stop by it took a period
 * more than the fewest (a 20 mm side of a square at 100 mm/s: 113
 * periods, not 112).
 */
static void choose_step(const struct ctl *c, double *ds, double *v, double *a)
{
	struct land t;
	double cs[3];
	unsigned int n;
	int ng = 0, nl, nc;

	if (land_target(c, &t)) {
		struct ctl g = *c;

		/* the drops are at the limit or beyond it: the motion ends
		 * there at a = 0, and the landing holds the one at the
		 * limit (t.cap[1]) */
		g.first = 1;
		g.nd = 0;
		greedy_step(&g, ds, v, a);
		if (land_from(c, &t, *ds, *v, *a, &n) >= 0)
			ng = (int)n + 1;
		nc = land_climb(&g, &t, ng ? (*a - c->a) / c->h : -INFINITY,
				cs, cs + 1, cs + 2);
		if (ng && (!nc || ng <= nc))
			return;
		c->p->qn = 0;
		nl = ng ? 0 : land_first(&g, &t, ds, v, a);
		if (nc && (!nl || nc < nl)) {
			c->p->qn = 0;	/* no least-squares landing of nl's */
			*ds = cs[0];
			*v = cs[1];
			*a = cs[2];
			return;
		}
		if (nl)
			return;
	}
	greedy_step(c, ds, v, a);
}

/* Past the end of the head block into the next ones. */
static void advance_blocks(struct sh2000_path *p)
{
	struct pl_block *b = head(p);

	while (p->s >= b->L) {
		if (p->count <= 1) {
			p->s = b->L;
			break;
		}
		p->s -= b->L;
		pop_head(p);
		b = head(p);
	}
}

/* The least distance the jerk search (highest_jerk(), its step 2 J /
 * 65536, 2 A / 65536 for the trapezoid) surely steps from rest in h,
 * and at least 1e-6 mm: a stop nearer than that is stepped onto at
 * once, with a = 0 at its end. A step of the search covers J h^3 / 6 of
 * it from rest (a h^2 / 2); the search itself only moves once its jerk
 * covers the whole distance, so a stop a hair nearer than its step was
 * never reached (a raw plan at a jerk of 5e8 stood 1.2e-6 mm before one
 * for ever). */
static double rest_hair(const struct sh2000_path *p, double A, double h)
{
	double step = isinf(p->lim.J) ? A * h * h / 65536.0 :
		      p->lim.J * h * h * h / 196608.0;

	return fmax(1e-6, 4.0 * step);
}

/* One substep; returns 1 when the motion has come to rest. */
static int substep(struct sh2000_path *p, double h)
{
	struct pl_block *b = head(p);
	int halt = p->paused || p->stopping;
	double zone = 2.0 * p->cfg.period_s, ds, v, a;
	struct ctl c;
	unsigned int n;

	c.lim.J = p->lim.J;
	c.lim.A = b->A;
	c.trap = isinf(p->lim.J);
	c.quant = p->quant;
	c.jmax = p->lim.J;
	c.p = p;
	c.h = h;
	c.v = p->v;
	c.a = p->a;
	c.vcur = halt ? 0.0 : pl_cap(p, b);
	/* a stop has no zone: s a rounding below zero (a curve's arc
	 * accounting) must not hold the carriage at the corner for ever */
	pl_accel_fn_init(p, b, &c.af);
	if (b->corner && b->vj > 0.0 && p->s < zone * b->vj) {
		c.vcur = fmin(c.vcur, b->vj);
		c.lim.A = fmin(c.lim.A, p->lim.A);
		c.af.dyn = 0;
	} else if (pl_ring_zone(p, b, p->s)) {
		c.lim.A = fmin(c.lim.A, pl_accel_room(p, b->A));
	} else if (c.af.dyn) {
		/* at the fastest this state gets to before braking, as
		 * the checks read it */
		c.lim.A = head_accel(&c, c.v, c.a);
	}
	/* a higher feed only once the lower one is feed_zone behind */
	if (!halt && b->feed > b->prev_feed &&
	    p->s < p->feed_zone * pl_prev_cap(p, b))
		c.vcur = fmin(c.vcur, fmax(pl_prev_cap(p, b), 0.0));
	c.lim.J = model_jerk(p, c.lim.A);
	n = limits_ahead(p, h, c.vcur, halt,
			 c.af.dyn ? c.af.Amax : c.lim.A, &c.nd);
	c.cons = p->cons;
	c.n = n;
	c.first = 0;
	c.drops = p->drops;
	if (n && p->cons[PL_CONS * (n - 1) + 1] == 0.0 &&
	    p->cons[PL_CONS * (n - 1)] < rest_hair(p, c.lim.A, h) &&
	    p->v < 1e-4 && !halt) {
		/* at rest a hair before a stop (exact stop, end of the
		 * queue): the transitions land within rounding of it */
		ds = fmax(p->cons[PL_CONS * (n - 1)], 0.0);
		v = a = 0.0;
	} else {
		choose_step(&c, &ds, &v, &a);
	}
	p->s += fmax(ds, 0.0);
	p->dist_now += fmax(ds, 0.0);
	p->v = fmax(v, 0.0);
	p->a = a;
	advance_blocks(p);
	b = head(p);
	if (p->v <= 1e-12 && fabs(p->a) <= 1e-9 &&
	    ((p->count == 1 && p->s >= b->L) || halt)) {
		p->v = p->a = 0.0;
		return 1;
	}
	return 0;
}

/* ---- sampling ----------------------------------------------------------- */

/* ---- output ------------------------------------------------------------ */

/* A point for the sink, queued: the sink may hold it (-EAGAIN, a feed hold
 * on the card) and take it later; nothing the controller made is lost. */
static void queue_point(struct sh2000_path *p, const double x[SH2000_AXES],
			unsigned int flags)
{
	struct sh2000_path_point *pt;
	unsigned int a;

	pt = &p->outq[(p->outq_head + p->outq_n) % PL_OUTQ];
	p->outq_n++;
	memset(pt, 0, sizeof(*pt));
	for (a = 0; a < SH2000_AXES; a++) {
		pt->mm[a] = x[a];
		if (p->cfg.counts_per_mm[a] > 0.0)
			pt->counts[a] = (int32_t)llround(x[a] *
							 p->cfg.counts_per_mm[a]);
	}
	pt->flags = flags;
	pt->seq = p->count ? head(p)->seq : p->seq;
	pt->index = p->points;
	p->points++;
	if (flags & SH2000_PATH_F_END)
		p->motions++;
}

/* Hand the queued points to the sink, oldest first. */
static int drain(struct sh2000_path *p)
{
	while (p->outq_n) {
		int r = p->sink(p->ctx, &p->outq[p->outq_head]);

		if (r == -EAGAIN)
			return pl_err(p, r, "the sink holds the points (a feed hold); call again");
		if (r < 0) {
			p->fail = r;
			return pl_err(p, r, "the sink failed: %d", r);
		}
		p->outq_head = (p->outq_head + 1) % PL_OUTQ;
		p->outq_n--;
	}
	return 0;
}

/* Whether the card's compensated spline may stop exactly on a rest point
 * whose stop and start accelerate at up to A (bscomp.c): the exact stop
 * keeps the card's acceleration within the S-curve's only where its ramp
 * A/J lasts a period or more. A faster ramp is a step to the spline, which
 * a stop exact in one period overshoots (1.14 of amax at 5000 mm/s^2 and
 * the default jerk, 1.03 at 9000, 0.96 at 10000 where A/J is 0.9 T):
 * there the stop rings as before. The trapezoid's steps never take it.
 * stop: the motion that ends there lasted PL_REST_PERIODS (or there is
 * none);
 * next: the length of the move that starts there (0: none), at least what
 * the S-curve covers from rest to rest in PL_REST_PERIODS. */
static int exact_rest(const struct sh2000_path *p, double A, int stop,
		      double next)
{
	double t = PL_REST_PERIODS * p->cfg.period_s;

	return !isinf(p->lim.J) && A >= p->lim.J * p->cfg.period_s &&
	       (!stop || p->since_rest >= PL_REST_PERIODS) &&
	       (next == 0.0 || next >= p->lim.J * t * t * t / 32.0);
}

static int emit(struct sh2000_path *p, const double q[SH2000_AXES], int end)
{
	double P[SH2000_AXES];
	int last, rest = !end && p->v <= 1e-12 && fabs(p->a) <= 1e-9 &&
			 p->count;
	unsigned int k;

	if (!p->comp) {
		/* at rest on the way (a corner taken at v = 0): the card's
		 * approximating spline meets a point only where three records
		 * in a row are that point, so it holds there two periods more
		 * (else it cuts the corner by a sixth of the steps around it) */
		for (k = 0; k < (rest ? 3u : 1u); k++)
			queue_point(p, q, end ? SH2000_PATH_F_END : 0);
		return drain(p);
	}
	/* the compensated spline stops on it, not rings through it, where
	 * it may */
	p->since_rest++;
	if (rest) {
		/* resting on: as it was when it came to rest */
		rest = p->since_rest <= 1 ? p->rest_exact :
		       exact_rest(p, fmin(p->a_prev, head(p)->A), 1,
				  head(p)->L);
		p->rest_exact = rest;
		p->since_rest = 0;
	}
	if (pl_bscomp_push(p->comp, q, rest, P))
		queue_point(p, P, 0);
	if (end)
		pl_bscomp_exact(p->comp, exact_rest(p, p->count ?
				fmin(p->a_prev, head(p)->A) : p->a_prev, 1,
				0.0));
	while (end && sh2000_bscomp_flush(p->comp, P, &last))
		queue_point(p, P, last ? SH2000_PATH_F_END : 0);
	return drain(p);
}

int pl_period(struct sh2000_path *p)
{
	double h = p->cfg.period_s / p->substeps, q[SH2000_AXES], ds;
	unsigned int k;
	int rest = 0, r;

	if (p->fail)
		return pl_err(p, p->fail, "the sink failed (%d); reset the planner",
			      p->fail);
	r = drain(p);
	if (r)
		return r;
	if (!p->moving) {
		if (p->pending)
			pl_nurbs_expand(p);
		if (p->stopping) {
			pl_stopped(p);
			return 1;
		}
		if (p->count == 0 || p->paused)
			return 1;
		p->moving = 1;
		p->still = 0;
		p->v = p->a = 0.0;
		p->dist_now = 0.0;
		p->a_prev = INFINITY;
		if (p->comp) {
			p->rest_exact = exact_rest(p, head(p)->A, 0,
						   head(p)->L);
			pl_bscomp_exact(p->comp, p->rest_exact);
			p->since_rest = 0;
			sh2000_bscomp_start(p->comp, p->pos);
		}
	}
	for (k = 0; k < p->substeps && !rest; k++) {
		rest = substep(p, h);
		/* stopped on the way (a corner taken at rest) within the
		 * period: it rests there to the period's end, so that the stop
		 * is a point the card's spline can stop on (emit()) */
		if (!rest && p->v <= 1e-12 && fabs(p->a) <= 1e-9)
			break;
	}
	ds = p->dist_now;
	p->dist_now = 0.0;
	if (!rest && !(ds > 0.0) && !p->paused && !p->stopping &&
	    ++p->still > PL_STILL_MAX)
		return pl_err(p, -EDEADLK,
			      "the planner stood still for %u periods %.3g mm before the end of its move, at %.6f %.6f %.6f: a fault of the planner (please report the program and the configuration)",
			      p->still, pl_max(head(p)->L - p->s, 0.0),
			      p->pos[0], p->pos[1], p->pos[2]);
	if (ds > 0.0 || rest)
		p->still = 0;
	if (rest && p->count == 1 && p->s >= head(p)->L) {
		memcpy(q, head(p)->p1, sizeof(q));
		pop_head(p);
		p->s = 0.0;
		p->hist_id = 0;
	} else if (head(p)->type == BLK_NURBS) {
		pl_nurbs_sample(p, head(p), ds, q);
	} else {
		pl_block_pos(head(p), p->s, q);
		p->hist_id = 0;
	}
	memcpy(p->pos, q, sizeof(q));
	r = emit(p, q, rest);
	if (r)
		return r;
	if (rest) {
		p->moving = 0;
		if (p->stopping)
			pl_stopped(p);
		return 1;
	}
	return 0;
}

int pl_make_room(struct sh2000_path *p)
{
	unsigned int need = pl_room(p);

	while (p->count + need > p->cap) {
		int r = pl_period(p);

		if (r < 0)
			return r;
		/* at rest (paused): room for the block itself will do, its
		 * corner is then taken at the junction speed */
		if (r == 1 && p->count < p->cap)
			return 0;
		if (r == 1)
			return pl_err(p, -EAGAIN,
				      "the look-ahead window is full and the planner is paused");
	}
	return 0;
}

int sh2000_path_run(struct sh2000_path *p, unsigned int max_points)
{
	uint64_t p0 = p->points;

	while (p->points - p0 < max_points) {
		int r = pl_period(p);

		if (r < 0)
			return r;
		if (r == 1)
			break;
	}
	return (int)(p->points - p0);
}

int sh2000_path_finish(struct sh2000_path *p)
{
	pl_rest_after(p);	/* the last block ends at rest */
	for (;;) {
		int r = pl_period(p);

		if (r < 0)
			return r;
		if (r == 1) {
			if (p->count == 0 && !p->pending)
				return 0;
			if (p->paused)
				return pl_err(p, -EAGAIN,
					      "paused with %u blocks left; resume and finish again",
					      p->count);
		}
	}
}
