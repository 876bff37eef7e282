/* SPDX-License-Identifier: MIT */
/*
 * LinuxCNC's standalone interpreter (rs274, Debian's linuxcnc-uspace)
 * prints the canonical machining commands a program makes, one a line:
 *
 *     14 N0030  STRAIGHT_FEED(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)
 *
 * (output counter, the source's N word or "N.....", the call). This reads
 * that text into the same representation as the built-in G-code reader.
 * Values are in the program's units (USE_LENGTH_UNITS; A always in mm)
 * relative to the active G5x and G92 origins, which are added back, and
 * name the tool's tip: the tool length offset (USE_TOOL_LENGTH_OFFSET) is
 * added too, as LinuxCNC's motion does.
 */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prog_internal.h"

#define MAX_ARGS 16

struct cstate {
	double unit;		/* mm per program unit */
	enum sh2000_plane plane;
	double feed_mm_min;
	double g5x[SH2000_AXES], g92[SH2000_AXES];	/* mm */
	bool ended;
	bool pallet;		/* PALLET_SHUTTLE: M30 is ending the program */
	/* just after ON_RESET(): rs274's own settings, not the program's;
	 * which of reset_sequence[] it printed (a second one is the
	 * program's) */
	bool resetting;
	unsigned int reset_seen;
	double naive_mm;	/* SET_NAIVECAM_TOLERANCE, mm */
	/* the program's last SET_MOTION_CONTROL_MODE (path_set: one was
	 * seen), given again with a naive CAM tolerance that follows it */
	bool path_set;
	enum sh2000_path_mode path_mode;
	double path_tol_mm;
	double res_mm;		/* rounding of the position as last printed */
	struct prog_tool_state tools;	/* the tool and its offset, mm */
};

struct carg {
	const char *s;
	size_t n;
	unsigned int col;
};

struct cline {
	unsigned int line, col;		/* col: the command name */
	char name[48];
	struct carg arg[MAX_ARGS];
	int nargs;
	const char *raw;		/* between the parentheses */
	size_t nraw;
};

static bool name_is(const struct cline *l, const char *n)
{
	return !strcmp(l->name, n);
}

static bool in_list(const char *name, const char *const *list)
{
	for (; *list; list++)
		if (!strcmp(name, *list))
			return true;
	return false;
}

/* Commands that do not change the path on this card. */
static const char *const ignored[] = {
	"SET_FEED_REFERENCE", "SET_TRAVERSE_RATE", "ENABLE_FEED_OVERRIDE", "DISABLE_FEED_OVERRIDE",
	"ENABLE_SPEED_OVERRIDE", "DISABLE_SPEED_OVERRIDE",
	"ENABLE_ADAPTIVE_FEED", "DISABLE_ADAPTIVE_FEED", "ENABLE_FEED_HOLD",
	"DISABLE_FEED_HOLD", "SET_CUTTER_RADIUS_COMPENSATION",
	"START_CUTTER_RADIUS_COMPENSATION", "STOP_CUTTER_RADIUS_COMPENSATION",
	"STOP_SPEED_FEED_SYNCH", "STOP_SPINDLE_TURNING", "FLOOD_OFF",
	"MIST_OFF", "SET_SPINDLE_MODE", "TURN_PROBE_OFF", "USE_NO_SPINDLE_FORCE",
	"SET_TOOL_TABLE_ENTRY", "ON_RESET", "INIT_CANON", "SET_BLOCK_DELETE",
	"SET_OPTIONAL_PROGRAM_STOP", "COMMENT", "CHANGE_TOOL_NUMBER",
	"START_CHANGE",
	NULL,
};

/* LinuxCNC canonical commands that would move or act in ways this card
 * cannot: errors. */
static const char *const unsupported[] = {
	"STRAIGHT_PROBE", "RIGID_TAP", "CLAMP_AXIS", "UNCLAMP_AXIS",
	"SPINDLE_RETRACT", "SPINDLE_RETRACT_TRAVERSE",
	"TURN_PROBE_ON", "SYSTEM", "START_SPEED_FEED_SYNCH",
	"SET_MOTION_OUTPUT_BIT", "CLEAR_MOTION_OUTPUT_BIT",
	"SET_AUX_OUTPUT_BIT", "CLEAR_AUX_OUTPUT_BIT", "SET_MOTION_OUTPUT_VALUE",
	"SET_AUX_OUTPUT_VALUE", "WAIT", "USER_DEFINED_FUNCTION",
	NULL,
};

