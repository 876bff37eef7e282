/* SPDX-License-Identifier: MIT */
/*
 * Compensation tables (protocol 1.5): what a table image means, for both
 * sides. The card model evaluates the image with these functions every
 * servo cycle and checks it with them at COMP_COMMIT; the host checks a
 * file with the same rule before it sends anything, so a table the
 * library accepts is one the card accepts. The image's words are in
 * sh2000_protocol.h; docs/compensation.md says what the tables are for.
 */
#ifndef SH2000_COMP_H
#define SH2000_COMP_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/card.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the card holds: image words and tables (the project's assumption:
 * a quarter of the SRAM half that data gathering leaves). */
#define SH2000_COMP_MAX_WORDS		16384u
#define SH2000_COMP_MAX_TABLES		16u

/* The card's tables, in its status. */
enum sh2000_comp_state {
	SH2000_COMP_NONE = 0,		/* no tables: nominal set-points */
	SH2000_COMP_ACTIVE = 1,		/* the tables correct every cycle */
	SH2000_COMP_SWITCHING = 2,	/* blending towards the new set */
};

/* Why an image is refused (the card's COMMIT VALUE carries it). */
enum sh2000_comp_reason {
	SH2000_COMP_R_OK = 0,
	SH2000_COMP_R_HEADER = 1,	/* magic, format, reserved word */
	SH2000_COMP_R_SIZE = 2,		/* larger than the card holds, or
					 * its words do not add up */
	SH2000_COMP_R_KIND = 3,		/* unknown kind of table */
	SH2000_COMP_R_AXIS = 4,		/* an axis beyond the card's */
	SH2000_COMP_R_POINTS = 5,	/* fewer than 2 points (grid: per
					 * direction) */
	SH2000_COMP_R_ORDER = 6,	/* positions not strictly increasing,
					 * or a grid step <= 0 */
	SH2000_COMP_R_VALUE = 7,	/* a correction not finite */
	SH2000_COMP_R_OFFSET = 8,	/* a correction above
					 * SH2000_COMP_MAX_OFFSET counts */
	SH2000_COMP_R_SLOPE = 9,	/* the corrected set-point would be
					 * faster than the axis' VMAX share */
	SH2000_COMP_R_ACCEL = 10,	/* ... or its AMAX share */
	SH2000_COMP_R_SUM = 11,		/* the image's sum does not match */
	SH2000_COMP_R_PAGES = 12,	/* pages missing or out of order */
};

/* The limits a set of tables is checked against, at load: the largest
 * correction of a table (they hold their ends' values beyond them; a
 * squareness is a line, not bounded), and the share of
 * each target axis' VMAX and AMAX the corrections of all its tables may
 * add together when every source axis moves at its own VMAX and AMAX (the
 * planner keeps 5 % of both free: docs/planner.md). */
#define SH2000_COMP_MAX_OFFSET		100000.0	/* counts: 1 mm at 10 nm */
/* Beyond a table's end its slope runs out to 0 over this many of its end
 * segments (comp_table.c), then the correction holds. */
#define SH2000_COMP_RUNOUT		16.0
#define SH2000_COMP_VMAX_SHARE		0.02
#define SH2000_COMP_AMAX_SHARE		0.04

/* The axes' parameters the check needs, in counts, counts/s, counts/s^2. */
struct sh2000_comp_limits {
	double vmax[SH2000_AXES], amax[SH2000_AXES];
};

/* One table of an image, found by sh2000_comp_parse(). */
struct sh2000_comp_desc {
	unsigned int kind;		/* enum sh2000_comp_kind */
	unsigned int target, src1, src2, n1, n2;
	size_t data;			/* its data's first word in the image */
};

struct sh2000_comp_index {
	uint32_t id;
	unsigned int tables;
	struct sh2000_comp_desc t[SH2000_COMP_MAX_TABLES];
};

/* Where and why an image is refused: table 0.., point (a position of a
 * TABLE; i + n1 * j of a GRID) or -1 for the table as a whole. */
struct sh2000_comp_fault {
	int table, point;
	enum sh2000_comp_reason reason;
};

/* The layout of image w[0..n-1]: 0 and *ix filled, or -1 and *why. */
int sh2000_comp_parse(const uint16_t *w, size_t n,
		      struct sh2000_comp_index *ix,
		      struct sh2000_comp_fault *why);
