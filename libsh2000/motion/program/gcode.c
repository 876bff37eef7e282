/* SPDX-License-Identifier: MIT */
/*
 * The built-in RS-274 reader: the subset of LinuxCNC's G-code listed in
 * docs/programs.md, with LinuxCNC's modal groups, word rules, arc rules and
 * G5.2/G5.3 NURBS blocks. Every line is checked; nothing is skipped
 * silently. This half interprets a line's words against the modal state
 * (LinuxCNC's interp_convert); gcode_read.c splits the line into words.
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gcode_read.h"

struct gstate {
	enum sh2000_plane plane;
	bool inch, incremental, arc_absolute;
	int motion;
	double feed_mm_min;
	bool ended;		/* M2/M30 or closing % seen */
	bool percent;		/* the program opened with % */
	bool seen_content;
	/* open G5.2 block */
	bool nurbs_open;
	bool nurbs_failed;	/* its G5.2 line was an error: quiet to G5.3 */
	unsigned int nurbs_line, nurbs_col, nurbs_order;
	size_t npts, cap;
	double (*pts)[SH2000_AXES];
	double *w;
	struct prog_tool_state tools;	/* T, M6, the tool length offset */
	bool tlo_inch;			/* the offset was set under G20 */
};

static bool nurbs_push(struct prog_ctx *c, struct gstate *st, double x,
		       double y, double w)
{
	if (st->npts == st->cap) {
		size_t cap = st->cap ? st->cap * 2 : 16;
		void *p = realloc(st->pts, cap * sizeof(*st->pts));
		void *q;

		if (!p)
			goto oom;
		st->pts = p;
		q = realloc(st->w, cap * sizeof(*st->w));
		if (!q)
			goto oom;
		st->w = q;
		st->cap = cap;
	}
	st->pts[st->npts][SH2000_PROG_X] = x;
	st->pts[st->npts][SH2000_PROG_Y] = y;
	st->pts[st->npts][SH2000_PROG_Z] = c->pos[SH2000_PROG_Z];
	st->pts[st->npts][SH2000_PROG_A] = c->pos[SH2000_PROG_A];
	st->w[st->npts++] = w;
	return true;
oom:
	c->oom = true;
	c->stop = true;
	return false;
}

static double feed_mm_s(const struct gstate *st)
{
	return st->feed_mm_min / 60.0;
}

static int need_feed(struct prog_ctx *c, const struct gstate *st,
		     unsigned int line, unsigned int col, const char *what)
{
	if (st->feed_mm_min > 0)
		return 0;
	return prog_err(c, SH2000_PD_FEED, line, col,
			"%s with zero feed rate: program F before the first feed move",
			what);
}

/* G5.2 line: open the block or add a control point. */
static int do_nurbs_point(struct prog_ctx *c, struct gstate *st,
			  const struct gline *l, unsigned int bcol, double unit)
{
	bool xy = HAS(l, 'X') || HAS(l, 'Y');
	int ret;

	if (st->plane != SH2000_PLANE_XY)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, bcol,
				"G5.2 NURBS is read in the XY plane (G17) only");
	if (st->incremental)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, bcol,
				"G5.2 NURBS in incremental distance mode (G91) is not supported: LinuxCNC measures every control point from the curve's start, not from the previous point; use G90");
	if (HAS(l, 'Z') || HAS(l, 'A'))
		return prog_err(c, SH2000_PD_NURBS, l->line,
				HAS(l, 'Z') ? COL(l, 'Z') : COL(l, 'A'),
				"G5.2 control points take X and Y only");
	if (HAS(l, 'X') != HAS(l, 'Y'))
		return prog_err(c, SH2000_PD_MISSING, l->line,
				HAS(l, 'X') ? COL(l, 'X') : COL(l, 'Y'),
				"G5.2 control point needs both X and Y");
	if (HAS(l, 'P') && !(VAL(l, 'P') > 0))
		return prog_err(c, SH2000_PD_RANGE, l->line, COL(l, 'P'),
				"P (control point weight) must be > 0");
	/* LinuxCNC's manual says P defaults to 1; its interpreter (2.9)
	 * rejects a control point without P (or, on the opening line,
	 * takes -1): require it, as the interpreter does */
	if (xy && !HAS(l, 'P'))
		return prog_err(c, SH2000_PD_MISSING, l->line, COL(l, 'X'),
				"control point without P (weight): LinuxCNC requires a positive weight on every G5.2 control point");
	if (HAS(l, 'L')) {
		double L = VAL(l, 'L');

		if (L != floor(L) || L < 3 || L > SH2000_NURBS_MAX_DEGREE + 1)
			return prog_err(c, SH2000_PD_RANGE, l->line, COL(l, 'L'),
					"L (NURBS order) must be an integer from 3 to %d (LinuxCNC ignores smaller values)",
					SH2000_NURBS_MAX_DEGREE + 1);
	}
	if (!st->nurbs_open) {
		ret = need_feed(c, st, l->line, bcol, "G5.2 NURBS");
		if (ret)
			return ret;
		st->nurbs_open = true;
		st->nurbs_line = l->line;
		st->nurbs_col = bcol;
		st->nurbs_order = 3;
		st->npts = 0;
		/* the current point is the first control point; a P without
		 * X Y on the opening line is its weight */
		if (!nurbs_push(c, st, c->pos[SH2000_PROG_X], c->pos[SH2000_PROG_Y],
				!xy && HAS(l, 'P') ? VAL(l, 'P') : 1.0))
			return -ENOMEM;
	} else if (!xy && HAS(l, 'P')) {
		return prog_err(c, SH2000_PD_NURBS, l->line, COL(l, 'P'),
				"P without X and Y sets the weight of the first control point only (on the opening G5.2 line)");
	}
	if (HAS(l, 'L'))
		st->nurbs_order = (unsigned int)VAL(l, 'L');
	if (xy && !nurbs_push(c, st,
			      VAL(l, 'X') * unit + st->tools.offset[SH2000_PROG_X],
			      VAL(l, 'Y') * unit + st->tools.offset[SH2000_PROG_Y],
			      VAL(l, 'P')))
		return -ENOMEM;
	st->motion = MOT_G52;
	return 0;
}

