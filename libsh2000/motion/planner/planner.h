/* SPDX-License-Identifier: MIT */
/*
 * The planner's internal interface: blocks, the NURBS evaluator, the
 * profile arithmetic and the controller. path.h is the public side.
 */
#ifndef SH2000_PLANNER_H
#define SH2000_PLANNER_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "sh2000/geometry.h"
#include "sh2000/path.h"


/* ---- nurbs.c: a curve the planner holds (its own copy) -------------- */

struct pl_nurbs {
	struct sh2000_nurbs c;	/* the copy, evaluated by geometry.h */
	double umin, umax;
	uint64_t id;		/* for the predictor's history */
	unsigned int refs;	/* blocks in the window that use it */
	unsigned int span;	/* expansion: next knot span ... */
	unsigned int sub;	/* ... and next subdivision in it */
	double cut;		/* a cusp or a halving inside that
				 * subdivision: the next block starts
				 * there (NAN when none) */
	int expanded;		/* every block of it has been queued */
	size_t bytes;		/* what the copy holds */
};

/* The controller's scratch per limit ahead (distance, speed, three for
 * the acceleration, where the acceleration first drops with the speed
 * to pass there, a nearer limit that implies it, and a drop of the
 * acceleration at the limit itself) and per drop of the acceleration
 * (distance and three), control.c */
#define PL_CONS 9u
#define PL_DROP 4u

/* Points the planner can hold for a sink that cannot take them yet: one
 * period's plus a whole compensation flush (2 * 64 + 3 at most). */
#define PL_OUTQ 160u

/* Periods a motion between two rests lasts at least for its rests to be
 * exact (control.c): shorter ones bring the one-sided knots of both rests
 * together, and the card's jerk then reached 1.47 times the planned one
 * (G0 X0.03; 1.32 as the filter ran through) where longer moves stay as
 * they were. */
#define PL_REST_PERIODS 7

/* A corner no faster than this a period (mm) is taken at rest, exactly:
 * braked to a few nanometres a period without the landing a stop gets,
 * the card's compensated spline rang through it (88 nm past a 90 degree
 * corner too narrow to blend at G64 P1e-7, taken at 1e-4 mm/s; 0.4 um
 * past a 135 degree one at P1e-6, at 8e-4 mm/s). */
#define PL_CREEP_MM 0.001

/* In raw output a path tolerance below this (mm) takes every corner at
 * rest, exactly: the raw spline's cut of a narrow blend or of a corner
 * taken at speed passed such a tolerance (123 nm at G64 P1e-4 on a
 * zigzag at 200 mm/s, 0.8 um at P1e-7 with the trapezoid). */
#define PL_RAW_TOL_REST_MM 0.001

/* Moves merged into one line at most (G64 Q). */
#define PL_MERGE_MAX 32u

/* The largest centripetal share a curve block that its curvature holds
 * below its feed takes (LinuxCNC's blend arcs: sqrt(1 - 0.5^2), half of
 * the acceleration left along the path). */
#define PL_SHARE_MAX 0.866

/* Free blocks a primitive wants in the window: its own and the blend
 * blocks that may replace the corner before it (pl_room()). */
#define PL_ROOM 3u
/* Blocks a new limit bounds the speed of, back from it (queue.c): a
 * limit further back than this is met by a nearer one, or loosely. */
#define PL_BOUND_BACK 32u

/* Sub-blocks per non-empty knot span. */
#define PL_NURBS_SUBDIV 16u

/* A copy of a checked curve; NULL when out of memory. */
struct pl_nurbs *pl_nurbs_new(struct sh2000_path *p,
			      const struct sh2000_nurbs *n);
/* Drop a reference; the copy goes with the last one once expanded. */
void pl_nurbs_put(struct sh2000_path *p, struct pl_nurbs *nb);
/* C, C' and C'' at u (d1, d2 may be NULL). */
void pl_nurbs_eval(const struct pl_nurbs *nb, double u, double c[SH2000_AXES],
		   double d1[SH2000_AXES], double d2[SH2000_AXES]);
/* Arc length between u0 and u1 (adaptive Gauss-Legendre). */
double pl_nurbs_length(const struct pl_nurbs *nb, double u0, double u1);
/* The same for a piece whose speed |C'| is known to be even (within 4x):
 * one 8-point rule. */
