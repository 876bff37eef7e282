// SPDX-License-Identifier: MIT
/*
 * Planner figures, printed as a table (not a timed test):
 *  - contour error of the card's fine path against the exact geometry for
 *    a circle (R 5 mm, 300 mm/s, 2 ms coarse period, 20 fine steps) and a
 *    NURBS test curve, raw versus compensated: the fine path computed with
 *    the shared sh2000_bspline over the emitted points, and the card
 *    model's own fine set-points (through libsh2000's `sim` card);
 *  - the DDA paper's [R3] DDA on the same circle as a baseline (10 nm and 1 um);
 *  - NURBS chord error and feed fluctuation;
 *  - following error of the simulated axes on the circle, PID alone versus
 *    PID plus velocity and acceleration feed-forward;
 *  - coarse points planned per second on one core.
 * Usage: bench_planner [throughput [lines|circles|freeform]]
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dda.h"
#include "plcheck.h"

#ifdef BENCH_WITH_CARD
#include "plcard.h"
#endif

static double cpu_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* ---- geometry --------------------------------------------------------- */

#define R_CIRC 5.0
#define FEED 300.0

static const double circ_ctrl[9][4] = {
	{ 5, 0, 0, 0 }, { 5, 5, 0, 0 }, { 0, 5, 0, 0 }, { -5, 5, 0, 0 },
	{ -5, 0, 0, 0 }, { -5, -5, 0, 0 }, { 0, -5, 0, 0 }, { 5, -5, 0, 0 },
	{ 5, 0, 0, 0 },
};
static const double circ_w[9] = { 1, M_SQRT1_2, 1, M_SQRT1_2, 1, M_SQRT1_2,
				  1, M_SQRT1_2, 1 };
static const double circ_k[12] = { 0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75,
				   0.75, 1, 1, 1 };

/* the free-form test curve: cubic, 8 control points, uneven weights */
static const double ff_ctrl[8][4] = {
	{ 0, 0, 0, 0 }, { 5, 10, 0, 0 }, { 10, -5, 1, 0 }, { 15, 8, 2, 0 },
	{ 20, 0, 2, 0 }, { 22, 12, 1, 0 }, { 30, 5, 0, 0 }, { 32, 0, 0, 0 },
};
static const double ff_w[8] = { 1, 2, 0.5, 1, 3, 1, 1, 1 };
static const double ff_k[12] = { 0, 0, 0, 0, 0.2, 0.4, 0.5, 0.8, 1, 1, 1, 1 };

enum shape { CIRCLE_ARC, CIRCLE_NURBS, FREEFORM };

static const char *shape_name[] = { "circle (arc)", "circle (NURBS)",
				    "free-form NURBS" };

/* Offsets the shape to start at `o` (the card starts at 300 mm). */
static int add_shape(struct sh2000_path *p, enum shape s, const double o[4])
{
	double ctrl[9][4];
	unsigned int i, a;

	if (s == CIRCLE_ARC) {
		struct sh2000_path_arc arc;

		memset(&arc, 0, sizeof(arc));
		arc.plane = SH2000_PLANE_XY;
		memcpy(arc.end, o, sizeof(arc.end));
		arc.centre[0] = o[0] - R_CIRC;
		arc.centre[1] = o[1];
		arc.ccw = 1;
		return sh2000_path_arc(p, &arc, FEED);
	}
	if (s == CIRCLE_NURBS) {
		struct sh2000_nurbs n = { 2, 9, (const double (*)[4])ctrl,
					       circ_w, circ_k };

		for (i = 0; i < 9; i++)
			for (a = 0; a < 4; a++)
				ctrl[i][a] = circ_ctrl[i][a] + o[a] -
					     (a == 0 ? R_CIRC : 0);
		return sh2000_path_nurbs(p, &n, FEED);
	} else {
		struct sh2000_nurbs n = { 3, 8, (const double (*)[4])ctrl,
					       ff_w, ff_k };

		for (i = 0; i < 8; i++)
			for (a = 0; a < 4; a++)
				ctrl[i][a] = ff_ctrl[i][a] + o[a];
		return sh2000_path_nurbs(p, &n, FEED);
	}
}

