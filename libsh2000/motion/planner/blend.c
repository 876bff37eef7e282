// SPDX-License-Identifier: MIT
/*
 * Corner blending within the path tolerance (G64 P): where two moves meet
 * at a corner, the ends of both are cut away and replaced by a curve
 * tangent to both, as deep as the tolerance allows (without a tolerance,
 * G64 alone, as deep as the moves allow) and no longer than half of either
 * move. The path stays within the tolerance and the corner is taken at the
 * blend's speed instead of the speed at which the axes can turn in one
 * period.
 *
 * Two straight moves: one circular arc in the plane of the two moves
 * (LinuxCNC's trajectory planner blends the same way); its depth is exact.
 * A corner next to an arc, a helix or the end of a NURBS (line-arc,
 * arc-line, arc-arc in any planes, a NURBS' first or last block against
 * any of them): a biarc, two circular arcs meeting tangentially, from the
 * point and tangent where the first move is cut to those where the second
 * one is (biarc.c). No single circle is tangent to a helix and a line in
 * general, while a biarc exists for any two points and tangents, in any
 * number of axes, and is made of the blend arcs the controller already
 * knows. Its depth has no closed form: it is measured against the pieces
 * cut away and the cut is shortened until it fits.
 *
 * A wide turn between moves much faster than its blend is not blended
 * but visited at rest, exactly, where that is faster (stop_faster()).
 */
#include <math.h>
#include <string.h>

#include "planner.h"

/* Blends narrower than this are not worth a block. */
#define BLEND_MIN_MM 1e-6
/* What the blend itself may take of the tolerance: the rest is for the
 * card's spline, which passes the curvature steps at the arc's ends within
 * about half a micrometre when compensated at the card model's 5000
 * mm/s^2 (a micrometre is kept; at most half the tolerance), and cuts the
 * arc inwards by (vT)^2 / 6R when raw (half the tolerance; the arc's speed
 * keeps the cut within it). The compensated spline's error grows with the
 * step of acceleration it passes, so the room kept is at least
 * A T^2 / BLEND_SPLINE_DIV for the axes' least acceleration A: at the
 * planner's default 50000 mm/s^2 a blend of two lines at F240020 passed
 * the spline 2.09 um beyond the blend (fuzz_plan, regress-blend-ring). */
#define BLEND_SPLINE_MM 0.001
#define BLEND_SPLINE_DIV 50.0
#define BLEND_SHARE_RAW 0.5
/* The card's spline rounds a blend shorter than its points are apart as
 * if the corner were sharp (pl_corner_spline_vlim()): two thirds of the
 * tolerance for that cut, a third for the speed changing around the
 * corner, which spaced the points unevenly and took a blend at 50000
 * mm/s^2 from 9.6 um (constant speed) to 11.1 um (fuzz_plan,
 * regress-blend-short). */
#define BLEND_CORNER_SPLINE 2.0
/* An arc is cut by at most this angle (rad): over it the arc stays close
 * to its tangent, so the corner's tolerance rule gives a first cut the
 * measurement rarely has to shorten. */
#define BLEND_ARC_TURN 0.5
/* What of the move before a corner a blend may take when the blend at its
 * start has taken its half (a sliver stays: the move keeps its length and
 * tangent). */
#define BLEND_TAIL_KEEP 0.98
/* The largest turn (rad) whose blend may take more than BLEND_SHARE_MIN
 * (up to PL_SHARE_MAX): past it an axis' own acceleration, the tangential
 * braking and then the centripetal, both along it, went past its amax on
 * the card's compensated set-points (2.2 times, the surfacing raster's
 * 90 degree ends at 0.866; tests/planner test_blend). */
#define BLEND_SHARE_TURN (M_PI / 4.0)
/* The least centripetal share of any blend (the configured one where it
 * is more). The blend's speed sqrt(s M R) grows with it and the braking
 * into it, at sqrt(1 - s^2) M, costs more: measured on the card's fine
 * set-points (bench/lcnc-compare's bench_peaks at margin 0.95), 0.7
 * planned 3D_Chips in 35.284 s (0.5: 35.666), cds 34.412 (34.598), the
 * pocket 11.072 (11.124), the surface 101.240 (101.252), every axis' peak
 * acceleration over a servo cycle within main's (3D_Chips 1.0026 amax,
 * main 1.0057); 0.6 was slower and 3D_Chips reached 1.0133, 0.8 slower
 * on cds, and at 0.866 tests/planner test_tolerance and test_blend
 * failed. */