static int parse_line(struct prog_ctx *c, const char *s, size_t n,
		      unsigned int line, struct cline *l)
{
	size_t i = 0, k, open, close;

	memset(l, 0, sizeof(*l));
	l->line = line;
	while (i < n && isspace((unsigned char)s[i]))
		i++;
	k = i;
	while (i < n && isdigit((unsigned char)s[i]))
		i++;
	if (i == k || i >= n || !isspace((unsigned char)s[i]))
		return prog_err(c, SH2000_PD_SYNTAX, line, (unsigned)k + 1,
				"not a canonical command line (expected \"<count> N<number> COMMAND(...)\")");
	while (i < n && isspace((unsigned char)s[i]))
		i++;
	if (i >= n || s[i] != 'N')
		return prog_err(c, SH2000_PD_SYNTAX, line, (unsigned)i + 1,
				"expected the N field (N<number> or N.....)");
	i++;
	while (i < n && (isdigit((unsigned char)s[i]) || s[i] == '.'))
		i++;
	while (i < n && isspace((unsigned char)s[i]))
		i++;
	l->col = (unsigned)i + 1;
	k = 0;
	while (i < n && (isupper((unsigned char)s[i]) || isdigit((unsigned char)s[i]) ||
			 s[i] == '_' || s[i] == '.')) {
		if (k + 1 < sizeof(l->name))
			l->name[k++] = s[i];
		i++;
	}
	l->name[k] = 0;
	if (k == 0 || i >= n || s[i] != '(')
		return prog_err(c, SH2000_PD_SYNTAX, line, l->col,
				"expected COMMAND(...)");
	open = i;
	close = n;
	while (close > open + 1 && s[close - 1] != ')')
		close--;
	if (s[close - 1] != ')')
		return prog_err(c, SH2000_PD_SYNTAX, line, (unsigned)open + 1,
				"'(' without ')'");
	for (k = close; k < n; k++)
		if (!isspace((unsigned char)s[k]))
			return prog_err(c, SH2000_PD_SYNTAX, line, (unsigned)k + 1,
					"text after the command's ')'");
	close--;		/* at ')' */
	l->raw = s + open + 1;
	l->nraw = close - open - 1;
	/* split on commas; strings (COMMENT, MESSAGE) are not split */
	if (l->nraw && l->raw[0] != '"') {
		size_t a = open + 1;

		for (;;) {
			size_t b = a, e;

			while (b < close && s[b] != ',')
				b++;
			e = b;
			while (a < e && isspace((unsigned char)s[a]))
				a++;
			while (e > a && isspace((unsigned char)s[e - 1]))
				e--;
			if (l->nargs == MAX_ARGS)
				return prog_err(c, SH2000_PD_SYNTAX, line, (unsigned)a + 1,
						"more than %d arguments", MAX_ARGS);
			l->arg[l->nargs].s = s + a;
			l->arg[l->nargs].n = e - a;
			l->arg[l->nargs].col = (unsigned)a + 1;
			l->nargs++;
			if (b >= close)
				break;
			a = b + 1;
		}
	}
	return 0;
}

static int num(struct prog_ctx *c, const struct cline *l, int i, double *v)
{
	char buf[64], *end;
	const struct carg *a = &l->arg[i];

	if (a->n == 0 || a->n >= sizeof(buf))
		return prog_err(c, SH2000_PD_SYNTAX, l->line, a->col,
				"%s: argument %d is not a number", l->name, i + 1);
	memcpy(buf, a->s, a->n);
	buf[a->n] = 0;
	*v = strtod(buf, &end);
	if (*end || !isfinite(*v))
		return prog_err(c, SH2000_PD_SYNTAX, l->line, a->col,
				"%s: argument %d '%s' is not a finite number",
				l->name, i + 1, buf);
	return 0;
}

