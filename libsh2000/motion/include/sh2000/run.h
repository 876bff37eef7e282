/* SPDX-License-Identifier: MIT */
/*
 * libsh2000: running a planned path on an open card. This header is the
 * reference; sh2000-upload (tools/upload/) is the worked example.
 *
 * A run owns a planner (sh2000/path.h) whose sink streams the coarse points
 * to the card: points are gathered into all-or-nothing batches and pushed
 * with sh2000_push_counts() as soon as the ring has room for a batch. The
 * first batch of a motion is larger (the priming batch), so that the ring
 * starts well filled; after that the host tops the ring up a batch at a
 * time, which keeps 48..64 records (about 100 ms) queued. Waiting for room
 * polls the card, which keeps the host heartbeat going and returns any
 * latched card fault as the run's error (with sh2000_last_error()'s
 * message in sh2000_run_error()).
 *
 * Samples: with a sample callback, every servo cycle of a `sim` card (its
 * observer: the fine set-point and encoder position) or every status poll
 * of other cards becomes one sample in mm, timed in card time from the
 * run's creation.
 *
 * Not thread-safe: one thread drives a run. sh2000_run_stop(),
 * _pause() and _set_override() may be called from the callbacks.
 */
#ifndef SH2000_RUN_H
#define SH2000_RUN_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/path.h"
#include "sh2000/program.h"
#include "sh2000/sh2000.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One sample of the card's motion, positions in mm. */
struct sh2000_run_sample {
	double t;			/* s of card time since the run began */
	double cmd[SH2000_AXES];	/* set-point (fine-interpolated) */
	double act[SH2000_AXES];	/* encoder position */
	int per_cycle;			/* 1: a servo cycle (sim), 0: a poll */
};

/* What the progress callback sees (after every batch and every poll). */
struct sh2000_run_progress {
	uint64_t points;		/* coarse points pushed so far */
	double t;			/* s of card time since the run began */
	unsigned int queue_fill;	/* records queued at the last poll */
	/* the tag (sh2000_path_set_seq()) of the last point the card took
	 * from the ring, as the last poll shows; -1 before the first */
	int64_t seq;
	const struct sh2000_status *status;	/* the last poll */
	uint64_t reserved[4];	/* room to grow, zero (sh2000.h, above
				 * struct sh2000_status) */
};

struct sh2000_run_config {
	/* records per top-up batch, 1..64 (16) */
	unsigned int batch;
	/* records of the first batch of a motion, batch..64 (48) */
	unsigned int prime;
	/* give up waiting for room or idle after this long without the
	 * card consuming anything (2000 ms; < 0: never) */
	int stall_ms;
	/* poll at least this often while waiting when samples are wanted
	 * from a card that is not `sim` (0: one coarse period) */
	uint64_t sample_ns;
	void (*sample)(void *ctx, const struct sh2000_run_sample *s);
	void (*progress)(void *ctx, const struct sh2000_run_progress *p);
	void *ctx;
	uint64_t reserved[8];	/* room to grow, zero (sh2000.h, above
				 * struct sh2000_status) */
};

void sh2000_run_config_default(struct sh2000_run_config *cfg);

/*
 * A planner configuration for this card: its coarse period and fine steps,
 * each axis' vmax, amax and scale as the card has them, and the start at
 * the card's position (the set-point of an enabled axis, the encoder of a
 * disabled one). Other fields are the planner's defaults.
 */
int sh2000_run_path_config(struct sh2000 *h, struct sh2000_path_config *pc);

/*
 * Soft limits: the one policy every caller uses. A point up to
 * SH2000_LIMIT_SLACK_MM beyond a limit is put on the limit (the B-spline
 * compensation overshoots a stop by about 1 um; a target at a limit is
 * legitimate); further beyond is -SH2000_ELIMIT: the rule for one target.
 * The runner and sh2000_program_plan() judge a planned stream on the
 * card's fine set-points (the B-spline of the records) by the same slack,
 * and put records on the limit they pass (docs/library.md). Before that,
 * they give their planner the limits widened by the slack as its bounds
 * (sh2000_path_set_bounds()): a primitive whose end or extremes are beyond
 * them is refused when it is added, -SH2000_ELIMIT, nothing queued.
 */