#define BLEND_SHARE_MIN 0.7
/* Chords of a piece of an arc when measuring a biarc against it. */
#define PIECE_CHORDS 16u
/* Samples of each biarc arc, ends included. */
#define BIARC_SAMPLES 9u
/* Tries at shortening the cut of a biarc. */
#define BIARC_TRIES 12u
/* A corner is stopped on instead of blended (stop_faster()) only where
 * the blend's speed is at most this share of the speed the moves reach
 * on either side: the braking from well above it, which the comparison
 * counts on (at 0.4 and 0.5, G64's zigzag of tests/planner test_tolerance
 * took 10 % longer with its 135 degree corners stopped; 3D_Chips.ngc
 * planned 35.714 s at 0.25, 35.666 s at 0.35, 35.672 s at 0.5). */
#define STOP_VB_SHARE 0.35

/* Blocks a blend may cut: lines, arcs and NURBS blocks. */
static int cuttable(const struct pl_block *b)
{
	return b->type == BLK_LINE || b->type == BLK_ARC ||
	       b->type == BLK_NURBS;
}

/* Whether b starts where t ends: exactly, or for a NURBS, whose ends are
 * evaluated, within the rounding of its evaluation. */
static int meet(const struct pl_block *t, const struct pl_block *b)
{
	double d[SH2000_AXES];
	unsigned int a;

	if (t->type != BLK_NURBS && b->type != BLK_NURBS)
		return !memcmp(t->p1, b->p0, sizeof(t->p1));
	for (a = 0; a < SH2000_AXES; a++)
		d[a] = b->p0[a] - t->p1[a];
	return pl_dot(d, d) < BLEND_MIN_MM * BLEND_MIN_MM;
}

/* The last block queued, if it is one that can still be cut short. */
static struct pl_block *tail_block(struct sh2000_path *p)
{
	struct pl_block *t;

	if (!p->count || p->count + PL_ROOM > p->cap)
		return NULL;
	t = (struct pl_block *)pl_block_at(p, p->count - 1);
	if (!cuttable(t) || t->stop_after)
		return NULL;
	/* the controller may be in it: leave what it is about to reach */
	if (p->count == 1 && p->moving)
		return NULL;
	return t;
}

/* The longest cut of block b at a corner: half of it (the rest is for the
 * corner after it), but of the move before the corner (tail: under a
 * finite tolerance; G64 alone would round a whole run of near-tangent
 * moves away) nearly all that is left once the blend at its start has
 * taken its half; on an arc
 * no more than BLEND_ARC_TURN of its sweep. */
static double max_cut(const struct pl_block *b, int tail)
{
	double d = (tail && b->nblend ? BLEND_TAIL_KEEP : 0.5) * b->L;

	if (b->type == BLK_ARC)
		d = pl_min(d, BLEND_ARC_TURN * b->L / fabs(b->g.arc.sweep));
	return d;
}

/* The speed limit of a blend when the output is raw: the card's spline
 * cuts an arc of radius R by (vT)^2 / 6R, kept within the tolerance's
 * other share. */
static void raw_limit(const struct sh2000_path *p, double share,
		      struct pl_block *k)
{
	double tol = p->cfg.corner_tol;

	if (p->cfg.output == SH2000_OUTPUT_RAW && !isinf(tol) &&
	    k->type == BLK_BLEND)
		k->vlim = pl_min(k->vlim, sqrt(6.0 * k->g.blend.R *
						  (1.0 - share) * 0.9 * tol) /
				 p->cfg.period_s);
}

/* Largest distance of a point from the polyline through n points. */
static double poly_dist(const double x[SH2000_AXES],
			const double (*pts)[SH2000_AXES], unsigned int n)
{
	double m = INFINITY;
	unsigned int i;

	for (i = 0; i + 1 < n; i++)
		m = pl_min(m, pl_seg_dist(x, pts[i], pts[i + 1]));
	return m;
}

/* The piece b of a NURBS block as a polyline, evenly in its parameter;
 * in *sag how far the curve strays from its chords: twice what it does
 * at each chord's middle parameter (a chord this short of a smooth curve
 * is nearly an arc's, whose sagitta is at its middle). */