/* All arguments as numbers; between min and max of them. */
static int nums(struct prog_ctx *c, const struct cline *l, int min, int max,
		double *v)
{
	if (l->nargs < min || l->nargs > max)
		return prog_err(c, SH2000_PD_SYNTAX, l->line, l->col,
				"%s: %d arguments, expected %d to %d", l->name,
				l->nargs, min, max);
	for (int i = 0; i < l->nargs; i++)
		if (num(c, l, i, &v[i]))
			return -SH2000_PROG_EINVALID;
	return 0;
}

/* The one argument of a command that takes a number not below zero;
 * what names it in the message ("negative WHAT"). */
static int one_nonneg(struct prog_ctx *c, const struct cline *l,
		      const char *what, double *v)
{
	double a[MAX_ARGS];
	int ret = nums(c, l, 1, 1, a);

	if (ret)
		return ret;
	if (a[0] < 0)
		return prog_err(c, SH2000_PD_RANGE, l->line, l->arg[0].col,
				"negative %s %g", what, a[0]);
	*v = a[0];
	return 0;
}

static bool arg_is(const struct cline *l, int i, const char *word)
{
	return i < l->nargs && l->arg[i].n == strlen(word) &&
	       !memcmp(l->arg[i].s, word, l->arg[i].n);
}

/* B and C (and anything past them) must stay at zero. */
static int no_bc(struct prog_ctx *c, const struct cline *l, int first,
		 const double *v)
{
	for (int i = first; i < l->nargs; i++)
		if (v[i] != 0)
			return prog_err(c, SH2000_PD_NO_AXIS, l->line, l->arg[i].col,
					"%s: the %c axis moves, but the SH-2000TH has only X, Y, Z and the linear A",
					l->name, i - first < 2 ? "BC"[i - first] : '?');
	return 0;
}

static double mpos(const struct cstate *st, int axis, double v)
{
	/* rs274 prints A as written: LinuxCNC never scales A by G20 */
	return v * (axis == SH2000_PROG_A ? 1 : st->unit) + st->g5x[axis] +
	       st->g92[axis] + st->tools.offset[axis];
}

static int need_feed(struct prog_ctx *c, const struct cstate *st,
		     const struct cline *l)
{
	if (st->feed_mm_min > 0)
		return 0;
	return prog_err(c, SH2000_PD_FEED, l->line, l->col,
			"%s with zero feed rate (no SET_FEED_RATE before it)",
			l->name);
}

/* ---- the canonical commands, one handler each ---------------------------- */

static int cmd_straight(struct prog_ctx *c, struct cstate *st,
			const struct cline *l)
{
	bool feed = name_is(l, "STRAIGHT_FEED");
	double v[MAX_ARGS];
	struct sh2000_prog_block *b;
	int ret;

	if ((ret = nums(c, l, 3, 6, v)) || (ret = no_bc(c, l, 4, v)))
		return ret;
	if (feed && (ret = need_feed(c, st, l)))
		return ret;
	b = prog_push(c, feed ? SH2000_PROG_LINE : SH2000_PROG_RAPID, l->line,
		      l->col);
	if (!b)
		return -ENOMEM;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if ((int)a < l->nargs)
			b->end[a] = mpos(st, a, v[a]);
	if (feed)
		b->feed = st->feed_mm_min / 60;
	memcpy(c->pos, b->end, sizeof(c->pos));
	st->res_mm = 0.5e-4 * st->unit;
	return 0;
}

/* The radius tolerance of an arc rs274 printed: LinuxCNC's for the units,
 * plus what printing 4 decimals of it (and of its start) may add. */
static double arc_tolerance(const struct prog_ctx *c, const struct cstate *st)
{
	double tol = c->opt.arc_tolerance_mm > 0 ? c->opt.arc_tolerance_mm :
		     st->unit == PROG_MM_PER_INCH ? SH2000_ARC_CENTRE_TOL_INCH_MM :
		     SH2000_ARC_CENTRE_TOL_MM;

	return tol + 4 * (0.5e-4 * st->unit + st->res_mm);
}