/* Distance to the exact shape: a circle, or a dense polyline of the
 * NURBS (the planner itself, raw, 0.1 ms period, 1e-7 mm chord). */
struct exact {
	enum shape s;
	double o[4];
	double (*pts)[4];
	size_t n, hint;
};

static void exact_init(struct exact *e, enum shape s, const double o[4])
{
	memset(e, 0, sizeof(*e));
	e->s = s;
	memcpy(e->o, o, sizeof(e->o));
	if (s == FREEFORM) {
		struct sh2000_path_config c;
		struct sh2000_path *p;
		struct rec r;

		sh2000_path_config_default(&c);
		c.output = SH2000_OUTPUT_RAW;
		c.period_s = 1e-4;
		c.chord_tol = 1e-7;
		memcpy(c.start, o, sizeof(c.start));
		rec_init(&r, o);
		if (sh2000_path_create(&p, &c, rec_sink, &r, NULL, 0) ||
		    add_shape(p, s, o) || sh2000_path_finish(p))
			abort();
		sh2000_path_destroy(p);
		e->pts = r.x;	/* keeps r's array */
		e->n = r.n;
		free(r.flags);
	}
}

static double exact_dist(struct exact *e, const double x[4])
{
	if (e->s != FREEFORM)
		return fabs(hypot(x[0] - (e->o[0] - R_CIRC), x[1] - e->o[1]) -
			    R_CIRC);
	{
		double m = INFINITY;
		size_t i, lo = e->hint > 600 ? e->hint - 600 : 0;
		size_t hi = e->hint + 600 < e->n ? e->hint + 600 : e->n;

		if (e->hint == 0)
			hi = e->n;
		for (i = lo + 1; i < hi; i++) {
			double d = dist_seg(x, e->pts[i - 1], e->pts[i]);

			if (d < m) {
				m = d;
				e->hint = i;
			}
		}
		return m;
	}
}

struct err_acc {
	struct exact *e;
	double max, sum2;
	size_t n;
};

static void err_fn(void *ctx, const double x[4])
{
	struct err_acc *a = ctx;
	double d = exact_dist(a->e, x);

	a->max = fmax(a->max, d);
	a->sum2 += d * d;
	a->n++;
}

static void config(struct sh2000_path_config *c, int raw, const double o[4])
{
	sh2000_path_config_default(c);
	c->output = raw ? SH2000_OUTPUT_RAW : SH2000_OUTPUT_COMPENSATED;
	c->chord_tol = 0.01;	/* allows 300 mm/s on R 5 at 2 ms */
	memcpy(c->start, o, sizeof(c->start));
}

/* ---- through sh2000_bspline ------------------------------------------- */

static void contour_bspline(enum shape s, int raw, double *emax, double *erms,
			    struct sh2000_path_stats *st, double *vpeak)
{
	static const double o[4] = { 0, 0, 0, 0 };
	struct sh2000_path_config c;
	struct sh2000_path *p;
	struct exact ex;
	struct err_acc acc;
	struct rec r;
	struct fd_result fd;
	double oo[4];

	memcpy(oo, o, sizeof(oo));
	if (s != FREEFORM)
		oo[0] = R_CIRC;
	config(&c, raw, oo);
	rec_init(&r, oo);
	if (sh2000_path_create(&p, &c, rec_sink, &r, NULL, 0) ||
	    add_shape(p, s, oo) || sh2000_path_finish(p)) {
		fprintf(stderr, "bench_planner: %s\n", sh2000_path_error(p));
		exit(1);
	}
	sh2000_path_stats(p, st);
	exact_init(&ex, s, oo);
	memset(&acc, 0, sizeof(acc));
	acc.e = &ex;
	fine_path(&r, c.fine_steps, err_fn, &acc);
	*emax = acc.max;
	*erms = sqrt(acc.sum2 / acc.n);
	fd = fd_check(&r, &c);
	*vpeak = fd.vmax_seen;
	free(ex.pts);
	sh2000_path_destroy(p);
	rec_free(&r);
}