static unsigned int nurbs_poly(const struct pl_block *b,
			       double (*pts)[SH2000_AXES], double *sag)
{
	double u0 = b->g.nurbs.u0, du = (b->g.nurbs.u1 - u0) / PIECE_CHORDS;
	double m[SH2000_AXES];
	unsigned int i;

	*sag = 0.0;
	for (i = 0; i < PIECE_CHORDS; i++)
		pl_nurbs_eval(b->g.nurbs.nb, u0 + du * i, pts[i], NULL, NULL);
	memcpy(pts[PIECE_CHORDS], b->p1, sizeof(b->p1));	/* C(u1) */
	for (i = 0; i < PIECE_CHORDS; i++) {
		pl_nurbs_eval(b->g.nurbs.nb, u0 + du * (i + 0.5), m, NULL, NULL);
		*sag = pl_max(*sag, 2.0 * pl_seg_dist(m, pts[i], pts[i + 1]));
	}
	return PIECE_CHORDS + 1;
}

/* The piece b of a line, an arc or a NURBS block as a polyline; returns
 * its points and in *sag how far the chords may fall inside the curve. */
static unsigned int piece_poly(const struct pl_block *b,
			       double (*pts)[SH2000_AXES], double *sag)
{
	unsigned int i, n = b->type == BLK_LINE ? 1 : PIECE_CHORDS;

	if (b->type == BLK_NURBS)
		return nurbs_poly(b, pts, sag);
	*sag = 0.0;
	if (b->type == BLK_ARC) {
		double h = b->L / n;

		*sag = h * h / (8.0 * pl_min(b->g.arc.r0, b->g.arc.r1));
	}
	for (i = 0; i <= n; i++)
		pl_block_pos(b, b->L * i / n, pts[i]);
	return n + 1;
}

/* How far the blend blocks k[0..n) stray from the two pieces they
 * replace (a bound: their sampled points against the pieces' chords plus
 * the chords' sagitta). */
static double deviation(const struct pl_block *ca, const struct pl_block *cb,
			const struct pl_block *k, unsigned int n)
{
	double pa[PIECE_CHORDS + 1][SH2000_AXES];
	double pb[PIECE_CHORDS + 1][SH2000_AXES];
	double sa, sb, dev = 0.0, x[SH2000_AXES];
	unsigned int na = piece_poly(ca, pa, &sa), nb = piece_poly(cb, pb, &sb);
	unsigned int i, j;

	for (i = 0; i < n; i++)
		for (j = 0; j < BIARC_SAMPLES; j++) {
			pl_block_pos(&k[i], k[i].L * j / (BIARC_SAMPLES - 1), x);
			dev = pl_max(dev, pl_min(poly_dist(x, pa, na) + sa,
						 poly_dist(x, pb, nb) + sb));
		}
	return dev;
}

/* The centripetal share a blend may take: where the moves' length bounds
 * it rather than the tolerance (G64 alone, or short moves of a curve as
 * CAM writes them, blended end to end), or before a move too short to
 * reach its feed from rest, the blend is about all there is between the
 * corners and runs at its limit, so more of the acceleration goes across
 * the path. Before a longer move the braking at the blend's smaller
 * tangential acceleration (control.c checks a limit at the least
 * acceleration before it) costs more than the blend's speed gains. */
static double blend_smax(const struct sh2000_path *p,
			 const struct pl_block *t, const struct pl_block *b,
			 double phi)
{
	double f = pl_min(b->feed, p->cfg.vmax[0]), tol = p->cfg.corner_tol;
	/* the cut the tolerance allows (blend_lines) against the moves' */
	double dtol = isinf(tol) ? INFINITY : tol / tan(phi / 4);
	int by_length = dtol > pl_min(max_cut(t, !isinf(tol)), max_cut(b, 0));

	return phi < BLEND_SHARE_TURN &&
	       (by_length || b->L < f * f / (2.0 * p->a_top)) ?
	       PL_SHARE_MAX : pl_max(p->cfg.centripetal_share, BLEND_SHARE_MIN);
}

/* Two lines: the arc whose middle lies share * tol from the corner, its
 * cut d along both. */
