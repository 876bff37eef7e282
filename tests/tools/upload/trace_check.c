// SPDX-License-Identifier: MIT
/*
 * Measures an sh2000-upload trace against known geometry, for the black-box
 * tests (upload_tests.sh). The trace is split into motion segments: runs of
 * rows where the XY set-point moves more than 0.1 um within 50 rows, rests
 * shorter than 20 ms merged. Prints key=value lines; the script judges.
 *
 *   trace_check FILE segments
 *   trace_check FILE circle SEG CX CY R     radius deviation of cmd and act
 *   trace_check FILE poly SEG X,Y X,Y ...   distance from a polyline
 *   trace_check FILE end                    the last row
 *   trace_check FILE header                 1 if the header is exact
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define COLS 9
#define WIN 50
#define MOVE_MM 1e-4
#define GAP_ROWS 200
#define MIN_ROWS 20

static const char header[] = "t,cmd_x,act_x,cmd_y,act_y,cmd_z,act_z,cmd_a,act_a";

struct row { double v[COLS]; };

static struct row *rows;
static size_t nrows;
static size_t seg_a[4096], seg_b[4096], nseg;

static int load(const char *path, int *hdr_ok)
{
	FILE *f = fopen(path, "r");
	char line[1024];
	size_t cap = 0;

	if (!f) {
		perror(path);
		return -1;
	}
	if (!fgets(line, sizeof(line), f)) {
		fclose(f);
		*hdr_ok = 0;
		return 0;
	}
	line[strcspn(line, "\r\n")] = 0;
	*hdr_ok = strcmp(line, header) == 0;
	while (fgets(line, sizeof(line), f)) {
		struct row r;
		char *p = line, *e;
		int c;

		for (c = 0; c < COLS; c++) {
			r.v[c] = strtod(p, &e);
			if (e == p) {
				fprintf(stderr, "%s: row %zu: bad field %d\n",
					path, nrows + 2, c);
				fclose(f);
				return -1;
			}
			p = *e == ',' ? e + 1 : e;
		}
		if (nrows == cap) {
			cap = cap ? cap * 2 : 4096;
			rows = realloc(rows, cap * sizeof(*rows));
			if (!rows)
				abort();
		}
		rows[nrows++] = r;
	}
	fclose(f);
	return 0;
}

static double dxy(size_t i, size_t j)
{
	return hypot(rows[i].v[1] - rows[j].v[1], rows[i].v[3] - rows[j].v[3]);
}

static void segment(void)
{
	char *mv = calloc(nrows ? nrows : 1, 1);
	size_t i, a;

	for (i = 0; i < nrows; i++)
		mv[i] = (i + WIN < nrows && dxy(i, i + WIN) > MOVE_MM) ||
			(i >= WIN && dxy(i, i - WIN) > MOVE_MM);
	for (i = 0; i < nrows;) {
		if (!mv[i]) {
			i++;
			continue;
		}
		a = i;
		while (i < nrows && mv[i])
			i++;
		if (nseg && a - seg_b[nseg - 1] < GAP_ROWS) {
			seg_b[nseg - 1] = i;
		} else if (nseg < 4096) {
			seg_a[nseg] = a;
			seg_b[nseg] = i;
			nseg++;
		}
	}
	/* drop blips */
	for (i = a = 0; i < nseg; i++)
		if (seg_b[i] - seg_a[i] >= MIN_ROWS) {
			seg_a[a] = seg_a[i];
			seg_b[a] = seg_b[i];
			a++;
		}
	nseg = a;
	free(mv);
}

static double dist_seg(double px, double py, const double *s)
{
	double dx = s[2] - s[0], dy = s[3] - s[1];
	double t = ((px - s[0]) * dx + (py - s[1]) * dy) / (dx * dx + dy * dy);

	if (t < 0)
		t = 0;
	if (t > 1)
		t = 1;
	return hypot(px - s[0] - t * dx, py - s[1] - t * dy);
}

