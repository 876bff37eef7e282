// SPDX-License-Identifier: MIT
/*
 * Reading a compensation table file (docs/compensation.md "The file") into
 * the card's image, keeping each table's and point's line so that every
 * refusal, the host's check or the card's, names FILE:LINE. Positions and
 * corrections are in mm in the file, counts in the image (the axes'
 * scales). The image's rules are the protocol's (sh2000_comp_parse,
 * sh2000_comp_check): this file only reads the text and places the words.
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sh2000_internal.h"

#define MAX_NUMS	1024u		/* numbers on one line (a grid row) */

struct ctab {
	unsigned int kind, target, src1, src2, n1, n2;
	unsigned int line;		/* the table's own line */
	double coef;			/* SQUARE */
	double g[4];			/* GRID: u0, du, v0, dv (mm) */
	double *pos, *val;		/* TABLE points; GRID values */
	unsigned int *lines;		/* a TABLE's points, a GRID's rows */
	size_t npts, cap, nlines;
};

struct sh2000_comp_file {
	char path[256];
	uint32_t id;
	unsigned int tables;
	struct ctab t[SH2000_COMP_MAX_TABLES];
	uint16_t *w;
	size_t words;
};

static int ferr(const struct sh2000_comp_file *f, unsigned int line,
		char *msg, size_t len, const char *fmt, ...)
{
	char why[256];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(why, sizeof(why), fmt, ap);
	va_end(ap);
	if (msg && len)
		snprintf(msg, len, "%s:%u: %s", f->path, line, why);
	return -SH2000_EPARAM;
}

/* A failure that is not the table's: the file's name and what (never a
 * bare code, so a caller's message says why). */
static int syserr(const char *path, int code, char *msg, size_t len,
		  const char *what)
{
	if (msg && len)
		snprintf(msg, len, "%s: %s: %s", path, what, strerror(-code));
	return code;
}

static int axis_of(const char *s)
{
	const char *p;

	if (!s || !s[0] || s[1])
		return -1;
	p = strchr(SH2000_AXIS_LETTERS, toupper((unsigned char)s[0]));
	return p ? (int)(p - SH2000_AXIS_LETTERS) : -1;
}

/* Numbers of a data line: count, or -1 when one is not a finite number. */
static int numbers(char *s, double *out, unsigned int max)
{
	unsigned int n = 0;
	char *tok, *save = NULL, *end;

	for (tok = strtok_r(s, " \t,;\r\n", &save); tok;
	     tok = strtok_r(NULL, " \t,;\r\n", &save)) {
		if (n == max)
			return -1;
		out[n] = strtod(tok, &end);
		if (*end || !isfinite(out[n]))
			return -1;
		n++;
	}
	return (int)n;
}

static int grow(struct ctab *t, size_t need)
{
	double *p, *v;
	unsigned int *l;
	size_t cap = t->cap ? t->cap : 64;

	while (cap < need)
		cap *= 2;
	if (cap == t->cap)
		return 0;
	p = realloc(t->pos, cap * sizeof(*p));
	if (p)
		t->pos = p;
	v = realloc(t->val, cap * sizeof(*v));
	if (v)
		t->val = v;
	l = realloc(t->lines, cap * sizeof(*l));
	if (l)
		t->lines = l;
	if (!p || !v || !l)
		return -ENOMEM;
	t->cap = cap;
	return 0;
}

/* A data line of the last table. */
static int data_line(struct sh2000_comp_file *f, char *s, unsigned int line,
		     char *msg, size_t len)
{
	double num[MAX_NUMS];
	struct ctab *t = &f->t[f->tables - 1];
	int n = numbers(s, num, MAX_NUMS), i;

	if (n < 0)
		return ferr(f, line, msg, len, "not a list of numbers");
	if (t->kind == SH2000_COMP_SQUARE)
		return ferr(f, line, msg, len, "a squareness takes no data lines");
	if (t->kind == SH2000_COMP_TABLE) {
		if (n != 2 && n != 3)
			return ferr(f, line, msg, len,
				    "want: position correction, or LinuxCNC's nominal forward reverse");
		if (grow(t, t->npts + 1))
			return syserr(f->path, -ENOMEM, msg, len, "the table's points");
		t->pos[t->npts] = num[0];
		/* LinuxCNC's form: the positions to command going forward and
		 * in reverse; the card's tables have one correction, the mean */
		t->val[t->npts] = n == 2 ? num[1] : 0.5 * (num[1] + num[2]) - num[0];
		t->lines[t->npts++] = line;
		return 0;
	}
	if ((unsigned int)n != t->n1 || t->nlines == t->n2)
		return ferr(f, line, msg, len, "a grid row of %u corrections (%u rows) wanted",
			    t->n1, t->n2);
	if (grow(t, t->npts + (size_t)n))
		return syserr(f->path, -ENOMEM, msg, len, "the grid's points");
	for (i = 0; i < n; i++)
		t->val[t->npts++] = num[i];
	t->lines[t->nlines++] = line;
	return 0;
}

