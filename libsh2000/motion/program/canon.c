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
 * relative to the
 * active G5x and G92 origins, which are added back.
 */
#include <ctype.h>
#include <errno.h>
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
	double res_mm;		/* rounding of the position as last printed */
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
	"SET_FEED_REFERENCE", "SET_MOTION_CONTROL_MODE", "SET_NAIVECAM_TOLERANCE",
	"SET_TRAVERSE_RATE", "ENABLE_FEED_OVERRIDE", "DISABLE_FEED_OVERRIDE",
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
	       st->g92[axis];
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

static int do_line(struct prog_ctx *c, struct cstate *st, struct cline *l)
{
	double v[MAX_ARGS];
	struct sh2000_prog_block *b;
	int ret;

	if (name_is(l, "STRAIGHT_TRAVERSE") || name_is(l, "STRAIGHT_FEED")) {
		bool feed = name_is(l, "STRAIGHT_FEED");

		if ((ret = nums(c, l, 3, 6, v)) || (ret = no_bc(c, l, 4, v)))
			return ret;
		if (feed && (ret = need_feed(c, st, l)))
			return ret;
		b = prog_push(c, feed ? SH2000_PROG_LINE : SH2000_PROG_RAPID,
			      l->line, l->col);
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
	if (name_is(l, "ARC_FEED")) {
		unsigned int a1, a2, an;
		double tol, end[SH2000_AXES];
		int rot;

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
		tol = c->opt.arc_tolerance_mm > 0 ? c->opt.arc_tolerance_mm :
		      st->unit == PROG_MM_PER_INCH ? SH2000_ARC_CENTRE_TOL_INCH_MM :
		      SH2000_ARC_CENTRE_TOL_MM;
		/* rs274 checked the arc before rounding it to 4 decimals */
		tol += 4 * (0.5e-4 * st->unit + st->res_mm);
		/* rs274 prints 4 decimals: a full circle's end may miss its
		 * start by the rounding of both prints (the start's maybe in
		 * other units) */
		ret = prog_arc_fill(c, b, st->plane, mpos(st, (int)a1, v[2]),
				    mpos(st, (int)a2, v[3]), rot > 0,
				    (unsigned int)abs(rot), tol,
				    M_SQRT2 * (0.5e-4 * st->unit + st->res_mm) + 1e-9,
				    l->line, l->col);
		st->res_mm = 0.5e-4 * st->unit;
		memcpy(c->pos, end, sizeof(c->pos));
		if (ret)
			c->prog->count--;
		return ret;
	}
	if (name_is(l, "SET_FEED_RATE")) {
		if ((ret = nums(c, l, 1, 1, v)))
			return ret;
		if (v[0] < 0)
			return prog_err(c, SH2000_PD_RANGE, l->line, l->arg[0].col,
					"negative feed rate %g", v[0]);
		if (v[0] * st->unit != st->feed_mm_min) {
			st->feed_mm_min = v[0] * st->unit;
			b = prog_push(c, SH2000_PROG_FEED, l->line, l->col);
			if (!b)
				return -ENOMEM;
			b->u.feed_mm_min = st->feed_mm_min;
			b->feed = st->feed_mm_min / 60;
		}
		return 0;
	}
	if (name_is(l, "SET_FEED_MODE")) {
		if ((ret = nums(c, l, 1, 2, v)))
			return ret;
		if (v[l->nargs - 1] != 0)
			return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
					"SET_FEED_MODE: only units per minute (G94) is supported");
		return 0;
	}
	if (name_is(l, "USE_LENGTH_UNITS")) {
		if (arg_is(l, 0, "CANON_UNITS_MM") && l->nargs == 1)
			st->unit = 1;
		else if (arg_is(l, 0, "CANON_UNITS_INCHES") && l->nargs == 1)
			st->unit = PROG_MM_PER_INCH;
		else if (arg_is(l, 0, "CANON_UNITS_CM") && l->nargs == 1)
			st->unit = 10;
		else
			return prog_err(c, SH2000_PD_UNKNOWN, l->line, l->col,
					"USE_LENGTH_UNITS: unknown units");
		return 0;
	}
	if (name_is(l, "SELECT_PLANE")) {
		if (arg_is(l, 0, "CANON_PLANE_XY") && l->nargs == 1)
			st->plane = SH2000_PLANE_XY;
		else if (arg_is(l, 0, "CANON_PLANE_XZ") && l->nargs == 1)
			st->plane = SH2000_PLANE_XZ;
		else if (arg_is(l, 0, "CANON_PLANE_YZ") && l->nargs == 1)
			st->plane = SH2000_PLANE_YZ;
		else
			return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
					"SELECT_PLANE: only the XY, XZ and YZ planes");
		return 0;
	}
	if (name_is(l, "DWELL")) {
		if ((ret = nums(c, l, 1, 1, v)))
			return ret;
		if (v[0] < 0)
			return prog_err(c, SH2000_PD_RANGE, l->line, l->arg[0].col,
					"negative dwell %g s", v[0]);
		b = prog_push(c, SH2000_PROG_DWELL, l->line, l->col);
		if (!b)
			return -ENOMEM;
		b->u.dwell_s = v[0];
		return 0;
	}
	if (name_is(l, "PROGRAM_STOP") || name_is(l, "OPTIONAL_PROGRAM_STOP")) {
		b = prog_push(c, SH2000_PROG_PAUSE, l->line, l->col);
		if (!b)
			return -ENOMEM;
		b->u.optional = name_is(l, "OPTIONAL_PROGRAM_STOP");
		return 0;
	}
	if (name_is(l, "PROGRAM_END")) {
		b = prog_push(c, SH2000_PROG_END, l->line, l->col);
		if (!b)
			return -ENOMEM;
		b->u.end_code = st->pallet ? 30 : 2;
		st->ended = true;
		return 0;
	}
	if (name_is(l, "PALLET_SHUTTLE")) {
		/* rs274 prints it for M30, just before PROGRAM_END */
		st->pallet = true;
		return 0;
	}
	if (name_is(l, "SET_G5X_OFFSET") || name_is(l, "SET_G92_OFFSET") ||
	    name_is(l, "SET_ORIGIN_OFFSETS")) {
		bool g5x = name_is(l, "SET_G5X_OFFSET");
		int first = g5x ? 1 : 0;
		double *off = name_is(l, "SET_G92_OFFSET") ? st->g92 : st->g5x;

		if ((ret = nums(c, l, first + 3, first + 6, v)) ||
		    (ret = no_bc(c, l, first + 4, v)))
			return ret;
		for (unsigned int a = 0; a < SH2000_AXES; a++)
			if (first + (int)a < l->nargs)
				off[a] = v[first + a] *
					 (a == SH2000_PROG_A ? 1 : st->unit);
		return 0;
	}
	if (name_is(l, "SET_XY_ROTATION")) {
		if ((ret = nums(c, l, 1, 1, v)))
			return ret;
		if (v[0] != 0)
			return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
					"SET_XY_ROTATION(%g): rotated coordinate systems are not supported",
					v[0]);
		return 0;
	}
	if (name_is(l, "USE_TOOL_LENGTH_OFFSET")) {
		/* "x y z, a b c, u v w": every number must be zero */
		const char *p = l->raw, *e = l->raw + l->nraw;

		while (p < e) {
			char *q;
			double x;

			if (isspace((unsigned char)*p) || *p == ',') {
				p++;
				continue;
			}
			x = strtod(p, &q);
			if (q == p || q > e)
				return prog_err(c, SH2000_PD_SYNTAX, l->line,
						(unsigned)(p - l->raw) + l->col + (unsigned)strlen(l->name) + 1,
						"USE_TOOL_LENGTH_OFFSET: not a number");
			if (x != 0)
				return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
						"tool length offsets are not supported (the card has no tool)");
			p = q;
		}
		return 0;
	}
	if (name_is(l, "NURBS_FEED"))
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
				"NURBS_FEED: rs274 prints only the number of control points, so the curve cannot be rebuilt; read the G-code file with the built-in parser, which reads G5.2/G5.3");
	if (name_is(l, "MESSAGE") || !strncmp(l->name, "LOG", 3)) {
		prog_warn_once(c, PW_MESSAGE, SH2000_PD_IGNORED, l->line, l->col,
			       "%s not acted on: the tools do not display or log program messages (later ones are not reported)",
			       l->name);
		return 0;
	}
	if (name_is(l, "START_SPINDLE_CLOCKWISE") ||
	    name_is(l, "START_SPINDLE_COUNTERCLOCKWISE") ||
	    name_is(l, "ORIENT_SPINDLE")) {
		prog_warn_once(c, PW_SPINDLE, SH2000_PD_NOT_ACTED, l->line, l->col,
			       "%s (spindle) not acted on: the SH-2000TH has no spindle output; later spindle commands are not reported",
			       l->name);
		return 0;
	}
	if (name_is(l, "SET_SPINDLE_SPEED")) {
		if ((ret = nums(c, l, 1, 2, v)))
			return ret;
		if (v[l->nargs - 1] != 0)
			prog_warn_once(c, PW_SPEED, SH2000_PD_NOT_ACTED, l->line, l->col,
				       "SET_SPINDLE_SPEED(%g) (spindle speed) not acted on: the SH-2000TH has no spindle output; later ones are not reported",
				       v[l->nargs - 1]);
		return 0;
	}
	if (name_is(l, "FLOOD_ON") || name_is(l, "MIST_ON")) {
		prog_warn_once(c, PW_COOLANT, SH2000_PD_NOT_ACTED, l->line, l->col,
			       "%s (coolant) not acted on: the SH-2000TH has no coolant output; later coolant commands are not reported",
			       l->name);
		return 0;
	}
	if (name_is(l, "CHANGE_TOOL") || name_is(l, "SELECT_TOOL") ||
	    name_is(l, "SELECT_POCKET")) {
		prog_warn_once(c, PW_TOOL, SH2000_PD_NOT_ACTED, l->line, l->col,
			       "%s (tool) not acted on: the SH-2000TH has no tool changer; later tool commands are not reported",
			       l->name);
		return 0;
	}
	if (in_list(l->name, ignored))
		return 0;
	if (in_list(l->name, unsupported) || !strncmp(l->name, "SPINDLE.", 8))
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, l->col,
				"%s is not supported on the SH-2000TH", l->name);
	return prog_err(c, SH2000_PD_UNKNOWN, l->line, l->col,
			"unknown canonical command %s", l->name);
}