double pl_nurbs_length_even(const struct pl_nurbs *nb, double u0, double u1);
/* The parameter at arc length s from u0 along [u0, u1], whose length is
 * L; the arc length it reaches in *len. */
double pl_nurbs_u_at(const struct pl_nurbs *nb, double u0, double u1, double L,
		     double s, double *len);
/* Curvature and unit tangent at u; returns |C'(u)|. */
double pl_nurbs_frame(const struct pl_nurbs *nb, double u,
		      double t[SH2000_AXES], double *kappa);

/* ---- blocks ----------------------------------------------------------- */

enum { BLK_LINE = 1, BLK_ARC = 2, BLK_NURBS = 3, BLK_BLEND = 4 };

struct pl_block {
	int type;
	uint32_t seq;
	double L;		/* length along the path, mm */
	double vlim;		/* what the geometry and axes allow, mm/s */
	double feed;		/* programmed, mm/s (may be INFINITY) */
	/* the block before: a rise in the speed limit waits until the card
	 * has left that block's speed behind (queue.c) */
	double prev_feed, prev_vlim;
	double vj;		/* limit at the junction into this block */
	double A;		/* path acceleration allowed in it, mm/s^2
				 * (pl_block_accel()) */
	double share;		/* a curve's centripetal share of the
				 * acceleration (pl_curve_block_vlim());
				 * 0: the configured one */
	int stop_after;		/* exact stop at the end (point-to-point) */
	int rapid;		/* a rapid (G0) or the blend between two */
	int corner;		/* the junction into it is a corner */
	/* a line to rest, from rest or out of a curve (ring_start), with
	 * one jerk a period: no ringing allowance but over the two periods
	 * after a curve (pl_block_accel(), pl_ring_zone()) */
	int rest_line, ring_start;
	/* the fastest the motion can enter it: the junction, its limit and
	 * what the blocks before it can reach (pl_fwd_exit()) */
	double vin;
	/* the fastest the motion can leave it: what the blocks after it
	 * allow, from those that can no longer change (queue.c) */
	double vout;
	double t0[SH2000_AXES], t1[SH2000_AXES];	/* unit tangents at start and end */
	double p0[SH2000_AXES], p1[SH2000_AXES];	/* exact start and end points */
	/* a line's programmed start, before a blend cut it; the blend blocks
	 * queued right before it (0..2) */
	double c0[SH2000_AXES];
	unsigned int nblend;
	union {
		struct {
			double d[SH2000_AXES];	/* unit direction */
		} line;
		struct sh2000_arc arc;	/* resolved (geometry.h) */
		struct {	/* a corner's arc in any plane (blend.c) */
			double c[SH2000_AXES];	/* centre */
			double u[SH2000_AXES];	/* centre to start, unit */
			double w[SH2000_AXES];	/* tangent at the start */
			double R, phi;		/* radius, angle */
		} blend;
		struct {
			struct pl_nurbs *nb;
			double u0, u1;
		} nurbs;
	} g;
};

/* Position at distance s (0..L) into the block. NURBS blocks map s to u by
 * linear interpolation only; the controller refines it. */
void pl_block_pos(const struct pl_block *b, double s, double pos[SH2000_AXES]);

/* ---- profile arithmetic (path coordinate) ------------------------------ */

struct pl_limits {
	double A, J;		/* J = INFINITY: trapezoid */
};

/* Piecewise-constant-jerk transition from (v, a) to (v1, 0). */
struct pl_trans {
	int n;
	double dur[3];
	double jerk[3];		/* trapezoid: 0, the acceleration is acc[] */
	double acc[3];		/* acceleration at the start of each phase */
};

void pl_trans_plan(const struct pl_limits *lim, double v, double a,
		   double v1, struct pl_trans *tr);
/* Distance to reach a speed <= vt from (v, a), a ending at 0. */
double pl_brake_dist(const struct pl_limits *lim, double v, double a,
		     double vt);
/* Length of the transition from v0 to v1, both at rest acceleration. */
double pl_trans_len(const struct pl_limits *lim, double v0, double v1);
/* Largest start speed (a = 0) that can slow to v1 (a = 0) within L. */
double pl_reach_back(const struct pl_limits *lim, double v1, double L);
/* Advance (s, v, a) by dt with constant jerk j (inline: the controller's
 * innermost step). */
