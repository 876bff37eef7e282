/* SPDX-License-Identifier: MIT */
/*
 * CSV point lists: one point a line, columns x,y[,z[,a[,f]]] or named by a
 * header; the first point is reached at rapid, the rest are feed lines.
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "prog_internal.h"

enum col_kind { COL_X, COL_Y, COL_Z, COL_A, COL_F_MIN, COL_F_S, COL_KINDS };

#define MAX_COLS 8

struct field {
	const char *s;
	size_t n;
	unsigned int col;
};

static const char *const col_names[COL_KINDS] = {
	"x", "y", "z", "a", "f", "feed_mm_s",
};

/* Fields of a line without its comment; returns the count (MAX_COLS + 1
 * when there are more). */
static int split(const char *s, size_t n, struct field *f)
{
	size_t i = 0, end = n;
	int nf = 0;

	for (size_t k = 0; k < n; k++)
		if (s[k] == '#') {
			end = k;
			break;
		}
	for (;;) {
		size_t a = i, b;

		while (i < end && s[i] != ',')
			i++;
		b = i;
		while (a < b && isspace((unsigned char)s[a]))
			a++;
		while (b > a && isspace((unsigned char)s[b - 1]))
			b--;
		if (nf < MAX_COLS) {
			f[nf].s = s + a;
			f[nf].n = b - a;
			f[nf].col = (unsigned)a + 1;
		}
		nf++;
		if (i >= end)
			break;
		i++;
	}
	return nf > MAX_COLS ? MAX_COLS + 1 : nf;
}

static bool empty_line(const char *s, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		if (s[i] == '#')
			return true;
		if (!isspace((unsigned char)s[i]))
			return false;
	}
	return true;
}

static int number(struct prog_ctx *c, const struct field *f,
		  unsigned int line, const char *what, double *out)
{
	char buf[64];
	char *end;

	for (size_t i = 0; i < f->n; i++)
		if (!strchr("0123456789+-.eE", f->s[i]))
			return prog_err(c, SH2000_PD_SYNTAX, line, f->col,
					"%s: '%.*s' is not a number", what,
					(int)f->n, f->s);
	if (f->n >= sizeof(buf))
		return prog_err(c, SH2000_PD_RANGE, line, f->col,
				"%s: number too long", what);
	memcpy(buf, f->s, f->n);
	buf[f->n] = 0;
	*out = strtod(buf, &end);
	if (*end || end == buf)
		return prog_err(c, SH2000_PD_SYNTAX, line, f->col,
				"%s: '%s' is not a number", what, buf);
	if (!isfinite(*out))
		return prog_err(c, SH2000_PD_RANGE, line, f->col,
				"%s: %s is out of range", what, buf);
	return 0;
}

struct csv_state {
	int kinds[MAX_COLS], ncols;
	bool header, first, feed_block;
	double feed;
	unsigned int npoints;
};

/* Column kind of header field f, COL_KINDS if unknown. */
static int column_kind(const struct field *f)
{
	int k;

	for (k = 0; k < COL_KINDS; k++)
		if (f->n == strlen(col_names[k]) &&
		    !strncasecmp(f->s, col_names[k], f->n))
			return k;
	if (f->n == 4 && !strncasecmp(f->s, "feed", 4))
		return COL_F_MIN;
	return COL_KINDS;
}

/* A header line names the columns. */
static int check_header(struct prog_ctx *c, struct csv_state *st,
			const struct field *f, int nf, unsigned int line)
{
	bool seen[COL_KINDS] = { false };

	if (nf > MAX_COLS)
		return prog_err(c, SH2000_PD_SYNTAX, line, 1,
				"more than %d columns", MAX_COLS);
	for (int i = 0; i < nf; i++) {
		int k = column_kind(&f[i]);

		if (k == COL_KINDS)
			return prog_err(c, SH2000_PD_UNKNOWN, line, f[i].col,
					"unknown column '%.*s' (columns: x, y, z, a, f or feed in mm/min, feed_mm_s)",
					(int)f[i].n, f[i].s);
		if (seen[k] || ((k == COL_F_MIN || k == COL_F_S) &&
				(seen[COL_F_MIN] || seen[COL_F_S])))
			return prog_err(c, SH2000_PD_CONFLICT, line, f[i].col,
					"column '%.*s' given twice", (int)f[i].n,
					f[i].s);
		seen[k] = true;
		st->kinds[i] = k;
	}
	if (!seen[COL_X] && !seen[COL_Y] && !seen[COL_Z] && !seen[COL_A])
		return prog_err(c, SH2000_PD_MISSING, line, 1,
				"header names no axis column (x, y, z, a)");
	st->ncols = nf;
	return 0;
}