#define SH2000_LIMIT_SLACK_MM	0.002

struct sh2000_limits {
	double lo[SH2000_AXES], hi[SH2000_AXES];	/* mm */
};

/* The card's soft limits (SOFT_MIN, SOFT_MAX) in mm. */
int sh2000_limits_get(struct sh2000 *h, struct sh2000_limits *l);
/* 0: inside; 1: moved onto a limit (mm changed); -SH2000_ELIMIT: beyond,
 * msg says which axis, the value and the limit. */
int sh2000_limits_apply(const struct sh2000_limits *l,
			double mm[SH2000_AXES], char *msg, size_t len);

/*
 * Home one axis (flags SH2000_HOME_F_*) and wait up to timeout_ms for the
 * end: 0 when the axis is homed; -SH2000_ESTOPPED when a STOP (another
 * program's) ended it with nothing latched; a latched fault's error
 * otherwise. msg gets the words.
 */
int sh2000_run_home(struct sh2000 *h, unsigned int axis, unsigned int flags,
		    int timeout_ms, char *msg, size_t len);
/*
 * The same, and the caller's end: stop_asked(ctx) (NULL: none) is asked
 * every 20 ms of the wait; when it returns non-zero, or when timeout_ms
 * passes, the homing ends with a controlled STOP and a wait for the card
 * at rest (10 s at most), so nothing is latched: -ECANCELED (asked) or
 * -SH2000_ETIMEOUT (the timeout). sh2000_run_home() ends its timeout so.
 */
int sh2000_run_home_until(struct sh2000 *h, unsigned int axis,
			  unsigned int flags, int timeout_ms,
			  int (*stop_asked)(void *ctx), void *ctx,
			  char *msg, size_t len);

struct sh2000_run;

/* The card must be idle. msg gets the reason on failure. */
int sh2000_run_create(struct sh2000_run **out, struct sh2000 *h,
		      const struct sh2000_path_config *pc,
		      const struct sh2000_run_config *rc, char *msg,
		      size_t msglen);
/* Removes the sim observer; does not stop the card (call
 * sh2000_run_stop() and sh2000_run_finish() first for that). */
void sh2000_run_destroy(struct sh2000_run *r);

/* The planner: add primitives to it. Adding may already stream points
 * (the look-ahead window is full), so its errors may be the card's. It
 * has the card's soft limits, with SH2000_LIMIT_SLACK_MM, as its bounds:
 * a primitive beyond them is refused when added (-SH2000_ELIMIT, the words
 * in sh2000_run_error()), and nothing moves. */
struct sh2000_path *sh2000_run_path(struct sh2000_run *r);

/*
 * Plan, stream and execute everything added so far, then wait until the
 * card is idle at the end. 0 when done; -EAGAIN when paused (the card is
 * at rest, sh2000_run_resume() and call again); a negative error
 * otherwise (the card is stopped; see sh2000_run_error()).
 */
int sh2000_run_finish(struct sh2000_run *r);

/* Let seconds of card time pass with the card idle (a dwell), sampling. */
int sh2000_run_dwell(struct sh2000_run *r, double seconds);

/* Decelerate to rest on the path and discard the rest of the plan. */
void sh2000_run_stop(struct sh2000_run *r);
/* 1 once sh2000_run_stop() was called, until sh2000_run_finish() reports
 * it (-ECANCELED). */
int sh2000_run_stop_requested(const struct sh2000_run *r);
/*
 * Feed hold: decelerate to rest on the path; sh2000_run_finish() (and a
 * primitive added while the window is full) returns -EAGAIN once the card
 * is at rest. On a card with a time base (protocol 1.1, docs/protocol.md
 * 8.4) the card itself holds, starting within one servo cycle of the
 * request however much is queued; otherwise the planner decelerates. The
 * request is sent at the run's next poll (callbacks may ask).
 */
void sh2000_run_pause(struct sh2000_run *r);
void sh2000_run_resume(struct sh2000_run *r);
/* 1 while a card-side feed hold is asked for. */
int sh2000_run_held(const struct sh2000_run *r);
/* During a card-side hold: keep the card's host heartbeat, the polls and
 * the progress callback going for up to ms of card time, or until the
 * hold ends (a callback resumed) or a stop. 0, or the card's error. */