static inline void pl_integrate(double *s, double *v, double *a, double j,
				double dt)
{
	*s += dt * (*v + dt * (*a / 2.0 + dt * j / 6.0));
	*v += dt * (*a + dt * j / 2.0);
	*a += dt * j;
}

/* quant.c: the jerks j[0..n-1] of n periods of length h from (v, a) that
 * land on speed vt with acceleration 0 (n = 2), at distance d as well
 * (n = 3); -1 if the system is singular. */
#define PL_QUANT_MAX 8
int pl_quant_solve(double h, double v, double a, unsigned int n, int dist,
		   double d, double vt, double *j);
/* quant.c: the fewest periods n <= nmax of length h that land from
 * (v, a) on speed vt < v at distance d with acceleration 0, braking at up
 * to A (to Aend at the last PL_LAND_END period ends: the allowed
 * acceleration drops at d) with jerks up to J (J h >= A), and the
 * acceleration a1 at the end
 * of the first; -2 if every landing passes d (the speed is too high
 * for it), -1 if there is none else. strict: with 1e-6 to spare on the
 * earliest braking (a state a landing will start from), else 1e-6 past
 * it (a landing under way). 1 where vt > 0 and the latest braking in n
 * ends short of d by less than a period at vt: cruising at vt from there
 * passes d sooner than landing on it. */
#define PL_LAND_END 2
int pl_quant_land(double h, double v0, double a0, double vt, double d,
		  double A, double Aend, double J, int strict,
		  unsigned int nmax, unsigned int *n_out, double *a1);

/* search.c: the highest x in [lo, hi] with f(x) >= 0, f non-increasing,
 * f(lo) = flo >= 0 > fhi = f(hi), to within tol. */
double pl_highest_pass(double (*f)(const void *ctx, double x), const void *ctx,
		       double lo, double hi, double flo, double fhi,
		       double tol);

/* ---- the planner ------------------------------------------------------ */

struct sh2000_bscomp;

/* sh2000_bscomp_push() for a point the motion rests on (v = 0, a = 0) and
 * goes on from (a corner under G61): with rest set, the card's spline
 * stops on it exactly (bscomp.c). */
int pl_bscomp_push(struct sh2000_bscomp *c, const double *q, int rest,
		   double *p);
/* Whether the next start (sh2000_bscomp_start) and end (the flush) are
 * rest points the card's spline stops on exactly; off by default
 * (sh2000_bscomp_* as documented in path.h). */
void pl_bscomp_exact(struct sh2000_bscomp *c, int on);

struct sh2000_path {
	/* the configuration in force (the path mode changes it) and as
	 * created */
	struct sh2000_path_config cfg, base;
	sh2000_path_sink_fn sink;
	void *ctx;
	char err[256];

	/* limits in path terms: lim.A is the acceleration next to a corner
	 * that is not blended (the axes' room for the corner's turn is
	 * what it leaves); each block has its own (pl_block_accel()):
	 * a_curve along curves, up to a_top on lines; a_scale is what the
	 * trapezoid's steps through the compensation cost */
	struct pl_limits lim;
	double a_curve, a_top, a_scale, a_ring;
	double amin;		/* smallest axis acceleration */
	/* s: how long before a drop and after a rise of the speed limit the
	 * lower limit holds, so that the card's spline, which spreads a
	 * change over this many periods, never carries the higher speed
	 * into the slower block */
	double feed_zone;
	/* mm/s the cruise stays below the programmed feed: what the card's
	 * compensated spline rings above a speed a transition ends at */
	double feed_margin;
	unsigned int substeps;
	int quant;	/* one jerk a period, transitions landed (control.c) */
	/* periods in a row the motion stood still without resting */
	unsigned int still;

	/* the look-ahead window: a ring of blocks */
	struct pl_block *blk;
	unsigned int cap, head, count;
	struct pl_nurbs *pending;	/* NURBS still being expanded */
	double pending_feed;
	double *cons;		/* controller scratch: (distance, speed,
				 * acceleration) of the limits ahead ... */
	double *drops;		/* ... and (distance, acceleration) where
				 * the acceleration allowed drops */
	double qend[SH2000_AXES];	/* end of the queued primitives */
	double tail_feed, tail_vlim;	/* of the last block queued */
	/* the corners merged into the last block (merge.c) */
	double merged[PL_MERGE_MAX][SH2000_AXES];
	unsigned int merged_n;
	double tend[SH2000_AXES];	/* tangent there (0: none / after a stop) */
	int stop_next;		/* next block starts from rest */
	int tail_rapid;		/* the last block queued is a rapid */
	uint32_t seq;
	uint64_t nurbs_ids;