static unsigned int blend_lines(struct sh2000_path *p, struct pl_block *t,
				struct pl_block *b, double phi, double tol,
				double smax, struct pl_block *k)
{
	double d, R;

	R = isinf(tol) ? INFINITY : tol * cos(phi / 2) / (1.0 - cos(phi / 2));
	d = R * tan(phi / 2);
	d = pl_min(d, pl_min(max_cut(t, !isinf(tol)), max_cut(b, 0)));
	if (d < BLEND_MIN_MM)
		return 0;
	pl_block_cut(t, 0.0, t->L - d, t);
	pl_block_cut(b, d, b->L, b);
	if (pl_arc_to(p, t->p1, t->t1, b->p0, pl_min(t->feed, b->feed), smax,
		      k))
		return 0;
	memcpy(k->t1, b->t0, sizeof(k->t1));	/* tangent to b exactly */
	return 1;
}

/* Next to an arc or a NURBS: a biarc, its cuts shortened until it stays
 * within tol of the corner's pieces (and no slower than the corner
 * itself). */
static unsigned int blend_curves(struct sh2000_path *p, struct pl_block *t,
				 struct pl_block *b, double phi, double tol,
				 double smax, struct pl_block *k)
{
	double d, dt, db, vcorner = pl_junction(p, t->t1, b->t0);
	struct pl_block ta, tb, ca, cb;
	unsigned int n, i, tries;

	d = isinf(tol) ? INFINITY : tol / tan(phi / 4);	/* R tan(phi/2) */
	dt = pl_min(d, max_cut(t, !isinf(tol)));
	db = pl_min(d, max_cut(b, 0));
	for (tries = 0; tries < BIARC_TRIES; tries++) {
		double dev, vmin = INFINITY, scale = 0.5;

		if (pl_max(dt, db) < BLEND_MIN_MM)
			return 0;
		pl_block_cut(t, 0.0, t->L - dt, &ta);
		pl_block_cut(t, t->L - dt, t->L, &ca);
		pl_block_cut(b, db, b->L, &tb);
		pl_block_cut(b, 0.0, db, &cb);
		n = pl_biarc(p, ta.p1, ta.t1, tb.p0, tb.t0,
			     pl_min(t->feed, b->feed), smax, k);
		if (n) {
			dev = deviation(&ca, &cb, k, n);
			for (i = 0; i < n; i++)
				vmin = pl_min(vmin, k[i].vlim);
			if (dev <= tol) {
				if (vmin <= vcorner)
					return 0;
				*t = ta;
				*b = tb;
				return n;
			}
			scale = pl_max(0.3, 0.95 * tol / dev);
		}
		dt *= scale;
		db *= scale;
	}
	return 0;
}

/* What a side of the corner (piece x cut from x0, acceleration A) costs
 * more when it stops instead of leaving the blend at vb: the braking from
 * vb to rest, vb / A, less the braking's distance at the speed V the move
 * reaches, plus the cut d (the piece the blend replaces) at V. V counts
 * from v0, the fastest the motion can enter the move before the corner
 * (its vin: a short move inside a curve is run at the curve's speed, not
 * from the blend's), or from vb after the corner. */
static double stop_cost(const struct sh2000_path *p,
			const struct pl_block *x0, const struct pl_block *x,
			double vb, double v0)
{
	double A = pl_block_accel(p, x), d = x0->L - x->L;
	/* the fastest in the move, from v0 (at least vb) halfway (as it is
	 * on the way to the next corner): at most its limit */
	double V = pl_min(pl_cap(p, x0), sqrt(pl_max(v0, vb) * pl_max(v0, vb) +
					      A * x0->L));

	if (vb > STOP_VB_SHARE * V)
		return INFINITY;
	return vb / A - vb * vb / (2.0 * A * V) + d / V;
}

/*
 * Whether stopping on the corner is faster than the blend k[0..n) the
 * pieces t and b (cut from t0 and b0) would join through. The blend runs
 * at its speed limit vb, so the motion brakes to vb and speeds up from it
 * either way, and a stop adds the braking from vb to rest on each side
 * (stop_cost()) where the blend takes its length at vb. For a circular
 * blend of radius R at the centripetal share s of the acceleration M
 * between moves much faster than vb, vb = sqrt(s M R): the blend costs
 * R phi / vb, the stop 2 vb / M, so a turn phi wider than 2s radians (57
 * degrees at the default share) is faster stopped, whatever the
 * tolerance. Both moves must last what the S-curve covers from rest to
 * rest in PL_REST_PERIODS, so that the stops are exact (control.c; the
 * 0.05 mm step-overs of a surfacing raster took 0.36 s longer stopped).
 * Compensated output with the S-curve only: raw output holds a rest point
 * for two periods more, and the trapezoid's stops ring.
 */