int sh2000_run_hold_wait(struct sh2000_run *r, unsigned int ms);
/* Feed override, 0 < factor <= 2: on the card's time base up to 1 (at
 * once), in the plan above it. */
int sh2000_run_set_override(struct sh2000_run *r, double factor);

/*
 * The last failure in words. The run's own (a card error, a set-point
 * beyond a soft limit, a planner failure sh2000_run_finish() met, a bad
 * argument) stays the answer through later successful calls, and through
 * the planner's own report of it ("the sink failed: ..."); a call on the
 * planner (sh2000_run_path()) that fails after it, with other words than
 * the planner had then, makes the planner's words (sh2000_path_error())
 * the answer, until the run fails again. "" before any failure.
 */
const char *sh2000_run_error(const struct sh2000_run *r);

struct sh2000_run_stats {
	uint64_t points;	/* coarse points pushed */
	uint64_t batches;	/* pushes */
	uint64_t motions;	/* points with END (motions from rest to rest) */
	uint64_t polls;		/* status polls made by the run */
	uint64_t samples;	/* samples delivered */
	double time_s;		/* card time from creation to the last poll */
	double distance_mm;	/* length of the set-point path (samples) */
	double max_ferr_mm;	/* largest |cmd - act| of one axis seen */
	unsigned int max_ferr_axis;
	/* least ring fill seen while the card was moving with more of the
	 * motion still to come (SH2000_RING_RECORDS when never seen) */
	unsigned int min_fill;
	uint64_t underruns;	/* card stopped because the ring ran dry */
	uint64_t reserved[8];	/* room to grow, zero (sh2000.h, above
				 * struct sh2000_status) */
};

void sh2000_run_stats(const struct sh2000_run *r, struct sh2000_run_stats *st);

/* ---- a whole program in two passes, in constant memory ------------------ */

/*
 * The way to run a program (sh2000-upload is the worked example): open a
 * reader (program.h), plan all of it once with sh2000_program_plan() --
 * every error in the program, every planner error and every planned point
 * beyond a soft limit is found before anything moves -- then rewind the
 * reader and stream it with sh2000_run_program(). Neither pass holds more
 * than the planner's look-ahead window and the current line.
 */
struct sh2000_program_opts {
	double override;		/* feed override (1) */
	int optional_stop;		/* M1 pauses like M0 (0: skipped) */
	/* the card's soft limits the plan must keep (NULL: none) */
	const struct sh2000_limits *limits;
	uint64_t reserved[8];	/* room to grow, zero (sh2000.h, above
				 * struct sh2000_status) */
};

void sh2000_program_opts_default(struct sh2000_program_opts *o);

struct sh2000_program_plan {
	uint64_t blocks;	/* read */
	uint64_t points;	/* coarse points planned */
	double seconds;		/* planned time, dwells included */
	unsigned int moved;	/* bit a: axis a moves (half a count or more) */
	uint64_t optional_skipped;	/* M1 not paused at (optional_stop 0) */
	/* a failure: "file:line[:column]" of the block and the reason */
	char where[256];
	char error[320];
	union {
		uint64_t reserved[8];	/* room to grow, zero (sh2000.h,
					 * above struct sh2000_status) */
		__extension__ struct {
			/* The largest acceleration of the card's set-points
			 * (the spline through the records: exact), as a
			 * fraction of its axis' amax, and that axis; for a
			 * plan refused over amax, the one refused. */
			double accel_peak;
			unsigned int accel_axis;
			/* 1: refused because the set-points pass an axis'
			 * amax (-ERANGE) */
			unsigned int accel_over;
			/* the planner's margin (pc->margin) it was planned
			 * with, and how many times sh2000_program_check()
			 * planned it again with a smaller one */
			double margin;
			unsigned int replans;
		};
	};
};

/*
 * Before the first pass: holds still (pc->still_axes) every axis no block
 * of r moves away from pc->start, so that a slow axis the program never
 * moves does not bound its plan; both passes then plan with *pc. Reads r
 * through once without a diagnostic and leaves it at its first line
 * (sh2000_prog_reader_axes()). 0, -ENOMEM or -EIO.
 */