static int do_nurbs_end(struct prog_ctx *c, struct gstate *st,
			const struct gline *l, unsigned int bcol)
{
	struct sh2000_prog_block *b;
	struct prog_nurbs_buf n;
	struct sh2000_nurbs view;
	size_t np = st->npts, nk;
	unsigned int k = st->nurbs_order;
	int ret;

	if (!st->nurbs_open)
		return prog_err(c, SH2000_PD_NURBS, l->line, bcol,
				"G5.3 without an open G5.2 NURBS block");
	st->nurbs_open = false;
	st->motion = MOT_NONE;
	if (np < k)
		return prog_err(c, SH2000_PD_NURBS, l->line, bcol,
				"G5.3: the NURBS block opened at line %u has %zu control points (with the start point), fewer than its order L=%u",
				st->nurbs_line, np, k);
	ret = prog_nurbs_alloc(c, &n, k - 1, np);
	if (ret)
		return ret;
	nk = np + k;
	memcpy(n.points, st->pts, np * sizeof(*n.points));
	memcpy(n.weights, st->w, np * sizeof(*n.weights));
	/* LinuxCNC's knot_vector_creator(n = np - 1, k): clamped, uniform,
	 * integer knots 0 .. np - k + 1 */
	for (size_t i = 0; i < nk; i++) {
		if (i < k)
			n.knots[i] = 0;
		else if (i <= np - 1)
			n.knots[i] = (double)(i - k + 1);
		else
			n.knots[i] = (double)(np - k + 1);
	}
	view = prog_nurbs_view(&n);
	ret = prog_nurbs_check(c, &view, st->nurbs_line, st->nurbs_col);
	b = ret ? NULL : prog_push(c, SH2000_PROG_NURBS, st->nurbs_line,
				   st->nurbs_col);
	if (!b) {
		prog_nurbs_free(&n);
		return ret ? ret : -ENOMEM;
	}
	prog_nurbs_give(&n, b);
	b->feed = feed_mm_s(st);
	memcpy(b->end, st->pts[np - 1], sizeof(b->end));
	memcpy(c->pos, b->end, sizeof(c->pos));
	return 0;
}

