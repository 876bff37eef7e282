// SPDX-License-Identifier: MIT
/*
 * What the planner's margin buys on the card's set-points: a program
 * (rs274's canonical output, `rs274 -g`, as bench/lcnc-compare/run makes
 * it) planned at the card model's limits (every axis 400 mm/s, 5000
 * mm/s^2, the default jerk) with each margin given, its records rounded to
 * the card's counts (10 nm) as the card gets them, and the card's fine
 * set-points (its four-record window through sh2000_bspline, every servo
 * cycle, unrounded: tests/planner/spcheck.h) measured against the limits.
 *
 *   bench_peaks [-a AMAX] [-j JERK] [-r] FILE.canon [MARGIN...]
 *                                   (default: 0.95 0.97 0.99 1)
 *
 * -a sets every axis' amax (mm/s^2), -j the path jerk (mm/s^3), -r the
 * raw output (no compensation), to measure the planner away from the
 * card model's limits.
 *
 * One line per margin: the planned time; each axis' peak velocity and
 * acceleration over every servo cycle (first and second differences over
 * one cycle, and the acceleration's mean over three cycles), as fractions
 * of vmax and amax; the largest step between two records as a fraction of
 * vmax times the coarse period (the card refuses a record over 1.05 of
 * that plus 2 counts: docs/protocol.md, the record checks), and when the
 * acceleration's peak comes (s from the start). A benchmark:
 * it prints figures and never fails on them.
 */
#include <ctype.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "spcheck.h"

#define CARD_VMAX	400.0	/* mm/s, the card model's defaults */
#define CARD_AMAX	5000.0	/* mm/s^2 */
#define CARD_SCALE	1e5	/* counts per mm: 10 nm */

/* What the command line changes of the card model's limits. */
struct limits {
	double amax, jerk;
	int raw;
};

struct meas {
	struct sp_check sp;
	double hist[5][SH2000_AXES];	/* the last five fine set-points */
	unsigned long long fine;
	double a3;		/* peak |mean acceleration over 3 cycles| */
	double last[SH2000_AXES];	/* the record before, mm */
	int have_last;
	double step;		/* peak record step / (vmax T) */
	unsigned long long points;
};

/* Every fine set-point: the mean of the last three second differences. */
static void each(void *ctx, const double y[SH2000_AXES])
{
	struct meas *m = ctx;
	double h = m->sp.h;
	unsigned int k;

	memmove(m->hist[0], m->hist[1], 4 * sizeof(m->hist[0]));
	memcpy(m->hist[4], y, sizeof(m->hist[4]));
	if (++m->fine < 5)
		return;
	for (k = 0; k < SH2000_AXES; k++) {
		double a = ((m->hist[4][k] - m->hist[3][k]) -
			    (m->hist[1][k] - m->hist[0][k])) / (3 * h * h);

		m->a3 = fmax(m->a3, fabs(a) / m->sp.cfg.amax[k]);
	}
}

/* A record as the card gets it (whole counts) into the card's window. */
static int sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct meas *m = ctx;
	struct sh2000_path_point q = *pt;
	unsigned int k;

	m->points++;
	for (k = 0; k < SH2000_AXES; k++) {
		q.mm[k] = pt->counts[k] / CARD_SCALE;
		if (m->have_last)
			m->step = fmax(m->step, fabs(q.mm[k] - m->last[k]) /
					   (m->sp.cfg.vmax[k] *
					    m->sp.cfg.period_s));
	}
	memcpy(m->last, q.mm, sizeof(m->last));
	m->have_last = 1;
	sp_point(&m->sp, &q);
	return 0;
}