	/* controller */
	double s, v, a;		/* in the head block */
	double override;
	int paused, stopping, moving;
	int fail;
	double pos[SH2000_AXES];	/* last sampled point */
	double dist;		/* path distance at the last sample */
	double dist_now;	/* path distance travelled so far */
	double a_prev;		/* A of the block last left (a stop's) */
	/* a landing in whole periods under way (control.c, quant.c): its
	 * jerks, the next one's index, how many */
	double qj[PL_QUANT_MAX];
	unsigned int qi, qn;
	/* the short line after the head a landing reached to (control.c,
	 * land_reach()), until the head moves on */
	const struct pl_block *land_line;
	unsigned int since_rest;	/* periods since the motion rested */
	int rest_exact;		/* whether that rest was exact */

	/* NURBS predictor history (same curve only) */
	uint64_t hist_id;
	unsigned int hist_n;
	double hist_u[3];
	double hist_c[SH2000_AXES];
	double hist_speed;	/* |C'| at hist_u[0] */

	/* output: points the sink has not taken yet (at most one period's
	 * and a compensation flush) */
	struct sh2000_path_point outq[PL_OUTQ];
	unsigned int outq_head, outq_n;
	struct sh2000_bscomp *comp;
	int comp_started;
	uint64_t points, motions, blocks;
	double chord_err, feed_fluct, feed_fluct_pred;
	uint64_t nurbs_steps, nurbs_corr;
	size_t mem, mem_peak;

	/* the caller's bounds every primitive keeps within
	 * (sh2000_path_set_bounds(); bounded 0: none) */
	int bounded;
	double bound_lo[SH2000_AXES], bound_hi[SH2000_AXES];
};

