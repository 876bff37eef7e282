// SPDX-License-Identifier: MIT
/*
 * B-spline compensation as a stream: control points P with
 * P[i-1] + 4 P[i] + P[i+1] = 6 Q[i], so that the card's uniform cubic
 * B-spline, whose value at a knot is (P[i-1] + 4 P[i] + P[i+1]) / 6, passes
 * through every planned point Q.
 *
 * The inverse of the tridiagonal operator is the symmetric filter
 * P[n] = sqrt(3) * sum_k (-r)^|k| Q[n+k], r = 2 - sqrt(3) ~ 0.268: a
 * point's influence decays as r^k, so a half-window of 12 points leaves a
 * relative error below 1e-7 (the truncated weights are renormalised so a
 * constant stays exact).
 *
 * A motion from rest to rest is Q extended by its start point X before and
 * its end point E after. The card starts from a window of X (start from
 * rest: [X, X, X, P1]) and pads with E after END. So the filter runs over
 * the extended sequence: the control points before the first planned point
 * (they differ from X by less than a micrometre; those that differ by less
 * than COMP_EPS are left out) and after the last one are emitted too, and
 * the last record is E exactly. Both ends are then exact to COMP_EPS.
 *
 * Interpolation rings: through the points of a stop the spline overshoots
 * the end point (about J T^3 / 70 for an S-curve, 2.4 um for a trapezoid
 * that stops in two periods) and before a start it backs off the start
 * point. Where the window is straight and runs one way (a move from rest
 * along a line, the approach to a stop along one), the control points are
 * kept from passing the rest point and from turning back along the line:
 * a cubic B-spline stays within the hull of its control points and is
 * monotone where they are, so the card's set-points then never pass the
 * end point nor go backwards. The points moved are those the ringing
 * moved, by as much.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "planner.h"

/* mm: a control point this close to the rest point is the rest point */
#define COMP_EPS 1e-7

struct sh2000_bscomp {
	unsigned int half, naxes, len;	/* len = 2 half + 1 */
	double *w;		/* weights by window position 0..len-1 */
	/* ring of len points, each stored twice (at i and i + len) so that
	 * the window from the oldest is contiguous: no modulo per tap */
	double *q;
	unsigned int head;	/* oldest */
	double *x0, *last;	/* rest point at start, last Q */
	double *u;		/* direction of a straight window */
	int emitting;		/* a point has left: no more skipping */
	/* control points still kept from backing off x0, and how far along
	 * u the last one got */
	unsigned int guard;
	double guard_s;
	/* flush */
	int flushing;
	double *tail;		/* up to len points */
	unsigned int ntail, itail;
};

int sh2000_bscomp_create(struct sh2000_bscomp **out, unsigned int half,
			 unsigned int naxes)
{
	struct sh2000_bscomp *c;
	double r = 2.0 - sqrt(3.0), sum = 0.0, w = sqrt(3.0);
	unsigned int k;

	*out = NULL;
	if (half < 1 || half > 64 || naxes < 1 || naxes > 16)
		return -EINVAL;
	c = calloc(1, sizeof(*c));
	if (!c)
		return -ENOMEM;
	c->half = half;
	c->naxes = naxes;
	c->len = 2 * half + 1;
	c->w = calloc(c->len, sizeof(double));
	c->q = calloc((size_t)2 * c->len * naxes, sizeof(double));
	c->x0 = calloc(naxes, sizeof(double));
	c->last = calloc(naxes, sizeof(double));
	c->tail = calloc((size_t)c->len * naxes, sizeof(double));
	c->u = calloc(naxes, sizeof(double));
	if (!c->w || !c->q || !c->x0 || !c->last || !c->tail || !c->u) {
		sh2000_bscomp_destroy(c);
		return -ENOMEM;
	}
	for (k = 0; k <= half; k++) {
		c->w[half + k] = w;
		sum += k ? 2.0 * w : w;
		w *= -r;
	}
	for (k = 0; k <= half; k++) {
		c->w[half + k] /= sum;
		c->w[half - k] = c->w[half + k];
	}
	*out = c;
	return 0;
}

void sh2000_bscomp_destroy(struct sh2000_bscomp *c)
{
	if (!c)
		return;
	free(c->w);
	free(c->q);
	free(c->x0);
	free(c->last);
	free(c->tail);
	free(c->u);
	free(c);
}

void sh2000_bscomp_start(struct sh2000_bscomp *c, const double *x)
{
	unsigned int i;

	for (i = 0; i < 2 * c->len; i++)
		memcpy(c->q + (size_t)i * c->naxes, x, c->naxes * sizeof(double));
	memcpy(c->x0, x, c->naxes * sizeof(double));
	memcpy(c->last, x, c->naxes * sizeof(double));
	c->head = 0;
	c->emitting = 0;
	c->flushing = 0;
	c->ntail = c->itail = 0;
	c->guard = c->len;
	c->guard_s = 0.0;
}

/* P at the centre of the window: the sum over the window from the oldest
 * point, in that order on every axis (the same sums as ever). */
static void centre(const struct sh2000_bscomp *c, double *p)
{
	const double *q = c->q + (size_t)c->head * c->naxes;
	unsigned int ax, k;

	for (ax = 0; ax < c->naxes; ax++) {
		double s = 0.0;

		for (k = 0; k < c->len; k++)
			s += c->w[k] * q[(size_t)k * c->naxes + ax];
		p[ax] = s;
	}
}

static void shift_in(struct sh2000_bscomp *c, const double *q)
{
	size_t n = c->naxes * sizeof(double);

	memcpy(c->q + (size_t)c->head * c->naxes, q, n);
	memcpy(c->q + (size_t)(c->head + c->len) * c->naxes, q, n);
	c->head = (c->head + 1) % c->len;
}