static int do_arc(struct prog_ctx *c, struct gstate *st, const struct gline *l,
		  bool ccw, unsigned int bcol, double unit,
		  const double target[SH2000_AXES])
{
	static const char letter_of[SH2000_AXES] = { 'I', 'J', 'K', 0 };
	unsigned int a1, a2, an, turns = 1;
	char L1, L2, Ln;
	double c1, c2, tol;
	struct sh2000_prog_block *b;
	bool ijk = HAS(l, 'I') || HAS(l, 'J') || HAS(l, 'K');
	int ret;

	ret = need_feed(c, st, l->line, bcol, ccw ? "G3 arc" : "G2 arc");
	if (ret)
		return ret;
	if (HAS(l, 'R') && ijk)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'R'),
				"arc with both R and I/J/K: use one format");
	if (!HAS(l, 'R') && !ijk)
		return prog_err(c, SH2000_PD_MISSING, l->line, bcol,
				"arc needs I/J/K (centre) or R (radius)");
	sh2000_plane_axes(st->plane, &a1, &a2, &an);
	L1 = letter_of[a1];
	L2 = letter_of[a2];
	Ln = letter_of[an];
	if (HAS(l, 'P')) {
		double p = VAL(l, 'P');

		if (fabs(p - round(p)) > 1e-6 || p < 1 || p > 1e6)
			return prog_err(c, SH2000_PD_RANGE, l->line, COL(l, 'P'),
					"P (number of turns) must be an integer >= 1");
		turns = (unsigned int)lround(p);
	}
	if (ijk) {
		double o1, o2;

		if (HAS(l, Ln))
			return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, Ln),
					"%c word with an arc in the %s plane (G%d)",
					Ln, sh2000_plane_name(st->plane),
					(int)st->plane);
		if (st->arc_absolute && (!HAS(l, L1) || !HAS(l, L2)))
			return prog_err(c, SH2000_PD_MISSING, l->line, bcol,
					"%c word missing in absolute centre arc (G90.1 needs both %c and %c)",
					HAS(l, L1) ? L2 : L1, L1, L2);
		o1 = HAS(l, L1) ? VAL(l, L1) * unit : 0;
		o2 = HAS(l, L2) ? VAL(l, L2) * unit : 0;
		/* an absolute centre is where the tip's path turns */
		c1 = st->arc_absolute ? o1 + st->tools.offset[a1] : c->pos[a1] + o1;
		c2 = st->arc_absolute ? o2 + st->tools.offset[a2] : c->pos[a2] + o2;
	} else {
		const char *axes = SH2000_AXIS_LETTERS;

		if (!HAS(l, axes[a1]) && !HAS(l, axes[a2]))
			return prog_err(c, SH2000_PD_MISSING, l->line, bcol,
					"R-format arc needs %c or %c: a full circle needs I/J/K",
					axes[a1], axes[a2]);
		ret = prog_arc_centre_r(c, c->pos[a1], c->pos[a2], target[a1],
					target[a2], VAL(l, 'R') * unit, ccw,
					&c1, &c2, l->line, bcol);
		if (ret)
			return ret;
	}
	b = prog_push(c, SH2000_PROG_ARC, l->line, bcol);
	if (!b)
		return -ENOMEM;
	memcpy(b->end, target, sizeof(b->end));
	b->feed = feed_mm_s(st);
	tol = c->opt.arc_tolerance_mm > 0 ? c->opt.arc_tolerance_mm :
	      st->inch ? SH2000_ARC_CENTRE_TOL_INCH_MM : SH2000_ARC_CENTRE_TOL_MM;
	ret = prog_arc_fill(c, b, st->plane, c1, c2, ccw, turns, tol, 0, l->line,
			    bcol);
	if (ret) {
		c->prog->count--;
		return ret;
	}
	return 0;
}

static void warn_not_acted(struct prog_ctx *c, const struct gline *l)
{
	if (HAS(l, 'S'))
		prog_warn_once(c, PW_SPEED, SH2000_PD_NOT_ACTED, l->line,
			       COL(l, 'S'),
			       "S%g (spindle speed) not acted on: the SH-2000TH has no spindle output; later S words are not reported",
			       VAL(l, 'S'));
	if (l->m[MGRP_SPINDLE] >= 0)
		prog_warn_once(c, PW_SPINDLE, SH2000_PD_NOT_ACTED, l->line,
			       l->mcol[MGRP_SPINDLE],
			       "M%d (spindle %s) not acted on: the SH-2000TH has no spindle output; later M3/M4/M5 are not reported",
			       l->m[MGRP_SPINDLE],
			       l->m[MGRP_SPINDLE] == 5 ? "stop" :
			       l->m[MGRP_SPINDLE] == 3 ? "clockwise" :
			       "counter-clockwise");
	if (l->m[MGRP_COOLANT] >= 0)
		prog_warn_once(c, PW_COOLANT, SH2000_PD_NOT_ACTED, l->line,
			       l->mcol[MGRP_COOLANT],
			       "M%d (coolant %s) not acted on: the SH-2000TH has no coolant output; later M7/M8/M9 are not reported",
			       l->m[MGRP_COOLANT],
			       l->m[MGRP_COOLANT] == 9 ? "off" :
			       l->m[MGRP_COOLANT] == 7 ? "mist" : "flood");
}