static int get_seg(const char *s, size_t *a, size_t *b)
{
	long k = strtol(s, NULL, 10);

	if (k < 1 || (size_t)k > nseg) {
		fprintf(stderr, "segment %ld of %zu does not exist\n", k, nseg);
		return -1;
	}
	*a = seg_a[k - 1];
	*b = seg_b[k - 1];
	return 0;
}

int main(int argc, char **argv)
{
	int hdr_ok = 0;
	size_t i, a, b;

	if (argc < 3) {
		fprintf(stderr, "usage: trace_check FILE segments|circle|poly|end|header ...\n");
		return 2;
	}
	if (load(argv[1], &hdr_ok))
		return 1;
	segment();
	if (!strcmp(argv[2], "header")) {
		printf("header_ok=%d\nrows=%zu\n", hdr_ok, nrows);
	} else if (!strcmp(argv[2], "segments")) {
		printf("segments=%zu\n", nseg);
		for (i = 0; i < nseg; i++)
			printf("segment%zu=%zu..%zu\n", i + 1, seg_a[i], seg_b[i]);
	} else if (!strcmp(argv[2], "circle") && argc == 7) {
		double cx = atof(argv[4]), cy = atof(argv[5]), r = atof(argv[6]);
		double mc = 0, ma = 0;

		if (get_seg(argv[3], &a, &b))
			return 1;
		for (i = a; i < b; i++) {
			double ec = fabs(hypot(rows[i].v[1] - cx, rows[i].v[3] - cy) - r);
			double ea = fabs(hypot(rows[i].v[2] - cx, rows[i].v[4] - cy) - r);

			mc = ec > mc ? ec : mc;
			ma = ea > ma ? ea : ma;
		}
		printf("rows=%zu\ncmd_dev_um=%.4f\nact_dev_um=%.4f\n", b - a,
		       mc * 1e3, ma * 1e3);
	} else if (!strcmp(argv[2], "poly") && argc >= 6) {
		double pts[64][2], mc = 0, ma = 0;
		int n = 0, k;

		if (get_seg(argv[3], &a, &b))
			return 1;
		for (k = 4; k < argc && n < 64; k++, n++)
			if (sscanf(argv[k], "%lf,%lf", &pts[n][0], &pts[n][1]) != 2)
				return 2;
		for (i = a; i < b; i++) {
			double dc = INFINITY, da = INFINITY;

			for (k = 0; k + 1 < n; k++) {
				double s[4] = { pts[k][0], pts[k][1],
						pts[k + 1][0], pts[k + 1][1] };
				double c = dist_seg(rows[i].v[1], rows[i].v[3], s);
				double t = dist_seg(rows[i].v[2], rows[i].v[4], s);

				dc = c < dc ? c : dc;
				da = t < da ? t : da;
			}
			mc = dc > mc ? dc : mc;
			ma = da > ma ? da : ma;
		}
		printf("rows=%zu\ncmd_dev_um=%.4f\nact_dev_um=%.4f\n", b - a,
		       mc * 1e3, ma * 1e3);
	} else if (!strcmp(argv[2], "end")) {
		if (!nrows) {
			printf("rows=0\n");
			return 0;
		}
		printf("rows=%zu\n", nrows);
		printf("cmd=%.6f,%.6f,%.6f,%.6f\n", rows[nrows - 1].v[1],
		       rows[nrows - 1].v[3], rows[nrows - 1].v[5],
		       rows[nrows - 1].v[7]);
		printf("act=%.6f,%.6f,%.6f,%.6f\n", rows[nrows - 1].v[2],
		       rows[nrows - 1].v[4], rows[nrows - 1].v[6],
		       rows[nrows - 1].v[8]);
	} else {
		fprintf(stderr, "trace_check: bad arguments\n");
		return 2;
	}
	free(rows);
	return 0;
}
