/* SPDX-License-Identifier: MIT */
/*
 * Test and benchmark helpers for the planner: a sink that records points,
 * the limit check on finite differences, the card's fine interpolation
 * (through the shared sh2000_bspline) and distances to exact geometry.
 * Header-only so that tests and benchmarks share one copy.
 */
#ifndef SH2000_PLCHECK_H
#define SH2000_PLCHECK_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sh2000/bspline.h"
#include "sh2000/path.h"

struct rec {
	double (*x)[4];
	unsigned int *flags;
	size_t n, cap;
	double start[4];
	int fail_at;		/* sink returns -EIO at this index (0: never) */
};

static inline void rec_init(struct rec *r, const double start[4])
{
	memset(r, 0, sizeof(*r));
	memcpy(r->start, start, sizeof(r->start));
}

static inline void rec_free(struct rec *r)
{
	free(r->x);
	free(r->flags);
	memset(r, 0, sizeof(*r));
}

static inline int rec_sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct rec *r = ctx;

	if (r->fail_at && (size_t)r->fail_at == r->n + 1)
		return -5;
	if (r->n == r->cap) {
		r->cap = r->cap ? 2 * r->cap : 1024;
		r->x = realloc(r->x, r->cap * sizeof(*r->x));
		r->flags = realloc(r->flags, r->cap * sizeof(*r->flags));
		if (!r->x || !r->flags)
			abort();
	}
	memcpy(r->x[r->n], pt->mm, sizeof(pt->mm));
	r->flags[r->n] = pt->flags;
	r->n++;
	return 0;
}

/* The records as the card sees them: its window starts full of the start
 * point, and after every END it pads with the end point (3 pushes bring
 * the window to 4 equal points). Returns a malloc'd array, *n points. */
static inline double (*card_seq(const struct rec *r, size_t *n))[4]
{
	size_t ends = 0, i, k = 0;
	double (*x)[4];
	unsigned int j;

	for (i = 0; i < r->n; i++)
		ends += (r->flags[i] & SH2000_PATH_F_END) != 0;
	x = malloc((r->n + 3 * ends + 6) * sizeof(*x));
	for (j = 0; j < 3; j++)
		memcpy(x[k++], r->start, sizeof(x[0]));
	for (i = 0; i < r->n; i++) {
		memcpy(x[k++], r->x[i], sizeof(x[0]));
		if (r->flags[i] & SH2000_PATH_F_END)
			for (j = 0; j < 3; j++)
				memcpy(x[k++], r->x[i], sizeof(x[0]));
	}
	*n = k;
	return x;
}

/* Largest ratio of a finite-difference speed / acceleration at the coarse
 * period to the axis limit, over all axes, on the card's sequence. */
struct fd_result {
	double v_ratio, a_ratio;
	double vmax_seen, amax_seen;
	size_t v_at, a_at;	/* where, in the card's sequence */
};

static inline struct fd_result fd_check(const struct rec *r,
					const struct sh2000_path_config *c)
{
	struct fd_result res = { 0, 0, 0, 0, 0, 0 };
	double T = c->period_s;
	size_t n, i;
	double (*x)[4] = card_seq(r, &n);
	unsigned int ax;

	for (i = 1; i < n; i++) {
		for (ax = 0; ax < 4; ax++) {
			double v = fabs(x[i][ax] - x[i - 1][ax]) / T;

			if (v / c->vmax[ax] > res.v_ratio)
				res.v_at = i;
			res.v_ratio = fmax(res.v_ratio, v / c->vmax[ax]);
			res.vmax_seen = fmax(res.vmax_seen, v);
			if (i + 1 < n) {
				double a = fabs(x[i + 1][ax] - 2 * x[i][ax] +
						x[i - 1][ax]) / (T * T);

				if (a / c->amax[ax] > res.a_ratio)
					res.a_at = i;
				res.a_ratio = fmax(res.a_ratio, a / c->amax[ax]);
				res.amax_seen = fmax(res.amax_seen, a);
			}
		}
	}
	free(x);
	return res;
}

/* The card's fine interpolation of that sequence: F fine steps per period
 * through sh2000_bspline over the 4-point window. Calls fn for every fine
 * point; returns how many. */
typedef void (*fine_fn)(void *ctx, const double x[4]);

static inline size_t fine_path(const struct rec *r, unsigned int F,
			       fine_fn fn, void *ctx)
{
	size_t n, i, cnt = 0;
	double (*x)[4] = card_seq(r, &n);
	unsigned int f, ax;

	for (i = 3; i < n; i++) {
		const double *w0 = x[i - 3], *w1 = x[i - 2], *w2 = x[i - 1];
		const double *w3 = x[i];

		for (f = 1; f <= F; f++) {
			double t = (double)f / F, y[4];

			for (ax = 0; ax < 4; ax++)
				y[ax] = sh2000_bspline(w0[ax], w1[ax], w2[ax],
						       w3[ax], t);
			fn(ctx, y);
			cnt++;
		}
	}
	free(x);
	return cnt;
}

/* Finite differences on the fine points. */
struct fine_fd {
	double h;
	double prev[2][4];
	unsigned int n;
	double v_ratio, a_ratio;
	const struct sh2000_path_config *c;
};

static inline void fine_fd_fn(void *ctx, const double x[4])
{
	struct fine_fd *f = ctx;
	unsigned int ax;

	if (f->n >= 1)
		for (ax = 0; ax < 4; ax++)
			f->v_ratio = fmax(f->v_ratio, fabs(x[ax] - f->prev[1][ax]) /
					  f->h / f->c->vmax[ax]);
	if (f->n >= 2)
		for (ax = 0; ax < 4; ax++)
			f->a_ratio = fmax(f->a_ratio,
					  fabs(x[ax] - 2 * f->prev[1][ax] +
					       f->prev[0][ax]) /
					  (f->h * f->h) / f->c->amax[ax]);
	memcpy(f->prev[0], f->prev[1], sizeof(f->prev[0]));
	memcpy(f->prev[1], x, sizeof(f->prev[1]));
	f->n++;
}

/* ---- distances to exact geometry ---- */

static inline double dist_seg(const double p[4], const double a[4],
			      const double b[4])
{
	double ab = 0, ap = 0, t, d = 0;
	unsigned int ax;

	for (ax = 0; ax < 4; ax++) {
		ab += (b[ax] - a[ax]) * (b[ax] - a[ax]);
		ap += (p[ax] - a[ax]) * (b[ax] - a[ax]);
	}
	t = ab > 0 ? fmin(fmax(ap / ab, 0.0), 1.0) : 0.0;
	for (ax = 0; ax < 4; ax++) {
		double q = a[ax] + t * (b[ax] - a[ax]) - p[ax];

		d += q * q;
	}
	return sqrt(d);
}

#endif /* SH2000_PLCHECK_H */
