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
 * Interpolation rings: through the points of a stop the spline would
 * overshoot the end point (about J T^3 / 70 for an S-curve, 2.4 um for a
 * trapezoid that stops in two periods) and before a start back off the
 * start point, and at a corner taken at rest (G61, G61.1) the points of the
 * leg after it would pull those of the leg before off the path. So a rest
 * point C (the start, the end, and every point the planner marks as one:
 * v = 0 and a = 0 there) splits the stream: each motion between two rests
 * is filtered alone (the points beyond its rests taken as the rests), and
 * the three control points around each rest are C itself. The card's
 * spline then stops on C at its knot with v = 0 and a = 0, and between two
 * rests it only ever uses the control points of one motion. The price is
 * the knot next to each rest: the one-sided solution of the tridiagonal
 * system, P_lin + alpha (-r)^k from each rest (alpha making P next to the
 * rest C), interpolates every point but that one.
 *
 * Where the window is straight and runs one way (a move from rest
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
	unsigned char *rest;	/* rest point flags, stored twice as q */
	int exact;		/* the start and the end are rest points */
	double *rp;		/* (-r)^k, k = 0..len */
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
	c->rest = calloc((size_t)2 * c->len, 1);
	c->rp = calloc(c->len + 1, sizeof(double));
	if (!c->w || !c->q || !c->x0 || !c->last || !c->tail || !c->u ||
	    !c->rest || !c->rp) {
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
	c->rp[0] = 1.0;
	for (k = 1; k <= c->len; k++)
		c->rp[k] = -r * c->rp[k - 1];
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
	free(c->rest);
	free(c->rp);
	free(c);
}

void sh2000_bscomp_start(struct sh2000_bscomp *c, const double *x)
{
	unsigned int i;

	for (i = 0; i < 2 * c->len; i++)
		memcpy(c->q + (size_t)i * c->naxes, x, c->naxes * sizeof(double));
	/* the start is a rest point: the newest of the window */
	memset(c->rest, 0, 2 * c->len);
	c->rest[c->len - 1] = c->rest[2 * c->len - 1] = (unsigned char)c->exact;
	memcpy(c->x0, x, c->naxes * sizeof(double));
	memcpy(c->last, x, c->naxes * sizeof(double));
	c->head = 0;
	c->emitting = 0;
	c->flushing = 0;
	c->ntail = c->itail = 0;
	c->guard = c->len;
	c->guard_s = 0.0;
}

/* The window's last rest point at or before its centre (*p0, -1 if none)
 * and its first after it (*p1, len if none), as positions in the window. */
static void rests(const struct sh2000_bscomp *c, int *p0, int *p1)
{
	const unsigned char *f = c->rest + c->head;
	int k;

	*p0 = -1;
	*p1 = (int)c->len;
	for (k = (int)c->half; k >= 0 && *p0 < 0; k--)
		if (f[k])
			*p0 = k;
	for (k = (int)c->half + 1; k < (int)c->len && *p1 == (int)c->len; k++)
		if (f[k])
			*p1 = k;
}

/* The filter centred at window position pos over the motion between the
 * rests p0 and p1 alone: the points up to p0 taken as the one at p0, those
 * from p1 on as the one at p1. Summed from the oldest point (without rests
 * in the window the same sums as ever). */
static double filt(const struct sh2000_bscomp *c, int pos, int p0, int p1,
		   unsigned int ax)
{
	const double *q = c->q + (size_t)c->head * c->naxes;
	double s = 0.0;
	unsigned int k;

	for (k = 0; k < c->len; k++) {
		int i = pos - (int)c->half + (int)k;

		i = i <= p0 ? p0 : i >= p1 ? p1 : i;
		s += c->w[k] * q[(size_t)i * c->naxes + ax];
	}
	return s;
}

/* P at the centre of the window. Next to a rest point (within one) it is
 * the rest point; else the filter over its own motion plus the one-sided
 * corrections alpha (-r)^k from each rest that make P next to it the rest
 * point (solved together where both rests are in the window). */
static void centre(const struct sh2000_bscomp *c, double *p)
{
	const double *q = c->q + (size_t)c->head * c->naxes;
	int h = (int)c->half, p0, p1, in0, in1;
	unsigned int ax;
	double g;

	rests(c, &p0, &p1);
	in0 = p0 >= 0;
	in1 = p1 < (int)c->len;
	if ((in0 && h <= p0 + 1) || (in1 && h >= p1 - 1)) {
		memcpy(p, q + (size_t)(in0 && h <= p0 + 1 ? p0 : p1) * c->naxes,
		       c->naxes * sizeof(double));
		return;
	}
	g = in0 && in1 ? c->rp[p1 - p0 - 2] : 0.0;
	for (ax = 0; ax < c->naxes; ax++) {
		double e0 = 0.0, e1 = 0.0, al, be;

		p[ax] = filt(c, h, p0, p1, ax);
		if (in0)
			e0 = q[(size_t)p0 * c->naxes + ax] -
			     filt(c, p0 + 1, p0, p1, ax);
		if (in1)
			e1 = q[(size_t)p1 * c->naxes + ax] -
			     filt(c, p1 - 1, p0, p1, ax);
		al = (e0 - g * e1) / (1.0 - g * g);
		be = (e1 - g * e0) / (1.0 - g * g);
		if (in0)
			p[ax] += al * c->rp[h - p0 - 1];
		if (in1)
			p[ax] += be * c->rp[p1 - 1 - h];
	}
}

static void shift_in(struct sh2000_bscomp *c, const double *q, int rest)
{
	size_t n = c->naxes * sizeof(double);

	memcpy(c->q + (size_t)c->head * c->naxes, q, n);
	memcpy(c->q + (size_t)(c->head + c->len) * c->naxes, q, n);
	c->rest[c->head] = c->rest[c->head + c->len] = rest != 0;
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

void pl_bscomp_exact(struct sh2000_bscomp *c, int on)
{
	c->exact = on != 0;
}

int sh2000_bscomp_push(struct sh2000_bscomp *c, const double *q, double *p)
{
	return pl_bscomp_push(c, q, 0, p);
}

int pl_bscomp_push(struct sh2000_bscomp *c, const double *q, int rest,
		   double *p)
{
	shift_in(c, q, rest);
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
		/* the end is a rest point: the newest of the window */
		i = (c->head + c->len - 1) % c->len;
		c->rest[i] = c->rest[i + c->len] = (unsigned char)c->exact;
		for (i = 0; i < c->len - 1; i++) {
			shift_in(c, e, 0);
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