/* A keyword line: a new table, or the id. 1 if it was one, 0 if the line
 * is data, < 0 an error. */
static int keyword_line(struct sh2000_comp_file *f, char *s, unsigned int line,
			char *msg, size_t len)
{
	char kw[16], a1[8] = "", a2[8] = "", a3[8] = "";
	double g[6];
	struct ctab *t;
	int n;

	if (sscanf(s, "%15s", kw) != 1 || !isalpha((unsigned char)kw[0]))
		return 0;
	if (!strcmp(kw, "id")) {
		unsigned long v;
		char *end;

		v = strtoul(s + 2, &end, 0);
		while (isspace((unsigned char)*end))
			end++;
		if (*end || v > 0xffffffffUL)
			return ferr(f, line, msg, len, "id: a number 0..0xffffffff wanted");
		f->id = (uint32_t)v;
		return 1;
	}
	if (f->tables == SH2000_COMP_MAX_TABLES)
		return ferr(f, line, msg, len, "more than the %u tables the card holds",
			    SH2000_COMP_MAX_TABLES);
	t = &f->t[f->tables];
	memset(t, 0, sizeof(*t));
	t->line = line;
	n = sscanf(s, "%*s %7s %7s %7s", a1, a2, a3);
	if (!strcmp(kw, "pitch") && n == 1) {
		t->kind = SH2000_COMP_TABLE;
		t->target = t->src1 = (unsigned int)axis_of(a1);
	} else if (!strcmp(kw, "cross") && n == 2) {
		t->kind = SH2000_COMP_TABLE;
		t->target = (unsigned int)axis_of(a1);
		t->src1 = (unsigned int)axis_of(a2);
	} else if (!strcmp(kw, "square") &&
		   sscanf(s, "%*s %7s %7s %lf", a1, a2, &t->coef) == 3 &&
		   isfinite(t->coef)) {
		t->kind = SH2000_COMP_SQUARE;
		t->target = (unsigned int)axis_of(a1);
		t->src1 = (unsigned int)axis_of(a2);
	} else if (!strcmp(kw, "grid") &&
		   sscanf(s, "%*s %7s %7s %7s %lf %lf %lf %lf %lf %lf", a1, a2,
			  a3, &g[0], &g[1], &g[2], &g[3], &g[4], &g[5]) == 9) {
		t->kind = SH2000_COMP_GRID;
		t->target = (unsigned int)axis_of(a1);
		t->src1 = (unsigned int)axis_of(a2);
		t->src2 = (unsigned int)axis_of(a3);
		t->g[0] = g[0];
		t->g[1] = g[1];
		t->g[2] = g[3];
		t->g[3] = g[4];
		if (!(g[2] >= 2 && g[2] <= 65535 && g[5] >= 2 && g[5] <= 65535) ||
		    g[2] != floor(g[2]) || g[5] != floor(g[5]))
			return ferr(f, line, msg, len, "grid: 2..65535 points each way wanted");
		t->n1 = (unsigned int)g[2];
		t->n2 = (unsigned int)g[5];
	} else {
		return ferr(f, line, msg, len,
			    "want: pitch A | cross T S | square T S K | grid T S1 S2 U0 DU N1 V0 DV N2 | id N");
	}
	if (t->target >= SH2000_AXES || t->src1 >= SH2000_AXES ||
	    (t->kind == SH2000_COMP_GRID && t->src2 >= SH2000_AXES))
		return ferr(f, line, msg, len, "an axis is one of %s", SH2000_AXIS_LETTERS);
	f->tables++;
	return 1;
}