static int cmd_arc_feed(struct prog_ctx *c, struct cstate *st,
			const struct cline *l)
{
	unsigned int a1, a2, an;
	double v[MAX_ARGS], end[SH2000_AXES];
	struct sh2000_prog_block *b;
	int rot, ret;

	if ((ret = nums(c, l, 6, 9, v)) || (ret = no_bc(c, l, 7, v)))
		return ret;
	if ((ret = need_feed(c, st, l)))
		return ret;
	if (v[4] != floor(v[4]) || v[4] == 0 || fabs(v[4]) > 1e6)
		return prog_err(c, SH2000_PD_RANGE, l->line, l->arg[4].col,
				"ARC_FEED: rotation %g is not a non-zero integer", v[4]);
	rot = (int)v[4];
	sh2000_plane_axes(st->plane, &a1, &a2, &an);
	memcpy(end, c->pos, sizeof(end));
	end[a1] = mpos(st, (int)a1, v[0]);
	end[a2] = mpos(st, (int)a2, v[1]);
	end[an] = mpos(st, (int)an, v[5]);
	if (l->nargs > 6)
		end[SH2000_PROG_A] = mpos(st, SH2000_PROG_A, v[6]);
	b = prog_push(c, SH2000_PROG_ARC, l->line, l->col);
	if (!b)
		return -ENOMEM;
	memcpy(b->end, end, sizeof(end));
	b->feed = st->feed_mm_min / 60;
	/* rs274 prints 4 decimals: a full circle's end may miss its start by
	 * the rounding of both prints (the start's maybe in other units) */
	ret = prog_arc_fill(c, b, st->plane, mpos(st, (int)a1, v[2]),
			    mpos(st, (int)a2, v[3]), rot > 0,
			    (unsigned int)abs(rot), arc_tolerance(c, st),
			    M_SQRT2 * (0.5e-4 * st->unit + st->res_mm) + 1e-9,
			    l->line, l->col);
	st->res_mm = 0.5e-4 * st->unit;
	memcpy(c->pos, end, sizeof(c->pos));
	if (ret)
		c->prog->count--;
	return ret;
}

static int cmd_feed_rate(struct prog_ctx *c, struct cstate *st,
			 const struct cline *l)
{
	struct sh2000_prog_block *b;
	double v = 0;
	int ret;

	if ((ret = one_nonneg(c, l, "feed rate", &v)))
		return ret;
	if (v * st->unit == st->feed_mm_min)
		return 0;
	st->feed_mm_min = v * st->unit;
	b = prog_push(c, SH2000_PROG_FEED, l->line, l->col);
	if (!b)
		return -ENOMEM;
	b->u.feed_mm_min = st->feed_mm_min;
	b->feed = st->feed_mm_min / 60;
	return 0;
}

static int cmd_feed_mode(struct prog_ctx *c, struct cstate *st,
			 const struct cline *l)
{
	double v[MAX_ARGS];
	int ret;

	(void)st;
	if ((ret = nums(c, l, 1, 2, v)))
		return ret;
	if (v[l->nargs - 1] != 0)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
				"SET_FEED_MODE: only units per minute (G94) is supported");
	return 0;
}

/* The word argument of l among words[]: its index, or -1. */
static int word_arg(const struct cline *l, const char *const *words, int n)
{
	for (int i = 0; i < n; i++)
		if (l->nargs == 1 && arg_is(l, 0, words[i]))
			return i;
	return -1;
}

static int cmd_units(struct prog_ctx *c, struct cstate *st,
		     const struct cline *l)
{
	static const char *const w[3] = {
		"CANON_UNITS_MM", "CANON_UNITS_INCHES", "CANON_UNITS_CM",
	};
	static const double unit[3] = { 1, PROG_MM_PER_INCH, 10 };
	int i = word_arg(l, w, 3);

	if (i < 0)
		return prog_err(c, SH2000_PD_UNKNOWN, l->line, l->col,
				"USE_LENGTH_UNITS: unknown units");
	st->unit = unit[i];
	return 0;
}

static int cmd_plane(struct prog_ctx *c, struct cstate *st,
		     const struct cline *l)
{
	static const char *const w[3] = {
		"CANON_PLANE_XY", "CANON_PLANE_XZ", "CANON_PLANE_YZ",
	};
	int i = word_arg(l, w, 3);

	if (i < 0)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
				"SELECT_PLANE: only the XY, XZ and YZ planes");
	st->plane = (enum sh2000_plane)(SH2000_PLANE_XY + i);
	return 0;
}

