// SPDX-License-Identifier: MIT
/*
 * One coarse period along a NURBS: the parameter of the next point. The
 * NURBS interpolator paper's [R2] predictor u(i+1) = 2.5 u(i) - 2 u(i-1) +
 * 0.5 u(i-2) gives a first guess, a Newton corrector makes the *arc
 * length* of the step equal to the planned step (Simpson's rule over the
 * step, whose speed at the start is already known): the card's spline
 * follows the curve, not the chord, so a step sized by its chord would
 * run fast by the chord's shortfall. Entering a curve, the arc length
 * into the block is inverted once, inside a bracket.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

static double norm(const double *x)
{
	double s = 0.0;
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		s += x[a] * x[a];
	return sqrt(s);
}

/* The point and speed |C'| at u. */
static double point_speed(const struct pl_nurbs *nb, double u, double c[4])
{
	double d1[SH2000_AXES];

	pl_nurbs_eval(nb, u, c, d1, NULL);
	return norm(d1);
}

/* Largest distance of mid from the chord a..b: the step's sagitta. */
static double sagitta(const double *a, const double *b, const double *mid)
{
	double e[SH2000_AXES], w[SH2000_AXES], ch, wp = 0.0;
	unsigned int k;

	for (k = 0; k < SH2000_AXES; k++)
		e[k] = b[k] - a[k];
	ch = norm(e);
	if (ch <= 0.0)
		return 0.0;
	for (k = 0; k < SH2000_AXES; k++) {
		e[k] /= ch;
		w[k] = mid[k] - a[k];
		wp += w[k] * e[k];
	}
	for (k = 0; k < SH2000_AXES; k++)
		w[k] -= wp * e[k];
	return norm(w);
}

/* The first guess for the next parameter. */
static double predict(const struct sh2000_path *p, const struct pl_block *b,
		      double ds)
{
	const double *hu = p->hist_u;

	if (p->hist_n >= 3)
		return 2.5 * hu[0] - 2.0 * hu[1] + 0.5 * hu[2];
	if (p->hist_n == 2)
		return 2.0 * hu[0] - hu[1];
	return hu[0] + (b->g.nurbs.u1 - b->g.nurbs.u0) * ds / b->L;
}

/* The step of arc length ds from the last point: the parameter, with the
 * point in c and the step's arc length in *len. */
static double step(struct sh2000_path *p, const struct pl_nurbs *nb,
		   double u, double ds, double c[4], double *len)
{
	double u0 = p->hist_u[0], sp0 = p->hist_speed, m[SH2000_AXES];
	double sp1 = 0.0, spm, L = 0.0, lo = u0, hi = nb->umax;
	unsigned int it;

	/* Newton, kept inside the bracket [lo, hi] of parameters whose arc
	 * is known short / long: near a cusp |C'| goes to zero and a plain
	 * Newton step would throw the point far along the curve */
	for (it = 0; it < 60; it++) {
		double f, un;

		sp1 = point_speed(nb, u, c);
		spm = point_speed(nb, 0.5 * (u0 + u), m);
		L = (u - u0) / 6.0 * (sp0 + 4.0 * spm + sp1);
		/* Simpson's rule only where the speed is even over the step */
		if (fmax(sp0, fmax(spm, sp1)) > 2.0 * fmin(sp0, fmin(spm, sp1)))
			L = pl_nurbs_length(nb, u0, u);
		f = L - ds;
		if (it == 0 && p->hist_n >= 3 && ds > 1e-6 && u < nb->umax)
			p->feed_fluct_pred = fmax(p->feed_fluct_pred,
						  fabs(f) / ds);
		if (fabs(f) < 1e-12 * (1.0 + ds))
			break;
		if (f < 0.0)
			lo = u;
		else
			hi = u;
		if (u == nb->umax && f < 0.0)
			break;		/* the curve ends first */
		if (hi - lo <= 1e-15 * (1.0 + fabs(hi)))
			break;
		p->nurbs_corr++;
		un = sp1 > 0.0 ? u - f / sp1 : NAN;
		u = un > lo && un < hi ? un : un >= hi && hi == nb->umax ? hi
						     : 0.5 * (lo + hi);
	}
	if (u < nb->umax && ds > 1e-6)
		p->feed_fluct = fmax(p->feed_fluct, fabs(L - ds) / ds);
	p->chord_err = fmax(p->chord_err, sagitta(p->hist_c, c, m));
	p->nurbs_steps++;
	p->hist_speed = sp1;
	*len = L;
	return u;
}

/* Entering the curve: the parameter at arc length p->s into block b. */
static double enter(struct sh2000_path *p, const struct pl_block *b,
		    double c[4])
{
	double s = fmin(fmax(p->s, 0.0), b->L), l;
	double u = pl_nurbs_u_at(b->g.nurbs.nb, b->g.nurbs.u0, b->g.nurbs.u1,
				 b->L, s, &l);

	p->hist_speed = point_speed(b->g.nurbs.nb, u, c);
	p->s = s <= 0.0 ? 0.0 : l;
	return u;
}

/* The arc length from the head block's start to the curve's end: the
 * blocks of this curve in the window. */
static double to_curve_end(const struct sh2000_path *p,
			   const struct pl_nurbs *nb)
{
	double s = 0.0;
	unsigned int i;

	for (i = 0; i < p->count; i++) {
		const struct pl_block *k = pl_block_at(p, i);

		if (k->type != BLK_NURBS || k->g.nurbs.nb != nb)
			break;
		s += k->L;
		if (k->g.nurbs.u1 >= nb->umax)
			break;
	}
	return s;
}

void pl_nurbs_sample(struct sh2000_path *p, struct pl_block *b, double ds,
		     double q[SH2000_AXES])
{
	const struct pl_nurbs *nb = b->g.nurbs.nb;
	double u, c[SH2000_AXES], *hu = p->hist_u, len;

	if (p->hist_id == nb->id && p->hist_n >= 1) {
		/* the controller advanced p->s by ds along this block */
		u = fmin(fmax(predict(p, b, ds), hu[0]), nb->umax);
		if (ds > 1e-12) {
			u = step(p, nb, u, ds, c, &len);
			/* the arc the step took; at the curve's end, the end
			 * of its blocks (whatever rounding the sums left) */
			if (u >= nb->umax)
				p->s = to_curve_end(p, nb);
			else
				p->s += len - ds;
		} else {
			u = hu[0];
			pl_nurbs_eval(nb, u, c, NULL, NULL);
		}
	} else {
		u = enter(p, b, c);
		p->hist_n = 0;
	}
	hu[2] = hu[1];
	hu[1] = hu[0];
	hu[0] = u;
	if (p->hist_n < 3)
		p->hist_n++;
	p->hist_id = nb->id;
	memcpy(p->hist_c, c, sizeof(c));
	memcpy(q, c, sizeof(c));
}