static int read_lines(struct sh2000_comp_file *f, FILE *fp, char *msg,
		      size_t len)
{
	char buf[16384];
	unsigned int line = 0;
	int r = 0;

	errno = 0;
	while (!r && fgets(buf, sizeof(buf), fp)) {
		char *c = strchr(buf, '#'), *s = buf;

		line++;
		if (c)
			*c = '\0';
		while (isspace((unsigned char)*s))
			s++;
		if (!*s)
			continue;
		r = keyword_line(f, s, line, msg, len);
		if (r == 0)
			r = f->tables ? data_line(f, s, line, msg, len) :
			    ferr(f, line, msg, len, "data before any table");
		else if (r > 0)
			r = 0;
	}
	if (r)
		return r;
	if (ferror(fp))
		return syserr(f->path, errno ? -errno : -EIO, msg, len, "cannot read it");
	if (f->tables && f->t[f->tables - 1].kind == SH2000_COMP_GRID &&
	    f->t[f->tables - 1].nlines != f->t[f->tables - 1].n2)
		return ferr(f, f->t[f->tables - 1].line, msg, len,
			    "grid: %u rows wanted, %zu given",
			    f->t[f->tables - 1].n2, f->t[f->tables - 1].nlines);
	return 0;
}

static size_t table_words(const struct ctab *t)
{
	switch (t->kind) {
	case SH2000_COMP_TABLE:
		return SH2000_COMP_DESC_WORDS + 4u * t->npts;
	case SH2000_COMP_SQUARE:
		return SH2000_COMP_DESC_WORDS + 2u;
	default:
		return SH2000_COMP_DESC_WORDS + 8u + 2u * t->npts;
	}
}

static void put32(uint16_t *w, size_t at, uint32_t v)
{
	w[at] = (uint16_t)(v & 0xffffu);
	w[at + 1] = (uint16_t)(v >> 16);
}

/* Counts of mm on an axis, saturated to int32 (the card's check refuses
 * what does not fit in its travel anyway). */
static uint32_t counts(double mm, double scale)
{
	double c = nearbyint(mm * scale);

	if (c > 2147483647.0)
		c = 2147483647.0;
	if (c < -2147483648.0)
		c = -2147483648.0;
	return (uint32_t)(int32_t)c;
}

static size_t place_table(uint16_t *w, size_t at, const struct ctab *t,
			  const double scale[SH2000_AXES])
{
	double k = scale[t->target];
	size_t i;

	w[at + SH2000_CT_KIND] = (uint16_t)t->kind;
	w[at + SH2000_CT_TARGET] = (uint16_t)t->target;
	w[at + SH2000_CT_SRC1] = (uint16_t)t->src1;
	w[at + SH2000_CT_SRC2] = (uint16_t)(t->kind == SH2000_COMP_GRID ? t->src2 : 0);
	w[at + SH2000_CT_N1] = (uint16_t)(t->kind == SH2000_COMP_TABLE ? t->npts :
					  t->kind == SH2000_COMP_GRID ? t->n1 : 0);
	w[at + SH2000_CT_N2] = (uint16_t)(t->kind == SH2000_COMP_GRID ? t->n2 : 0);
	at += SH2000_COMP_DESC_WORDS;
	if (t->kind == SH2000_COMP_SQUARE) {
		put32(w, at, sh2000_f32_bits(t->coef * k / scale[t->src1]));
		return at + 2;
	}
	if (t->kind == SH2000_COMP_TABLE) {
		for (i = 0; i < t->npts; i++) {
			put32(w, at + 2 * i, counts(t->pos[i], scale[t->src1]));
			put32(w, at + 2 * (t->npts + i), sh2000_f32_bits(t->val[i] * k));
		}
		return at + 4 * t->npts;
	}
	put32(w, at, counts(t->g[0], scale[t->src1]));
	put32(w, at + 2, counts(t->g[1], scale[t->src1]));
	put32(w, at + 4, counts(t->g[2], scale[t->src2]));
	put32(w, at + 6, counts(t->g[3], scale[t->src2]));
	for (i = 0; i < t->npts; i++)
		put32(w, at + 8 + 2 * i, sh2000_f32_bits(t->val[i] * k));
	return at + 8 + 2 * t->npts;
}

