/* SPDX-License-Identifier: MIT */
/*
 * The built-in RS-274 reader: the subset of LinuxCNC's G-code listed in
 * docs/programs.md, with LinuxCNC's modal groups, word rules, arc rules and
 * G5.2/G5.3 NURBS blocks. Every line is checked; nothing is skipped
 * silently.
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prog_internal.h"

enum motion { MOT_NONE = -1, MOT_G0 = 0, MOT_G1 = 10, MOT_G2 = 20,
	      MOT_G3 = 30, MOT_G52 = 52, MOT_G53 = 53, MOT_G80 = 800 };

/* modal groups as LinuxCNC numbers them */
enum { GRP_NONMODAL = 0, GRP_MOTION = 1, GRP_PLANE = 2, GRP_DIST = 3,
       GRP_ARCDIST = 4, GRP_FEEDMODE = 5, GRP_UNITS = 6, GRP_CUTTER = 7,
       GRP_TOOLLEN = 8, GRP_COORD = 12, GRP_PATH = 13, GRP_COUNT = 16 };
enum { MGRP_STOP = 0, MGRP_TOOL = 1, MGRP_SPINDLE = 2, MGRP_COOLANT = 3,
       MGRP_COUNT = 4 };

#define G_UNKNOWN (-2)
#define G_UNSUPPORTED (-1)

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

struct gline {
	unsigned int line;
	unsigned int first_col;		/* first word other than N */
	int g[GRP_COUNT];		/* code * 10 per group, -1 none */
	unsigned int gcol[GRP_COUNT];
	int m[MGRP_COUNT];
	unsigned int mcol[MGRP_COUNT];
	bool has[26];
	double val[26];
	unsigned int col[26];
	bool any_word;
};

#define HAS(l, c) ((l)->has[(c) - 'A'])
#define VAL(l, c) ((l)->val[(c) - 'A'])
#define COL(l, c) ((l)->col[(c) - 'A'])

static int g_group(int code)
{
	switch (code) {
	case 0: case 10: case 20: case 30: case 52: case 53: case 800:
		return GRP_MOTION;
	case 40: return GRP_NONMODAL;
	case 170: case 180: case 190: return GRP_PLANE;
	case 200: case 210: return GRP_UNITS;
	case 900: case 910: return GRP_DIST;
	case 901: case 911: return GRP_ARCDIST;
	case 940: return GRP_FEEDMODE;
	case 400: return GRP_CUTTER;
	case 430: case 431: case 432: case 490: return GRP_TOOLLEN;
	case 540: return GRP_COORD;
	case 610: case 611: case 640: return GRP_PATH;
	}
	/* the rest of LinuxCNC's G codes */
	static const int known[] = {
		50, 51, 70, 80, 100, 171, 181, 191, 280, 281, 300, 301, 330,
		331, 382, 383, 384, 385, 410, 411, 420, 421, 520, 530, 550, 560, 570, 580, 590, 591, 592, 593, 700, 710,
		711, 712, 720, 721, 722, 730, 740, 760, 810, 820, 830, 840,
		850, 860, 870, 880, 890, 920, 921, 922, 923, 930, 950, 960,
		970, 980, 990,
	};
	for (size_t i = 0; i < sizeof(known) / sizeof(known[0]); i++)
		if (known[i] == code)
			return G_UNSUPPORTED;
	return G_UNKNOWN;
}

static const char *g_group_name(int grp)
{
	switch (grp) {
	case GRP_NONMODAL: return "non-modal (G4)";
	case GRP_MOTION: return "motion";
	case GRP_PLANE: return "plane";
	case GRP_DIST: return "distance mode";
	case GRP_ARCDIST: return "arc distance mode";
	case GRP_FEEDMODE: return "feed mode";
	case GRP_UNITS: return "units";
	case GRP_CUTTER: return "cutter compensation";
	case GRP_TOOLLEN: return "tool length offset";
	case GRP_COORD: return "coordinate system";
	case GRP_PATH: return "path control";
	}
	return "?";
}

/* "G5.2" for 52 */
static const char *gname(int code, char *buf, size_t n)
{
	if (code % 10)
		snprintf(buf, n, "G%d.%d", code / 10, code % 10);
	else
		snprintf(buf, n, "G%d", code / 10);
	return buf;
}

static int m_group(int code)
{
	switch (code) {
	case 0: case 1: case 2: case 30: return MGRP_STOP;
	case 3: case 4: case 5: return MGRP_SPINDLE;
	case 6: return MGRP_TOOL;
	case 7: case 8: case 9: return MGRP_COOLANT;
	}
	if (code == 19 || (code >= 48 && code <= 53) || code == 60 ||
	    (code >= 61 && code <= 68) || (code >= 70 && code <= 73) ||
	    code == 98 || code == 99 || (code >= 100 && code <= 199))
		return G_UNSUPPORTED;
	return G_UNKNOWN;
}

static bool is_blank(char ch)
{
	return ch == ' ' || ch == '\t' || ch == '\f' || ch == '\v';
}