static int cmd_dwell(struct prog_ctx *c, struct cstate *st,
		     const struct cline *l)
{
	struct sh2000_prog_block *b;
	double v = 0;
	int ret;

	(void)st;
	if ((ret = one_nonneg(c, l, "dwell", &v)))
		return ret;
	b = prog_push(c, SH2000_PROG_DWELL, l->line, l->col);
	if (!b)
		return -ENOMEM;
	b->u.dwell_s = v;
	return 0;
}

static int cmd_stop(struct prog_ctx *c, struct cstate *st,
		    const struct cline *l)
{
	struct sh2000_prog_block *b = prog_push(c, SH2000_PROG_PAUSE, l->line,
						 l->col);

	(void)st;
	if (!b)
		return -ENOMEM;
	b->u.optional = name_is(l, "OPTIONAL_PROGRAM_STOP");
	return 0;
}

static int cmd_end(struct prog_ctx *c, struct cstate *st,
		   const struct cline *l)
{
	struct sh2000_prog_block *b = prog_push(c, SH2000_PROG_END, l->line,
						 l->col);

	if (!b)
		return -ENOMEM;
	b->u.end_code = st->pallet ? 30 : 2;
	st->ended = true;
	return 0;
}

static int cmd_pallet(struct prog_ctx *c, struct cstate *st,
		      const struct cline *l)
{
	(void)c;
	(void)l;
	/* rs274 prints it for M30, just before PROGRAM_END */
	st->pallet = true;
	return 0;
}

static int cmd_offsets(struct prog_ctx *c, struct cstate *st,
		       const struct cline *l)
{
	int first = name_is(l, "SET_G5X_OFFSET") ? 1 : 0, ret;
	double *off = name_is(l, "SET_G92_OFFSET") ? st->g92 : st->g5x;
	double v[MAX_ARGS];

	if ((ret = nums(c, l, first + 3, first + 6, v)) ||
	    (ret = no_bc(c, l, first + 4, v)))
		return ret;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if (first + (int)a < l->nargs)
			off[a] = v[first + a] * (a == SH2000_PROG_A ? 1 : st->unit);
	return 0;
}

static int cmd_rotation(struct prog_ctx *c, struct cstate *st,
			const struct cline *l)
{
	double v[MAX_ARGS];
	int ret;

	(void)st;
	if ((ret = nums(c, l, 1, 1, v)))
		return ret;
	if (v[0] != 0)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
				"SET_XY_ROTATION(%g): rotated coordinate systems are not supported",
				v[0]);
	return 0;
}

/* USE_TOOL_LENGTH_OFFSET(x y z, a b c, u v w) in the program's units (A
 * unscaled), or the older USE_TOOL_LENGTH_OFFSET(z): from here on the
 * machine is that far from the positions printed. */
static int cmd_tool_offset(struct prog_ctx *c, struct cstate *st,
			   const struct cline *l)
{
	const char *p = l->raw, *e = l->raw + l->nraw;
	unsigned int col0 = l->col + (unsigned)strlen(l->name) + 1;
	double v[9] = { 0 };
	int n = 0;

	while (p < e) {
		char *q;

		if (isspace((unsigned char)*p) || *p == ',') {
			p++;
			continue;
		}
		if (n < 9)
			v[n] = strtod(p, &q);
		if (n >= 9 || q == p || q > e || !isfinite(v[n]))
			return prog_err(c, SH2000_PD_SYNTAX, l->line,
					(unsigned)(p - l->raw) + col0,
					"USE_TOOL_LENGTH_OFFSET: %s",
					n >= 9 ? "more than 9 numbers" :
					"not a finite number");
		n++;
		p = q;
	}
	if (n != 1 && n != 9)
		return prog_err(c, SH2000_PD_SYNTAX, l->line, l->col,
				"USE_TOOL_LENGTH_OFFSET: %d numbers, expected 9 (x y z, a b c, u v w) or 1 (z)",
				n);
	if (n == 1) {
		v[2] = v[0];
		v[0] = 0;
	}
	for (int i = 4; i < 9; i++)
		if (v[i] != 0)
			return prog_err(c, SH2000_PD_NO_AXIS, l->line, l->col,
					"USE_TOOL_LENGTH_OFFSET: a %c offset, but the SH-2000TH has only X, Y, Z and the linear A",
					"BCUVW"[i - 4]);
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		double mm = v[a] * (a == SH2000_PROG_A ? 1 : st->unit);

		/* a position plus it must stay a number */
		if (!(fabs(mm) <= 1e9))
			return prog_err(c, SH2000_PD_RANGE, l->line, l->col,
					"USE_TOOL_LENGTH_OFFSET: %c offset %g mm out of range",
					SH2000_AXIS_LETTERS[a], mm);
	}
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		st->tools.offset[a] = v[a] * (a == SH2000_PROG_A ? 1 : st->unit);
	return 0;
}