static double dist_inf(const struct sh2000_bscomp *c, const double *a,
		       const double *b)
{
	double m = 0.0;
	unsigned int ax;

	for (ax = 0; ax < c->naxes; ax++)
		m = fmax(m, fabs(a[ax] - b[ax]));
	return m;
}

/* Whether the window is straight and runs one way: every point within
 * COMP_EPS of the line from its oldest to its newest point and no point
 * behind the one before along it. Sets c->u to the direction. */
static int straight(struct sh2000_bscomp *c)
{
	const double *q = c->q + (size_t)c->head * c->naxes;
	const double *o = q, *e = q + (size_t)(c->len - 1) * c->naxes;
	double d = 0.0, prev = 0.0;
	unsigned int ax, k;

	for (ax = 0; ax < c->naxes; ax++)
		d += (e[ax] - o[ax]) * (e[ax] - o[ax]);
	d = sqrt(d);
	if (d <= COMP_EPS)
		return 0;
	for (ax = 0; ax < c->naxes; ax++)
		c->u[ax] = (e[ax] - o[ax]) / d;
	for (k = 1; k < c->len; k++) {
		const double *x = q + (size_t)k * c->naxes;
		double s = 0.0, perp = 0.0;

		for (ax = 0; ax < c->naxes; ax++)
			s += (x[ax] - o[ax]) * c->u[ax];
		for (ax = 0; ax < c->naxes; ax++) {
			double t = x[ax] - o[ax] - s * c->u[ax];

			perp += t * t;
		}
		if (perp > COMP_EPS * COMP_EPS || s < prev - COMP_EPS)
			return 0;
		prev = s;
	}
	return 1;
}

/* Moves p along c->u so that its distance along u from o is at least lo
 * (lo_set) and at most hi (hi_set); returns that distance. */
static double clamp_along(const struct sh2000_bscomp *c, double *p,
			  const double *o, double lo, int lo_set, double hi,
			  int hi_set)
{
	double s = 0.0, t;
	unsigned int ax;

	for (ax = 0; ax < c->naxes; ax++)
		s += (p[ax] - o[ax]) * c->u[ax];
	t = lo_set && s < lo ? lo : hi_set && s > hi ? hi : s;
	for (ax = 0; ax < c->naxes && t != s; ax++)
		p[ax] += (t - s) * c->u[ax];
	return t;
}

/* A move from rest: while the window is straight and runs one way, the
 * control points never back off x0 nor turn back; the start's ringing has
 * died away after a window's length of them. */
static void guard_start(struct sh2000_bscomp *c, double *p)
{
	if (!c->guard)
		return;
	if (!straight(c)) {
		/* still at rest, or a curve: nothing to keep, or no line to
		 * keep to */
		if (c->emitting || dist_inf(c, p, c->x0) > COMP_EPS)
			c->guard = 0;
		return;
	}
	c->guard_s = clamp_along(c, p, c->x0, c->guard_s, 1, 0.0, 0);
	if (c->emitting || dist_inf(c, p, c->x0) > COMP_EPS)
		c->guard--;
}

int sh2000_bscomp_push(struct sh2000_bscomp *c, const double *q, double *p)
{
	shift_in(c, q);
	memcpy(c->last, q, c->naxes * sizeof(double));
	centre(c, p);
	guard_start(c, p);
	if (!c->emitting) {
		if (dist_inf(c, p, c->x0) <= COMP_EPS)
			return 0;
		c->emitting = 1;
	}
	return 1;
}

int sh2000_bscomp_flush(struct sh2000_bscomp *c, double *p, int *last)
{
	unsigned int i, n = 0;

	if (!c->flushing) {
		/* the P that still depend on a Q other than E */
		double *e = c->last, hi = 0.0;
		int guard = straight(c);

		c->flushing = 1;
		for (i = 0; i < c->len - 1; i++) {
			shift_in(c, e);
			centre(c, c->tail + (size_t)i * c->naxes);
		}
		/* a straight approach: none passes E nor turns back; a move
		 * so short that its start is in the tail too: none backs off
		 * the start either */
		for (i = 0; guard && i < c->len - 1 && c->guard; i++, c->guard--)
			c->guard_s = clamp_along(c, c->tail + (size_t)i * c->naxes,
						 c->x0, c->guard_s, 1, 0.0, 0);
		for (i = c->len - 1; guard && i-- > 0;)
			hi = clamp_along(c, c->tail + (size_t)i * c->naxes, e,
					 0.0, 0, hi, 1);
		for (i = 0; i < c->len - 1; i++)
			if (dist_inf(c, c->tail + (size_t)i * c->naxes, e) >
			    COMP_EPS)
				n = i + 1;
		/* nothing ever left the rest point: skip to E */
		if (!c->emitting && n == 0 && dist_inf(c, e, c->x0) <= COMP_EPS)
			n = 0;
		c->ntail = n;
		c->itail = 0;
		/* the tail's last entry is E itself */
		memcpy(c->tail + (size_t)n * c->naxes, e,
		       c->naxes * sizeof(double));
		c->ntail = n + 1;
	}
	if (c->flushing == 2 || c->itail >= c->ntail)
		return 0;
	memcpy(p, c->tail + (size_t)c->itail * c->naxes,
	       c->naxes * sizeof(double));
	*last = 0;
	if (++c->itail == c->ntail) {
		*last = 1;
		c->flushing = 2;
	}
	c->emitting = 1;
	return 1;
}