/* The words that need a user: P, L, I J K R. */
static int check_users(struct prog_ctx *c, const struct gline *l, int motion)
{
	bool arc = motion == MOT_G2 || motion == MOT_G3;
	bool dwell = l->g[GRP_NONMODAL] == 40;

	if (HAS(l, 'P') && dwell && (arc || motion == MOT_G52))
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'P'),
				"G4 and %s on one line both use P",
				motion == MOT_G52 ? "G5.2" : arc && motion == MOT_G2 ? "G2" : "G3");
	if (HAS(l, 'P') && !dwell && !arc && motion != MOT_G52 &&
	    l->g[GRP_PATH] != 640)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'P'),
				"P word with no G4, G2/G3, G5.2 or G64 to use it");
	if (HAS(l, 'L') && motion != MOT_G52)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'L'),
				"L word with no G5.2 to use it");
	if (HAS(l, 'H') && l->g[GRP_TOOLLEN] != 430 && l->g[GRP_TOOLLEN] != 432)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'H'),
				"H word with no G43 or G43.2 to use it");
	if (HAS(l, 'K') && !arc && l->g[GRP_TOOLLEN] == 431)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'K'),
				"K word with G43.1: LinuxCNC 2.9 takes the dynamic offset from axis words (G43.1 Z-), not from K");
	for (const char *w = "IJKR"; *w; w++)
		if (HAS(l, *w) && !arc)
			return prog_err(c, SH2000_PD_CONFLICT, l->line,
					COL(l, *w),
					"%c word with no G2 or G3 to use it", *w);
	if (l->g[GRP_PATH] == 640 && HAS(l, 'P') && dwell)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'P'),
				"G4 and G64 on one line both use P");
	return 0;
}

/* A line inside an open G5.2 block may hold only X, Y, P and L. */
static int nurbs_line_check(struct prog_ctx *c, const struct gstate *st,
			    const struct gline *l)
{
	char nb[16];

	for (int i = 0; i < 26; i++)
		if (l->has[i] && !strchr("XYPL", 'A' + i))
			return prog_err(c, SH2000_PD_NURBS, l->line, l->col[i],
					"%c word inside the NURBS block opened by G5.2 at line %u: only X, Y, P and L may appear until G5.3",
					'A' + i, st->nurbs_line);
	for (int g = 0; g < GRP_COUNT; g++)
		if (l->g[g] >= 0 && l->g[g] != 52 && l->g[g] != 53)
			return prog_err(c, SH2000_PD_NURBS, l->line, l->gcol[g],
					"%s inside the NURBS block opened by G5.2 at line %u: close it with G5.3 first",
					gcode_gname(l->g[g], nb, sizeof(nb)), st->nurbs_line);
	for (int g = 0; g < MGRP_COUNT; g++)
		if (l->m[g] >= 0)
			return prog_err(c, SH2000_PD_NURBS, l->line, l->mcol[g],
					"M%d inside the NURBS block opened by G5.2 at line %u: close it with G5.3 first",
					l->m[g], st->nurbs_line);
	return 0;
}

/* Axis words that make a move: not those of a G43.1 line without a
 * motion word (they are its offset; LinuxCNC moves too only when the line
 * has G0/G1... as well). */
static bool axis_words_move(const struct gline *l)
{
	return (HAS(l, 'X') || HAS(l, 'Y') || HAS(l, 'Z') || HAS(l, 'A')) &&
	       (l->g[GRP_TOOLLEN] != 431 || l->g[GRP_MOTION] >= 0);
}

/* The motion this line runs: its own, or the modal one when it has axis
 * words (LinuxCNC's motion_to_be); *bcol where the block starts. */
static int line_motion(struct prog_ctx *c, const struct gstate *st,
		       const struct gline *l, int *motion, unsigned int *bcol)
{
	bool axis = axis_words_move(l);
	int mword = l->g[GRP_MOTION];

	*motion = mword >= 0 ? mword : axis ? st->motion : MOT_NONE;
	*bcol = mword >= 0 ? l->gcol[GRP_MOTION] : l->first_col;
	if (mword == MOT_G80 && axis)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, l->gcol[GRP_MOTION],
				"axis words with G80 (motion off)");
	if (mword < 0 && axis && st->motion == MOT_NONE)
		return prog_err(c, SH2000_PD_MISSING, l->line, l->first_col,
				"axis words without a motion mode: program G0, G1, G2, G3 or G5.2 first");
	if (mword == MOT_G53 && axis)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, l->first_col,
				"axis words with G5.3 (end of NURBS block)");
	return check_users(c, l, *motion);
}