/* ---- DDA baseline ------------------------------------------------------ */

struct dda_acc {
	double r, scale, max, sum2;
	uint64_t n;
};

static void dda_fn(void *ctx, const int32_t pos[3], unsigned int mask)
{
	struct dda_acc *a = ctx;
	double d = fabs(hypot(pos[0], pos[1]) - a->r) / a->scale;

	(void)mask;
	a->max = fmax(a->max, d);
	a->sum2 += d * d;
	a->n++;
}

static void dda_circle(double counts_per_mm, double *emax, double *erms,
		       uint64_t *cycles)
{
	struct sh2000_dda_config cfg = { 24, 1, 1 };
	struct sh2000_dda_result res;
	int32_t R = (int32_t)lround(R_CIRC * counts_per_mm);
	int32_t c[2] = { 0, 0 }, s[2] = { R, 0 };
	struct dda_acc a = { R, counts_per_mm, 0, 0, 0 };

	if (sh2000_dda_arc(&cfg, c, s, s, 1, dda_fn, &a, &res))
		abort();
	*emax = a.max;
	*erms = sqrt(a.sum2 / a.n);
	*cycles = res.iterations;
}

/* ---- throughput --------------------------------------------------------- */

static int null_sink(void *ctx, const struct sh2000_path_point *pt)
{
	(void)pt;
	(*(uint64_t *)ctx)++;
	return 0;
}

static double throughput(int what, int raw)
{
	struct sh2000_path_config c;
	struct sh2000_path *p;
	uint64_t n = 0;
	double o[4] = { 0 }, t0, t;
	unsigned int i;

	config(&c, raw, o);
	if (what == 1)
		c.start[0] = R_CIRC;
	if (sh2000_path_create(&p, &c, null_sink, &n, NULL, 0))
		abort();
	t0 = cpu_s();
	for (i = 0; i < (what == 0 ? 20000u : 200u); i++) {
		int r;

		if (what == 0) {
			double e[4] = { 0.5 * (i + 1), (i & 1) ? 0.3 : 0.0,
					0.01 * i, 0 };

			r = sh2000_path_line(p, e, FEED);
		} else if (what == 1) {
			double oo[4] = { R_CIRC, 0, 0, 0 };

			r = add_shape(p, CIRCLE_NURBS, oo);
		} else {
			double oo[4] = { 0, 0, 0, 0 };

			oo[0] = 0;
			r = i % 2 ? sh2000_path_line(p, oo, FEED)
				  : add_shape(p, FREEFORM, oo);
		}
		if (r)
			abort();
	}
	if (sh2000_path_finish(p))
		abort();
	t = cpu_s() - t0;
	sh2000_path_destroy(p);
	return n / t;
}

/* ---- through the card model -------------------------------------------- */

#ifdef BENCH_WITH_CARD
struct card_acc {
	struct exact *ex;
	double emax, esum2, fmax, fsum2;
	uint64_t n;
	double prev[2][4];
	double vf, af, h;
};

static void card_fn(void *ctx, const double x[4], const double act[4])
{
	struct card_acc *c = ctx;
	double d = exact_dist(c->ex, x);
	double fe = hypot(x[0] - act[0], x[1] - act[1]);
	unsigned int a;

	c->emax = fmax(c->emax, d);
	c->esum2 += d * d;
	c->fmax = fmax(c->fmax, fe);
	c->fsum2 += fe * fe;
	if (c->n >= 2)
		for (a = 0; a < 2; a++) {
			c->vf = fmax(c->vf, fabs(x[a] - c->prev[1][a]) / c->h);
			c->af = fmax(c->af, fabs(x[a] - 2 * c->prev[1][a] +
						 c->prev[0][a]) / (c->h * c->h));
		}
	memcpy(c->prev[0], c->prev[1], sizeof(c->prev[0]));
	memcpy(c->prev[1], x, sizeof(c->prev[1]));
	c->n++;
}