static int build(struct sh2000_comp_file *f, const double scale[SH2000_AXES],
		 char *msg, size_t len)
{
	struct sh2000_comp_index ix;
	struct sh2000_comp_fault why;
	size_t n = SH2000_COMP_HEADER_WORDS, at;
	unsigned int i;

	for (i = 0; i < f->tables; i++) {
		const struct ctab *t = &f->t[i];

		if (t->kind == SH2000_COMP_GRID && t->nlines != t->n2)
			return ferr(f, t->line, msg, len, "grid: %u rows wanted, %zu given",
				    t->n2, t->nlines);
		n += table_words(t);
		if (n > SH2000_COMP_MAX_WORDS)
			return ferr(f, t->line, msg, len,
				    "the tables up to this one need %zu words: the card holds %u",
				    n, SH2000_COMP_MAX_WORDS);
	}
	f->w = calloc(n, sizeof(*f->w));
	if (!f->w)
		return syserr(f->path, -ENOMEM, msg, len, "the card's image");
	f->w[SH2000_CI_MAGIC] = SH2000_COMP_MAGIC;
	f->w[SH2000_CI_FORMAT] = SH2000_COMP_FORMAT;
	put32(f->w, SH2000_CI_ID_LO, f->id);
	f->w[SH2000_CI_TABLES] = (uint16_t)f->tables;
	at = SH2000_COMP_HEADER_WORDS;
	for (i = 0; i < f->tables; i++)
		at = place_table(f->w, at, &f->t[i], scale);
	f->words = n;
	if (sh2000_comp_parse(f->w, n, &ix, &why)) {
		sh2000_comp_file_explain(f, &why, msg, len);
		return -SH2000_EPARAM;
	}
	return 0;
}

/* FNV-1a of the file's name without its folders: the default identity. */
static uint32_t name_id(const char *path)
{
	const char *b = strrchr(path, '/');
	uint32_t h = 2166136261u;

	for (b = b ? b + 1 : path; *b; b++)
		h = (h ^ (uint8_t)*b) * 16777619u;
	return h;
}

int sh2000_comp_file_read(struct sh2000_comp_file **out, const char *path,
			  const double scale[SH2000_AXES], char *msg,
			  size_t len)
{
	struct sh2000_comp_file *f;
	struct stat sb;
	FILE *fp;
	int r;

	if (!out || !path || !scale)
		return -EINVAL;
	*out = NULL;
	fp = fopen(path, "r");
	if (!fp) {
		r = -errno;
		if (msg && len)
			snprintf(msg, len, "%s: %s", path, strerror(-r));
		return r;
	}
	/* a directory opens for reading; its first read fails */
	if (fstat(fileno(fp), &sb) == 0 && S_ISDIR(sb.st_mode)) {
		fclose(fp);
		return syserr(path, -EISDIR, msg, len, "not a table file");
	}
	f = calloc(1, sizeof(*f));
	if (!f) {
		fclose(fp);
		return syserr(path, -ENOMEM, msg, len, "reading it");
	}
	snprintf(f->path, sizeof(f->path), "%s", path);
	f->id = name_id(path);
	r = read_lines(f, fp, msg, len);
	fclose(fp);
	if (!r)
		r = build(f, scale, msg, len);
	if (r) {
		sh2000_comp_file_free(f);
		return r;
	}
	*out = f;
	return 0;
}

void sh2000_comp_file_free(struct sh2000_comp_file *f)
{
	unsigned int i;

	if (!f)
		return;
	for (i = 0; i < SH2000_COMP_MAX_TABLES; i++) {
		free(f->t[i].pos);
		free(f->t[i].val);
		free(f->t[i].lines);
	}
	free(f->w);
	free(f);
}

const uint16_t *sh2000_comp_file_image(const struct sh2000_comp_file *f,
				       size_t *words)
{
	if (words)
		*words = f ? f->words : 0;
	return f ? f->w : NULL;
}

unsigned int sh2000_comp_file_line(const struct sh2000_comp_file *f,
				   int table, int point)
{
	const struct ctab *t;

	if (!f || table < 0 || (unsigned int)table >= f->tables)
		return 0;
	t = &f->t[table];
	if (point < 0)
		return t->line;
	if (t->kind == SH2000_COMP_TABLE && (size_t)point < t->npts)
		return t->lines[point];
	if (t->kind == SH2000_COMP_GRID && (size_t)point / t->n1 < t->nlines)
		return t->lines[(size_t)point / t->n1];
	return t->line;
}