/* F: LinuxCNC sets the feed (step 4 of its order of execution) before it
 * changes units (step 16), so F is in the units before the line's
 * G20/G21. */
static int do_feed_word(struct prog_ctx *c, struct gstate *st,
			const struct gline *l)
{
	double f = VAL(l, 'F'), unit = st->inch ? PROG_MM_PER_INCH : 1.0;
	struct sh2000_prog_block *b;

	if (l->g[GRP_UNITS] >= 0 && (l->g[GRP_UNITS] == 200) != st->inch)
		prog_warn_once(c, PW_UNITS_F, SH2000_PD_ORDER, l->line, COL(l, 'F'),
			       "F%g is read in %s, the units before this line's %s, as LinuxCNC does (it sets the feed before it changes units); put G20/G21 on a line of its own (later cases are not reported)",
			       f, st->inch ? "inches" : "mm",
			       l->g[GRP_UNITS] == 200 ? "G20" : "G21");
	if (f < 0)
		return prog_err(c, SH2000_PD_RANGE, l->line, COL(l, 'F'),
				"negative feed rate F%g", f);
	if (f * unit == st->feed_mm_min)
		return 0;
	st->feed_mm_min = f * unit;
	b = prog_push(c, SH2000_PROG_FEED, l->line, COL(l, 'F'));
	if (!b)
		return -ENOMEM;
	b->u.feed_mm_min = st->feed_mm_min;
	b->feed = feed_mm_s(st);
	return 0;
}

static int do_dwell(struct prog_ctx *c, const struct gline *l)
{
	struct sh2000_prog_block *b;

	if (!HAS(l, 'P'))
		return prog_err(c, SH2000_PD_MISSING, l->line, l->gcol[GRP_NONMODAL],
				"G4 without P (dwell seconds)");
	if (VAL(l, 'P') < 0)
		return prog_err(c, SH2000_PD_RANGE, l->line, COL(l, 'P'),
				"G4 P (dwell seconds) is negative");
	b = prog_push(c, SH2000_PROG_DWELL, l->line, l->gcol[GRP_NONMODAL]);
	if (!b)
		return -ENOMEM;
	b->u.dwell_s = VAL(l, 'P');
	return 0;
}

/* G61, G61.1, G64 [P [Q]]: the path control mode, in mm. */
static int do_path_mode(struct prog_ctx *c, const struct gstate *st,
			const struct gline *l)
{
	double unit = st->inch ? PROG_MM_PER_INCH : 1.0;
	int code = l->g[GRP_PATH];
	struct sh2000_prog_block *b;

	if (HAS(l, 'Q') && code != 640)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'Q'),
				"Q word with no G64 to use it");
	if (code == 640 && HAS(l, 'Q') && !HAS(l, 'P'))
		return prog_err(c, SH2000_PD_MISSING, l->line, COL(l, 'Q'),
				"G64 Q (naive CAM tolerance) needs P (blending tolerance)");
	if ((HAS(l, 'P') && code == 640 && VAL(l, 'P') < 0) ||
	    (HAS(l, 'Q') && VAL(l, 'Q') < 0))
		return prog_err(c, SH2000_PD_RANGE, l->line,
				COL(l, VAL(l, 'P') < 0 ? 'P' : 'Q'),
				"G64 tolerances must not be negative");
	b = prog_push(c, SH2000_PROG_PATH_MODE, l->line, l->gcol[GRP_PATH]);
	if (!b)
		return -ENOMEM;
	b->u.path.mode = code == 610 ? SH2000_PATH_EXACT_PATH :
			 code == 611 ? SH2000_PATH_EXACT_STOP :
			 SH2000_PATH_BLEND;
	b->u.path.tolerance = code == 640 && HAS(l, 'P') ? VAL(l, 'P') * unit : 0;
	/* LinuxCNC: Q defaults to P */
	b->u.path.naive_tolerance = HAS(l, 'Q') ? VAL(l, 'Q') * unit :
				    b->u.path.tolerance;
	return 0;
}

