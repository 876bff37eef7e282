// SPDX-License-Identifier: MIT
/*
 * A table made from a laser system's CSV, checked before it is written by
 * the library that `sh2000ctl comp load` uses, with the card's scales and
 * limits: sh2000_comp_file_read (the image's rules: positions strictly
 * increasing in the card's counts, finite corrections) and
 * sh2000_comp_file_check (a slope, bend or size the axis can follow). The
 * rules stay the library's alone; this file only turns the line its
 * message names in the table file back into the CSV's row. A table the
 * card takes is judged against the card's soft limits too
 * (sh2000_comp_reach_file()): a warning where it moves the tool past one.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "calib.h"

/* cal_tables_write of one curve: its comment, the table's line, then one
 * line a point, the first at this line. */
#define FIRST_POINT_LINE	3u

/* The CSV row of the table's point k: the table has one point more
 * before the first row and after the last, each made from the step next
 * to it, so a fault there is that step's second row. lo: the first row a
 * fault may name (1 for the positions' order, which a step breaks). */
static unsigned int row_of(unsigned int k, unsigned int rows, unsigned int lo)
{
	unsigned int r = k ? k - 1 : 0;

	if (r < lo)
		r = lo;
	return r < rows ? r : rows - 1;
}

/* "TMP:LINE: why" from the library into "CSV:ROWLINE: why". */
static void name_row(const char *lib, const char *tmp, const unsigned int *lines,
		     unsigned int rows, unsigned int lo, const char *csv,
		     char *msg, size_t len)
{
	size_t n = strlen(tmp);
	unsigned int line;
	int used = 0;

	if (strncmp(lib, tmp, n) || lib[n] != ':' ||
	    sscanf(lib + n + 1, "%u: %n", &line, &used) != 1 || !used) {
		snprintf(msg, len, "%s: %s", csv, lib);
		return;
	}
	if (line < FIRST_POINT_LINE) {
		snprintf(msg, len, "%s: %s", csv, lib + n + 1 + used);
		return;
	}
	snprintf(msg, len, "%s:%u: %s", csv,
		 lines[row_of(line - FIRST_POINT_LINE, rows, lo)],
		 lib + n + 1 + used);
}

static int card_limits(struct sh2000 *h, double scale[SH2000_AXES],
		       struct sh2000_comp_limits *lim)
{
	unsigned int a;
	int r = 0;

	for (a = 0; !r && a < SH2000_AXES; a++)
		r = sh2000_param_get(h, (int)a, SH2000_P_SCALE, &scale[a]);
	return r ? r : sh2000_comp_limits_get(h, lim);
}

/* Where the table moves the tool past the card's soft limits (the card
 * judges them on nominal positions, then adds the correction): the
 * library's judgement and words, handed to warn; the table is still
 * written. A failure to judge is no fault of the table: nothing said. */
static void warn_reach(struct sh2000 *h, const char *tmp,
		       void (*warn)(const char *words))
{
	struct sh2000_comp_reach reach[SH2000_AXES];
	struct sh2000_comp_window win;
	char words[512];

	if (!warn || sh2000_comp_reach_file(h, tmp, &win, reach) <= 0)
		return;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		for (unsigned int side = 0; side < 2u; side++)
			if (sh2000_comp_reach_warning(&win, reach, a, side, words,
						      sizeof(words)) > 0)
				warn(words);
}

int cal_csv_check(const struct cal_tables *t, const unsigned int *lines,
		  unsigned int rows, const char *csv, struct sh2000 *h,
		  void (*warn)(const char *words), char *msg, size_t len)
{
	char tmp[] = "/tmp/sh2000-comp-csv-XXXXXX", why[512];
	struct sh2000_comp_file *f = NULL;
	struct sh2000_comp_limits lim;
	double scale[SH2000_AXES];
	int fd, r, lo = 1;

	r = card_limits(h, scale, &lim);
	if (r < 0) {
		snprintf(msg, len, "%s", sh2000_last_error(h));
		return r;
	}
	fd = mkstemp(tmp);
	if (fd < 0) {
		snprintf(msg, len, "%s: %s", tmp, strerror(errno));
		return -errno;
	}
	close(fd);
	r = cal_tables_save(t, tmp, csv);
	if (!r)
		r = sh2000_comp_file_read(&f, tmp, scale, why, sizeof(why));
	if (!r) {
		lo = 0;
		r = sh2000_comp_file_check(f, &lim, why, sizeof(why));
	}
	if (!r)
		warn_reach(h, tmp, warn);
	unlink(tmp);
	sh2000_comp_file_free(f);
	if (r == -SH2000_EPARAM)
		name_row(why, tmp, lines, rows, (unsigned int)lo, csv, msg, len);
	else if (r < 0)
		snprintf(msg, len, "%s: %s", csv, sh2000_strerror(r));
	return r;
}
