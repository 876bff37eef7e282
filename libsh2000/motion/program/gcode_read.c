/* SPDX-License-Identifier: MIT */
/*
 * The G-code reader's first half (gcode_read.h): a line into words, as
 * LinuxCNC's interp_read does. Numbers, comments, the letters a word may
 * have, and the modal group of each G and M code are checked here; what the
 * words mean together is gcode.c's.
 */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gcode_read.h"

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
const char *gcode_gname(int code, char *buf, size_t n)
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

bool gcode_is_blank(char ch)
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

/* The number s[start..end) ("-1.5e-3") written out without its exponent
 * ("-0.0015") into out (160 bytes); false when that would be long (more
 * than 40 digits or an exponent beyond 30). */
static bool plain_decimal(const char *s, size_t start, size_t end, char *out)
{
	char d[40];
	long nd = 0, point = -1, exp, o = 0, k = (long)start, w;

	if (s[k] == '-')
		out[o++] = '-';
	if (s[k] == '+' || s[k] == '-')
		k++;
	for (; k < (long)end && s[k] != 'e' && s[k] != 'E'; k++) {
		if (s[k] == '.')
			point = nd;
		else if (nd < (long)sizeof(d))
			d[nd++] = s[k];
		else
			return false;
	}
	/* the exponent, [sign] digits up to end (exponent_err()): the line
	 * need not end in a NUL (strtol ran past the end of a program whose
	 * last line ended in one) */
	exp = 0;
	w = ++k < (long)end && s[k] == '-' ? -1 : 1;
	if (k < (long)end && (s[k] == '+' || s[k] == '-'))
		k++;
	for (; k < (long)end && exp <= 30; k++)
		exp = exp * 10 + (s[k] - '0');
	exp *= w;
	if (exp < -30 || exp > 30)
		return false;
	point = (point < 0 ? nd : point) + exp;	/* digits before the point */
	for (w = 0; w < point - 1 && (w >= nd || d[w] == '0'); w++)
		;		/* leading zeros of the whole part */
	if (w >= nd && point > 0)
		w = point - 1;	/* all zeros: one stays */
	if (point <= 0)
		out[o++] = '0';
	for (k = w; k < point; k++)
		out[o++] = k < nd ? d[k] : '0';
	w = point > 0 ? point : 0;	/* the fraction's first digit */
	while (nd > w && d[nd - 1] == '0')
		nd--;		/* trailing zeros of the fraction */
	if (nd > w)
		out[o++] = '.';
	for (k = point < 0 ? point : w; k < nd; k++)
		out[o++] = k < 0 ? '0' : d[k];
	out[o] = 0;
	return true;
}

/* An exponent right after a number ("1e9"): RS274NGC numbers have none, and
 * the E would be read as a word of its own; say so, with the number
 * written out. Column of the E, as the E word's error was. 0 when there
 * is no exponent at s[j]. */
static int exponent_err(struct prog_ctx *c, const char *s, size_t n,
			size_t start, size_t j, unsigned int line)
{
	size_t k = j + 1, e;
	char plain[160];

	if (j >= n || (s[j] != 'e' && s[j] != 'E'))
		return 0;
	if (k < n && (s[k] == '+' || s[k] == '-'))
		k++;
	for (e = k; e < n && isdigit((unsigned char)s[e]); e++)
		;
	if (e == k)
		return 0;	/* "X1E" or "X1 E-": an E word of its own */
	if (e - start > 60 || !plain_decimal(s, start, e, plain))
		return prog_err(c, SH2000_PD_UNSUPPORTED, line, (unsigned)j + 1,
				"numbers take no exponent (%.*s)",
				(int)(e - start < 60 ? e - start : 60), s + start);
	return prog_err(c, SH2000_PD_UNSUPPORTED, line, (unsigned)j + 1,
			"numbers take no exponent (%.*s): write %s",
			(int)(e - start), s + start, plain);
}

/* Read one word's number at s[*i]; LinuxCNC's form: sign, digits, point. */
static int read_number(struct prog_ctx *c, const char *s, size_t n,
		       size_t *i, unsigned int line, char letter,
		       unsigned int lcol, double *out)
{
	size_t j = *i, start, digits = 0;
	int err;
	char buf[128];

	while (j < n && gcode_is_blank(s[j]))
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
	if ((err = exponent_err(c, s, n, start, j, line)))
		return err;
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

	while (n && gcode_is_blank(*s))
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
				"unknown G code %s", gcode_gname((int)code, nb, sizeof(nb)));
	if (grp == G_UNSUPPORTED)
		return prog_err(c, SH2000_PD_UNSUPPORTED, l->line, col,
				"%s is not in the built-in parser's subset (LinuxCNC's rs274 reads full RS274NGC)",
				gcode_gname((int)code, nb, sizeof(nb)));
	if (l->g[grp] >= 0)
		return prog_err(c, SH2000_PD_CONFLICT, l->line, col,
				"%s and %s on one line: both are in modal group %d (%s)",
				gcode_gname(l->g[grp], nb2, sizeof(nb2)),
				gcode_gname((int)code, nb, sizeof(nb)), grp,
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

int gcode_lex_line(struct prog_ctx *c, const char *s, size_t n,
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
	while (i < n && gcode_is_blank(s[i]))
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

		if (gcode_is_blank((char)ch)) {
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