int pl_err(struct sh2000_path *p, int code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
void *pl_alloc(struct sh2000_path *p, size_t n);
void pl_free(struct sh2000_path *p, void *ptr, size_t n);

/* queue.c: queue a validated block (the ring has room). */
void pl_push_block(struct sh2000_path *p, struct pl_block *b);
void pl_rest_after(struct sh2000_path *p);
/* Whether the distance s into block b is in its ring zone: the two
 * periods after a curve on a line to rest, which keep the allowance. */
int pl_ring_zone(const struct sh2000_path *p, const struct pl_block *b,
		 double s);
/* Queue b after the blend of the corner into it, if any. */
void pl_push_blended(struct sh2000_path *p, struct pl_block *b);
/* Take the last block and the blend before it out of the window (the block
 * before them stays, as cut); the caller queues them again. */
void pl_unqueue_tail(struct sh2000_path *p);
/* Empty the window (a stop or a reset), releasing the curves. */
void pl_drop_blocks(struct sh2000_path *p);
/* Make room for a block and its blend (PL_ROOM; only for the block while
 * paused): runs the controller. 0 or negative errno. */
int pl_make_room(struct sh2000_path *p);
/* One coarse period. Returns 1 if the motion is at rest with nothing
 * (more) to do, 0 otherwise, negative on a sink error. */
int pl_period(struct sh2000_path *p);
/* A stop has come to rest: drop the rest of the program. */
void pl_stopped(struct sh2000_path *p);
/* merge.c: take line b (not yet queued) into the last line queued when
 * the naive CAM tolerance allows; 1 if it was (nothing to queue). */
int pl_merge_line(struct sh2000_path *p, const struct pl_block *b);
/* blend.c: cut the corner between the last block queued and b (not yet
 * queued), lines or arcs, with a tangent curve within the tolerance: the
 * number of its blocks in k[] (the tail and b cut short), or 0. */
unsigned int pl_blend_corner(struct sh2000_path *p, struct pl_block *b,
			     struct pl_block k[2]);
/* biarc.c: the circular arc from a along unit tangent ta to b (a line when
 * straight) into *k, its centripetal share up to smax
 * (pl_curve_block_vlim()): 0, or -1 when it would turn 180 degrees or
 * more. */
int pl_arc_to(const struct sh2000_path *p, const double a[SH2000_AXES],
	      const double ta[SH2000_AXES], const double b[SH2000_AXES],
	      double feed, double smax, struct pl_block *k);
/* Two arcs meeting tangentially from a along ta to b along tb (shares up
 * to smax): 2 blocks in k[], or 0 when there is no such pair. */
unsigned int pl_biarc(const struct sh2000_path *p,
		      const double a[SH2000_AXES], const double ta[SH2000_AXES],
		      const double b[SH2000_AXES], const double tb[SH2000_AXES],
		      double feed, double smax, struct pl_block k[2]);
/* cut.c: an arc block's length and end tangents from its arc and ends. */
void pl_arc_frame(struct pl_block *b);
/* The piece of line or arc b from s0 to s1 along it into *out (out may be
 * b). */
void pl_block_cut(const struct pl_block *b, double s0, double s1,
		  struct pl_block *out);
/* nurbs_step.c: the point of NURBS block b after the controller moved ds
 * along it (p->s is corrected to the arc the step took). */
void pl_nurbs_sample(struct sh2000_path *p, struct pl_block *b, double ds,
		     double q[SH2000_AXES]);
/* expand.c: expand as much of the pending NURBS as fits; 1 when fully
 * queued. */
int pl_nurbs_expand(struct sh2000_path *p);
/* Speed limit at a point of a curve: axis speeds for the tangent t, and
 * for curvature kappa the centripetal share, the chord tolerance and the
 * jerk. */
double pl_curve_vlim(const struct sh2000_path *p, const double t[SH2000_AXES],
		     double kappa);
/* The speed limit of a curve block k of constant curvature kappa (worst
 * tangent t) and its centripetal share: the configured one where the
 * block reaches its feed with it, more (up to PL_SHARE_MAX) where the
 * curvature holds it below, just enough for the feed. Such a block runs
 * at its limit, so what it gives up is tangential acceleration it seldom
 * uses. smax: the most it may take (0: the configured share alone). Sets
 * k->vlim and k->share. */
void pl_curve_block_vlim(const struct sh2000_path *p, struct pl_block *k,
			 const double t[SH2000_AXES], double kappa,
			 double smax);
/* The path acceleration allowed along block b: a line's, at which its
 * most loaded axis reaches its amax (times the margin); a curve's
 * tangential share (a_curve). */
double pl_block_accel(const struct sh2000_path *p, const struct pl_block *b);
/* The path acceleration block b allows at speed v and below, as the
 * controller reads it (pl_accel_at()): a blend arc of a turn under 45
 * degrees gives the centripetal acceleration v^2 / R only what the speed
 * reached needs (never less than the configured share), the rest goes
 * along the path; every other block has its constant A. */
struct pl_accel_fn {
	int dyn;		/* 0: the constant A */
	double A;		/* the block's A: the least at any speed */
	double Amax;		/* at rest: the most */
	double s0, s1;		/* the share's bounds ... */
	double kM;		/* ... and v^2 kM the share at v */
	double T[SH2000_AXES], N[SH2000_AXES];	/* per axis (limits.c) */
};
void pl_accel_fn_init(const struct sh2000_path *p, const struct pl_block *b,
		      struct pl_accel_fn *f);
/* Whether block b's acceleration follows the speed (a short blend; its
 * curvature is 1 / R). */
int pl_accel_dyn(const struct pl_block *b);
/* What such a blend of curvature kappa allows at speed v at least, by
 * its curvature alone (not less than 0). */
double pl_accel_curv(const struct sh2000_path *p, double v, double kappa);
double pl_accel_at(const struct sh2000_path *p, const struct pl_accel_fn *f,
		   double v);
/* The fastest the motion can leave block b (or be anywhere in it): from
 * its entry bound vin at no more than any block's acceleration. */
double pl_fwd_exit(const struct sh2000_path *p, const struct pl_block *b);
/* The fastest the motion can be anywhere in block b: from vin and to
 * vout at no more than any block's acceleration. */
double pl_peak(const struct sh2000_path *p, const struct pl_block *b);
/* What of an acceleration A the compensated spline's ringing leaves. */
static inline double pl_accel_room(const struct sh2000_path *p, double A)
{
	return A - p->a_ring > A / 1.4 ? A - p->a_ring : A / 1.4;
}
/* Speed allowed through the tangent junction from block b0 into b1 where
 * the curvature steps (a line into a blend, a blend into one turning
 * another way): the compensated spline through a step of the path's
 * acceleration overshoots it by about PL_CURV_RING of the step on the
 * card's servo cycles, so each axis' centripetal acceleration there plus
 * that stays within its amax (times the margin). INFINITY raw or next to
 * a NURBS. */
#define PL_CURV_RING 0.5
double pl_curv_step(const struct sh2000_path *p, const struct pl_block *b0,
		    const struct pl_block *b1);
/*
 * The card's spline rounding a corner, one rule for the junction and the
 * blend: its points lie v T apart, and a corner between two of them is
 * cut by about v T sh / 3 (sh the sine of half the turn), sharp or
 * blended (a blend shorter than about 1.4 v T; computed for an
 * interpolating cubic B-spline at constant speed, at every phase of the
 * points: 0.34). The speed at which that cut is k / 3 of tol at most: the
 * junction takes k = PL_JUNCTION_SPLINE (half the tolerance, half for the
 * speed changing around the corner), a blend blend.c's BLEND_CORNER_SPLINE.
 */
#define PL_JUNCTION_SPLINE 1.5
double pl_corner_spline_vlim(const struct sh2000_path *p, double sh,
			     double tol, double k);
/* Speed allowed through the corner from tangent t1 (in) to t0 (out). */
double pl_junction(const struct sh2000_path *p, const double t1[SH2000_AXES],
		   const double t0[SH2000_AXES]);

/* ---- the speed limits the controller reads many times a period: inline,
 * without libm's fmin/fmax calls (no NaN reaches them) ---------------- */

static inline double pl_min(double a, double b)
{
	return a < b ? a : b;
}

static inline double pl_max(double a, double b)
{
	return a > b ? a : b;
}

/* The dot product of two axis vectors (tangents, directions). */
static inline double pl_dot(const double a[SH2000_AXES],
			    const double b[SH2000_AXES])
{
	double s = 0.0;

	for (unsigned int ax = 0; ax < SH2000_AXES; ax++)
		s += a[ax] * b[ax];
	return s;
}

/* Free blocks a primitive waits for: PL_ROOM, or only its own in a window
 * too small to give the blends room without running it dry. */
static inline unsigned int pl_room(const struct sh2000_path *p)
{
	return p->cap > 2 * PL_ROOM ? PL_ROOM : 1;
}

/* Distance of x from the segment a..b (4 axes). */
static inline double pl_seg_dist(const double x[SH2000_AXES],
				 const double a[SH2000_AXES],
				 const double b[SH2000_AXES])
{
	double d[SH2000_AXES], w[SH2000_AXES], dd = 0.0, t = 0.0, e = 0.0;
	unsigned int k;

	for (k = 0; k < SH2000_AXES; k++) {
		d[k] = b[k] - a[k];
		w[k] = x[k] - a[k];
		dd += d[k] * d[k];
		t += w[k] * d[k];
	}
	t = dd > 0.0 ? pl_min(pl_max(t / dd, 0.0), 1.0) : 0.0;
	for (k = 0; k < SH2000_AXES; k++)
		e += (w[k] - t * d[k]) * (w[k] - t * d[k]);
	return sqrt(e);
}

/* Block i of the window (0: the head). */
static inline const struct pl_block *pl_block_at(const struct sh2000_path *p,
						 unsigned int i)
{
	return &p->blk[(p->head + i) % p->cap];
}

/* A programmed feed with the override, kept feed_margin below it (but
 * never below half of it). */
static inline double pl_feed_cap(const struct sh2000_path *p, double feed)
{
	double f = feed * p->override;

	return pl_max(f - p->feed_margin, 0.5 * f);
}

/* The speed limit of block b: its geometry's and its feed's. */
static inline double pl_cap(const struct sh2000_path *p,
			    const struct pl_block *b)
{
	return pl_min(b->vlim, pl_feed_cap(p, b->feed));
}

/* The speed limit of the block before b. */
static inline double pl_prev_cap(const struct sh2000_path *p,
				 const struct pl_block *b)
{
	return pl_min(b->prev_vlim, pl_feed_cap(p, b->prev_feed));
}

/* How fast block i >= 1 may be entered: its junction, its limit and the
 * limit of the block before. */
static inline double pl_entry_limit(const struct sh2000_path *p,
				    unsigned int i)
{
	const struct pl_block *b = pl_block_at(p, i);

	return pl_min(pl_min(b->vj, b->vlim), pl_min(b->prev_vlim,
		      pl_feed_cap(p, pl_min(b->feed, b->prev_feed))));
}

#endif /* SH2000_PLANNER_H */