/* A parsed image against the axes' limits: 0, or -1 and *why. */
int sh2000_comp_check(const uint16_t *w, const struct sh2000_comp_index *ix,
		      const struct sh2000_comp_limits *lim,
		      struct sh2000_comp_fault *why);
/* The corrections (counts, added to each axis' set-point) at nominal
 * positions pos[] (counts): the sum of every table's. */
void sh2000_comp_eval(const uint16_t *w, const struct sh2000_comp_index *ix,
		      const double pos[SH2000_AXES], double off[SH2000_AXES]);
/* One table's correction at pos[] and its derivatives by its sources:
 * d[0] = d/dsrc1, d[1] = d/dsrc2 (GRID), dd[0..2] the second ones
 * (11, 22, 12). */
double sh2000_comp_eval_table(const uint16_t *w,
			      const struct sh2000_comp_desc *t,
			      const double pos[SH2000_AXES], double d[2],
			      double dd[3]);
/* Where table t changes along its source axis 1 (second 0) or 2 (second
 * 1, a GRID): from its first point less its run-out to its last point
 * plus its run-out (SH2000_COMP_RUNOUT), in counts; beyond, it holds. A
 * SQUARE changes everywhere: -INFINITY..INFINITY. */
void sh2000_comp_table_span(const uint16_t *w,
			    const struct sh2000_comp_desc *t, int second,
			    double span[2]);
/*
 * How far the tables move each axis inside its soft limits. The card
 * judges its soft limits on the nominal set-point and adds the tables'
 * correction after (docs/compensation.md "Soft limits and the
 * corrections"), so a correction at a soft limit takes the tool beyond it.
 * sh2000_comp_reach() is the one owner of that judgement: sh2000ctl's
 * `comp load`, hal_sh2000's `comp=` and sh2000-comp ask it (for a card
 * and a file: sh2000_comp_reach_file(), sh2000/sh2000.h).
 *
 * Both structs end in `reserved` (zero; a later field takes its place in
 * an anonymous union, so the size and every offset stay: docs/install.md
 * "Versions and the ABI").
 */
/* The window the corrections are judged over: the card's SOFT_MIN and
 * SOFT_MAX in counts, as the card holds them (-2^31 and 2^31-1 are off),
 * and the scales that name them in mm. */
struct sh2000_comp_window {
	int32_t soft_min[SH2000_AXES], soft_max[SH2000_AXES];	/* counts */
	double scale[SH2000_AXES];	/* counts/mm, > 0 */
	uint64_t reserved[4];		/* room to grow, zero */
};

/* A corrected position within this of its soft limit (counts) is not
 * beyond it: the card's set-points are whole counts. */
#define SH2000_COMP_REACH_SLACK		0.5

/* One axis' reach (counts). With several tables on the axis each is
 * taken at its own worst and the ranges added: then a bound, not exact. */
struct sh2000_comp_reach {
	unsigned int tables;	/* tables that correct the axis; 0: none,
				 * and the rest is 0 */
	double lo, hi;		/* its smallest and largest correction with
				 * every source axis inside its soft limits
				 * (where one is off, across the table's
				 * points and run-outs; a squareness there,
				 * a metre either way) */
	double beyond[2];	/* how far the corrected position at its
				 * soft_min [0] / soft_max [1] lies beyond
				 * that limit; 0 when within
				 * SH2000_COMP_REACH_SLACK or the limit is
				 * off */
	uint64_t reserved[4];	/* room to grow, zero */
};

/* The reach of every axis for parsed image w with window *win: the
 * number of axes a table corrects (>= 0), or -1 when an argument is NULL.
 * The tables are evaluated by sh2000_comp_eval_table(), the card's code,
 * sampled across the window (at most 0.2 um missed of a peak over 1 m). */
int sh2000_comp_reach(const uint16_t *w, const struct sh2000_comp_index *ix,
		      const struct sh2000_comp_window *win,
		      struct sh2000_comp_reach reach[SH2000_AXES]);
/* The words for axis `axis` beyond its soft_min (side 0) or soft_max
 * (side 1) into msg[len] (no "warning: " before them, no newline): the
 * length snprintf gives, 0 (msg "") when it is not beyond. */
int sh2000_comp_reach_warning(const struct sh2000_comp_window *win,
			      const struct sh2000_comp_reach reach[SH2000_AXES],
			      unsigned int axis, unsigned int side, char *msg,
			      size_t len);
/* Words for a reason, never NULL. */
const char *sh2000_comp_reason_name(unsigned int reason);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_COMP_H */