static int stop_faster(const struct sh2000_path *p,
		       const struct pl_block *t0, const struct pl_block *b0,
		       const struct pl_block *t, const struct pl_block *b,
		       const struct pl_block *k, unsigned int n)
{
	double vb = INFINITY, tb = 0.0, rt = PL_REST_PERIODS * p->cfg.period_s;
	double lmin = p->lim.J * rt * rt * rt / 32.0;
	unsigned int i;

	if (p->cfg.output != SH2000_OUTPUT_COMPENSATED || isinf(p->lim.J) ||
	    !n || t0->L < lmin || b0->L < lmin)
		return 0;
	for (i = 0; i < n; i++) {
		vb = pl_min(vb, k[i].vlim);
		tb += k[i].L / k[i].vlim;
	}
	/* a blend at the moves' own speed costs nothing */
	if (!(vb < pl_min(pl_cap(p, t0), pl_cap(p, b0))))
		return 0;
	return tb > stop_cost(p, t0, t, vb, t0->vin) +
		    stop_cost(p, b0, b, vb, 0.0);
}

/* mm of the tolerance kept for the compensated spline (at grow 1) */
static double spline_room(const struct sh2000_path *p)
{
	double T = p->cfg.period_s;

	return pl_max(BLEND_SPLINE_MM,
		      p->cfg.margin * p->amin * T * T / BLEND_SPLINE_DIV);
}

unsigned int pl_blend_corner(struct sh2000_path *p, struct pl_block *b,
			     struct pl_block k[2])
{
	double tol = p->cfg.corner_tol, phi, share, smax, grow;
	struct pl_block *t, t0, b0;
	unsigned int n, i;

	if (!cuttable(b) ||
	    p->cfg.mode != SH2000_PATH_BLEND || !(tol > 0.0) ||
	    (p->cfg.output == SH2000_OUTPUT_RAW && tol < PL_RAW_TOL_REST_MM) ||
	    p->stop_next)
		return 0;	/* the corner's junction rule (pl_junction()) */
	t = tail_block(p);
	if (!t || !meet(t, b))
		return 0;
	/* inside one curve: a cusp or a knot of multiplicity degree, where
	 * the curve itself turns (expand.c stops there) */
	if (t->type == BLK_NURBS && b->type == BLK_NURBS &&
	    t->g.nurbs.nb == b->g.nurbs.nb)
		return 0;
	phi = acos(pl_max(-1.0, pl_min(1.0, pl_dot(t->t1, b->t0))));
	if (phi < 1e-6 || phi > M_PI - 1e-3)
		return 0;	/* straight on, or back along itself */
	/* the spline's error at the arc's ends grows faster than the
	 * centripetal acceleration the arc takes: its square (measured,
	 * tests/planner test_corner_tolerance) */
	smax = blend_smax(p, t, b, phi);
	grow = smax / p->cfg.centripetal_share;
	share = p->cfg.output == SH2000_OUTPUT_RAW ? BLEND_SHARE_RAW :
		pl_max(0.5, pl_min(0.95, 1.0 - spline_room(p) * grow * grow /
					 tol));
	t0 = *t;
	b0 = *b;
	if (t->type == BLK_LINE && b->type == BLK_LINE)
		n = blend_lines(p, t, b, phi, share * tol, smax, k);
	else
		n = blend_curves(p, t, b, phi, share * tol, smax, k);
	for (i = 0; i < n; i++)
		k[i].vlim = pl_min(k[i].vlim,
				   pl_corner_spline_vlim(p, sin(phi / 2), tol,
							 BLEND_CORNER_SPLINE));
	if (stop_faster(p, &t0, &b0, t, b, k, n)) {
		/* the corner is visited at rest instead, uncut */
		*t = t0;
		*b = b0;
		p->stop_next = 1;
		return 0;
	}
	for (i = 0; i < n; i++)
		raw_limit(p, share, &k[i]);
	return n;
}