/* The first line: a header, or the first point fixing the column count. */
static bool read_first(struct prog_ctx *c, struct csv_state *st,
		       const struct field *f, int nf, unsigned int line)
{
	st->first = false;
	if (nf > 0 && f[0].n && isalpha((unsigned char)f[0].s[0])) {
		st->header = true;
		/* a bad header ends the reading */
		if (check_header(c, st, f, nf, line))
			c->stop = true;
		return true;
	}
	if (nf < 2 || nf > 5) {
		prog_err(c, SH2000_PD_SYNTAX, line, 1,
			 "%d fields: without a header a line is x,y[,z[,a[,f]]] (2 to 5 fields)",
			 nf > MAX_COLS ? MAX_COLS + 1 : nf);
		c->stop = true;
		return true;
	}
	st->ncols = nf;
	for (int i = 0; i < nf; i++)
		st->kinds[i] = i < 4 ? i : COL_F_MIN;
	return false;
}

/* The point and feed of a data line (empty fields: unchanged). */
static int read_values(struct prog_ctx *c, const struct csv_state *st,
		       const struct field *f, unsigned int line,
		       double p[SH2000_AXES], double *feed)
{
	static const char *const what[COL_KINDS] = {
		"x", "y", "z", "a", "feed", "feed_mm_s",
	};

	memcpy(p, c->pos, SH2000_AXES * sizeof(*p));
	for (int i = 0; i < st->ncols; i++) {
		int k = st->kinds[i];
		double v = 0;

		if (f[i].n == 0)
			continue;
		if (number(c, &f[i], line, what[k], &v))
			return -SH2000_PROG_EINVALID;
		if (k < COL_F_MIN) {
			p[k] = v;
			continue;
		}
		if (!(v > 0))
			return prog_err(c, SH2000_PD_RANGE, line, f[i].col,
					"feed %g must be > 0", v);
		*feed = k == COL_F_MIN ? v / 60.0 : v;
	}
	return 0;
}

/* The blocks of one point: a feed change, then a rapid to the first
 * point or a line to the others. */
static void emit_point(struct prog_ctx *c, struct csv_state *st,
		       const double p[SH2000_AXES], double nfeed,
		       unsigned int line)
{
	struct sh2000_prog_block *b;

	if (nfeed != st->feed ||
	    (!st->feed_block && st->npoints > 0 && nfeed > 0)) {
		b = prog_push(c, SH2000_PROG_FEED, line, 1);
		if (!b)
			return;
		b->feed = nfeed;
		b->u.feed_mm_min = nfeed * 60.0;
		st->feed = nfeed;
		st->feed_block = true;
	}
	if (st->npoints++ == 0) {
		if (!memcmp(p, c->pos, SH2000_AXES * sizeof(*p)))
			return;
		b = prog_push(c, SH2000_PROG_RAPID, line, 1);
	} else if (!(st->feed > 0)) {
		prog_err(c, SH2000_PD_FEED, line, 1,
			 "no feed rate for this move: add an f (mm/min) or feed_mm_s column, or give the tool a feed");
		memcpy(c->pos, p, SH2000_AXES * sizeof(*p));
		return;
	} else {
		b = prog_push(c, SH2000_PROG_LINE, line, 1);
		if (b)
			b->feed = st->feed;
	}
	if (!b)
		return;
	memcpy(b->end, p, SH2000_AXES * sizeof(*p));
	memcpy(c->pos, p, SH2000_AXES * sizeof(*p));
}

static void csv_init(struct prog_ctx *c, void *state)
{
	struct csv_state *st = state;

	memset(st, 0, sizeof(*st));
	st->first = true;
	st->feed = c->opt.feed_mm_s > 0 ? c->opt.feed_mm_s : 0;
}

static void csv_line(struct prog_ctx *c, void *state, const char *s,
		     size_t n, unsigned int line)
{
	struct csv_state *st = state;
	struct field f[MAX_COLS];
	double p[SH2000_AXES], nfeed = st->feed;
	int nf;

	if (empty_line(s, n))
		return;
	nf = split(s, n, f);
	if (st->first && read_first(c, st, f, nf, line))
		return;
	if (nf != st->ncols) {
		prog_err(c, SH2000_PD_SYNTAX, line,
			 nf > st->ncols ? f[st->ncols].col : (unsigned)n + 1,
			 "%s%d fields, expected %d like the %s",
			 nf > MAX_COLS ? "more than " : "",
			 nf > MAX_COLS ? MAX_COLS : nf, st->ncols,
			 st->header ? "header" : "first line");
		return;
	}
	if (!read_values(c, st, f, line, p, &nfeed))
		emit_point(c, st, p, nfeed, line);
}

static void csv_finish(struct prog_ctx *c, void *state, unsigned int line)
{
	struct csv_state *st = state;

	if (st->npoints == 0 && !c->stop)
		prog_err(c, SH2000_PD_MISSING, line ? line : 1, 1,
			 "no points in the file");
}

const struct prog_format_ops prog_csv_ops = {
	.state_size = sizeof(struct csv_state),
	.init = csv_init,
	.line = csv_line,
	.finish = csv_finish,
};
