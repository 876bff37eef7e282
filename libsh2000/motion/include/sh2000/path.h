/* SPDX-License-Identifier: MIT */
/*
 * libsh2000's motion planner: path geometry and feeds in, coarse
 * interpolation points out (docs/planner.md is the tour).
 *
 * The planner knows nothing about the card. It consumes primitives (lines,
 * arcs, NURBS, point-to-point moves) and limits, and hands one point per
 * coarse period to a sink callback: absolute positions of the 4 axes in mm
 * (and in counts when scales are given), with SH2000_PATH_F_END on the last
 * point of every motion. Pushing the points to a card is the caller's job
 * (a few lines over the library's segment push).
 *
 * Memory is constant: a look-ahead window of a fixed number of blocks and a
 * fixed compensation window, both allocated by sh2000_path_create(). The
 * only other allocation is a copy of each NURBS while it is in the window.
 *
 * Errors: functions return 0 (or a count) on success and a negative errno
 * on failure; sh2000_path_error() says what was wrong in words. A rejected
 * primitive leaves nothing behind: validation is complete before any of it
 * is queued. A planner is not thread-safe; the override, pause and stop
 * calls may be made from inside the sink.
 */
#ifndef SH2000_PATH_H
#define SH2000_PATH_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/card.h"
#include "sh2000/geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

enum sh2000_path_profile {
	SH2000_PROFILE_SCURVE = 0,	/* jerk-limited, 7 phases (default) */
	SH2000_PROFILE_TRAPEZOID = 1,	/* acceleration-limited, 3 phases */
};

enum sh2000_path_output {
	/* control points P with P[i-1] + 4P[i] + P[i+1] = 6Q[i]: the card's
	 * B-spline passes through the planned points Q (default) */
	SH2000_OUTPUT_COMPENSATED = 0,
	/* the planned points themselves: the card's B-spline cuts curves */
	SH2000_OUTPUT_RAW = 1,
};

/*
 * How corners are taken, as LinuxCNC's path control modes: G64 blends
 * within a tolerance (or as fast as the axes allow without one), G61
 * visits every programmed point (a corner is only as fast as the axes can
 * turn it without rounding it: a stop at a sharp one), G61.1 comes to rest
 * at the end of every block.
 */
enum sh2000_path_mode {
	SH2000_PATH_BLEND = 0,		/* G64 [P [Q]] */
	SH2000_PATH_EXACT_PATH = 1,	/* G61 */
	SH2000_PATH_EXACT_STOP = 2,	/* G61.1 */
};

struct sh2000_path_config {
	double period_s;		/* coarse period (default 0.002 s) */
	unsigned int fine_steps;	/* card servo cycles per period (20) */
	double vmax[SH2000_AXES];	/* mm/s, > 0 */
	double amax[SH2000_AXES];	/* mm/s^2, > 0 */
	/* path jerk, mm/s^3 (S-curve); planned with no more than a control
	 * step can use (docs/planner.md "A jerk above what a period can
	 * use") */
	double jerk;
	enum sh2000_path_profile profile;
	enum sh2000_path_output output;
	enum sh2000_path_mode mode;	/* at the start (BLEND) */
	/* mm a corner may be rounded (0.01); INFINITY: as fast as the axes
	 * allow (G64 without P) */
	double corner_tol;
	double chord_tol;		/* mm sagitta between points (0.01) */
	/* mm a run of straight feed moves may deviate from one line and be
	 * taken as that line (LinuxCNC's naive CAM detector, G64 Q); 0: off */
	double naive_tol;
	/* share of each axis' acceleration given to curvature; the rest is
	 * for acceleration along the path (0.5) */
	double centripetal_share;
	/* fraction of every limit the plan uses, the rest is headroom for
	 * rounding to counts and the compensation's overshoot (0.95) */
	double margin;
	double counts_per_mm[SH2000_AXES];	/* 0: no counts */
	double start[SH2000_AXES];		/* position at create, mm */
	unsigned int window;		/* look-ahead blocks (256) */
	unsigned int comp_window;	/* compensation half-window (12) */
	/* The room to grow (sh2000.h, above struct sh2000_status) holds the
	 * fields added since, over its first words: size and offsets stay
	 * (docs/install.md, "Growing a struct"). An anonymous union, and in
	 * it an anonymous struct (C11; __extension__ for C++) for the fields
	 * past the first word. */
	union {
		/* the card's gantry pair (bits of its two axes, both
		 * enabled; 0: none): its sides must move together
		 * (sh2000_run_path_config() fills it) */
		unsigned int gantry_pair;
		uint64_t reserved[16];	/* room to grow, zero */
		__extension__ struct {
			unsigned int : 32;	/* gantry_pair */
			/* Axes held where they stand (bit a: axis a; 0:
			 * none). Their vmax and amax do not bound the plan:
			 * a slow axis a program never moves does not slow
			 * the others (the least amax sets the path's share
			 * of the acceleration). A block that moves one
			 * further than SH2000_PATH_STILL_TOL_MM is refused.
			 * sh2000_program_axes() fills it from a program. */
			unsigned int still_axes;
		};
	};
};

