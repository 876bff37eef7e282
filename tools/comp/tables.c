// SPDX-License-Identifier: MIT
/*
 * The calibration's tables as a table file (docs/compensation.md "The
 * file"), and a laser system's CSV read into one curve.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "calib.h"

static void write_line(FILE *f, const char *head, const struct cal_line *l)
{
	unsigned int i;

	if (!l->n)
		return;
	fprintf(f, "%s\n", head);
	for (i = 0; i < l->n; i++)
		fprintf(f, "%.4f %.9f\n", l->pos[i], l->corr[i]);
}

int cal_tables_write(const struct cal_tables *t, FILE *f, const char *comment)
{
	char head[32];
	unsigned int a, i, j;

	fprintf(f, "# SH-2000 compensation tables (mm): %s\n", comment ? comment : "");
	for (a = 0; a < SH2000_AXES; a++) {
		snprintf(head, sizeof(head), "pitch %c", SH2000_AXIS_LETTERS[a]);
		write_line(f, head, &t->pitch[a]);
	}
	write_line(f, "cross Y X", &t->cross_yx);
	write_line(f, "cross X Y", &t->cross_xy);
	if (t->square_xy != 0.0)
		fprintf(f, "square X Y %.9g\n", t->square_xy);
	if (t->gn1 && t->gn2) {
		fprintf(f, "grid Z X Y %.4f %.4f %u %.4f %.4f %u\n", t->gu0,
			t->gdu, t->gn1, t->gv0, t->gdv, t->gn2);
		for (j = 0; j < t->gn2; j++)
			for (i = 0; i < t->gn1; i++)
				fprintf(f, "%.9f%c", t->grid[j * t->gn1 + i],
					i + 1 == t->gn1 ? '\n' : ' ');
	}
	return ferror(f) ? -EIO : 0;
}

int cal_tables_save(const struct cal_tables *t, const char *path,
		    const char *comment)
{
	FILE *f = fopen(path, "w");
	int r;

	if (!f)
		return -errno;
	r = cal_tables_write(t, f, comment);
	if (fclose(f) && !r)
		r = -errno;
	return r;
}

/* Corrections relative to the first row, and one point more beyond each
 * end (the card's tables have slope 0 at their ends). */
static void finish_csv(struct cal_line *l)
{
	unsigned int i, n = l->n;
	double c0 = l->corr[0], h0, h1;

	for (i = 0; i < n; i++)
		l->corr[i] -= c0;
	h0 = l->pos[1] - l->pos[0];
	h1 = l->pos[n - 1] - l->pos[n - 2];
	memmove(&l->pos[1], &l->pos[0], n * sizeof(l->pos[0]));
	memmove(&l->corr[1], &l->corr[0], n * sizeof(l->corr[0]));
	l->pos[0] = l->pos[1] - h0;
	l->corr[0] = l->corr[1];
	l->pos[n + 1] = l->pos[n] + h1;
	l->corr[n + 1] = l->corr[n];
	l->n = n + 2;
}

/* A row's two numbers, each whole (no unit or other text stuck to it),
 * finite, separated by commas, semicolons or blanks, nothing after them:
 * 2; 0 when the row does not start with a number (a header); -1 else. */
static int csv_row(const char *s, double v[2])
{
	unsigned int k;
	char *end;

	for (k = 0; k < 2; k++) {
		while (k && *s && strchr(" \t,;", *s))
			s++;
		v[k] = strtod(s, &end);
		if (end == s)
			return k ? -1 : 0;
		if (!isfinite(v[k]) || (*end && !strchr(" \t,;\r\n", *end)))
			return -1;
		s = end;
	}
	while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
		s++;
	return *s ? -1 : 2;
}

/* One row: its point, or "FILE:LINE: why". */
static int csv_point(struct cal_line *out, unsigned int *lines, int cross,
		     const char *s, const char *path, unsigned int line,
		     int *header, char *msg, size_t len)
{
	double v[2];
	int k = csv_row(s, v);

	if (k == 0 && *header) {
		*header = 0;	/* the first row names the columns */
		return 0;
	}
	*header = 0;
	if (k != 2) {
		snprintf(msg, len, "%s:%u: want: nominal,%s (two numbers in mm)",
			 path, line, cross ? "deviation" : "measured");
		return -1;
	}
	if (out->n + 3 > CAL_MAX_POINTS) {
		snprintf(msg, len, "%s:%u: more than %u points", path, line,
			 CAL_MAX_POINTS - 2);
		return -1;
	}
	if (lines)
		lines[out->n] = line;
	out->pos[out->n] = v[0];
	out->corr[out->n++] = cross ? -v[1] : v[0] - v[1];
	return 0;
}

int cal_from_csv(struct cal_line *out, unsigned int *lines, const char *path,
		 int cross, char *msg, size_t len)
{
	char buf[512];
	unsigned int line = 0;
	int header = 1, r = 0;
	FILE *f = fopen(path, "r");

	out->n = 0;
	if (!f) {
		int e = errno;

		snprintf(msg, len, "%s: cannot read: %s", path, strerror(e));
		return -e;
	}
	while (!r && fgets(buf, sizeof(buf), f)) {
		char *s = buf;

		line++;
		while (*s == ' ' || *s == '\t')
			s++;
		if (*s == '#' || *s == '\n' || *s == '\r' || !*s)
			continue;
		r = csv_point(out, lines, cross, s, path, line, &header, msg, len);
	}
	fclose(f);
	if (!r && out->n < 2) {
		snprintf(msg, len, "%s:%u: %u point%s: a table wants 2 or more",
			 path, line, out->n, out->n == 1 ? "" : "s");
		r = -1;
	}
	if (!r)
		finish_csv(out);
	return r;
}