/* G43 <H->, G43.1 axis words, G43.2 H-, G49: the tool length offset in
 * mm, in force from this line's motion on (the machine does not move). */
static int do_tool_length(struct prog_ctx *c, struct gstate *st,
			  const struct gline *l, double unit)
{
	static const char axes[] = SH2000_AXIS_LETTERS;
	double *off = st->tools.offset, add[SH2000_AXES], h = VAL(l, 'H');
	int code = l->g[GRP_TOOLLEN];
	bool axis = HAS(l, 'X') || HAS(l, 'Y') || HAS(l, 'Z') || HAS(l, 'A');
	char what[64];

	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if (off[a] != 0 && st->tlo_inch != st->inch)
			prog_warn_once(c, PW_TLO_UNITS, SH2000_PD_ORDER, l->line,
				       l->gcol[GRP_TOOLLEN],
				       "a tool length offset set under %s is changed under %s: here offsets stay in mm, but LinuxCNC 2.9's interpreter (as Debian's rs274 shows) keeps the old offset's number in the new units and moves the tool by the difference; put G20/G21 before the first G43 (later cases are not reported)",
				       st->tlo_inch ? "G20" : "G21",
				       st->inch ? "G20" : "G21");
	st->tlo_inch = st->inch;
	if (code == 490 || code == 431) {
		for (unsigned int a = 0; a < SH2000_AXES; a++) {
			off[a] = code == 431 && HAS(l, axes[a]) ?
				 VAL(l, axes[a]) * (a == SH2000_PROG_A ? 1 : unit) : 0;
			/* a position plus it must stay a number */
			if (fabs(off[a]) > 1e9)
				return prog_err(c, SH2000_PD_RANGE, l->line,
						COL(l, axes[a]),
						"G43.1 %c offset out of range",
						axes[a]);
		}
		return 0;
	}
	if (code == 432 && (!HAS(l, 'H') || axis))
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line,
				l->gcol[GRP_TOOLLEN],
				"G43.2 adds the offsets of the tool its H word names; with axis words (or without H) it is not supported");
	if (HAS(l, 'H') && (h != floor(h) || h < 0 || h > 1e9))
		return prog_err(c, SH2000_PD_RANGE, l->line, COL(l, 'H'),
				"H%g: a tool number is an integer >= 0", h);
	if (HAS(l, 'H'))
		snprintf(what, sizeof(what), "%s H%d",
			 code == 430 ? "G43" : "G43.2", (int)h);
	else
		snprintf(what, sizeof(what), "G43 (T%d in the spindle)",
			 st->tools.loaded);
	if (prog_tool_offsets(c, HAS(l, 'H') ? (int)h : st->tools.loaded, add,
			      what, l->line,
			      HAS(l, 'H') ? COL(l, 'H') : l->gcol[GRP_TOOLLEN]))
		return -SH2000_PROG_EINVALID;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		off[a] = (code == 432 ? off[a] : 0) + add[a];
	return 0;
}

/* T, M6 and the tool length offset, in LinuxCNC's order (select, change,
 * then, after the units, the offset). */
static int do_tools(struct prog_ctx *c, struct gstate *st,
		    const struct gline *l)
{
	int ret;

	if (HAS(l, 'T') && (ret = prog_tool_select(c, &st->tools, VAL(l, 'T'),
						    l->line, COL(l, 'T'))))
		return ret;
	if (l->m[MGRP_TOOL] == 6 &&
	    (ret = prog_tool_change(c, &st->tools, "M6", l->line,
				    l->mcol[MGRP_TOOL])))
		return ret;
	if (l->g[GRP_TOOLLEN] < 0)
		return 0;
	return do_tool_length(c, st, l, st->inch ? PROG_MM_PER_INCH : 1.0);
}