/* One shape through the `sim` card; 0 or -1 (then the card part is left
 * out). */
/* The card's following-error limit in these runs, mm. */
#define BENCH_FERR_LIMIT_MM 1.0

static int card_contour(enum shape s, int raw, int ff, double *emax,
			double *erms, double *ferr_max, double *ferr_rms,
			double *vfine, double *afine)
{
	static struct plcard pc;
	struct sh2000_path_config c;
	struct sh2000_path *p;
	struct card_acc acc;
	struct exact ex;
	double o[4];

	sh2000_path_config_default(&c);
	if (plcard_open(&pc, c.vmax, c.amax, ff, o)) {
		fprintf(stderr, "bench_planner: card: %s\n", pc.msg);
		return -1;
	}
	/* the following error is what the PID-only runs measure: some
	 * 0.2 mm on the circle, the card's default limit (its y tripped) */
	for (unsigned int a = 0; a < 4; a++)
		if (sh2000_param_set(pc.h, (int)a, SH2000_P_FERR_LIMIT,
				     BENCH_FERR_LIMIT_MM)) {
			fprintf(stderr, "bench_planner: card: %s\n",
				sh2000_last_error(pc.h));
			plcard_close(&pc);
			return -1;
		}
	config(&c, raw, o);
	exact_init(&ex, s, o);
	memset(&acc, 0, sizeof(acc));
	acc.ex = &ex;
	acc.h = c.period_s / c.fine_steps;
	pc.fn = card_fn;
	pc.ctx = &acc;
	if (sh2000_path_create(&p, &c, plcard_sink, &pc, NULL, 0))
		return -1;
	pc.record = 1;
	if (add_shape(p, s, o) || sh2000_path_finish(p) || plcard_idle(&pc)) {
		fprintf(stderr, "bench_planner: card run: %s / %s\n",
			sh2000_path_error(p), pc.msg);
		return -1;
	}
	pc.record = 0;
	*emax = acc.emax;
	*erms = sqrt(acc.esum2 / acc.n);
	*ferr_max = acc.fmax;
	*ferr_rms = sqrt(acc.fsum2 / acc.n);
	*vfine = acc.vf;
	*afine = acc.af;
	sh2000_path_destroy(p);
	plcard_close(&pc);
	free(ex.pts);
	return 0;
}
#endif

/* The throughput table; only the cases whose name is `only` (lines,
 * circles, freeform) when given: one case alone is what a profiler wants. */
static void print_throughput(const char *only)
{
	static const char *const name[] = { "lines", "circles", "freeform" };
	static const char *const what[] = {
		"20000 lines of 0.5 mm, 300 mm/s",
		"200 NURBS circles R 5, 300 mm/s",
		"100 free-form NURBS + lines",
	};
	int raw, k;

	printf("Throughput (CPU time of this thread, sink discards the points):\n");
	printf("%-40s %-12s %16s\n", "program", "output", "points/s");
	for (raw = 1; raw >= 0; raw--)
		for (k = 0; k < 3; k++)
			if (!only || !strcmp(only, name[k]))
				printf("%-40s %-12s %16.0f\n", what[k],
				       raw ? "raw" : "compensated",
				       throughput(k, raw));
	printf("(real time needs %d points/s at a 2 ms period)\n", 500);
}

/* bench_planner [throughput [lines|circles|freeform]]: everything, or the
 * throughput table alone, or one of its cases */