/* The program planned at one margin, measured into *m. */
static int plan_at(const struct sh2000_program *prog,
		   const struct limits *lim, double margin, struct meas *m)
{
	struct sh2000_path_config cfg;
	struct sh2000_path *p;
	char err[256];
	int r = 0;

	sh2000_path_config_default(&cfg);
	cfg.margin = margin;
	if (lim->jerk > 0.0)
		cfg.jerk = lim->jerk;
	if (lim->raw)
		cfg.output = SH2000_OUTPUT_RAW;
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		cfg.vmax[a] = CARD_VMAX;
		cfg.amax[a] = lim->amax;
		cfg.counts_per_mm[a] = CARD_SCALE;
	}
	memset(m, 0, sizeof(*m));
	sp_init(&m->sp, &cfg, cfg.start, NULL, 0);
	m->sp.each = each;
	m->sp.each_ctx = m;
	if (sh2000_path_create(&p, &cfg, sink, m, err, sizeof(err))) {
		fprintf(stderr, "bench_peaks: %s\n", err);
		return -1;
	}
	for (size_t i = 0; i < prog->count && !r; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];

		if (b->kind == SH2000_PROG_END)
			break;
		if (b->kind == SH2000_PROG_DWELL ||
		    b->kind == SH2000_PROG_PAUSE) {
			r = sh2000_path_finish(p);
			continue;
		}
		r = sh2000_path_add_block(p, b);
	}
	if (!r)
		r = sh2000_path_finish(p);
	if (r)
		fprintf(stderr, "bench_peaks: margin %g: %s\n", margin,
			sh2000_path_error(p));
	sh2000_path_destroy(p);
	return r ? -1 : 0;
}

/* The file's canonical lines ("<count> N<number> COMMAND(...)"): rs274
 * also prints other lines ("executing") to the same stream. */
static char *canon_lines(const char *path, size_t *len)
{
	FILE *f = fopen(path, "r");
	char line[4096], *out = NULL;
	size_t n = 0;

	if (!f)
		return NULL;
	while (fgets(line, sizeof(line), f)) {
		const char *s = line;
		size_t l = strlen(line);
		char *grown;

		while (*s == ' ')
			s++;
		if (!isdigit((unsigned char)*s))
			continue;
		grown = realloc(out, n + l + 1);
		if (!grown)
			break;
		out = grown;
		memcpy(out + n, line, l + 1);
		n += l;
	}
	fclose(f);
	*len = n;
	return out;
}

int main(int argc, char **argv)
{
	static const double dflt[] = { 0.95, 0.97, 0.99, 1.0 };
	struct sh2000_prog_options po;
	struct sh2000_prog_diags d;
	struct sh2000_program prog;
	static struct meas m;
	struct limits lim = { CARD_AMAX, 0.0, 0 };
	size_t len = 0;
	char *text, *end;
	int bad = 0, n, opt;

	while ((opt = getopt(argc, argv, "a:j:r")) != -1) {
		double *x = opt == 'a' ? &lim.amax : &lim.jerk;

		if (opt == 'r') {
			lim.raw = 1;
			continue;
		}
		if (opt != 'a' && opt != 'j')
			goto usage;
		*x = strtod(optarg, &end);
		if (*end || !(*x > 0.0) || !isfinite(*x)) {
			fprintf(stderr, "bench_peaks: -%c: not a number > 0: %s\n",
				opt, optarg);
			return 2;
		}
	}
	if (optind >= argc) {
usage:
		fprintf(stderr, "usage: bench_peaks [-a AMAX] [-j JERK] [-r] FILE.canon [MARGIN...]\n");
		return 2;
	}
	argv += optind;
	argc -= optind;
	n = argc > 1 ? argc - 1 : 4;
	text = canon_lines(argv[0], &len);
	sh2000_prog_options_default(&po);
	sh2000_program_init(&prog);
	sh2000_prog_diags_init(&d);
	if (!text || sh2000_program_read(&prog, SH2000_PROG_CANON, argv[0],
					 text, len, &po, &d)) {
		sh2000_prog_diags_print(&d, stderr);
		fprintf(stderr, "bench_peaks: cannot read %s\n", argv[0]);
		return 1;
	}
	for (int i = 0; i < n; i++) {
		double margin = argc > 1 ? atof(argv[i + 1]) : dflt[i];

		if (plan_at(&prog, &lim, margin, &m)) {
			bad = 1;
			continue;
		}
		printf("margin %.3f: planned %.3f s, peak axis v/vmax %.5f, a/amax %.4f (1 servo cycle) %.4f (mean of 3), record step/(vmax T) %.5f, a peak at %.4f s\n",
		       margin, m.points * m.sp.cfg.period_s, m.sp.v_ratio,
		       m.sp.a_ratio, m.a3, m.step, m.sp.a_at * m.sp.h);
	}
	sh2000_prog_diags_free(&d);
	sh2000_program_free(&prog);
	free(text);
	return bad;
}