/* SELECT_TOOL(n) and CHANGE_TOOL(n): T and M6. */
static int cmd_tool(struct prog_ctx *c, struct cstate *st,
		    const struct cline *l)
{
	double v[MAX_ARGS];
	int ret;

	if ((ret = nums(c, l, 1, 1, v)))
		return ret;
	if (name_is(l, "SELECT_TOOL"))
		return prog_tool_select(c, &st->tools, v[0], l->line, l->col);
	/* rs274 prints the tool it selected (and checked) before */
	if (v[0] != floor(v[0]) || v[0] < 0 || v[0] > INT_MAX)
		return prog_err(c, SH2000_PD_RANGE, l->line, l->arg[0].col,
				"CHANGE_TOOL(%g): a tool number is an integer >= 0",
				v[0]);
	st->tools.selected = (int)v[0];
	return prog_tool_change(c, &st->tools, "CHANGE_TOOL", l->line, l->col);
}

static int cmd_nurbs_feed(struct prog_ctx *c, struct cstate *st,
			  const struct cline *l)
{
	(void)st;
	return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
			"NURBS_FEED: rs274 prints only the number of control points, so the curve cannot be rebuilt; read the G-code file with the built-in parser, which reads G5.2/G5.3");
}

static int cmd_spindle_speed(struct prog_ctx *c, struct cstate *st,
			     const struct cline *l)
{
	double v[MAX_ARGS];
	int ret;

	(void)st;
	if ((ret = nums(c, l, 1, 2, v)))
		return ret;
	if (v[l->nargs - 1] != 0)
		prog_warn_once(c, PW_SPEED, SH2000_PD_NOT_ACTED, l->line, l->col,
			       "SET_SPINDLE_SPEED(%g) (spindle speed) not acted on: the SH-2000TH has no spindle output; later ones are not reported",
			       v[l->nargs - 1]);
	return 0;
}

/* SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP | CANON_EXACT_PATH |
 * CANON_CONTINUOUS, tolerance) and SET_NAIVECAM_TOLERANCE(q): G61.1, G61,
 * G64 P Q. The ones rs274 prints while resetting are its defaults, not
 * the program's. */
static int path_block(struct prog_ctx *c, const struct cline *l,
		      enum sh2000_path_mode mode, double tol, double naive)
{
	struct sh2000_prog_block *b = prog_push(c, SH2000_PROG_PATH_MODE,
						 l->line, l->col);

	if (!b)
		return -ENOMEM;
	b->u.path.mode = mode;
	b->u.path.tolerance = tol;
	b->u.path.naive_tolerance = naive;
	return 0;
}