/* A table as its keyword line names it: "pitch table X", "cross table Y
 * by X", "square X by Y", "grid Z by X and Y". */
static void table_name(const struct ctab *t, char *name, size_t len)
{
	char a = SH2000_AXIS_LETTERS[t->target], s1 = SH2000_AXIS_LETTERS[t->src1];

	if (t->kind == SH2000_COMP_TABLE && t->target == t->src1)
		snprintf(name, len, "pitch table %c", a);
	else if (t->kind == SH2000_COMP_TABLE)
		snprintf(name, len, "cross table %c by %c", a, s1);
	else if (t->kind == SH2000_COMP_SQUARE)
		snprintf(name, len, "square %c by %c", a, s1);
	else
		snprintf(name, len, "grid %c by %c and %c", a, s1,
			 SH2000_AXIS_LETTERS[t->src2]);
}

const char *sh2000_comp_file_explain(const struct sh2000_comp_file *f,
				     const struct sh2000_comp_fault *why,
				     char *msg, size_t len)
{
	const struct ctab *t;
	char name[48];

	if (!msg || !len)
		return msg;
	if (!f || why->table < 0 || (unsigned int)why->table >= f->tables) {
		snprintf(msg, len, "%s: %s", f ? f->path : "?",
			 sh2000_comp_reason_name(why->reason));
		return msg;
	}
	t = &f->t[why->table];
	table_name(t, name, sizeof(name));
	snprintf(msg, len, "%s:%u: %s: %s", f->path,
		 sh2000_comp_file_line(f, why->table, why->point), name,
		 sh2000_comp_reason_name(why->reason));
	return msg;
}

int sh2000_comp_file_check(const struct sh2000_comp_file *f,
			   const struct sh2000_comp_limits *lim, char *msg,
			   size_t len)
{
	struct sh2000_comp_index ix;
	struct sh2000_comp_fault why;

	if (!f || !lim)
		return -EINVAL;
	if (sh2000_comp_parse(f->w, f->words, &ix, &why) ||
	    sh2000_comp_check(f->w, &ix, lim, &why)) {
		sh2000_comp_file_explain(f, &why, msg, len);
		return -SH2000_EPARAM;
	}
	return 0;
}

/* The file read with the card's scales and checked against the card's
 * limits: 0 and *out, or an error with the message in sh2000_last_error
 * (FILE:LINE: why when a table is at fault). Nothing is sent. */
static int read_checked(struct sh2000 *h, const char *path,
			struct sh2000_comp_file **out)
{
	struct sh2000_comp_limits lim;
	struct sh2000_comp_file *f = NULL;
	double scale[SH2000_AXES];
	char msg[512];
	unsigned int a;
	int r = 0;

	*out = NULL;
	if (!h || !path)
		return -EINVAL;
	for (a = 0; !r && a < SH2000_AXES; a++)
		r = sh2000_param_get(h, (int)a, SH2000_P_SCALE, &scale[a]);
	if (!r)
		r = sh2000_comp_limits_get(h, &lim);
	if (r < 0)
		return r;
	snprintf(msg, sizeof(msg), "%s: cannot be read", path);
	r = sh2000_comp_file_read(&f, path, scale, msg, sizeof(msg));
	if (!r)
		r = sh2000_comp_file_check(f, &lim, msg, sizeof(msg));
	if (r < 0) {
		sh2000_comp_file_free(f);
		return sh2000_fail(h, r, "%s", msg);
	}
	*out = f;
	return 0;
}

int sh2000_comp_check_file(struct sh2000 *h, const char *path)
{
	struct sh2000_comp_file *f;
	int r = read_checked(h, path, &f);

	sh2000_comp_file_free(f);
	return r;
}

int sh2000_comp_load_file(struct sh2000 *h, const char *path)
{
	struct sh2000_comp_file *f;
	struct sh2000_comp_fault why;
	char msg[512];
	int r = read_checked(h, path, &f);

	if (r < 0)
		return r;
	r = sh2000_comp_load_image(h, f->w, f->words, &why);
	if (r == -SH2000_ECMD_VALUE || r == -SH2000_ECMD_CHECKSUM)
		r = sh2000_fail(h, r, "%s (the card's check)",
				sh2000_comp_file_explain(f, &why, msg, sizeof(msg)));
	sh2000_comp_file_free(f);
	return r;
}