int main(int argc, char **argv)
{
	struct sh2000_path_stats st;
	enum shape s;
	int raw;

	if (argc > 1 && !strcmp(argv[1], "throughput")) {
		print_throughput(argc > 2 ? argv[2] : NULL);
		return 0;
	}

	printf("Planner benchmark: R %.0f mm circle at %.0f mm/s, 2 ms coarse period, 20 fine steps,\n"
	       "defaults otherwise (vmax 500 mm/s, amax 50000 mm/s^2, jerk 5e6 mm/s^3, S-curve),\n"
	       "chord tolerance 0.01 mm. Contour error = distance of each fine point to the exact curve.\n\n",
	       R_CIRC, FEED);
	printf("%-18s %-12s %14s %14s %12s %14s %14s %14s %10s\n", "shape",
	       "output", "max err (um)", "rms err (um)", "peak v mm/s",
	       "chord err (um)", "feed fluct", "predict only", "corr/step");
	for (s = CIRCLE_ARC; s <= FREEFORM; s++) {
		for (raw = 1; raw >= 0; raw--) {
			double emax, erms, vp;

			contour_bspline(s, raw, &emax, &erms, &st, &vp);
			printf("%-18s %-12s %14.4f %14.4f %12.1f", shape_name[s],
			       raw ? "raw" : "compensated", emax * 1e3,
			       erms * 1e3, vp);
			if (s != CIRCLE_ARC)
				printf(" %14.3f %14.2g %14.2g %10.2f\n",
				       st.nurbs_chord_error * 1e3,
				       st.nurbs_feed_fluctuation,
				       st.nurbs_feed_fluctuation_predicted,
				       (double)st.nurbs_corrections /
				       st.nurbs_steps);
			else
				printf(" %14s %14s %14s %10s\n", "-", "-", "-", "-");
		}
	}
	printf("(fine path: sh2000_bspline over the emitted points, the card's window and END padding;\n"
	       " chord err: largest sagitta between consecutive points; feed fluct: largest |chord - planned\n"
	       " step| / step, with the corrector and with the NURBS interpolator paper's [R2] prediction alone; corr/step: Newton\n"
	       " corrections per step)\n\n");

	printf("DDA baseline (the DDA paper [R3], 24-bit, half-loading, normalised), the same circle:\n");
	printf("%-18s %14s %14s %14s\n", "resolution", "max err (um)",
	       "rms err (um)", "cycles");
	{
		static const double res[] = { 100000.0, 1000.0 };
		unsigned int i;

		for (i = 0; i < 2; i++) {
			double emax, erms;
			uint64_t cyc;

			dda_circle(res[i], &emax, &erms, &cyc);
			printf("%-18s %14.4f %14.4f %14llu\n",
			       i ? "1 um" : "10 nm", emax * 1e3, erms * 1e3,
			       (unsigned long long)cyc);
		}
	}
	printf("\n");

#ifdef BENCH_WITH_CARD
	printf("Through the card model (libsh2000 `sim`: protocol, firmware fine interpolation, PID, plant):\n");
	printf("%-18s %-12s %-8s %14s %14s %14s %14s %12s %14s\n", "shape",
	       "output", "servo", "cmd max (um)", "cmd rms (um)",
	       "ferr max (um)", "ferr rms (um)", "fine v mm/s",
	       "fine a mm/s^2");
	for (s = CIRCLE_ARC; s <= FREEFORM; s++) {
		for (raw = 1; raw >= 0; raw--) {
			int ff;

			for (ff = 0; ff <= 1; ff++) {
				double emax, erms, fm, fr, vf, af;

				if (s != CIRCLE_ARC && ff == 0)
					continue;
				if (card_contour(s, raw, ff, &emax, &erms, &fm,
						 &fr, &vf, &af))
					goto card_done;
				printf("%-18s %-12s %-8s %14.4f %14.4f %14.2f %14.2f %12.1f %14.0f\n",
				       shape_name[s],
				       raw ? "raw" : "compensated",
				       ff ? "PID+FF" : "PID", emax * 1e3,
				       erms * 1e3, fm * 1e3, fr * 1e3, vf, af);
			}
		}
	}
	printf("(cmd: the card's fine set-points against the exact curve; ferr: set-point minus encoder, XY)\n\n");
card_done:
#else
	printf("Through the card model: not built (needs libsh2000).\n\n");
#endif

	print_throughput(NULL);
	return 0;
}