static int cmd_motion_mode(struct prog_ctx *c, struct cstate *st,
			   const struct cline *l)
{
	static const char *const w[3] = {
		"CANON_CONTINUOUS", "CANON_EXACT_PATH", "CANON_EXACT_STOP",
	};
	double tol = 0;
	int i = -1;

	for (int k = 0; k < 3 && l->nargs >= 1; k++)
		if (arg_is(l, 0, w[k]))
			i = k;
	if (i < 0 || l->nargs > 2)
		return prog_err(c, SH2000_PD_UNKNOWN, l->line, l->col,
				"SET_MOTION_CONTROL_MODE: unknown mode");
	if (l->nargs == 2 && num(c, l, 1, &tol))
		return -SH2000_PROG_EINVALID;
	if (tol < 0)
		return prog_err(c, SH2000_PD_RANGE, l->line, l->arg[1].col,
				"SET_MOTION_CONTROL_MODE: negative tolerance %g", tol);
	if (st->resetting)
		return 0;
	tol *= st->unit;
	st->naive_mm = tol;	/* until SET_NAIVECAM_TOLERANCE says */
	st->path_set = true;
	st->path_mode = (enum sh2000_path_mode)i;
	st->path_tol_mm = tol;
	return path_block(c, l, st->path_mode, tol, tol);
}

static int cmd_naivecam(struct prog_ctx *c, struct cstate *st,
			const struct cline *l)
{
	struct sh2000_prog_block *last;
	double v = 0;
	int ret;

	if ((ret = one_nonneg(c, l, "naive CAM tolerance", &v)))
		return ret;
	if (st->resetting)
		return 0;
	st->naive_mm = v * st->unit;
	/* rs274 prints it right after the mode G64 set: one setting, made
	 * in that block while the reader still holds it ... */
	last = c->prog->count ? &c->prog->blocks[c->prog->count - 1] : NULL;
	if (last && last->kind == SH2000_PROG_PATH_MODE &&
	    last->pos.line == l->line - 1) {
		last->u.path.naive_tolerance = st->naive_mm;
		return 0;
	}
	/* ... else (a streaming reader has handed that block out) the mode
	 * again with it; before any mode of the program's, the next mode
	 * sets its own */
	if (!st->path_set)
		return 0;
	return path_block(c, l, st->path_mode, st->path_tol_mm, st->naive_mm);
}

typedef int (*cmd_fn)(struct prog_ctx *c, struct cstate *st,
		      const struct cline *l);

static const struct {
	const char *name;
	cmd_fn fn;
} commands[] = {
	{ "STRAIGHT_TRAVERSE", cmd_straight },
	{ "STRAIGHT_FEED", cmd_straight },
	{ "ARC_FEED", cmd_arc_feed },
	{ "SET_FEED_RATE", cmd_feed_rate },
	{ "SET_FEED_MODE", cmd_feed_mode },
	{ "USE_LENGTH_UNITS", cmd_units },
	{ "SELECT_PLANE", cmd_plane },
	{ "DWELL", cmd_dwell },
	{ "PROGRAM_STOP", cmd_stop },
	{ "OPTIONAL_PROGRAM_STOP", cmd_stop },
	{ "PROGRAM_END", cmd_end },
	{ "PALLET_SHUTTLE", cmd_pallet },
	{ "SET_G5X_OFFSET", cmd_offsets },
	{ "SET_G92_OFFSET", cmd_offsets },
	{ "SET_ORIGIN_OFFSETS", cmd_offsets },
	{ "SET_XY_ROTATION", cmd_rotation },
	{ "USE_TOOL_LENGTH_OFFSET", cmd_tool_offset },
	{ "SELECT_TOOL", cmd_tool },
	{ "CHANGE_TOOL", cmd_tool },
	{ "NURBS_FEED", cmd_nurbs_feed },
	{ "SET_SPINDLE_SPEED", cmd_spindle_speed },
	{ "SET_MOTION_CONTROL_MODE", cmd_motion_mode },
	{ "SET_NAIVECAM_TOLERANCE", cmd_naivecam },
};

/* What rs274 prints while it resets, before the program's own lines. */
static const char *const reset_sequence[] = {
	"SET_MOTION_CONTROL_MODE", "SET_NAIVECAM_TOLERANCE", "SET_FEED_MODE",
	"SET_FEED_RATE", "STOP_SPINDLE_TURNING", "SET_SPINDLE_MODE",
	"ENABLE_FEED_OVERRIDE", "ENABLE_SPEED_OVERRIDE",
	"ENABLE_ADAPTIVE_FEED", "ENABLE_FEED_HOLD", "SELECT_PLANE",
	"SET_FEED_REFERENCE", NULL,
};