/* The modal settings of a line, in LinuxCNC's order after F. */
static int do_modes(struct prog_ctx *c, struct gstate *st,
		    const struct gline *l)
{
	int ret = 0;

	if (l->g[GRP_UNITS] >= 0)
		st->inch = l->g[GRP_UNITS] == 200;
	warn_not_acted(c, l);
	if ((ret = do_tools(c, st, l)))
		return ret;
	if (HAS(l, 'A') && st->inch)
		prog_warn_once(c, PW_A_INCH, SH2000_PD_ORDER, l->line, COL(l, 'A'),
			       "A%g is read in mm although the program is in inches: G20 does not scale A, as in LinuxCNC (later cases are not reported)",
			       VAL(l, 'A'));
	if (l->g[GRP_NONMODAL] == 40 && (ret = do_dwell(c, l)))
		return ret;
	if (l->g[GRP_PLANE] >= 0)
		st->plane = (enum sh2000_plane)(l->g[GRP_PLANE] / 10);
	if (l->g[GRP_PATH] >= 0 && (ret = do_path_mode(c, st, l)))
		return ret;
	if (HAS(l, 'Q') && l->g[GRP_PATH] < 0)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, COL(l, 'Q'),
				"Q word with no G64 to use it");
	if (l->g[GRP_DIST] >= 0)
		st->incremental = l->g[GRP_DIST] == 910;
	if (l->g[GRP_ARCDIST] >= 0)
		st->arc_absolute = l->g[GRP_ARCDIST] == 901;
	/* G40 G54 G94 select the only state this reader has */
	return 0;
}

/* The end point of a move: the axis words in the line's units and
 * distance mode (A is mm even under G20: LinuxCNC never scales A). An
 * absolute word names the tool's tip: the machine goes to it plus the
 * tool length offset; a distance is the same for both. */
static int move_target(struct prog_ctx *c, const struct gstate *st,
		       const struct gline *l, double unit,
		       double target[SH2000_AXES])
{
	static const char axes[] = SH2000_AXIS_LETTERS;

	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		target[a] = c->pos[a];
		if (HAS(l, axes[a]))
			target[a] = VAL(l, axes[a]) *
				    (a == SH2000_PROG_A ? 1 : unit) +
				    (st->incremental ? c->pos[a] :
				     st->tools.offset[a]);
		if (!isfinite(target[a]))
			return prog_err(c, SH2000_PD_RANGE, l->line,
					COL(l, axes[a]), "%c target out of range",
					axes[a]);
	}
	return 0;
}

/* G0, G1, G2, G3 to the line's target; the machine goes on from the
 * programmed end even when the move has an error. */
static int do_move(struct prog_ctx *c, struct gstate *st,
		   const struct gline *l, int motion, unsigned int bcol,
		   double unit)
{
	double target[SH2000_AXES];
	struct sh2000_prog_block *b;
	int ret = move_target(c, st, l, unit, target);

	if (ret)
		return ret;
	if (motion == MOT_G2 || motion == MOT_G3)
		ret = do_arc(c, st, l, motion == MOT_G3, bcol, unit, target);
	else if (motion == MOT_G1 &&
		 (ret = need_feed(c, st, l->line, bcol, "G1 move")))
		;
	else if ((b = prog_push(c, motion == MOT_G0 ? SH2000_PROG_RAPID :
				SH2000_PROG_LINE, l->line, bcol))) {
		memcpy(b->end, target, sizeof(b->end));
		if (motion == MOT_G1)
			b->feed = feed_mm_s(st);
	} else {
		return -ENOMEM;
	}
	memcpy(c->pos, target, sizeof(c->pos));
	return ret;
}

/* G5.2 points and G5.3; 1 when the line's motion is not NURBS. */
static int do_nurbs_motion(struct prog_ctx *c, struct gstate *st,
			   const struct gline *l, int motion,
			   unsigned int bcol, double unit)
{
	int mword = l->g[GRP_MOTION], ret;
	bool opening;

	if (mword == MOT_G53 && st->nurbs_failed) {
		/* the block's opening was reported; its end needs no error */
		st->nurbs_failed = false;
		st->motion = MOT_NONE;
		return 0;
	}
	if (mword == MOT_G53)
		return do_nurbs_end(c, st, l, bcol);
	if (motion != MOT_G52)
		return 1;
	if (st->nurbs_failed && mword < 0)
		return 0;	/* points of a block whose G5.2 line failed */
	opening = !st->nurbs_open;
	st->nurbs_failed = false;
	ret = do_nurbs_point(c, st, l, bcol, unit);
	if (ret)
		st->nurbs_failed = opening && !st->nurbs_open;
	return ret;
}

/* M0, M1 (pause), M2, M30 (end). */
static int do_stop_m(struct prog_ctx *c, struct gstate *st,
		     const struct gline *l)
{
	int m = l->m[MGRP_STOP];
	struct sh2000_prog_block *b;

	b = prog_push(c, m <= 1 ? SH2000_PROG_PAUSE : SH2000_PROG_END, l->line,
		      l->mcol[MGRP_STOP]);
	if (!b)
		return -ENOMEM;
	if (m <= 1) {
		b->u.optional = m == 1;
	} else {
		b->u.end_code = m;
		st->ended = true;
	}
	return 0;
}