int prog_read_canon(struct prog_ctx *c, const char *text, size_t len)
{
	struct cstate st = { .unit = 1, .plane = SH2000_PLANE_XY };
	unsigned int line = 0;
	size_t off = 0;

	while (off < len && !c->stop) {
		const char *s = text + off;
		struct cline l;
		size_t n, i = 0;

		off = prog_next_line(text, len, off, &n);
		line++;
		while (i < n && isspace((unsigned char)s[i]))
			i++;
		if (i == n)
			continue;
		if (parse_line(c, s, n, line, &l))
			continue;
		if (st.ended) {
			/* rs274 resets (ON_RESET) after the end: no matter */
			if (!in_list(l.name, ignored))
				prog_warn_once(c, PW_AFTER_END, SH2000_PD_IGNORED,
					       line, l.col,
					       "%s and anything else after PROGRAM_END is not read",
					       l.name);
			continue;
		}
		do_line(c, &st, &l);
	}
	/* rs274 stops printing at the first error in the program */
	if (!st.ended && !c->stop)
		prog_err(c, SH2000_PD_MISSING, line ? line : 1, 1,
			 "no PROGRAM_END(): rs274 stopped early (an error in the G-code?) or the file is cut short");
	return c->errors ? -SH2000_PROG_EINVALID : 0;
}