static bool starts_ci(const char *s, size_t n, const char *pre)
{
	size_t k = strlen(pre);

	if (n < k)
		return false;
	for (size_t i = 0; i < k; i++)
		if (toupper((unsigned char)s[i]) != pre[i])
			return false;
	return true;
}

/* Read one word's number at s[*i]; LinuxCNC's form: sign, digits, point. */
static int read_number(struct prog_ctx *c, const char *s, size_t n,
		       size_t *i, unsigned int line, char letter,
		       unsigned int lcol, double *out)
{
	size_t j = *i, start, digits = 0;
	char buf[128];

	while (j < n && is_blank(s[j]))
		j++;
	if (j < n && (s[j] == '#' || s[j] == '['))
		return prog_err(c, SH2000_PD_UNSUPPORTED, line, (unsigned)j + 1,
				"%s after %c: parameters and expressions are not in the built-in parser's subset (LinuxCNC's rs274 reads full RS274NGC)",
				s[j] == '#' ? "parameter" : "expression", letter);
	start = j;
	if (j < n && (s[j] == '+' || s[j] == '-'))
		j++;
	while (j < n && isdigit((unsigned char)s[j]))
		j++, digits++;
	if (j < n && s[j] == '.') {
		j++;
		while (j < n && isdigit((unsigned char)s[j]))
			j++, digits++;
	}
	if (digits == 0)
		return prog_err(c, SH2000_PD_SYNTAX, line, lcol,
				"%c word without a number", letter);
	if (j - start >= sizeof(buf))
		return prog_err(c, SH2000_PD_RANGE, line, lcol,
				"%c word: number too long", letter);
	memcpy(buf, s + start, j - start);
	buf[j - start] = 0;
	*out = strtod(buf, NULL);
	if (!isfinite(*out))
		return prog_err(c, SH2000_PD_RANGE, line, lcol,
				"%c word: number out of range", letter);
	*i = j;
	return 0;
}

/* (MSG,...), (DEBUG,...) and friends display or log in LinuxCNC. */
static void check_comment(struct prog_ctx *c, const char *s, size_t n,
			  unsigned int line, unsigned int col)
{
	static const char *const active[] = {
		"MSG,", "DEBUG,", "PRINT,", "LOGOPEN,", "LOGAPPEND,",
		"LOGCLOSE", "LOG,", "PROBEOPEN", "PROBECLOSE", "ABORT,",
	};

	while (n && is_blank(*s))
		s++, n--;
	for (size_t i = 0; i < sizeof(active) / sizeof(active[0]); i++)
		if (starts_ci(s, n, active[i])) {
			prog_warn_once(c, PW_MESSAGE, SH2000_PD_IGNORED, line, col,
				       "(%.*s...) comment not acted on: the tools do not display or log program messages; it is read as a plain comment (later ones are not reported)",
				       (int)strcspn(active[i], ","), active[i]);
			return;
		}
}

/* A comment at s[*i] == '(': checked, skipped. */
static int lex_comment(struct prog_ctx *c, const char *s, size_t n,
		       size_t *i, unsigned int line)
{
	unsigned int col = (unsigned)*i + 1;
	size_t j = *i + 1;

	while (j < n && s[j] != ')' && s[j] != '(')
		j++;
	if (j >= n)
		return prog_err(c, SH2000_PD_SYNTAX, line, col,
				"comment not closed: '(' without ')'");
	if (s[j] == '(')
		return prog_err(c, SH2000_PD_SYNTAX, line, (unsigned)j + 1,
				"nested comment: '(' inside a comment");
	check_comment(c, s + *i + 1, j - *i - 1, line, col);
	*i = j + 1;
	return 0;
}

/* What is not a word letter where one should start. */
static int lex_not_word(struct prog_ctx *c, unsigned char ch,
			unsigned int line, unsigned int col)
{
	if (ch == '#')
		return prog_err(c, SH2000_PD_UNSUPPORTED, line, col,
				"parameters (#) are not in the built-in parser's subset (LinuxCNC's rs274 reads full RS274NGC)");
	if (ch == '[')
		return prog_err(c, SH2000_PD_UNSUPPORTED, line, col,
				"expressions ([...]) are not in the built-in parser's subset (LinuxCNC's rs274 reads full RS274NGC)");
	if (isprint(ch))
		return prog_err(c, SH2000_PD_SYNTAX, line, col,
				"unexpected character '%c'", ch);
	return prog_err(c, SH2000_PD_SYNTAX, line, col,
			"unexpected byte 0x%02x", ch);
}

static int lex_g(struct prog_ctx *c, struct gline *l, double v,
		 unsigned int col)
{
	long code = fabs(v) < 1000 ? lround(v * 10) : -1;
	char nb[16], nb2[16];
	int grp;

	if (code < 0 || code > 9999 || fabs(v * 10 - (double)code) > 1e-4)
		return prog_err(c, SH2000_PD_UNKNOWN, l->line, col,
				"G%g is not a G code", v);
	grp = g_group((int)code);
	if (grp == G_UNKNOWN)
		return prog_err(c, SH2000_PD_UNKNOWN, l->line, col,
				"unknown G code %s", gname((int)code, nb, sizeof(nb)));
	if (grp == G_UNSUPPORTED)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, col,
				"%s is not in the built-in parser's subset (LinuxCNC's rs274 reads full RS274NGC)",
				gname((int)code, nb, sizeof(nb)));
	if (l->g[grp] >= 0)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, col,
				"%s and %s on one line: both are in modal group %d (%s)",
				gname(l->g[grp], nb2, sizeof(nb2)),
				gname((int)code, nb, sizeof(nb)), grp,
				g_group_name(grp));
	l->g[grp] = (int)code;
	l->gcol[grp] = col;
	return 0;
}