static int exec_line(struct prog_ctx *c, struct gstate *st, struct gline *l)
{
	bool axis = axis_words_move(l);
	int mword = l->g[GRP_MOTION], motion, ret;
	unsigned int bcol;
	double unit;

	if (st->nurbs_open && (ret = nurbs_line_check(c, st, l)))
		return ret;
	if ((ret = line_motion(c, st, l, &motion, &bcol)))
		return ret;
	if (HAS(l, 'F') && (ret = do_feed_word(c, st, l)))
		return ret;
	if ((ret = do_modes(c, st, l)))
		return ret;
	unit = st->inch ? PROG_MM_PER_INCH : 1.0;
	if (mword >= 0 && mword != MOT_G53)
		st->motion = mword == MOT_G80 ? MOT_NONE : mword;
	if (mword >= 0 && mword != MOT_G52 && mword != MOT_G53)
		st->nurbs_failed = false;
	if (motion == MOT_G52 && st->motion != MOT_G52)
		st->motion = MOT_G52;
	ret = do_nurbs_motion(c, st, l, motion, bcol, unit);
	if (ret == 1 && motion >= 0 && motion != MOT_G80 &&
	    (axis || motion == MOT_G2 || motion == MOT_G3))
		ret = do_move(c, st, l, motion, bcol, unit);
	else if (ret == 1)
		ret = 0;
	if (ret)
		return ret;
	return l->m[MGRP_STOP] >= 0 ? do_stop_m(c, st, l) : 0;
}

/* A line with only '%' (and blanks): the RS274 tape delimiter. */
static bool percent_line(const char *s, size_t n)
{
	size_t i = 0;

	while (i < n && gcode_is_blank(s[i]))
		i++;
	if (i == n || s[i] != '%')
		return false;
	for (i++; i < n; i++)
		if (!gcode_is_blank(s[i]))
			return false;
	return true;
}

static bool blank_line(const char *s, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (!gcode_is_blank(s[i]))
			return false;
	return true;
}

static void gcode_init(struct prog_ctx *c, void *state)
{
	struct gstate *st = state;

	(void)c;
	memset(st, 0, sizeof(*st));
	st->plane = SH2000_PLANE_XY;
	st->motion = MOT_NONE;
}

static void gcode_line(struct prog_ctx *c, void *state, const char *s,
		       size_t n, unsigned int line)
{
	struct gstate *st = state;
	struct gline l;

	if (st->ended) {
		if (!blank_line(s, n) && !percent_line(s, n))
			prog_warn_once(c, PW_AFTER_END, SH2000_PD_IGNORED, line, 1,
				       "text after the program end (M2/M30 or %%) is not read");
		return;
	}
	if (percent_line(s, n)) {
		if (!st->seen_content && !st->percent)
			st->percent = true;
		else if (st->percent)
			st->ended = true;
		else
			prog_err(c, SH2000_PD_SYNTAX, line, 1,
				 "'%%' ends a program only when the program starts with '%%'");
		return;
	}
	if (!blank_line(s, n))
		st->seen_content = true;
	if (gcode_lex_line(c, s, n, line, &l) || !l.any_word)
		return;
	exec_line(c, st, &l);
}

static void gcode_finish(struct prog_ctx *c, void *state, unsigned int line)
{
	struct gstate *st = state;

	if (st->nurbs_open && !c->stop)
		prog_err(c, SH2000_PD_NURBS, st->nurbs_line, st->nurbs_col,
			 "NURBS block opened by G5.2 is not closed by G5.3");
	if (st->percent && !st->ended && !c->stop)
		prog_err(c, SH2000_PD_SYNTAX, line ? line : 1, 1,
			 "program starts with '%%' but has no closing '%%'");
	/* as LinuxCNC: a file that just stops may have been cut short */
	else if (!st->ended && !c->stop)
		prog_err(c, SH2000_PD_MISSING, line ? line : 1, 1,
			 "the file ends without M2 or M30 (or a closing '%%'): it may be cut short");
}

static void gcode_release(void *state)
{
	struct gstate *st = state;

	free(st->pts);
	free(st->w);
	st->pts = NULL;
	st->w = NULL;
}

const struct prog_format_ops prog_gcode_ops = {
	.state_size = sizeof(struct gstate),
	.init = gcode_init,
	.line = gcode_line,
	.finish = gcode_finish,
	.release = gcode_release,
};