int sh2000_program_axes(struct sh2000_prog_reader *r,
			struct sh2000_path_config *pc);

/*
 * The first pass: read r from where it stands to the end, plan every
 * block with pc and check each planned point against o->limits (a block
 * whose end or extremes are beyond them, with the slack, is refused when
 * it is added, sh2000_path_set_bounds()). 0 (plan
 * filled); -SH2000_EPROGRAM when the program has errors (they are in the
 * reader's diags); -SH2000_ELIMIT, -EINVAL... when a block cannot be
 * planned or leaves the limits (plan->where and plan->error say which and
 * why); -ERANGE with plan->accel_over when the planned set-points
 * accelerate an axis past its amax (sh2000_program_check() plans again);
 * -ENOMEM, -EIO.
 */
int sh2000_program_plan(struct sh2000_prog_reader *r,
			const struct sh2000_path_config *pc,
			const struct sh2000_program_opts *o,
			struct sh2000_program_plan *plan);

/*
 * The first pass as every front end runs it: sh2000_program_axes(), then
 * sh2000_program_plan() with *pc. Where the planned set-points would
 * accelerate an axis past its amax (the planner's known limits:
 * docs/planner.md), the reader is rewound and the program planned again
 * with a smaller pc->margin, as many times as it takes (at most
 * SH2000_PROGRAM_REPLANS, in steps of 1 % that grow: down to about half
 * the margin): no accepted plan passes an axis' amax. *pc is then what
 * the second pass plans with (plan->margin, plan->replans say what
 * changed); on an error pc->margin is left as it was. r must be fresh
 * or at its first line, as sh2000_program_axes() leaves it. Returns as
 * sh2000_program_plan(); -ERANGE (plan->accel_over) when no margin down
 * to the least keeps the limits.
 */
int sh2000_program_check(struct sh2000_prog_reader *r,
			 struct sh2000_path_config *pc,
			 const struct sh2000_program_opts *o,
			 struct sh2000_program_plan *plan);
#define SH2000_PROGRAM_REPLANS	10

/* How far an enabled axis may stand from the plan's start when the second
 * pass begins: a thousandth of a millimetre (rounding of counts to mm). */
#define SH2000_MOVED_TOL_MM	SH2000_PATH_STILL_TOL_MM

/*
 * The guard between the two passes: the card still stands where the plan
 * starts. Reads the card's position as sh2000_run_path_config() does and
 * compares every enabled axis with pc->start: one that moved more than
 * SH2000_MOVED_TOL_MM since the check is -SH2000_EMOVED, with "axis X moved
 * by D mm since the program was checked" in msg, and pc is left as it
 * was. Otherwise the enabled axes' starts become where they stand now and
 * 0 is returned. A disabled axis keeps the start the check read: the card
 * does not drive it and takes records that hold it anywhere (a carriage let
 * go of by a fault may still coast). Every front end that runs a checked
 * program calls this before the second pass.
 */
int sh2000_run_check_start(struct sh2000 *h, struct sh2000_path_config *pc,
			   char *msg, size_t len);

/* At an M0 (or M1 with optional_stop) the card is at rest: return 0 to go
 * on, or a negative error to end the run with it. */
typedef int (*sh2000_program_pause_fn)(void *ctx,
				       const struct sh2000_prog_block *b);

/*
 * The second pass: stream every block of r through run (created on the
 * card with the same path config), dwelling at G4 and calling pause at
 * M0/M1. The tag of the points is the block's line (the progress
 * callback's seq). 0 when the program ended at rest; -ECANCELED after
 * sh2000_run_stop(); -EAGAIN never (pauses are the callback's); other
 * errors as sh2000_run_finish() (the card is stopped,
 * sh2000_run_error()). An error in the program now (the file changed
 * since the first pass) is -SH2000_EPROGRAM.
 */
int sh2000_run_program(struct sh2000_run *run, struct sh2000_prog_reader *r,
		       const struct sh2000_program_opts *o,
		       sh2000_program_pause_fn pause, void *ctx);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_RUN_H */