static int lex_m(struct prog_ctx *c, struct gline *l, double v,
		 unsigned int col)
{
	long code = fabs(v) < 10000 ? lround(v) : -1;
	int grp;

	if (code < 0 || code > 9999 || fabs(v - (double)code) > 1e-6)
		return prog_err(c, SH2000_PD_UNKNOWN, l->line, col,
				"M%g is not an M code", v);
	grp = m_group((int)code);
	if (grp == G_UNKNOWN)
		return prog_err(c, SH2000_PD_UNKNOWN, l->line, col,
				"unknown M code M%ld", code);
	if (grp == G_UNSUPPORTED)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, col,
				"M%ld is not in the built-in parser's subset", code);
	/* M7 M8 too: LinuxCNC 2.9 rejects the pair */
	if (l->m[grp] >= 0)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, col,
				"M%d and M%ld on one line: both are in the same modal group",
				l->m[grp], code);
	l->m[grp] = (int)code;
	l->mcol[grp] = col;
	return 0;
}

/* Word L with value v (the nwords-th word of the line) into l. */
static int lex_word(struct prog_ctx *c, struct gline *l, char L, double v,
		    unsigned int col, unsigned int nwords)
{
	int ret = 0;

	switch (L) {
	case 'N':
		if (nwords != 1)
			return prog_err(c, SH2000_PD_SYNTAX, l->line, col,
					"N word (line number) must begin the line");
		return 0;
	case 'G':
		ret = lex_g(c, l, v, col);
		break;
	case 'M':
		ret = lex_m(c, l, v, col);
		break;
	case 'B': case 'C': case 'U': case 'V': case 'W':
		return prog_err(c, SH2000_PD_NO_AXIS, l->line, col,
				"the SH-2000TH has no %c axis (its axes are X, Y, Z and the linear A)",
				L);
	case 'D': case 'E':
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, col,
				"%c word is not in the built-in parser's subset", L);
	default:
		if (HAS(l, L))
			return prog_err(c, SH2000_PD_CONFLICT, l->line, col,
					"%c word repeated on one line", L);
		HAS(l, L) = true;
		VAL(l, L) = v;
		COL(l, L) = col;
		break;
	}
	if (ret)
		return ret;
	if (!l->first_col)
		l->first_col = col;
	l->any_word = true;
	return 0;
}

/* Split a line into words; 0, or an error (the line is then dropped). */
static int lex_line(struct prog_ctx *c, const char *s, size_t n,
		    unsigned int line, struct gline *l)
{
	size_t i = 0;
	unsigned int nwords = 0;

	memset(l, 0, sizeof(*l));
	l->line = line;
	for (int g = 0; g < GRP_COUNT; g++)
		l->g[g] = -1;
	for (int g = 0; g < MGRP_COUNT; g++)
		l->m[g] = -1;
	while (i < n && is_blank(s[i]))
		i++;
	if (i < n && s[i] == '/')
		return prog_err(c, SH2000_PD_UNSUPPORTED, line, (unsigned)i + 1,
				"block delete (/) is not supported: the line would run or not depending on a switch this tool does not have");
	while (i < n) {
		unsigned int col = (unsigned)i + 1;
		unsigned char ch = (unsigned char)s[i];
		double v = 0;
		char L;
		int ret;

		if (is_blank((char)ch)) {
			i++;
			continue;
		}
		if (ch == ';')
			break;
		if (ch == '(') {
			if ((ret = lex_comment(c, s, n, &i, line)))
				return ret;
			continue;
		}
		if (!isalpha(ch))
			return lex_not_word(c, ch, line, col);
		L = (char)toupper(ch);
		i++;
		if (L == 'O')
			return prog_err(c, SH2000_PD_UNSUPPORTED, line, col,
					"O-words (subroutines, loops, conditionals) are not in the built-in parser's subset (LinuxCNC's rs274 reads full RS274NGC)");
		ret = read_number(c, s, n, &i, line, L, col, &v);
		if (!ret)
			ret = lex_word(c, l, L, v, col, ++nwords);
		if (ret)
			return ret;
	}
	return 0;
}

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
					gname(l->g[g], nb, sizeof(nb)), st->nurbs_line);
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

	while (i < n && is_blank(s[i]))
		i++;
	if (i == n || s[i] != '%')
		return false;
	for (i++; i < n; i++)
		if (!is_blank(s[i]))
			return false;
	return true;
}

static bool blank_line(const char *s, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (!is_blank(s[i]))
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
	if (lex_line(c, s, n, line, &l) || !l.any_word)
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