/* How far a primitive's point may lie from where a still axis stands
 * (still_axes): it is held there (a count's rounding to mm, a
 * card that drifted by a count between the check and the run); further
 * is a move, refused. */
#define SH2000_PATH_STILL_TOL_MM	0.001

/* Fills *cfg with the defaults (limits of a small linear-motor table). */
void sh2000_path_config_default(struct sh2000_path_config *cfg);

#define SH2000_PATH_F_END	0x0001u	/* last point of a motion */

struct sh2000_path_point {
	double mm[SH2000_AXES];
	int32_t counts[SH2000_AXES];	/* round(mm * scale), 0 if none */
	unsigned int flags;			/* SH2000_PATH_F_* */
	uint32_t seq;		/* tag of the primitive being traversed */
	uint64_t index;		/* points emitted before this one */
};

/* Called once per coarse point, in order. A negative return stops the
 * planner: the call that was running returns it and the planner refuses
 * work until sh2000_path_reset(). */
typedef int (*sh2000_path_sink_fn)(void *ctx,
				   const struct sh2000_path_point *pt);

struct sh2000_path;

/* -EINVAL with a message in *errbuf (if given) for a bad config. */
int sh2000_path_create(struct sh2000_path **out,
		       const struct sh2000_path_config *cfg,
		       sh2000_path_sink_fn sink, void *ctx,
		       char *errbuf, size_t errlen);
void sh2000_path_destroy(struct sh2000_path *p);

/* What the last failing call on this planner was unhappy about. */
const char *sh2000_path_error(const struct sh2000_path *p);

/*
 * The path control mode for the primitives added from now on, as G-code's
 * G61 / G61.1 / G64 P<tolerance> Q<naive_tolerance> (mm): BLEND with a
 * tolerance > 0 rounds corners by at most that and keeps arcs and curves
 * within it of their chords; BLEND with 0 keeps the best speed (corners
 * limited by the axes only, chords by the configured chord_tol);
 * naive_tolerance > 0 merges straight feed moves that stay within it of
 * one line. -EINVAL for a negative or non-finite tolerance.
 */
int sh2000_path_set_mode(struct sh2000_path *p, enum sh2000_path_mode mode,
			 double tolerance, double naive_tolerance);

/*
 * Bounds every primitive added from now on must keep within, per axis in
 * mm (lo[a] <= hi[a]; an infinite one bounds nothing): a line's or move's
 * end, an arc's end and its extremes in its plane, a NURBS' curve. A
 * primitive that leaves them is refused when it is added, with
 * -SH2000_ELIMIT and "line: end X 15.000000 mm is beyond the soft limit:
 * the bound is 10.002000 mm" in sh2000_path_error(); nothing of it is
 * queued and the planner takes the next primitive. The runner and
 * sh2000_program_plan() set the card's soft limits with their slack
 * (sh2000/run.h). Both NULL: no bounds (the default). -EINVAL for one
 * NULL, a NaN or lo[a] > hi[a] (the bounds stay as they were).
 */
int sh2000_path_set_bounds(struct sh2000_path *p, const double lo[SH2000_AXES],
			   const double hi[SH2000_AXES]);

/* Tag stored in the points of the primitives added from now on. */
void sh2000_path_set_seq(struct sh2000_path *p, uint32_t seq);

/* ---- primitives (each returns 0 or a negative errno) ---------------- */

/* Straight line from the end of the previous primitive to `end`, all four
 * axes interpolated, at `feed` mm/s along the path. */
int sh2000_path_line(struct sh2000_path *p,
		     const double end[SH2000_AXES], double feed);

/*
 * An arc or helix from the end of the previous primitive. The plane and
 * the sense are geometry.h's: ccw turns from the plane's first axis
 * towards its second (G3), in every plane.
 */
struct sh2000_path_arc {
	enum sh2000_plane plane;
	/* absolute end; the axes outside the plane move linearly (helix) */
	double end[SH2000_AXES];
	int ccw;
	int radius_form;	/* 0: centre given, 1: radius given */
	double centre[2];	/* absolute, (first, second) of the plane */
	/* radius form: |radius|, > 0 for the arc of at most 180 degrees,
	 * < 0 for the longer one */
	double radius;
	/* as G-code's P: 1 (or 0) the arc itself, each more one full turn
	 * more; with the centre form, end == start in the plane is a full
	 * circle */
	unsigned int turns;
	/* allowed difference of start and end radius, LinuxCNC's rule
	 * (geometry.h); 0: SH2000_ARC_CENTRE_TOL_MM */
	double tolerance;
};

int sh2000_path_arc(struct sh2000_path *p, const struct sh2000_path_arc *arc,
		    double feed);

