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

int prog_read_csv(struct prog_ctx *c, const char *text, size_t len)
{
	int kinds[MAX_COLS], ncols = 0;
	bool header = false, first = true, feed_block = false;
	double feed = c->opt.feed_mm_s > 0 ? c->opt.feed_mm_s : 0;
	unsigned int line = 0, npoints = 0;
	size_t off = 0;

	while (off < len && !c->stop) {
		const char *s = text + off;
		struct field f[MAX_COLS];
		double p[SH2000_AXES];
		double nfeed = feed;
		struct sh2000_prog_block *b;
		size_t n;
		int nf, bad = 0;

		off = prog_next_line(text, len, off, &n);
		line++;
		if (empty_line(s, n))
			continue;
		nf = split(s, n, f);
		if (first) {
			first = false;
			if (nf > 0 && f[0].n && isalpha((unsigned char)f[0].s[0])) {
				bool seen[COL_KINDS] = { false };

				header = true;
				if (nf > MAX_COLS) {
					prog_err(c, SH2000_PD_SYNTAX, line, 1,
						 "more than %d columns", MAX_COLS);
					return -SH2000_PROG_EINVALID;
				}
				ncols = nf;
				for (int i = 0; i < nf; i++) {
					int k;

					for (k = 0; k < COL_KINDS; k++)
						if (f[i].n == strlen(col_names[k]) &&
						    !strncasecmp(f[i].s, col_names[k], f[i].n))
							break;
					if (k == COL_KINDS && f[i].n == 4 &&
					    !strncasecmp(f[i].s, "feed", 4))
						k = COL_F_MIN;
					if (k == COL_KINDS) {
						prog_err(c, SH2000_PD_UNKNOWN, line, f[i].col,
							 "unknown column '%.*s' (columns: x, y, z, a, f or feed in mm/min, feed_mm_s)",
							 (int)f[i].n, f[i].s);
						return -SH2000_PROG_EINVALID;
					}
					if (seen[k] || ((k == COL_F_MIN || k == COL_F_S) &&
							(seen[COL_F_MIN] || seen[COL_F_S]))) {
						prog_err(c, SH2000_PD_CONFLICT, line, f[i].col,
							 "column '%.*s' given twice",
							 (int)f[i].n, f[i].s);
						return -SH2000_PROG_EINVALID;
					}
					seen[k] = true;
					kinds[i] = k;
				}
				if (!seen[COL_X] && !seen[COL_Y] && !seen[COL_Z] &&
				    !seen[COL_A]) {
					prog_err(c, SH2000_PD_MISSING, line, 1,
						 "header names no axis column (x, y, z, a)");
					return -SH2000_PROG_EINVALID;
				}
				continue;
			}
			if (nf < 2 || nf > 5) {
				prog_err(c, SH2000_PD_SYNTAX, line, 1,
					 "%d fields: without a header a line is x,y[,z[,a[,f]]] (2 to 5 fields)",
					 nf > MAX_COLS ? MAX_COLS + 1 : nf);
				return -SH2000_PROG_EINVALID;
			}
			ncols = nf;
			for (int i = 0; i < nf; i++)
				kinds[i] = i < 4 ? i : COL_F_MIN;
		}
		if (nf != ncols) {
			prog_err(c, SH2000_PD_SYNTAX, line,
				 nf > ncols ? f[ncols].col : (unsigned)n + 1,
				 "%s%d fields, expected %d like the %s",
				 nf > MAX_COLS ? "more than " : "",
				 nf > MAX_COLS ? MAX_COLS : nf, ncols,
				 header ? "header" : "first line");
			continue;
		}
		memcpy(p, c->pos, sizeof(p));
		for (int i = 0; i < nf; i++) {
			static const char *const what[COL_KINDS] = {
				"x", "y", "z", "a", "feed", "feed_mm_s",
			};
			double v = 0;

			if (f[i].n == 0)
				continue;	/* empty: unchanged */
			if (number(c, &f[i], line, what[kinds[i]], &v)) {
				bad = 1;
				break;
			}
			if (kinds[i] >= COL_F_MIN) {
				if (!(v > 0)) {
					prog_err(c, SH2000_PD_RANGE, line, f[i].col,
						 "feed %g must be > 0", v);
					bad = 1;
					break;
				}
				nfeed = kinds[i] == COL_F_MIN ? v / 60.0 : v;
			} else {
				p[kinds[i]] = v;
			}
		}
		if (bad)
			continue;
		if (nfeed != feed || (!feed_block && npoints > 0 && nfeed > 0)) {
			b = prog_push(c, SH2000_PROG_FEED, line, 1);
			if (!b)
				return -ENOMEM;
			b->feed = nfeed;
			b->u.feed_mm_min = nfeed * 60.0;
			feed = nfeed;
			feed_block = true;
		}
		if (npoints++ == 0) {
			if (!memcmp(p, c->pos, sizeof(p)))
				continue;
			b = prog_push(c, SH2000_PROG_RAPID, line, 1);
		} else {
			if (!(feed > 0)) {
				prog_err(c, SH2000_PD_FEED, line, 1,
					 "no feed rate for this move: add an f (mm/min) or feed_mm_s column, or give the tool a feed");
				memcpy(c->pos, p, sizeof(p));
				continue;
			}
			b = prog_push(c, SH2000_PROG_LINE, line, 1);
			if (b)
				b->feed = feed;
		}
		if (!b)
			return -ENOMEM;
		memcpy(b->end, p, sizeof(p));
		memcpy(c->pos, p, sizeof(p));
	}
	if (npoints == 0 && !c->stop)
		prog_err(c, SH2000_PD_MISSING, line ? line : 1, 1,
			 "no points in the file");
	return c->errors ? -SH2000_PROG_EINVALID : 0;
}