/* Commands accepted and not acted on: a warning once per kind. */
static const struct {
	const char *name;
	unsigned int kind;
	const char *what;
} not_acted[] = {
	{ "START_SPINDLE_CLOCKWISE", PW_SPINDLE, "spindle" },
	{ "START_SPINDLE_COUNTERCLOCKWISE", PW_SPINDLE, "spindle" },
	{ "ORIENT_SPINDLE", PW_SPINDLE, "spindle" },
	{ "FLOOD_ON", PW_COOLANT, "coolant" },
	{ "MIST_ON", PW_COOLANT, "coolant" },
	{ "SELECT_POCKET", PW_TOOL, "tool" },
};

static int warn_not_acted(struct prog_ctx *c, const struct cline *l,
			  unsigned int kind, const char *what)
{
	const char *why = kind == PW_SPINDLE ? "has no spindle output" :
			  kind == PW_COOLANT ? "has no coolant output" :
			  "has no tool changer";

	return prog_warn_once(c, kind, SH2000_PD_NOT_ACTED, l->line, l->col,
			      "%s (%s) not acted on: the SH-2000TH %s; later %s commands are not reported",
			      l->name, what, why, what);
}

static int do_line(struct prog_ctx *c, struct cstate *st, struct cline *l)
{
	size_t i;

	if (name_is(l, "ON_RESET")) {
		st->resetting = true;
		st->reset_seen = 0;
	} else if (st->resetting) {
		for (i = 0; reset_sequence[i]; i++)
			if (name_is(l, reset_sequence[i]))
				break;
		if (!reset_sequence[i] || (st->reset_seen & (1u << i)))
			st->resetting = false;
		else
			st->reset_seen |= 1u << i;
	}
	for (i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
		if (name_is(l, commands[i].name))
			return commands[i].fn(c, st, l);
	for (i = 0; i < sizeof(not_acted) / sizeof(not_acted[0]); i++)
		if (name_is(l, not_acted[i].name))
			return warn_not_acted(c, l, not_acted[i].kind,
					      not_acted[i].what);
	if (name_is(l, "MESSAGE") || !strncmp(l->name, "LOG", 3))
		return prog_warn_once(c, PW_MESSAGE, SH2000_PD_IGNORED, l->line,
				      l->col,
				      "%s not acted on: the tools do not display or log program messages (later ones are not reported)",
				      l->name);
	if (in_list(l->name, ignored))
		return 0;
	if (in_list(l->name, unsupported) || !strncmp(l->name, "SPINDLE.", 8))
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
				"%s is not supported on the SH-2000TH", l->name);
	return prog_err(c, SH2000_PD_UNKNOWN, l->line, l->col,
			"unknown canonical command %s", l->name);
}

static void canon_init(struct prog_ctx *c, void *state)
{
	struct cstate *st = state;

	(void)c;
	memset(st, 0, sizeof(*st));
	st->unit = 1;
	st->plane = SH2000_PLANE_XY;
}

static void canon_line(struct prog_ctx *c, void *state, const char *s,
		       size_t n, unsigned int line)
{
	struct cstate *st = state;
	struct cline l;
	size_t i = 0;

	while (i < n && isspace((unsigned char)s[i]))
		i++;
	if (i == n || parse_line(c, s, n, line, &l))
		return;
	if (st->ended) {
		/* rs274 resets (ON_RESET) after the end: no matter */
		if (!in_list(l.name, ignored))
			prog_warn_once(c, PW_AFTER_END, SH2000_PD_IGNORED, line,
				       l.col,
				       "%s and anything else after PROGRAM_END is not read",
				       l.name);
		return;
	}
	do_line(c, st, &l);
}

static void canon_finish(struct prog_ctx *c, void *state, unsigned int line)
{
	struct cstate *st = state;

	/* rs274 stops printing at the first error in the program */
	if (!st->ended && !c->stop)
		prog_err(c, SH2000_PD_MISSING, line ? line : 1, 1,
			 "no PROGRAM_END(): rs274 stopped early (an error in the G-code?) or the file is cut short");
}

const struct prog_format_ops prog_canon_ops = {
	.state_size = sizeof(struct cstate),
	.init = canon_init,
	.line = canon_line,
	.finish = canon_finish,
};