/* The curve over [knots[degree], knots[npoints]] must start at the current
 * position (within 0.001 mm); it is copied. Feed adapts to the chord
 * tolerance and to the acceleration and jerk limits along the curve. */
int sh2000_path_nurbs(struct sh2000_path *p, const struct sh2000_nurbs *n,
		      double feed);

/* Point-to-point: a straight move that starts and ends at rest, at `speed`
 * mm/s, or as fast as the axes allow when speed is 0. */
int sh2000_path_move_abs(struct sh2000_path *p,
			 const double target[SH2000_AXES], double speed);
/* A rapid (G0): a straight move as fast as the axes allow. Under G64 it
 * joins the rapids before and after it as feed moves join (blended
 * within the path tolerance, G64 Q merging none); it stops where it meets
 * a feed move, as LinuxCNC's planner does, and under G61 and G61.1. */
int sh2000_path_rapid(struct sh2000_path *p, const double target[SH2000_AXES]);
int sh2000_path_move_rel(struct sh2000_path *p,
			 const double delta[SH2000_AXES], double speed);
/* Jog one axis at signed `velocity` mm/s for at most `travel` mm; end it
 * early with sh2000_path_stop(). */
int sh2000_path_jog(struct sh2000_path *p, unsigned int axis,
		    double velocity, double travel);

/* End of the queued primitives: where the next one starts. */
void sh2000_path_end_position(const struct sh2000_path *p,
			      double pos[SH2000_AXES]);

/* ---- execution -------------------------------------------------------- */

/* Emit up to max_points points (the motion stops at the end of what is
 * queued, with END). Returns the number emitted, or a negative errno
 * (-EDEADLK: the motion stood still without resting, a planner fault). */
int sh2000_path_run(struct sh2000_path *p, unsigned int max_points);
/* Emit everything queued; the motion ends at rest on the last end point.
 * 0 when done, -EAGAIN if paused with work left. */
int sh2000_path_finish(struct sh2000_path *p);

/* Feed override, 0 < factor <= 2, from the next period; changes decelerate
 * and accelerate within the limits. */
int sh2000_path_set_override(struct sh2000_path *p, double factor);
/* Decelerate to rest on the path (END there); resume continues it. */
int sh2000_path_pause(struct sh2000_path *p);
int sh2000_path_resume(struct sh2000_path *p);
/* Decelerate to rest on the path and discard everything queued (also
 * ends a pause); the next primitive starts where the motion stopped. */
int sh2000_path_stop(struct sh2000_path *p);
/* Forget everything at once, without points, and start over at pos (the
 * card was stopped another way). Clears a sink failure. */
int sh2000_path_reset(struct sh2000_path *p,
		      const double pos[SH2000_AXES]);

struct sh2000_path_stats {
	uint64_t points;	/* points emitted */
	uint64_t motions;	/* points that carried END */
	uint64_t blocks;	/* blocks planned (NURBS: several per span) */
	double velocity;	/* current path velocity, mm/s */
	int moving;		/* 0 at rest */
	int paused;
	/* NURBS: largest sagitta between consecutive points, mm, and the
	 * largest |chord - planned step| / planned step */
	double nurbs_chord_error;
	double nurbs_feed_fluctuation;
	uint64_t nurbs_steps;
	/* corrector iterations over all steps, and the fluctuation the
	 * prediction alone would have left: what the corrector is for */
	uint64_t nurbs_corrections;
	double nurbs_feed_fluctuation_predicted;
	size_t mem_bytes;	/* heap the planner holds now */
	size_t mem_peak;	/* and at most so far */
	uint64_t reserved[8];	/* room to grow, zero (sh2000.h, above
				 * struct sh2000_status) */
};

void sh2000_path_stats(const struct sh2000_path *p,
		       struct sh2000_path_stats *st);

/* ---- B-spline compensation as a stand-alone stream filter ------------- */

/* Turns points Q (one axis set per period) into control points P so that
 * the uniform cubic B-spline over P passes through Q, with Q extended by
 * its first point before and its last point after (a motion from rest to
 * rest). Constant memory: a window of 2*half+1 points. */
struct sh2000_bscomp;

int sh2000_bscomp_create(struct sh2000_bscomp **out, unsigned int half,
			 unsigned int naxes);
void sh2000_bscomp_destroy(struct sh2000_bscomp *c);
/* Begin a motion at rest at x. */
void sh2000_bscomp_start(struct sh2000_bscomp *c, const double *x);
/* Feed Q; returns how many P are ready (0 or 1) and copies it to *p. */
int sh2000_bscomp_push(struct sh2000_bscomp *c, const double *q, double *p);
/* After the last Q: returns 1 and one P per call until done, the very
 * last one being exactly the last Q; 0 when done. *last is set on it. */
int sh2000_bscomp_flush(struct sh2000_bscomp *c, double *p, int *last);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_PATH_H */
